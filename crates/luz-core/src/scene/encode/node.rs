//! The encoder's ordered JSON tree and its printer; numbers as the shortest text that reads back
//! as the same `f32`, and unit vectors as a preimage of the decoder's normalisation.

use glam::{DVec3, Vec3};
use serde_json::Value;

// ---------------------------------------------------------------------------------------------
// An ordered JSON tree and its printer.

#[derive(Debug, Clone, PartialEq)]
pub(super) enum Node {
    Null,
    Bool(bool),
    Int(u64),
    Num(f32),
    Str(String),
    Arr(Vec<Node>),
    Obj(Vec<(String, Node)>),
}

impl Node {
    pub(super) fn obj() -> Self {
        Node::Obj(Vec::new())
    }

    /// Appends `key: value` (objects only).
    pub(super) fn put(&mut self, key: &str, value: impl Into<Node>) -> &mut Self {
        if let Node::Obj(fields) = self {
            fields.push((key.to_string(), value.into()));
        }
        self
    }

    pub(super) fn with(mut self, key: &str, value: impl Into<Node>) -> Self {
        self.put(key, value);
        self
    }

    pub(super) fn is_scalar(&self) -> bool {
        !matches!(self, Node::Arr(_) | Node::Obj(_))
    }

    pub(super) fn to_value(&self) -> Value {
        match self {
            Node::Null => Value::Null,
            Node::Bool(b) => Value::Bool(*b),
            Node::Int(i) => Value::from(*i),
            Node::Num(x) => num_value(*x)
                .and_then(serde_json::Number::from_f64)
                .map_or(Value::Null, Value::Number),
            Node::Str(s) => Value::String(s.clone()),
            Node::Arr(items) => Value::Array(items.iter().map(Node::to_value).collect()),
            Node::Obj(fields) => Value::Object(
                fields
                    .iter()
                    .map(|(k, v)| (k.clone(), v.to_value()))
                    .collect(),
            ),
        }
    }

    pub(super) fn write(&self, indent: usize, out: &mut String) {
        match self {
            Node::Null => out.push_str("null"),
            Node::Bool(b) => out.push_str(if *b { "true" } else { "false" }),
            Node::Int(i) => out.push_str(&i.to_string()),
            Node::Num(x) => out.push_str(num_text(*x).as_deref().unwrap_or("null")),
            Node::Str(s) => out.push_str(&json_string(s)),
            Node::Arr(items) if items.is_empty() => out.push_str("[]"),
            Node::Arr(items) if items.iter().all(Node::is_scalar) => {
                out.push('[');
                for (i, item) in items.iter().enumerate() {
                    if i > 0 {
                        out.push_str(", ");
                    }
                    item.write(indent, out);
                }
                out.push(']');
            }
            Node::Arr(items) => {
                out.push_str("[\n");
                for (i, item) in items.iter().enumerate() {
                    push_indent(out, indent + 1);
                    item.write(indent + 1, out);
                    out.push_str(if i + 1 < items.len() { ",\n" } else { "\n" });
                }
                push_indent(out, indent);
                out.push(']');
            }
            Node::Obj(fields) if fields.is_empty() => out.push_str("{}"),
            Node::Obj(fields) => {
                out.push_str("{\n");
                for (i, (key, value)) in fields.iter().enumerate() {
                    push_indent(out, indent + 1);
                    out.push_str(&json_string(key));
                    out.push_str(": ");
                    value.write(indent + 1, out);
                    out.push_str(if i + 1 < fields.len() { ",\n" } else { "\n" });
                }
                push_indent(out, indent);
                out.push('}');
            }
        }
    }
}

pub(super) fn push_indent(out: &mut String, level: usize) {
    for _ in 0..level {
        out.push_str("  ");
    }
}

pub(super) fn json_string(s: &str) -> String {
    serde_json::to_string(s).unwrap_or_else(|_| "\"\"".to_string())
}

impl From<bool> for Node {
    fn from(b: bool) -> Self {
        Node::Bool(b)
    }
}

impl From<u32> for Node {
    fn from(i: u32) -> Self {
        Node::Int(u64::from(i))
    }
}

impl From<f32> for Node {
    fn from(x: f32) -> Self {
        Node::Num(x)
    }
}

impl From<Vec3> for Node {
    fn from(v: Vec3) -> Self {
        Node::Arr(v.to_array().map(Node::Num).to_vec())
    }
}

impl From<&str> for Node {
    fn from(s: &str) -> Self {
        Node::Str(s.to_string())
    }
}

impl From<String> for Node {
    fn from(s: String) -> Self {
        Node::Str(s)
    }
}

/// The text of `x` in a scene file: the shortest decimal that reads back as `x` when parsed as
/// an `f64` and rounded to `f32` (what the decoder does); `None` for NaN and infinities, which
/// JSON cannot hold.
pub(super) fn num_text(x: f32) -> Option<String> {
    if !x.is_finite() {
        return None;
    }
    // `{:?}` is the shortest text that parses back (as an f32) to x, with an exponent for very
    // large or small values ("1e-7"), always valid JSON. Parsing it as an f64 and rounding could in
    // principle round twice the wrong way; then the f64 value of x itself is written (exact).
    let short = format!("{x:?}");
    if short.parse::<f64>().ok().map(|d| d as f32) == Some(x) {
        Some(short)
    } else {
        Some(format!("{:?}", f64::from(x)))
    }
}

/// The `f64` the decoder reads from [`num_text`].
pub(super) fn num_value(x: f32) -> Option<f64> {
    num_text(x).and_then(|t| t.parse().ok())
}

// ---------------------------------------------------------------------------------------------
// Vectors the decoder normalises.

/// The decoder's normalisation (`decode::unit`): in f64, then rounded to f32.
pub(super) fn unit(v: Vec3) -> Option<Vec3> {
    let d = DVec3::from(v.to_array().map(f64::from));
    let len = d.length();
    (len > 1e-12 && len.is_finite()).then(|| (d / len).as_vec3())
}

/// A vector `w` with `unit(w) == u`, for a unit vector `u` the decoder produced: `u` itself
/// when normalising it again does not move it (true of about 99 % of unit vectors), else a
/// nearby vector that normalises to exactly `u`. A vector that is not of unit length is returned
/// as it is (the decoder will normalise it), and so is `u` in the rare case that the search finds
/// nothing (it then moves by an ulp when the file is read).
///
/// The directions that round to `u` form a small region around `u + r`, where `r` corrects
/// `u`'s length error η = |u| − 1 (r·u = −η), spread over the components in proportion to the
/// rounding slack h_i of each (half an ulp). The search rounds that direction scaled by factors
/// in [1, 2) (each scale rounds the components differently) and tries the neighbours one ulp
/// away.
pub(super) fn unit_preimage(u: Vec3) -> Vec3 {
    if unit(u) == Some(u) || !u.is_finite() || (u.length() - 1.0).abs() > 1e-4 {
        return u;
    }
    let ud = DVec3::from(u.to_array().map(f64::from));
    let eta = ud.length() - 1.0;
    let half_ulp = |x: f32| {
        let up = f64::from(x.next_up()) - f64::from(x);
        let down = f64::from(x) - f64::from(x.next_down());
        up.min(down) / 2.0
    };
    let h = DVec3::new(half_ulp(u.x), half_ulp(u.y), half_ulp(u.z));
    let slack = h.dot(ud.abs());
    let target = if slack > 0.0 {
        ud - h * ud.signum() * (eta / slack)
    } else {
        ud
    };
    let around = |x: f32| [x, x.next_down(), x.next_up()];
    const SCALES: u32 = 2048;
    for k in 0..SCALES {
        let w = (target * (1.0 + f64::from(k) / f64::from(SCALES))).as_vec3();
        for x in around(w.x) {
            for y in around(w.y) {
                for z in around(w.z) {
                    let w = Vec3::new(x, y, z);
                    if unit(w) == Some(u) {
                        return w;
                    }
                }
            }
        }
    }
    u
}

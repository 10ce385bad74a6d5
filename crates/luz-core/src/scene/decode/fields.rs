//! Typed access to the JSON tree with paths: fields of an object (unknown and missing keys,
//! suggestions), numbers with range checks, vectors, colours, strings and choices.

use super::*;

// ---------------------------------------------------------------------------------------------
// Typed access with paths.

pub(super) fn child(path: &str, key: &str) -> String {
    let mut p = path.to_string();
    push_key(&mut p, key);
    p
}

pub(super) fn index(path: &str, i: usize) -> String {
    format!("{path}[{i}]")
}

/// Shortest text that reads back as the same f32 ("-1", "0.1", "1e-7").
pub(super) fn show(x: f32) -> String {
    format!("{x}")
}

/// Edit distance, for "did you mean" hints.
pub(super) fn distance(a: &str, b: &str) -> usize {
    let b: Vec<char> = b.chars().collect();
    let mut row: Vec<usize> = (0..=b.len()).collect();
    for (i, ca) in a.chars().enumerate() {
        let mut prev = row[0];
        row[0] = i + 1;
        for (j, cb) in b.iter().enumerate() {
            let cur = row[j + 1];
            row[j + 1] = (prev + usize::from(ca != *cb)).min(row[j] + 1).min(cur + 1);
            prev = cur;
        }
    }
    row[b.len()]
}

/// Most cells of edit-distance tables one [`suggestion`] fills (about 50 ms): the options may be
/// every material name of a huge scene. Beyond it there is no "did you mean".
pub(super) const SUGGESTION_WORK: usize = 50_000_000;

pub(super) fn suggestion(word: &str, options: &[&str]) -> String {
    let word = word.to_lowercase();
    let word_chars = word.chars().count();
    let mut best: Option<(usize, &str)> = None;
    let mut work = 0usize;
    for o in options {
        let (o_chars, limit) = (o.chars().count(), 2.max(o.len() / 4));
        // The distance is at least the difference in length: skip what the limit rejects anyway
        // (a huge unknown key must not cost its length times every option's).
        if word_chars.abs_diff(o_chars) > limit {
            continue;
        }
        work = work.saturating_add(word_chars.saturating_mul(o_chars));
        if work > SUGGESTION_WORK {
            best = None;
            break;
        }
        let d = distance(&word, o);
        if d <= limit && d < o.len() && best.is_none_or(|b| (d, *o) < b) {
            best = Some((d, o));
        }
    }
    best.map(|(_, o)| o)
        // A field name without its unit suffix ("sigma" for "sigma_deg").
        .or_else(|| {
            options
                .iter()
                .find(|o| {
                    word.len() >= 3
                        && o.strip_prefix(word.as_str())
                            .is_some_and(|rest| rest.starts_with('_'))
                })
                .copied()
        })
        .map(|o| format!(" (did you mean \"{o}\"?)"))
        .unwrap_or_default()
}

/// "a cook_torrance material", "an oren_nayar material".
pub(super) fn a_material(model: &str) -> String {
    let article = if model.starts_with(['a', 'e', 'i', 'o', 'u']) {
        "an"
    } else {
        "a"
    };
    format!("{article} {model} material")
}

pub(super) fn one_of(options: &[&str]) -> String {
    options
        .iter()
        .map(|o| format!("\"{o}\""))
        .collect::<Vec<_>>()
        .join(", ")
}

/// An object's fields with the object's path.
pub(super) struct Fields<'a> {
    pub(super) path: String,
    pub(super) fields: &'a [(String, Value)],
}

impl<'a> Fields<'a> {
    pub(super) fn new(v: &'a Value, path: &str) -> Result<Self> {
        match &v.kind {
            Kind::Object(fields) => Ok(Fields {
                path: path.to_string(),
                fields,
            }),
            k => Err(Invalid::new(
                path,
                format!("expected an object {{…}}, got {}", k.describe()),
            )),
        }
    }

    /// Fails on the first field not in `allowed`; `what` names the thing for the message.
    pub(super) fn allow(&self, allowed: &[&str], what: &str) -> Result<()> {
        for (key, _) in self.fields {
            if !allowed.contains(&key.as_str()) {
                return Err(Invalid::new(
                    &child(&self.path, key),
                    format!(
                        "unknown field \"{key}\"{}{}; expected one of: {}",
                        if what.is_empty() { "" } else { " for " },
                        what,
                        allowed.join(", ")
                    ) + &suggestion(key, allowed),
                ));
            }
        }
        Ok(())
    }

    /// The one field of `keys` the object gives (`None`: none of them). Two are an error at the
    /// second that names both, `what` they give and the keys to keep one of.
    pub(super) fn exclusive(
        &self,
        keys: &[&'static str],
        what: &str,
    ) -> Result<Option<&'static str>> {
        let mut given = self
            .fields
            .iter()
            .filter_map(|(k, _)| keys.iter().find(|s| **s == k.as_str()).copied());
        let first = given.next();
        if let (Some(key), Some(second)) = (first, given.next()) {
            return Err(self.err(
                second,
                format!(
                    "\"{key}\" and \"{second}\" both give {what}; keep exactly one of: {}",
                    keys.join(", ")
                ),
            ));
        }
        Ok(first)
    }

    pub(super) fn get(&self, key: &str) -> Option<&'a Value> {
        self.fields.iter().find(|(k, _)| k == key).map(|(_, v)| v)
    }

    pub(super) fn has(&self, key: &str) -> bool {
        self.get(key).is_some()
    }

    pub(super) fn path(&self, key: &str) -> String {
        child(&self.path, key)
    }

    pub(super) fn err(&self, key: &str, reason: impl Into<String>) -> Invalid {
        Invalid::new(&self.path(key), reason)
    }

    pub(super) fn req(&self, key: &str) -> Result<&'a Value> {
        self.get(key)
            .ok_or_else(|| self.err(key, "missing required field"))
    }

    pub(super) fn num(&self, key: &str, default: f32, check: Check) -> Result<f32> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => number(v, &self.path(key), check),
        }
    }

    pub(super) fn int(&self, key: &str, default: u32, lo: u32, hi: u32) -> Result<u32> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => integer(v, &self.path(key), lo, hi),
        }
    }

    pub(super) fn vec3(&self, key: &str, default: Vec3) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => vec3(v, &self.path(key), Check::Any),
        }
    }

    pub(super) fn color(&self, key: &str, default: Vec3) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => color(v, &self.path(key)),
        }
    }

    /// A colour whose every channel passes `check` (one number means grey).
    pub(super) fn color_in(&self, key: &str, default: Vec3, check: Check) -> Result<Vec3> {
        match self.get(key) {
            None => Ok(default),
            Some(v) => color_in(v, &self.path(key), check),
        }
    }

    pub(super) fn boolean(&self, key: &str, default: bool) -> Result<bool> {
        match self.get(key) {
            None => Ok(default),
            Some(Value {
                kind: Kind::Bool(b),
                ..
            }) => Ok(*b),
            Some(v) => Err(self.err(
                key,
                format!("expected true or false, got {}", v.kind.describe()),
            )),
        }
    }

    /// A selector: a string from `table`, mapped to its value.
    pub(super) fn select<T: Copy>(&self, key: &str, table: &[(&str, T)], default: T) -> Result<T> {
        let names: Vec<&str> = table.iter().map(|(n, _)| *n).collect();
        Ok(match self.choice(key, &names)? {
            None => default,
            Some(s) => table
                .iter()
                .find(|(n, _)| *n == s)
                .map_or(default, |(_, t)| *t),
        })
    }

    pub(super) fn string(&self, key: &str) -> Result<Option<&'a str>> {
        self.get(key)
            .map(|v| string(v, &self.path(key)))
            .transpose()
    }

    /// A string field that must be one of `options`.
    pub(super) fn choice(&self, key: &str, options: &[&str]) -> Result<Option<&'a str>> {
        match self.get(key) {
            None => Ok(None),
            Some(v) => choice(v, &self.path(key), options).map(Some),
        }
    }
}

#[derive(Clone, Copy)]
pub(super) enum Check {
    Any,
    NonNegative,
    Positive,
    /// Closed interval.
    In(f32, f32),
    /// Open interval.
    Between(f32, f32),
}

pub(super) fn number(v: &Value, path: &str, check: Check) -> Result<f32> {
    let Kind::Number { value, raw } = &v.kind else {
        return Err(Invalid::new(
            path,
            format!("expected a number, got {}", v.kind.describe()),
        ));
    };
    if !value.is_finite() {
        return Err(Invalid::new(
            path,
            format!("must be a finite number, got {raw} (overflows)"),
        ));
    }
    let x = *value as f32;
    if !x.is_finite() {
        return Err(Invalid::new(
            path,
            format!("must be a finite number, got {raw} (too large for a 32-bit float)"),
        ));
    }
    let ok = match check {
        Check::Any => None,
        Check::NonNegative => (x < 0.0).then(|| "must be ≥ 0".to_string()),
        Check::Positive => (x <= 0.0).then(|| "must be > 0".to_string()),
        Check::In(lo, hi) => {
            (!(lo..=hi).contains(&x)).then(|| format!("must be in [{}, {}]", show(lo), show(hi)))
        }
        Check::Between(lo, hi) => {
            (x <= lo || x >= hi).then(|| format!("must be in ({}, {})", show(lo), show(hi)))
        }
    };
    match ok {
        None => Ok(x),
        Some(rule) => Err(Invalid::new(path, format!("{rule}, got {raw}"))),
    }
}

pub(super) fn integer(v: &Value, path: &str, lo: u32, hi: u32) -> Result<u32> {
    let Kind::Number { value, raw } = &v.kind else {
        return Err(Invalid::new(
            path,
            format!("expected an integer, got {}", v.kind.describe()),
        ));
    };
    if value.fract() != 0.0 || !value.is_finite() {
        return Err(Invalid::new(
            path,
            format!("expected an integer, got {raw}"),
        ));
    }
    if *value < f64::from(lo) || *value > f64::from(hi) {
        return Err(Invalid::new(
            path,
            format!("must be in [{lo}, {hi}], got {raw}"),
        ));
    }
    Ok(*value as u32)
}

pub(super) fn array<'a>(v: &'a Value, path: &str, what: &str) -> Result<&'a [Value]> {
    match &v.kind {
        Kind::Array(items) => Ok(items),
        k => Err(Invalid::new(
            path,
            format!("expected {what}, got {}", k.describe()),
        )),
    }
}

pub(super) fn vec3(v: &Value, path: &str, check: Check) -> Result<Vec3> {
    let items = array(v, path, "an array of 3 numbers [x, y, z]")?;
    if items.len() != 3 {
        return Err(Invalid::new(
            path,
            format!(
                "expected an array of 3 numbers [x, y, z], got {} element{}",
                items.len(),
                if items.len() == 1 { "" } else { "s" }
            ),
        ));
    }
    let mut out = [0.0; 3];
    for (i, item) in items.iter().enumerate() {
        out[i] = number(item, &index(path, i), check)?;
    }
    Ok(Vec3::from_array(out))
}

/// A linear RGB colour: [r, g, b] or one number for grey; every channel ≥ 0.
pub(super) fn color(v: &Value, path: &str) -> Result<Vec3> {
    color_in(v, path, Check::NonNegative)
}

/// A colour-shaped value ([r, g, b] or one number for all three) whose channels pass `check`.
pub(super) fn color_in(v: &Value, path: &str, check: Check) -> Result<Vec3> {
    match &v.kind {
        Kind::Number { .. } => Ok(Vec3::splat(number(v, path, check)?)),
        Kind::Array(items) if items.len() == 3 => vec3(v, path, check),
        Kind::Array(items) => Err(Invalid::new(
            path,
            format!(
                "expected a colour [r, g, b] (or one number for grey), got {} element{}",
                items.len(),
                if items.len() == 1 { "" } else { "s" }
            ),
        )),
        k => Err(Invalid::new(
            path,
            format!(
                "expected a colour [r, g, b] (or one number for grey), got {}",
                k.describe()
            ),
        )),
    }
}

pub(super) fn string<'a>(v: &'a Value, path: &str) -> Result<&'a str> {
    match &v.kind {
        Kind::String(s) => Ok(s),
        k => Err(Invalid::new(
            path,
            format!("expected a string, got {}", k.describe()),
        )),
    }
}

/// A file named at `path`: a non-empty string, resolved against `base`; with its extension in
/// lower case.
pub(super) fn file_name(v: &Value, path: &str, base: &Path) -> Result<(PathBuf, Option<String>)> {
    let p = string(v, path)?;
    if p.trim().is_empty() {
        return Err(Invalid::new(path, "must not be empty"));
    }
    let file = base.join(p);
    let ext = crate::files::lowercase_extension(&file);
    Ok((file, ext))
}

pub(super) fn choice<'a>(v: &'a Value, path: &str, options: &[&str]) -> Result<&'a str> {
    let s = match &v.kind {
        Kind::String(s) => s.as_str(),
        k => {
            return Err(Invalid::new(
                path,
                format!("expected one of {}, got {}", one_of(options), k.describe()),
            ))
        }
    };
    if options.contains(&s) {
        Ok(s)
    } else {
        Err(Invalid::new(
            path,
            format!(
                "unknown value \"{s}\"; expected one of {}{}",
                one_of(options),
                suggestion(s, options)
            ),
        ))
    }
}

/// A unit vector from any non-zero vector (computed in f64 so huge components do not overflow).
pub(super) fn unit(v: Vec3) -> Option<Vec3> {
    let d = DVec3::from(v.to_array().map(f64::from));
    let len = d.length();
    (len > 1e-12 && len.is_finite()).then(|| (d / len).as_vec3())
}

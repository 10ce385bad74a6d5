//! A small, strict JSON reader that remembers where every value came from.
//!
//! Why not `serde_json`: a scene error must name the JSON path of the offending value, also for
//! syntax errors, truncated files and numbers such as `1e999` that `serde_json` rejects before any
//! path is known. This reader keeps the raw text of every number (so messages quote what the user
//! wrote), keeps object fields in file order, rejects duplicate keys, and never recurses deeper
//! than [`MAX_DEPTH`], so no input can overflow the stack.

use std::cell::Cell;
use std::collections::HashSet;
use std::fmt::Write as _;
use std::hash::{BuildHasher, RandomState};

/// Deepest nesting of arrays and objects accepted.
pub const MAX_DEPTH: usize = 64;

/// A JSON value with the line and column (1-based) where it starts.
#[derive(Debug, Clone, PartialEq)]
pub struct Value {
    pub kind: Kind,
    pub line: u32,
    pub column: u32,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Kind {
    Null,
    Bool(bool),
    /// `value` may be infinite when the literal overflows `f64` (e.g. `1e999`); `raw` is the text.
    Number {
        value: f64,
        raw: String,
    },
    String(String),
    Array(Vec<Value>),
    /// Fields in file order; keys are unique.
    Object(Vec<(String, Value)>),
}

impl Kind {
    /// "a string", "an array", … for messages.
    pub fn describe(&self) -> &'static str {
        match self {
            Kind::Null => "null",
            Kind::Bool(_) => "a boolean",
            Kind::Number { .. } => "a number",
            Kind::String(_) => "a string",
            Kind::Array(_) => "an array",
            Kind::Object(_) => "an object",
        }
    }
}

/// A syntax error: where (JSON path of the value being read, line, column) and why.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SyntaxError {
    pub path: String,
    pub line: u32,
    pub column: u32,
    pub reason: String,
}

/// One step of a JSON path.
#[derive(Debug, Clone)]
pub enum Step {
    Key(String),
    Index(usize),
}

/// Renders a path such as `lights[2].intensity` or `materials["my mat"].kd`; the empty path is
/// `(root)`.
pub fn render_path(steps: &[Step]) -> String {
    let mut out = String::new();
    for step in steps {
        match step {
            Step::Key(key) => push_key(&mut out, key),
            Step::Index(i) => {
                let _ = write!(out, "[{i}]");
            }
        }
    }
    if out.is_empty() {
        out.push_str("(root)");
    }
    out
}

/// Appends `.key` (or `["key"]` when the key is not a plain identifier) to a rendered path.
pub fn push_key(out: &mut String, key: &str) {
    let plain = !key.is_empty()
        && key
            .chars()
            .all(|c| c.is_ascii_alphanumeric() || c == '_' || c == '-');
    if plain {
        if !out.is_empty() {
            out.push('.');
        }
        out.push_str(key);
    } else {
        out.push('[');
        let _ = write!(out, "{key:?}");
        out.push(']');
    }
}

/// Parses a whole document (one value, surrounded by optional whitespace; a leading UTF-8 byte
/// order mark is skipped).
pub fn parse(text: &str) -> Result<Value, SyntaxError> {
    let text = text.strip_prefix('\u{feff}').unwrap_or(text);
    let mut p = Parser {
        bytes: text.as_bytes(),
        text,
        pos: 0,
        line: 1,
        line_start: 0,
        column_mark: Cell::new((0, 1)),
        path: Vec::new(),
    };
    p.skip_ws();
    if p.pos >= p.bytes.len() {
        return Err(p.error("the file is empty (expected a JSON object)"));
    }
    let value = p.value(0)?;
    p.skip_ws();
    if p.pos < p.bytes.len() {
        return Err(p.error(format!(
            "unexpected {} after the end of the document",
            p.describe_here()
        )));
    }
    Ok(value)
}

struct Parser<'a> {
    bytes: &'a [u8],
    text: &'a str,
    pos: usize,
    line: u32,
    line_start: usize,
    /// The last column computed: (byte offset, its column). Columns are counted from there, not
    /// from the start of the line, which made one-line files quadratic.
    column_mark: Cell<(usize, u32)>,
    path: Vec<Step>,
}

impl Parser<'_> {
    /// The 1-based column of the cursor, in characters.
    fn column(&self) -> u32 {
        let start = self.line_start.min(self.text.len());
        let end = self.pos.min(self.text.len());
        let (mark, mark_column) = self.column_mark.get();
        let (from, base) = if (start..=end).contains(&mark) {
            (mark, mark_column)
        } else {
            (start, 1)
        };
        let Some(slice) = self.text.get(from..end) else {
            // Not at a character boundary (unreachable): counted as the start of the line.
            return 1;
        };
        let column = base.saturating_add(u32::try_from(slice.chars().count()).unwrap_or(u32::MAX));
        self.column_mark.set((end, column));
        column
    }

    fn error(&self, reason: impl Into<String>) -> SyntaxError {
        SyntaxError {
            path: render_path(&self.path),
            line: self.line,
            column: self.column(),
            reason: reason.into(),
        }
    }

    fn describe_here(&self) -> String {
        match self.text.get(self.pos..).and_then(|s| s.chars().next()) {
            None => "end of file".to_string(),
            Some(c) if c.is_control() => format!("character {:?}", c),
            Some(c) => format!("'{c}'"),
        }
    }

    fn peek(&self) -> Option<u8> {
        self.bytes.get(self.pos).copied()
    }

    fn skip_ws(&mut self) {
        while let Some(b) = self.peek() {
            match b {
                b' ' | b'\t' | b'\r' => self.pos += 1,
                b'\n' => {
                    self.pos += 1;
                    self.line = self.line.saturating_add(1);
                    self.line_start = self.pos;
                }
                _ => break,
            }
        }
    }

    fn value(&mut self, depth: usize) -> Result<Value, SyntaxError> {
        self.skip_ws();
        let line = self.line;
        let column = self.column();
        let kind = match self.peek() {
            None => return Err(self.error("unexpected end of file: the document is incomplete")),
            Some(b'{') => {
                self.check_depth(depth)?;
                self.object(depth)?
            }
            Some(b'[') => {
                self.check_depth(depth)?;
                self.array(depth)?
            }
            Some(b'"') => Kind::String(self.string()?),
            Some(b'-' | b'0'..=b'9') => self.number()?,
            Some(b't') => self.literal("true", Kind::Bool(true))?,
            Some(b'f') => self.literal("false", Kind::Bool(false))?,
            Some(b'n') => self.literal("null", Kind::Null)?,
            Some(_) => {
                let word = self.word();
                if matches!(
                    word.as_str(),
                    "NaN" | "nan" | "Infinity" | "inf" | "-Infinity" | "+Infinity"
                ) {
                    return Err(self.error(format!(
                        "{word} is not a number JSON allows (numbers must be finite)"
                    )));
                }
                return Err(self.error(format!("expected a value, found {}", self.describe_here())));
            }
        };
        Ok(Value { kind, line, column })
    }

    /// The identifier-like word at the cursor (for messages).
    fn word(&self) -> String {
        let rest = self.text.get(self.pos..).unwrap_or("");
        rest.chars()
            .take_while(|c| c.is_ascii_alphanumeric() || matches!(c, '+' | '-' | '_' | '.'))
            .take(32)
            .collect()
    }

    fn check_depth(&self, depth: usize) -> Result<(), SyntaxError> {
        if depth >= MAX_DEPTH {
            Err(self.error(format!("nesting deeper than {MAX_DEPTH} levels")))
        } else {
            Ok(())
        }
    }

    fn literal(&mut self, word: &str, kind: Kind) -> Result<Kind, SyntaxError> {
        if self.bytes[self.pos..].starts_with(word.as_bytes()) {
            let end = self.pos + word.len();
            let next = self.bytes.get(end).copied();
            if !matches!(next, Some(b) if b.is_ascii_alphanumeric() || b == b'_') {
                self.pos = end;
                return Ok(kind);
            }
        }
        let found = self.word();
        if found == "nan" {
            return Err(self.error("nan is not a number JSON allows (numbers must be finite)"));
        }
        Err(self.error(format!("expected a value, found '{found}'")))
    }

    fn number(&mut self) -> Result<Kind, SyntaxError> {
        let start = self.pos;
        let bytes = self.bytes;
        let mut i = self.pos;
        if bytes.get(i) == Some(&b'-') {
            i += 1;
            if bytes[i..].starts_with(b"Infinity") || bytes[i..].starts_with(b"inf") {
                return Err(
                    self.error("-Infinity is not a number JSON allows (numbers must be finite)")
                );
            }
        }
        let digits = |i: &mut usize| {
            let s = *i;
            while matches!(bytes.get(*i), Some(b'0'..=b'9')) {
                *i += 1;
            }
            *i - s
        };
        let int_start = i;
        let n = digits(&mut i);
        if n == 0 {
            return Err(self.malformed_number(i, "expected a digit"));
        }
        if n > 1 && bytes[int_start] == b'0' {
            self.pos = int_start;
            return Err(self.error("malformed number: leading zeros are not allowed"));
        }
        if bytes.get(i) == Some(&b'.') {
            i += 1;
            if digits(&mut i) == 0 {
                return Err(self.malformed_number(i, "expected a digit after '.'"));
            }
        }
        if matches!(bytes.get(i), Some(b'e' | b'E')) {
            i += 1;
            if matches!(bytes.get(i), Some(b'+' | b'-')) {
                i += 1;
            }
            if digits(&mut i) == 0 {
                return Err(self.malformed_number(i, "expected a digit in the exponent"));
            }
        }
        if matches!(bytes.get(i), Some(b) if b.is_ascii_alphanumeric() || *b == b'.' || *b == b'_')
        {
            self.pos = i;
            return Err(self.error(format!(
                "malformed number: unexpected {} in a number",
                self.describe_here()
            )));
        }
        self.pos = i;
        let raw = self.text[start..i].to_string();
        // Rust's parser accepts every JSON number; overflow gives ±inf, which the decoder reports
        // with the path of the field.
        let value = raw.parse::<f64>().unwrap_or(f64::NAN);
        Ok(Kind::Number { value, raw })
    }

    /// The error of a number that is malformed at byte `i`: what was `expected` there and what
    /// was found.
    fn malformed_number(&mut self, i: usize, expected: &str) -> SyntaxError {
        self.pos = i;
        self.error(format!(
            "malformed number: {expected}, found {}",
            self.describe_here()
        ))
    }

    fn hex4(&mut self) -> Result<u32, SyntaxError> {
        let mut v = 0u32;
        for _ in 0..4 {
            let d = match self.peek() {
                Some(b @ b'0'..=b'9') => u32::from(b - b'0'),
                Some(b @ b'a'..=b'f') => u32::from(b - b'a' + 10),
                Some(b @ b'A'..=b'F') => u32::from(b - b'A' + 10),
                _ => {
                    return Err(self.error(format!(
                        "malformed \\u escape: expected a hex digit, found {}",
                        self.describe_here()
                    )))
                }
            };
            v = v * 16 + d;
            self.pos += 1;
        }
        Ok(v)
    }

    fn string(&mut self) -> Result<String, SyntaxError> {
        // At the opening quote.
        self.pos += 1;
        let mut out = String::new();
        loop {
            let Some(b) = self.peek() else {
                return Err(self.error("unexpected end of file inside a string"));
            };
            match b {
                b'"' => {
                    self.pos += 1;
                    return Ok(out);
                }
                b'\\' => {
                    self.pos += 1;
                    let Some(e) = self.peek() else {
                        return Err(self.error("unexpected end of file inside a string"));
                    };
                    self.pos += 1;
                    match e {
                        b'"' => out.push('"'),
                        b'\\' => out.push('\\'),
                        b'/' => out.push('/'),
                        b'b' => out.push('\u{8}'),
                        b'f' => out.push('\u{c}'),
                        b'n' => out.push('\n'),
                        b'r' => out.push('\r'),
                        b't' => out.push('\t'),
                        b'u' => {
                            let hi = self.hex4()?;
                            let c = if (0xD800..0xDC00).contains(&hi) {
                                if self.bytes[self.pos..].starts_with(b"\\u") {
                                    self.pos += 2;
                                    let lo = self.hex4()?;
                                    if !(0xDC00..0xE000).contains(&lo) {
                                        return Err(self.error("invalid UTF-16 surrogate pair"));
                                    }
                                    char::from_u32(0x10000 + ((hi - 0xD800) << 10) + (lo - 0xDC00))
                                } else {
                                    None
                                }
                            } else {
                                char::from_u32(hi)
                            };
                            match c {
                                Some(c) => out.push(c),
                                None => {
                                    return Err(self.error("invalid \\u escape (lone surrogate)"))
                                }
                            }
                        }
                        _ => {
                            self.pos -= 1;
                            return Err(self.error(format!(
                                "invalid escape \\{}",
                                self.describe_here().trim_matches('\'')
                            )));
                        }
                    }
                }
                b if b < 0x20 => {
                    return Err(self.error(if b == b'\n' {
                        "unterminated string (line break inside a string)".to_string()
                    } else {
                        "control character inside a string".to_string()
                    }))
                }
                _ => {
                    // Copy one whole UTF-8 character.
                    let rest = &self.text[self.pos..];
                    let c = rest.chars().next().unwrap_or('\u{fffd}');
                    out.push(c);
                    self.pos += c.len_utf8().max(1);
                }
            }
        }
    }

    fn array(&mut self, depth: usize) -> Result<Kind, SyntaxError> {
        self.pos += 1; // '['
        let mut items = Vec::new();
        if self.empty_until(b']') {
            return Ok(Kind::Array(items));
        }
        loop {
            self.path.push(Step::Index(items.len()));
            let v = self.value(depth + 1)?;
            self.path.pop();
            items.push(v);
            if self.after_item(b']', "an array")? {
                return Ok(Kind::Array(items));
            }
        }
    }

    fn object(&mut self, depth: usize) -> Result<Kind, SyntaxError> {
        self.pos += 1; // '{'
        let mut fields: Vec<(String, Value)> = Vec::new();
        // Hashes of the keys, once the object is large enough for a linear search per key to
        // matter (a hash seen before is then checked by a search).
        let mut hashes: Option<(RandomState, HashSet<u64>)> = None;
        if self.empty_until(b'}') {
            return Ok(Kind::Object(fields));
        }
        loop {
            self.skip_ws();
            match self.peek() {
                Some(b'"') => {}
                None => {
                    return Err(self.error("unexpected end of file inside an object (missing '}')"))
                }
                Some(_) => {
                    return Err(self.error(format!(
                        "expected a field name in double quotes, found {}",
                        self.describe_here()
                    )))
                }
            }
            let key = self.string()?;
            let duplicate = match &mut hashes {
                Some((state, set)) => {
                    !set.insert(state.hash_one(&key)) && fields.iter().any(|(k, _)| *k == key)
                }
                None => {
                    let duplicate = fields.iter().any(|(k, _)| *k == key);
                    if !duplicate && fields.len() >= 16 {
                        let state = RandomState::new();
                        let mut set: HashSet<u64> =
                            fields.iter().map(|(k, _)| state.hash_one(k)).collect();
                        set.insert(state.hash_one(&key));
                        hashes = Some((state, set));
                    }
                    duplicate
                }
            };
            // The key moves into the path while its value is read, and back out after.
            self.path.push(Step::Key(key));
            if duplicate {
                return Err(self.error("duplicate field"));
            }
            self.skip_ws();
            match self.peek() {
                Some(b':') => self.pos += 1,
                None => return Err(self.error("unexpected end of file (expected ':')")),
                Some(_) => {
                    return Err(self.error(format!(
                        "expected ':' after the field name, found {}",
                        self.describe_here()
                    )))
                }
            }
            let v = self.value(depth + 1)?;
            let Some(Step::Key(key)) = self.path.pop() else {
                unreachable!("the path ends with this field's key")
            };
            fields.push((key, v));
            if self.after_item(b'}', "an object")? {
                return Ok(Kind::Object(fields));
            }
        }
    }

    /// At the start of an array or an object: whether it ends at once (`close` consumed).
    fn empty_until(&mut self, close: u8) -> bool {
        self.skip_ws();
        let empty = self.peek() == Some(close);
        if empty {
            self.pos += 1;
        }
        empty
    }

    /// After an array's item or an object's field: `Ok(true)` at the container's end `close`,
    /// `Ok(false)` after a comma with more to come (both consumed).
    fn after_item(&mut self, close: u8, what: &str) -> Result<bool, SyntaxError> {
        let close_char = close as char;
        self.skip_ws();
        match self.peek() {
            Some(b',') => {
                self.pos += 1;
                self.skip_ws();
                if self.peek() == Some(close) {
                    return Err(self.error(format!("trailing comma before '{close_char}'")));
                }
                Ok(false)
            }
            Some(c) if c == close => {
                self.pos += 1;
                Ok(true)
            }
            None => Err(self.error(format!(
                "unexpected end of file inside {what} (missing '{close_char}')"
            ))),
            Some(_) => Err(self.error(format!(
                "expected ',' or '{close_char}' in {what}, found {}",
                self.describe_here()
            ))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn err(text: &str) -> SyntaxError {
        parse(text).expect_err(text)
    }

    #[test]
    fn parses_values_in_order() {
        let v = parse(r#"{"b": [1, -2.5e3, true, null], "a": "x\u00e9\n"}"#).unwrap();
        let Kind::Object(fields) = v.kind else {
            panic!()
        };
        assert_eq!(fields[0].0, "b");
        assert_eq!(fields[1].0, "a");
        assert_eq!(fields[1].1.kind, Kind::String("xé\n".into()));
        let Kind::Array(items) = &fields[0].1.kind else {
            panic!()
        };
        assert_eq!(
            items[1].kind,
            Kind::Number {
                value: -2500.0,
                raw: "-2.5e3".into()
            }
        );
    }

    #[test]
    fn overflowing_number_is_kept_raw() {
        let v = parse("[1e999]").unwrap();
        let Kind::Array(items) = v.kind else { panic!() };
        assert!(
            matches!(&items[0].kind, Kind::Number { value, raw } if value.is_infinite() && raw == "1e999")
        );
    }

    #[test]
    fn syntax_errors_have_paths_and_positions() {
        let e = err("{\"a\": {\"b\": [1, 2");
        assert_eq!(e.path, "a.b");
        assert!(e.reason.contains("end of file"), "{e:?}");
        let e = err("{\"a\": [1, NaN]}");
        assert_eq!(e.path, "a[1]");
        assert!(e.reason.contains("NaN"));
        let e = err("{\"a\": 1, \"a\": 2}");
        assert_eq!(e.path, "a");
        assert!(e.reason.contains("duplicate"));
        let e = err("{\n  \"a\": 01\n}");
        assert_eq!((e.line, e.column), (2, 8));
        assert!(err("[1,]").reason.contains("trailing comma"));
        assert!(err("").reason.contains("empty"));
        assert!(err("{} x").reason.contains("after the end"));
        assert!(err("\"\\ud800\"").reason.contains("surrogate"));
        assert!(err("[-]").reason.contains("malformed number"));
    }

    #[test]
    fn columns_count_characters_along_a_long_line() {
        // Columns are counted on from the previous value; multi-byte characters count once.
        let v = parse("[\"é\", \"日本\", 1,\n  2]").unwrap();
        let Kind::Array(items) = v.kind else { panic!() };
        let at: Vec<(u32, u32)> = items.iter().map(|i| (i.line, i.column)).collect();
        assert_eq!(at, [(1, 2), (1, 7), (1, 13), (2, 3)]);
        let e = err("[\"é\", \"\\é\"]");
        assert_eq!((e.line, e.column), (1, 9), "{e:?}");
        let long = format!("[{}x]", "\"é\",".repeat(10_000));
        assert_eq!(err(&long).column, 40_002);
    }

    #[test]
    fn duplicate_keys_are_found_in_large_objects() {
        let fields: Vec<String> = (0..100).map(|i| format!("\"k{i}\": {i}")).collect();
        let text = format!("{{{}, \"k42\": 0}}", fields.join(", "));
        let e = err(&text);
        assert_eq!(
            (e.path.as_str(), e.reason.as_str()),
            ("k42", "duplicate field")
        );
        let text = format!("{{{}, \"k100\": 0}}", fields.join(", "));
        let Kind::Object(fields) = parse(&text).unwrap().kind else {
            panic!()
        };
        assert_eq!(fields.len(), 101);
        assert_eq!(fields[100].0, "k100");
    }

    #[test]
    fn deep_nesting_is_an_error_not_a_stack_overflow() {
        let text = "[".repeat(100_000);
        assert!(err(&text).reason.contains("nesting"));
    }

    #[test]
    fn odd_keys_are_quoted_in_paths() {
        let steps = [
            Step::Key("materials".into()),
            Step::Key("my mat".into()),
            Step::Key("kd".into()),
            Step::Index(0),
        ];
        assert_eq!(render_path(&steps), "materials[\"my mat\"].kd[0]");
        assert_eq!(render_path(&[]), "(root)");
    }
}

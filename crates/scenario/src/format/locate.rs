//! Finds where a field sits in RON text, so range errors can point at it.
//!
//! RON deserialisation keeps no spans for values, so after validation we scan the text
//! once: a light tokenizer that skips strings and comments, tracks which key opened
//! each bracket and counts list elements, and returns the position of `key:` whose
//! path from the root matches.

/// 1-based (line, column) of the field at `path` (segments as in
/// [`super::validate::Violation::path`]), or `None` if it is not written out (a default).
pub(crate) fn field_position(text: &str, path: &[String]) -> Option<(usize, usize)> {
    let mut found = None;
    walk(text, |event| match event {
        Event::Key { path: p, line, col } | Event::Element { path: p, line, col } if p == path => {
            found = Some((line, col));
            false
        }
        _ => true,
    });
    found
}

/// A number written in RON text: where it is, which field it belongs to and its text.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Scalar {
    /// Path segments of the field it is the value of (list elements `[i]`; an element
    /// of a tuple belongs to the tuple's field).
    pub path: Vec<String>,
    /// 1-based line.
    pub line: usize,
    /// 1-based column.
    pub col: usize,
    /// Byte range in the text.
    pub span: std::ops::Range<usize>,
    /// The literal as written, e.g. `-1.5e3`, `NaN`, `inf`.
    pub text: String,
}

impl Scalar {
    /// The value, if the literal is a number (RON's `NaN` and `inf` included).
    pub fn value(&self) -> Option<f64> {
        let t = self.text.replace('_', "");
        match t.trim_start_matches(['+', '-']) {
            "NaN" => Some(f64::NAN),
            "inf" => Some(if t.starts_with('-') { f64::NEG_INFINITY } else { f64::INFINITY }),
            _ => t.parse::<f64>().ok().or_else(|| {
                // Hexadecimal, octal and binary integers.
                let (neg, u) = match t.strip_prefix('-') {
                    Some(u) => (true, u),
                    None => (false, t.trim_start_matches('+')),
                };
                let v = [("0x", 16), ("0o", 8), ("0b", 2)]
                    .iter()
                    .find_map(|(p, radix)| u.strip_prefix(p).and_then(|d| u128::from_str_radix(d, *radix).ok()))?
                    as f64;
                Some(if neg { -v } else { v })
            }),
        }
    }
}

/// Every number written in `text` (outside strings and comments), in order.
pub fn scalars(text: &str) -> Vec<Scalar> {
    let mut out = Vec::new();
    walk(text, |event| {
        if let Event::Scalar(s) = event {
            out.push(s);
        }
        true
    });
    out
}

enum Event {
    /// `key:` at `path` (the key included).
    Key {
        path: Vec<String>,
        line: usize,
        col: usize,
    },
    /// A list element that is a scalar, at `path` (its index included).
    Element {
        path: Vec<String>,
        line: usize,
        col: usize,
    },
    Scalar(Scalar),
}

/// Scans RON text once: a light tokenizer that skips strings and comments, tracks which
/// key opened each bracket and counts list elements. `on` returns false to stop.
fn walk(text: &str, mut on: impl FnMut(Event) -> bool) {
    struct Frame {
        key: Option<String>,
        list_index: Option<usize>,
    }
    let chars: Vec<(usize, char)> = text.char_indices().collect();
    let ch = |i: usize| chars.get(i).map(|c| c.1);
    let byte = |i: usize| chars.get(i).map_or(text.len(), |c| c.0);
    let mut frames: Vec<Frame> = Vec::new();
    let mut pending_key: Option<String> = None;
    let (mut line, mut col) = (1usize, 1usize);
    let mut i = 0;
    let advance = |i: &mut usize, line: &mut usize, col: &mut usize, n: usize| {
        for _ in 0..n {
            if let Some(&(_, c)) = chars.get(*i) {
                if c == '\n' {
                    *line += 1;
                    *col = 1;
                } else {
                    *col += 1;
                }
                *i += 1;
            }
        }
    };
    let current_path = |frames: &[Frame]| -> Vec<String> { frames.iter().filter_map(|f| f.key.clone()).collect() };
    while let Some(c) = ch(i) {
        let next = ch(i + 1);
        if c == '/' && next == Some('/') {
            while ch(i).is_some_and(|c| c != '\n') {
                advance(&mut i, &mut line, &mut col, 1);
            }
        } else if c == '/' && next == Some('*') {
            advance(&mut i, &mut line, &mut col, 2);
            while ch(i).is_some() && !(ch(i) == Some('*') && ch(i + 1) == Some('/')) {
                advance(&mut i, &mut line, &mut col, 1);
            }
            advance(&mut i, &mut line, &mut col, 2);
        } else if c == '"' {
            advance(&mut i, &mut line, &mut col, 1);
            while ch(i).is_some_and(|c| c != '"') {
                let n = if ch(i) == Some('\\') { 2 } else { 1 };
                advance(&mut i, &mut line, &mut col, n);
            }
            advance(&mut i, &mut line, &mut col, 1);
        } else if is_number_start(c, next, ch(i + 2)) {
            let (start_line, start_col, start) = (line, col, i);
            advance(&mut i, &mut line, &mut col, 1);
            while let Some(d) = ch(i) {
                let exponent_sign = matches!(d, '+' | '-') && matches!(ch(i - 1), Some('e' | 'E'));
                if !(d.is_ascii_alphanumeric() || d == '_' || d == '.' || exponent_sign) {
                    break;
                }
                advance(&mut i, &mut line, &mut col, 1);
            }
            let mut path = current_path(&frames);
            if let Some(k) = &pending_key {
                path.push(k.clone());
            } else if let Some(Frame { list_index: Some(n), .. }) = frames.last() {
                path.push(format!("[{n}]"));
            }
            let (a, b) = (byte(start), byte(i));
            let scalar = Scalar { path, line: start_line, col: start_col, span: a..b, text: text[a..b].to_string() };
            if !on(Event::Scalar(scalar)) {
                return;
            }
        } else if c.is_alphabetic() || c == '_' {
            let (start_line, start_col) = (line, col);
            let mut ident = String::new();
            while let Some(d) = ch(i).filter(|d| d.is_alphanumeric() || *d == '_') {
                ident.push(d);
                advance(&mut i, &mut line, &mut col, 1);
            }
            let mut j = i;
            while ch(j).is_some_and(char::is_whitespace) {
                j += 1;
            }
            if ch(j) == Some(':') && ch(j + 1) != Some(':') {
                let mut p = current_path(&frames);
                p.push(ident.clone());
                if !on(Event::Key { path: p, line: start_line, col: start_col }) {
                    return;
                }
                pending_key = Some(ident);
            } else if ident == "NaN" || ident == "inf" {
                // RON's non-finite float literals, in a value's place.
                let mut path = current_path(&frames);
                if let Some(k) = &pending_key {
                    path.push(k.clone());
                } else if let Some(Frame { list_index: Some(n), .. }) = frames.last() {
                    path.push(format!("[{n}]"));
                }
                let (a, b) = (byte(i) - ident.len(), byte(i));
                let scalar = Scalar { path, line: start_line, col: start_col, span: a..b, text: ident };
                if !on(Event::Scalar(scalar)) {
                    return;
                }
            }
        } else if matches!(c, '(' | '[' | '{') {
            // A bracket directly inside a list is an element: key it by its index.
            let key = match frames.last_mut() {
                Some(Frame { list_index: Some(n), .. }) if pending_key.is_none() => {
                    // The element itself is a field too (`job.goals[1]`): place it here.
                    let element = format!("[{n}]");
                    let mut p = current_path(&frames);
                    p.push(element.clone());
                    if !on(Event::Element { path: p, line, col }) {
                        return;
                    }
                    Some(element)
                }
                _ => pending_key.take(),
            };
            frames.push(Frame { key, list_index: (c == '[').then_some(0) });
            if c == '[' {
                // A scalar element of a list at index 0 has no bracket of its own.
                let mut p = current_path(&frames);
                p.push("[0]".into());
                if let Some((l, cc)) = scalar_after(&chars, i + 1, line, col + 1)
                    && !on(Event::Element { path: p, line: l, col: cc })
                {
                    return;
                }
            }
            advance(&mut i, &mut line, &mut col, 1);
        } else if matches!(c, ')' | ']' | '}') {
            frames.pop();
            pending_key = None;
            advance(&mut i, &mut line, &mut col, 1);
        } else if c == ',' {
            pending_key = None;
            if let Some(Frame { list_index: Some(n), .. }) = frames.last_mut() {
                *n += 1;
                let n = *n;
                let mut p = current_path(&frames);
                p.push(format!("[{n}]"));
                if let Some((l, cc)) = scalar_after(&chars, i + 1, line, col + 1)
                    && !on(Event::Element { path: p, line: l, col: cc })
                {
                    return;
                }
            }
            advance(&mut i, &mut line, &mut col, 1);
        } else {
            advance(&mut i, &mut line, &mut col, 1);
        }
    }
}

/// Whether a number starts at `c` (followed by `next`, `after`): a digit, a sign or a
/// point before a digit, or RON's `NaN`/`inf` with or without a sign.
fn is_number_start(c: char, next: Option<char>, after: Option<char>) -> bool {
    let digit = |x: Option<char>| x.is_some_and(|x| x.is_ascii_digit());
    c.is_ascii_digit()
        || (matches!(c, '-' | '+') && (digit(next) || (next == Some('.') && digit(after))))
        || (c == '.' && digit(next))
        || (matches!(c, '-' | '+') && matches!(next, Some('i' | 'N')))
}

/// The position of a scalar list element starting at or after `i` (after whitespace).
fn scalar_after(chars: &[(usize, char)], i: usize, line: usize, col: usize) -> Option<(usize, usize)> {
    let (mut l, mut c) = (line, col);
    let mut i = i;
    while let Some(&(_, x)) = chars.get(i).filter(|x| x.1.is_whitespace()) {
        if x == '\n' {
            l += 1;
            c = 1;
        } else {
            c += 1;
        }
        i += 1;
    }
    chars.get(i).is_some_and(|x| x.1.is_ascii_digit() || matches!(x.1, '-' | '+' | '.')).then_some((l, c))
}

#[cfg(test)]
mod tests {
    use super::field_position;

    fn at(text: &str, path: &[&str]) -> Option<(usize, usize)> {
        field_position(text, &path.iter().map(|s| s.to_string()).collect::<Vec<_>>())
    }

    #[test]
    fn finds_nested_fields_and_list_elements() {
        let text = "Scenario(\n  version: 1, // a: 2\n  job: SunTable(\n    site: (lat_deg: 95, lon_east_deg: 0),\n    note: \"x: y\",\n    horizon_deg: [1, 2,\n      300],\n    goals: [(x: 1), (x: 2)],\n  ),\n)";
        assert_eq!(at(text, &["version"]), Some((2, 3)));
        assert_eq!(at(text, &["job", "site", "lat_deg"]), Some((4, 12)));
        assert_eq!(at(text, &["job", "site", "lon_east_deg"]), Some((4, 25)));
        assert_eq!(at(text, &["job", "horizon_deg", "[0]"]), Some((6, 19)));
        assert_eq!(at(text, &["job", "horizon_deg", "[2]"]), Some((7, 7)));
        assert_eq!(at(text, &["job", "goals", "[1]", "x"]), Some((8, 22)));
        assert_eq!(at(text, &["job", "goals", "[1]"]), Some((8, 21)), "a bracketed element is placed at its bracket");
        assert_eq!(at(text, &["a"]), None, "comments are skipped");
        assert_eq!(at(text, &["job", "y"]), None, "strings are skipped");
        assert_eq!(at(text, &["job", "tau"]), None);
    }

    #[test]
    fn every_number_is_found_with_its_field() {
        let text = "S(\n  a: 1, // b: 2\n  c: [1.5, -2e-3,\n    NaN], d: (e: -inf, f: \"g: 3\"),\n  h: (0.3, 0x1F), i: Some(4_000),\n)";
        let found: Vec<(String, usize, usize, String)> =
            super::scalars(text).into_iter().map(|s| (s.path.join("."), s.line, s.col, s.text)).collect();
        let want = [
            ("a", 2, 6, "1"),
            ("c.[0]", 3, 7, "1.5"),
            ("c.[1]", 3, 12, "-2e-3"),
            ("c.[2]", 4, 5, "NaN"),
            ("d.e", 4, 18, "-inf"),
            ("h", 5, 7, "0.3"),
            ("h", 5, 12, "0x1F"),
            ("i", 5, 27, "4_000"),
        ];
        let want: Vec<(String, usize, usize, String)> =
            want.iter().map(|(p, l, c, t)| (p.to_string(), *l, *c, t.to_string())).collect();
        assert_eq!(found, want);
        let values: Vec<f64> = super::scalars(text).iter().map(|s| s.value().unwrap()).collect();
        assert_eq!(values[0], 1.0);
        assert!(values[3].is_nan() && values[4] == f64::NEG_INFINITY);
        assert_eq!((values[6], values[7]), (31.0, 4000.0));
        for s in super::scalars(text) {
            assert_eq!(&text[s.span.clone()], s.text);
        }
    }
}

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
    let mut s = Scanner::new(text);
    while let Some(c) = s.ch(s.i) {
        let next = s.ch(s.i + 1);
        let go_on = if c == '/' && next == Some('/') {
            s.line_comment();
            true
        } else if c == '/' && next == Some('*') {
            s.block_comment();
            true
        } else if c == '"' {
            s.string();
            true
        } else if is_number_start(c, next, s.ch(s.i + 2)) {
            on(Event::Scalar(s.number()))
        } else if c.is_alphabetic() || c == '_' {
            s.ident().is_none_or(&mut on)
        } else if matches!(c, '(' | '[' | '{') {
            s.open(c, &mut on)
        } else if matches!(c, ')' | ']' | '}') {
            s.frames.pop();
            s.pending_key = None;
            s.advance(1);
            true
        } else if c == ',' {
            s.comma(&mut on)
        } else {
            s.advance(1);
            true
        };
        if !go_on {
            return;
        }
    }
}

/// A bracket the scanner is inside: the key that opened it (or the list index it is
/// an element of), and for a list the index of its current element.
struct Frame {
    key: Option<String>,
    list_index: Option<usize>,
}

/// The scanner's position in the text (char index, 1-based line and column) and the
/// brackets it is inside.
struct Scanner<'t> {
    text: &'t str,
    chars: Vec<(usize, char)>,
    i: usize,
    line: usize,
    col: usize,
    frames: Vec<Frame>,
    pending_key: Option<String>,
}

impl<'t> Scanner<'t> {
    fn new(text: &'t str) -> Scanner<'t> {
        let chars = text.char_indices().collect();
        Scanner { text, chars, i: 0, line: 1, col: 1, frames: Vec::new(), pending_key: None }
    }

    fn ch(&self, i: usize) -> Option<char> {
        self.chars.get(i).map(|c| c.1)
    }

    fn byte(&self, i: usize) -> usize {
        self.chars.get(i).map_or(self.text.len(), |c| c.0)
    }

    fn advance(&mut self, n: usize) {
        for _ in 0..n {
            if let Some(&(_, c)) = self.chars.get(self.i) {
                if c == '\n' {
                    self.line += 1;
                    self.col = 1;
                } else {
                    self.col += 1;
                }
                self.i += 1;
            }
        }
    }

    fn current_path(&self) -> Vec<String> {
        self.frames.iter().filter_map(|f| f.key.clone()).collect()
    }

    /// The path of a value here: under the pending key, or the list element's index.
    fn value_path(&self) -> Vec<String> {
        let mut path = self.current_path();
        if let Some(k) = &self.pending_key {
            path.push(k.clone());
        } else if let Some(Frame { list_index: Some(n), .. }) = self.frames.last() {
            path.push(format!("[{n}]"));
        }
        path
    }

    fn line_comment(&mut self) {
        while self.ch(self.i).is_some_and(|c| c != '\n') {
            self.advance(1);
        }
    }

    fn block_comment(&mut self) {
        self.advance(2);
        while self.ch(self.i).is_some() && !(self.ch(self.i) == Some('*') && self.ch(self.i + 1) == Some('/')) {
            self.advance(1);
        }
        self.advance(2);
    }

    fn string(&mut self) {
        self.advance(1);
        while self.ch(self.i).is_some_and(|c| c != '"') {
            let n = if self.ch(self.i) == Some('\\') { 2 } else { 1 };
            self.advance(n);
        }
        self.advance(1);
    }

    fn number(&mut self) -> Scalar {
        let (start_line, start_col, start) = (self.line, self.col, self.i);
        self.advance(1);
        while let Some(d) = self.ch(self.i) {
            let exponent_sign = matches!(d, '+' | '-') && matches!(self.ch(self.i - 1), Some('e' | 'E'));
            if !(d.is_ascii_alphanumeric() || d == '_' || d == '.' || exponent_sign) {
                break;
            }
            self.advance(1);
        }
        let (a, b) = (self.byte(start), self.byte(self.i));
        Scalar {
            path: self.value_path(),
            line: start_line,
            col: start_col,
            span: a..b,
            text: self.text[a..b].to_string(),
        }
    }

    /// An identifier: a key (`name:`), RON's `NaN`/`inf` in a value's place, or
    /// anything else (a variant or struct name), which gives no event.
    fn ident(&mut self) -> Option<Event> {
        let (start_line, start_col) = (self.line, self.col);
        let mut ident = String::new();
        while let Some(d) = self.ch(self.i).filter(|d| d.is_alphanumeric() || *d == '_') {
            ident.push(d);
            self.advance(1);
        }
        let mut j = self.i;
        while self.ch(j).is_some_and(char::is_whitespace) {
            j += 1;
        }
        if self.ch(j) == Some(':') && self.ch(j + 1) != Some(':') {
            let mut path = self.current_path();
            path.push(ident.clone());
            self.pending_key = Some(ident);
            Some(Event::Key { path, line: start_line, col: start_col })
        } else if ident == "NaN" || ident == "inf" {
            let (a, b) = (self.byte(self.i) - ident.len(), self.byte(self.i));
            Some(Event::Scalar(Scalar {
                path: self.value_path(),
                line: start_line,
                col: start_col,
                span: a..b,
                text: ident,
            }))
        } else {
            None
        }
    }

    /// An opening bracket: a new frame, keyed by the pending key or, directly inside a
    /// list, by its index (the element itself is a field too: `job.goals[1]`).
    fn open(&mut self, c: char, on: &mut impl FnMut(Event) -> bool) -> bool {
        let key = match self.frames.last() {
            Some(Frame { list_index: Some(n), .. }) if self.pending_key.is_none() => {
                let element = format!("[{n}]");
                let mut path = self.current_path();
                path.push(element.clone());
                if !on(Event::Element { path, line: self.line, col: self.col }) {
                    return false;
                }
                Some(element)
            }
            _ => self.pending_key.take(),
        };
        self.frames.push(Frame { key, list_index: (c == '[').then_some(0) });
        // A scalar element of a list at index 0 has no bracket of its own.
        if c == '[' && !self.scalar_element(0, on) {
            return false;
        }
        self.advance(1);
        true
    }

    /// A comma: the pending key is done; in a list, the next element begins.
    fn comma(&mut self, on: &mut impl FnMut(Event) -> bool) -> bool {
        self.pending_key = None;
        if let Some(Frame { list_index: Some(n), .. }) = self.frames.last_mut() {
            *n += 1;
            let n = *n;
            if !self.scalar_element(n, on) {
                return false;
            }
        }
        self.advance(1);
        true
    }

    /// Element `n` of the list just opened or continued here, if it is a scalar.
    fn scalar_element(&self, n: usize, on: &mut impl FnMut(Event) -> bool) -> bool {
        let mut path = self.current_path();
        path.push(format!("[{n}]"));
        match scalar_after(&self.chars, self.i + 1, self.line, self.col + 1) {
            Some((line, col)) => on(Event::Element { path, line, col }),
            None => true,
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

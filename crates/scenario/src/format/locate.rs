//! Finds where a field sits in RON text, so range errors can point at it.
//!
//! RON deserialisation keeps no spans for values, so after validation we scan the text
//! once: a light tokenizer that skips strings and comments, tracks which key opened
//! each bracket and counts list elements, and returns the position of `key:` whose
//! path from the root matches.

/// 1-based (line, column) of the field at `path` (segments as in
/// [`super::validate::Violation::path`]), or `None` if it is not written out (a default).
pub(crate) fn field_position(text: &str, path: &[String]) -> Option<(usize, usize)> {
    struct Frame {
        key: Option<String>,
        list_index: Option<usize>,
    }
    let chars: Vec<char> = text.chars().collect();
    let mut frames: Vec<Frame> = Vec::new();
    let mut pending_key: Option<String> = None;
    let (mut line, mut col) = (1usize, 1usize);
    let mut i = 0;
    let advance = |i: &mut usize, line: &mut usize, col: &mut usize, n: usize, chars: &[char]| {
        for _ in 0..n {
            if *i < chars.len() {
                if chars[*i] == '\n' {
                    *line += 1;
                    *col = 1;
                } else {
                    *col += 1;
                }
                *i += 1;
            }
        }
    };
    let current_path = |frames: &[Frame]| -> Vec<String> {
        let mut p = Vec::new();
        for f in frames {
            if let Some(k) = &f.key {
                p.push(k.clone());
            }
        }
        p
    };
    while i < chars.len() {
        let c = chars[i];
        if c == '/' && chars.get(i + 1) == Some(&'/') {
            while i < chars.len() && chars[i] != '\n' {
                advance(&mut i, &mut line, &mut col, 1, &chars);
            }
        } else if c == '/' && chars.get(i + 1) == Some(&'*') {
            advance(&mut i, &mut line, &mut col, 2, &chars);
            while i < chars.len() && !(chars[i] == '*' && chars.get(i + 1) == Some(&'/')) {
                advance(&mut i, &mut line, &mut col, 1, &chars);
            }
            advance(&mut i, &mut line, &mut col, 2, &chars);
        } else if c == '"' {
            advance(&mut i, &mut line, &mut col, 1, &chars);
            while i < chars.len() && chars[i] != '"' {
                let n = if chars[i] == '\\' { 2 } else { 1 };
                advance(&mut i, &mut line, &mut col, n, &chars);
            }
            advance(&mut i, &mut line, &mut col, 1, &chars);
        } else if c.is_alphabetic() || c == '_' {
            let (start_line, start_col) = (line, col);
            let mut ident = String::new();
            while i < chars.len() && (chars[i].is_alphanumeric() || chars[i] == '_') {
                ident.push(chars[i]);
                advance(&mut i, &mut line, &mut col, 1, &chars);
            }
            let mut j = i;
            while j < chars.len() && chars[j].is_whitespace() {
                j += 1;
            }
            if chars.get(j) == Some(&':') && chars.get(j + 1) != Some(&':') {
                let mut p = current_path(&frames);
                p.push(ident.clone());
                if p == path {
                    return Some((start_line, start_col));
                }
                pending_key = Some(ident);
            }
        } else if matches!(c, '(' | '[' | '{') {
            // A bracket directly inside a list is an element: key it by its index.
            let key = match frames.last_mut() {
                Some(Frame { list_index: Some(n), .. }) if pending_key.is_none() => Some(format!("[{n}]")),
                _ => pending_key.take(),
            };
            frames.push(Frame { key, list_index: (c == '[').then_some(0) });
            if c == '[' {
                // A scalar element of a list at index 0 has no bracket of its own.
                let mut p = current_path(&frames);
                p.push("[0]".into());
                if p == path && next_is_scalar(&chars, i + 1) {
                    let mut l = line;
                    let mut cc = col + 1;
                    skip_ws_pos(&chars, i + 1, &mut l, &mut cc);
                    return Some((l, cc));
                }
            }
            advance(&mut i, &mut line, &mut col, 1, &chars);
        } else if matches!(c, ')' | ']' | '}') {
            frames.pop();
            pending_key = None;
            advance(&mut i, &mut line, &mut col, 1, &chars);
        } else if c == ',' {
            pending_key = None;
            if let Some(Frame { list_index: Some(n), .. }) = frames.last_mut() {
                *n += 1;
                let n = *n;
                let mut p = current_path(&frames);
                p.push(format!("[{n}]"));
                if p == path && next_is_scalar(&chars, i + 1) {
                    let (mut l, mut cc) = (line, col + 1);
                    skip_ws_pos(&chars, i + 1, &mut l, &mut cc);
                    return Some((l, cc));
                }
            }
            advance(&mut i, &mut line, &mut col, 1, &chars);
        } else {
            advance(&mut i, &mut line, &mut col, 1, &chars);
        }
    }
    None
}

fn next_is_scalar(chars: &[char], mut i: usize) -> bool {
    while i < chars.len() && chars[i].is_whitespace() {
        i += 1;
    }
    chars.get(i).is_some_and(|c| c.is_ascii_digit() || matches!(c, '-' | '+' | '.'))
}

fn skip_ws_pos(chars: &[char], mut i: usize, line: &mut usize, col: &mut usize) {
    while i < chars.len() && chars[i].is_whitespace() {
        if chars[i] == '\n' {
            *line += 1;
            *col = 1;
        } else {
            *col += 1;
        }
        i += 1;
    }
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
        assert_eq!(at(text, &["a"]), None, "comments are skipped");
        assert_eq!(at(text, &["job", "y"]), None, "strings are skipped");
        assert_eq!(at(text, &["job", "tau"]), None);
    }
}

//! Values set from outside a scenario file: `areo run --set PATH=VALUE` and a sweep's
//! axes. A value replaces the text of one field's value, so it must be one RON value
//! and nothing else — never text that closes the field and opens another, comments
//! out what follows it or switches the reader's extensions.

/// Whether `value` is exactly one RON value (a number, a string, a list, a tuple or
/// struct, an enum variant…) with no comment or attribute outside its strings: the
/// reason in words if not. Such a value, written in place of another value, changes
/// that value only.
pub(crate) fn one_value(value: &str) -> Result<(), String> {
    if value.trim().is_empty() {
        return Err("is empty: write one RON value (a number, a string in quotes, a list…)".into());
    }
    if let Some((_, col, what)) = areo_rover::refused_shape(value) {
        return Err(format!("has {what} (at column {col})"));
    }
    if let Some(what) = outside_strings(value) {
        return Err(format!("holds {what} outside a string: a setting is one RON value, nothing else"));
    }
    crate::format::ron_options().from_str::<ron::Value>(value).map(|_| ()).map_err(|e| match e.code {
        ron::Error::TrailingCharacters => format!(
            "is more than one RON value (text follows the value at column {}): a setting is one value of its field",
            e.span.start.col
        ),
        code => format!("is not a RON value: {code}"),
    })
}

/// The first comment (`//`, `/*`) or attribute (`#`) outside the value's string and
/// character literals.
fn outside_strings(value: &str) -> Option<&'static str> {
    let chars: Vec<char> = value.chars().collect();
    let mut i = 0;
    while i < chars.len() {
        match chars[i] {
            '"' => i = past_quoted(&chars, i + 1, '"'),
            '\'' => i = past_quoted(&chars, i + 1, '\''),
            // A raw string: r"…", r#"…"#, br#"…"# (the `#`s belong to it).
            'r' if !ident_before(&chars, i) && matches!(chars.get(i + 1), Some('#' | '"')) => {
                let hashes = chars[i + 1..].iter().take_while(|&&c| c == '#').count();
                if chars.get(i + 1 + hashes) != Some(&'"') {
                    return Some("an attribute (`#`)");
                }
                let close: Vec<char> = std::iter::once('"').chain(std::iter::repeat_n('#', hashes)).collect();
                let body = i + 2 + hashes;
                i = (body..chars.len())
                    .find(|&j| chars[j..].starts_with(&close))
                    .map_or(chars.len(), |j| j + close.len());
            }
            '/' if matches!(chars.get(i + 1), Some('/' | '*')) => return Some("a comment"),
            '#' => return Some("an attribute (`#`)"),
            _ => i += 1,
        }
    }
    None
}

/// Whether the character before `i` continues an identifier (so `r` is not a raw
/// string's prefix but part of a name such as `Ear`).
fn ident_before(chars: &[char], i: usize) -> bool {
    i > 0 && {
        let c = chars[i - 1];
        // `br"…"`: a byte string's `b` starts the literal.
        let byte_prefix = c == 'b' && !ident_before(chars, i - 1);
        (c.is_alphanumeric() || c == '_') && !byte_prefix
    }
}

/// The index past the literal whose body starts at `i` and ends at `quote` (escapes
/// skipped), or the end.
fn past_quoted(chars: &[char], mut i: usize, quote: char) -> usize {
    while i < chars.len() {
        match chars[i] {
            '\\' => i += 2,
            c if c == quote => return i + 1,
            _ => i += 1,
        }
    }
    chars.len()
}

#[cfg(test)]
mod tests {
    use super::one_value;

    #[test]
    fn one_value_of_any_shape_is_a_setting() {
        for v in [
            "0.5",
            "-3",
            "Mars",
            "Some(3)",
            "None",
            "Margin(max_duration_s: 3600)",
            "(x_m: 1, y_m: [1, 2])",
            "(1, 1)",
            "\"a // b /* c */ # d\"",
            "r#\"raw \" // text\"#",
            "'/'",
            "true",
            "[\"Earth\", \"r#\"]",
            "\"2012-08-06T22:15:00Z\"",
        ] {
            assert_eq!(one_value(v), Ok(()), "{v}");
        }
    }

    #[test]
    fn text_that_closes_the_field_or_hides_what_follows_is_refused() {
        for (v, says) in [
            ("0.5, regions: [(name: \"X\")]", "more than one RON value"),
            ("60), simulate: (steps: 3", "more than one RON value"),
            ("0.5 // the rest of the line", "a comment"),
            ("0.5 /* open", "a comment"),
            ("#![enable(implicit_some)] 3", "an attribute"),
            ("\"unclosed", "not a RON value"),
            ("", "is empty"),
            ("(a: 1", "not a RON value"),
            ("Some(3) )", "more than one RON value"),
        ] {
            let got = one_value(v).expect_err(v);
            assert!(got.contains(says), "{v}: {got}");
        }
    }
}

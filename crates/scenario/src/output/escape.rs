//! One escaping rule per output format, for the text a user writes that ends up in
//! areo's outputs — goal, region, rover and run names, descriptions, file names. Each
//! writer of a format passes its text through its rule here, so a name drawn from the
//! whole of Unicode leaves every output well-formed and inert:
//!
//! - [`script_json`]: JSON embedded in an HTML `<script>` element (the viewers' data
//!   block): `<`, `>`, `&`, U+2028 and U+2029 as `\u` escapes, so that no `</script`,
//!   `<!--` or `<script` can appear and the block stays one JavaScript string literal
//!   per string.
//! - [`xml`] and [`xml_chars`]: KML and SVG text. Characters XML 1.0 does not allow
//!   (C0 controls but tab, newline and return; U+FFFE, U+FFFF) become U+FFFD; `&`, `<`,
//!   `>`, `"` and `'` are escaped.
//! - [`csv_cell`]: a CSV cell that is text starting with `=`, `+`, `-`, `@`, a tab or a
//!   return gets a leading `'` (OWASP's advice against CSV injection: a spreadsheet
//!   would run it as a formula); numbers are left as they are.
//! - [`console`] and [`json_console`]: the terminal. Control characters (but newline
//!   and tab), the bidirectional and other invisible format characters (U+202E could
//!   make a name read backwards, "Trojan Source") and non-characters are shown as
//!   escapes: `\u{202e}` in text, `\u202e` in JSON (where it is the same string).

use std::borrow::Cow;

/// Whether `c` is a character the terminal must not receive raw: a control (other than
/// newline and tab), a bidirectional or invisible format character, a line or
/// paragraph separator, or a non-character.
fn unsafe_on_console(c: char) -> bool {
    (c.is_control() && c != '\n' && c != '\t')
        || matches!(
            c,
            '\u{061C}'
                | '\u{200B}'..='\u{200F}'
                | '\u{2028}'..='\u{202E}'
                | '\u{2060}'..='\u{2069}'
                | '\u{FEFF}'
                | '\u{FFF9}'..='\u{FFFB}'
        )
        || non_character(c)
}

/// Unicode's non-characters: U+FDD0..=U+FDEF and the last two code points of every
/// plane (U+FFFE, U+FFFF, U+1FFFE, …).
pub fn non_character(c: char) -> bool {
    matches!(c, '\u{FDD0}'..='\u{FDEF}') || (u32::from(c) & 0xFFFE) == 0xFFFE
}

/// Whether XML 1.0 allows `c` in a document.
fn xml_allows(c: char) -> bool {
    matches!(c, '\t' | '\n' | '\r' | '\u{20}'..='\u{D7FF}' | '\u{E000}'..='\u{FFFD}' | '\u{10000}'..)
}

/// JSON text made safe inside an HTML `<script>` element (see the module's notes).
/// The characters replaced occur in JSON only inside strings, where the `\u` escape
/// reads back as the same character.
pub fn script_json(json: &str) -> String {
    let mut out = String::with_capacity(json.len());
    for c in json.chars() {
        match c {
            '<' => out.push_str("\\u003c"),
            '>' => out.push_str("\\u003e"),
            '&' => out.push_str("\\u0026"),
            '\u{2028}' => out.push_str("\\u2028"),
            '\u{2029}' => out.push_str("\\u2029"),
            c => out.push(c),
        }
    }
    out
}

/// Text for an XML element or attribute: forbidden characters as U+FFFD, the five
/// specials escaped.
pub fn xml(text: &str) -> String {
    let mut out = String::with_capacity(text.len());
    for c in text.chars() {
        match c {
            '&' => out.push_str("&amp;"),
            '<' => out.push_str("&lt;"),
            '>' => out.push_str("&gt;"),
            '"' => out.push_str("&quot;"),
            '\'' => out.push_str("&apos;"),
            c if !xml_allows(c) => out.push('\u{FFFD}'),
            c => out.push(c),
        }
    }
    out
}

/// An XML document whose specials are already escaped (plotters' SVG) with the
/// characters XML forbids as U+FFFD.
pub fn xml_chars(document: String) -> String {
    if document.chars().all(xml_allows) {
        return document;
    }
    document.chars().map(|c| if xml_allows(c) { c } else { '\u{FFFD}' }).collect()
}

/// A CSV cell as written: text that a spreadsheet would take for a formula gets a
/// leading `'`; a number (`-0.5`, `+3`, `-inf`) is left as it is.
pub fn csv_cell(cell: &str) -> Cow<'_, str> {
    let formula = cell.starts_with(['=', '+', '-', '@', '\t', '\r']);
    if formula && cell.trim().parse::<f64>().is_err() { Cow::Owned(format!("'{cell}")) } else { Cow::Borrowed(cell) }
}

/// Text for the terminal: what must not reach it raw shown as `\u{…}`.
pub fn console(text: &str) -> Cow<'_, str> {
    if !text.chars().any(unsafe_on_console) {
        return Cow::Borrowed(text);
    }
    let mut out = String::with_capacity(text.len() + 16);
    for c in text.chars() {
        if unsafe_on_console(c) {
            out.extend(c.escape_unicode());
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

/// JSON for the terminal: what must not reach it raw as JSON `\u` escapes (UTF-16, as
/// JSON spells characters beyond U+FFFF), which read back as the same strings.
pub fn json_console(json: &str) -> Cow<'_, str> {
    if !json.chars().any(unsafe_on_console) {
        return Cow::Borrowed(json);
    }
    let mut out = String::with_capacity(json.len() + 16);
    for c in json.chars() {
        if unsafe_on_console(c) {
            let mut units = [0u16; 2];
            for u in c.encode_utf16(&mut units) {
                out.push_str(&format!("\\u{u:04x}"));
            }
        } else {
            out.push(c);
        }
    }
    Cow::Owned(out)
}

#[cfg(test)]
mod tests {
    use super::*;

    const NASTY: &str =
        "a</script><!--<script>&\u{2028}\u{2029}\u{202E}\u{2066}\u{FFFE}\u{FFFF}\u{1FFFF}\u{1B}[2J\u{9B}\u{7F}'\"=";

    #[test]
    fn a_script_block_can_hold_no_markup_and_reads_back_the_same_string() {
        let json = serde_json::to_string(&serde_json::json!({ "name": NASTY })).unwrap();
        let safe = script_json(&json);
        for bad in ["</", "<!--", "<script", "<", ">", "&", "\u{2028}", "\u{2029}"] {
            assert!(!safe.contains(bad), "{bad:?} in {safe}");
        }
        let back: serde_json::Value = serde_json::from_str(&safe).unwrap();
        assert_eq!(back["name"], NASTY);
    }

    #[test]
    fn xml_text_parses_strictly_and_keeps_every_allowed_character() {
        let doc = format!("<a t=\"{}\">{}</a>", xml(NASTY), xml(NASTY));
        let parsed = roxmltree::Document::parse(&doc).unwrap();
        let text = parsed.root_element().text().unwrap();
        let expected: String = NASTY.chars().map(|c| if xml_allows(c) { c } else { '\u{FFFD}' }).collect();
        assert_eq!(text, expected);
        assert_eq!(parsed.root_element().attribute("t"), Some(expected.as_str()));
        assert_eq!(text.matches('\u{FFFD}').count(), 3, "U+FFFE, U+FFFF and ESC");
        assert!(roxmltree::Document::parse(&xml_chars(format!("<a>{}</a>", "x\u{FFFF}\u{1}"))).is_ok());
    }

    #[test]
    fn formula_starts_are_defused_and_numbers_kept() {
        for (cell, out) in [
            ("=1+2", "'=1+2"),
            ("+cmd|' /C calc'!A0", "'+cmd|' /C calc'!A0"),
            ("-east", "'-east"),
            ("@SUM(A1)", "'@SUM(A1)"),
            ("\tx", "'\tx"),
            ("\rx", "'\rx"),
            ("-0.5", "-0.5"),
            ("+3", "+3"),
            ("-1e-9", "-1e-9"),
            ("east", "east"),
            ("", ""),
        ] {
            assert_eq!(csv_cell(cell), out, "{cell:?}");
        }
    }

    #[test]
    fn the_terminal_gets_no_control_bidi_or_non_character_raw() {
        let shown = console(NASTY);
        assert!(shown.chars().all(|c| !unsafe_on_console(c)), "{shown}");
        assert!(shown.contains("\\u{202e}") && shown.contains("\\u{1b}") && shown.contains("\\u{9b}"), "{shown}");
        assert_eq!(console("plain\nlines\tand tabs"), "plain\nlines\tand tabs");
        let json = serde_json::to_string(&serde_json::json!({ "name": NASTY })).unwrap();
        let safe = json_console(&json);
        assert!(safe.chars().all(|c| !unsafe_on_console(c)), "{safe}");
        let back: serde_json::Value = serde_json::from_str(&safe).unwrap();
        assert_eq!(back["name"], NASTY, "the same string");
    }
}

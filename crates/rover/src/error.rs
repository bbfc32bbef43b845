use std::path::PathBuf;

/// Everything that can go wrong in areo-rover.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A parameter file could not be read.
    #[error("{path}: {source}")]
    Io {
        /// The file.
        path: PathBuf,
        /// The OS error.
        source: std::io::Error,
    },
    /// A parameter file is not valid RON for the parameter format.
    #[error("{path}:{line}:{col}: {message}")]
    Syntax {
        /// The file.
        path: PathBuf,
        /// 1-based line.
        line: usize,
        /// 1-based column.
        col: usize,
        /// What the parser expected.
        message: String,
    },
    /// A parameter out of its range, or geometry that cannot be built.
    #[error("{origin}: `{field}` = {value}: {why}")]
    Invalid {
        /// Where the parameters came from (a file, or "parameters").
        origin: String,
        /// The field, e.g. `drive.gear_efficiency`.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What is allowed, or which constraint fails.
        why: String,
    },
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

/// Reads a parameter file's text, naming the file on failure.
pub(crate) fn read_text(path: &std::path::Path) -> Result<String> {
    areo_terrain::input::read_text(path, areo_terrain::input::TEXT_LIMIT)
        .map_err(|source| Error::Io { path: path.to_path_buf(), source })
}

/// The RON dialect every areo file is read with — parameter files here, scenarios and
/// expected outcomes in areo-scenario: optional fields may omit `Some(…)`, and a
/// variant wrapping a struct may be written with the struct's fields directly.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(
        ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES | ron::extensions::Extensions::IMPLICIT_SOME,
    )
}

/// The deepest bracket nesting areo reads in a RON file: far beyond any real file (the
/// shipped ones nest under 10) and low enough that neither the parser nor the error
/// locator works hard on a hostile one.
pub const MAX_NESTING: usize = 64;

/// The most items areo reads in one RON list: far beyond any real list (a horizon of
/// 3600 sectors, a polygon's vertices) and low enough that parsing a hostile one stays
/// small (a million items took 0.35 GB to parse and refuse).
pub const MAX_LIST_ITEMS: usize = 100_000;

/// Where `text` has a shape areo refuses before parsing, and what: the line and column
/// (1-based) of the first bracket nested deeper than [`MAX_NESTING`], or of the opening
/// of the first list with more than [`MAX_LIST_ITEMS`] items, outside strings and
/// comments; one pass over the text.
pub fn refused_shape(text: &str) -> Option<(usize, usize, String)> {
    let (mut depth, mut line, mut col) = (0usize, 1usize, 0usize);
    // Each open bracket: whether it is a list, where it opened, and its separators so far.
    let mut open: Vec<(bool, usize, usize, usize)> = Vec::new();
    let mut chars = text.chars().peekable();
    let (mut string, mut escaped, mut line_comment, mut block_comment) = (false, false, false, 0usize);
    while let Some(c) = chars.next() {
        col += 1;
        if c == '\n' {
            (line, col, line_comment) = (line + 1, 0, false);
            continue;
        }
        if line_comment {
            continue;
        }
        if string {
            match (escaped, c) {
                (true, _) => escaped = false,
                (false, '\\') => escaped = true,
                (false, '"') => string = false,
                _ => {}
            }
            continue;
        }
        let next = chars.peek().copied();
        match (c, next) {
            ('*', Some('/')) if block_comment > 0 => {
                block_comment -= 1;
                chars.next();
                col += 1;
            }
            ('/', Some('*')) => {
                block_comment += 1;
                chars.next();
                col += 1;
            }
            _ if block_comment > 0 => {}
            ('/', Some('/')) => line_comment = true,
            ('"', _) => string = true,
            ('(' | '[' | '{', _) => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Some((line, col, format!("brackets nested deeper than {MAX_NESTING}")));
                }
                open.push((c == '[', line, col, 0));
            }
            (')' | ']' | '}', _) => {
                depth = depth.saturating_sub(1);
                open.pop();
            }
            (',', _) => {
                if let Some((true, at_line, at_col, items)) = open.last_mut() {
                    *items += 1;
                    if *items >= MAX_LIST_ITEMS {
                        return Some((*at_line, *at_col, format!("a list of more than {MAX_LIST_ITEMS} items")));
                    }
                }
            }
            _ => {}
        }
    }
    None
}

/// Parses RON in areo's dialect ([`ron_options`]), turning errors into
/// [`Error::Syntax`] with `origin` and the position; a shape [`refused_shape`] names is
/// refused before parsing.
pub(crate) fn parse_ron<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T> {
    if let Some((line, col, message)) = refused_shape(text) {
        return Err(Error::Syntax { path: origin.into(), line, col, message });
    }
    ron_options().from_str(text).map_err(|e| Error::Syntax {
        path: origin.into(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })
}

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

/// The line and column (1-based) of the first bracket in `text` nested deeper than
/// [`MAX_NESTING`], outside strings and comments; one pass over the text.
pub fn too_deep(text: &str) -> Option<(usize, usize)> {
    let (mut depth, mut line, mut col) = (0usize, 1usize, 0usize);
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
                    return Some((line, col));
                }
            }
            (')' | ']' | '}', _) => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    None
}

/// Parses RON in areo's dialect ([`ron_options`]), turning errors into
/// [`Error::Syntax`] with `origin` and the position; nesting past [`MAX_NESTING`] is
/// refused before parsing.
pub(crate) fn parse_ron<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T> {
    if let Some((line, col)) = too_deep(text) {
        return Err(Error::Syntax {
            path: origin.into(),
            line,
            col,
            message: format!("brackets nested deeper than {MAX_NESTING}"),
        });
    }
    ron_options().from_str(text).map_err(|e| Error::Syntax {
        path: origin.into(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })
}

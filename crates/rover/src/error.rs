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
    std::fs::read_to_string(path).map_err(|source| Error::Io { path: path.to_path_buf(), source })
}

/// The RON dialect every areo file is read with — parameter files here, scenarios and
/// expected outcomes in areo-scenario: optional fields may omit `Some(…)`, and a
/// variant wrapping a struct may be written with the struct's fields directly.
pub fn ron_options() -> ron::Options {
    ron::Options::default().with_default_extension(
        ron::extensions::Extensions::UNWRAP_VARIANT_NEWTYPES | ron::extensions::Extensions::IMPLICIT_SOME,
    )
}

/// Parses RON in areo's dialect ([`ron_options`]), turning errors into
/// [`Error::Syntax`] with `origin` and the position.
pub(crate) fn parse_ron<T: serde::de::DeserializeOwned>(text: &str, origin: &str) -> Result<T> {
    ron_options().from_str(text).map_err(|e| Error::Syntax {
        path: origin.into(),
        line: e.span.start.line,
        col: e.span.start.col,
        message: e.code.to_string(),
    })
}

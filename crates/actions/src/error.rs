/// Everything that can go wrong in areo-actions.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// A setting is out of range.
    #[error("`{field}`: {message}")]
    Config {
        /// The field.
        field: String,
        /// What is wrong and what is allowed.
        message: String,
    },
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

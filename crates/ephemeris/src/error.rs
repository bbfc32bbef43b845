use thiserror::Error;

/// Everything that can go wrong in areo-ephemeris.
#[derive(Debug, Error)]
#[non_exhaustive]
pub enum Error {
    /// A time string that is not an ISO 8601 UTC instant.
    #[error("invalid UTC time {text:?}: {reason} (expected ISO 8601, e.g. 2012-08-06T05:17:57Z)")]
    BadTime {
        /// The text as given.
        text: String,
        /// What the parser said.
        reason: String,
    },
    /// A numeric argument outside its allowed range.
    #[error("{field} = {value} is out of range: allowed {allowed}")]
    OutOfRange {
        /// The argument's name, with its unit.
        field: &'static str,
        /// The value given.
        value: f64,
        /// The allowed range, in words.
        allowed: &'static str,
    },
    /// An empty or malformed horizon mask.
    #[error("horizon mask: {0}")]
    BadHorizonMask(&'static str),
}

/// `Result` with this crate's [`enum@Error`].
pub type Result<T, E = Error> = std::result::Result<T, E>;

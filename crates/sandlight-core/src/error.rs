//! The one error type of the core. The library never panics on user input: invalid input
//! becomes a `SandlightError` that names the parameter, the value and what is allowed.

use thiserror::Error;

#[derive(Debug, Error, Clone, PartialEq)]
pub enum SandlightError {
    /// A parameter outside its domain.
    #[error("{name} = {value} is out of range: {allowed}")]
    Parameter { name: String, value: String, allowed: String },
    /// The run was cancelled (Ctrl-C) before it finished.
    #[error("cancelled")]
    Cancelled,
}

impl SandlightError {
    pub fn parameter(name: &str, value: impl std::fmt::Display, allowed: &str) -> Self {
        SandlightError::Parameter { name: name.to_string(), value: value.to_string(), allowed: allowed.to_string() }
    }
}

/// Returns an error unless `lo <= value <= hi` (and value is finite).
pub fn check_range(name: &str, value: f64, lo: f64, hi: f64) -> Result<(), SandlightError> {
    if value.is_finite() && value >= lo && value <= hi {
        Ok(())
    } else {
        Err(SandlightError::parameter(name, value, &format!("must be a finite number in [{lo}, {hi}]")))
    }
}

//! The one error type of the crate: every bad input names the parameter, its value and what is
//! allowed; numerical failures name what failed.

/// Errors returned by the analytic solutions. None of the functions panic on bad input.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum AnalyticError {
    /// A parameter is outside its physical range.
    #[error("parameter `{name}` = {value} is not allowed: must be {allowed}")]
    OutOfRange { name: &'static str, value: f64, allowed: &'static str },
    /// A bracketed root search was given an interval without a sign change.
    #[error("no root of {what} in [{lower}, {upper}]: the function has the same sign at both ends")]
    NoBracket { what: &'static str, lower: f64, upper: f64 },
    /// An iteration did not converge.
    #[error("{what} did not converge after {iterations} iterations (last residual {residual:e})")]
    NoConvergence { what: &'static str, iterations: usize, residual: f64 },
    /// An input is structurally invalid (e.g. an unsorted profile table).
    #[error("invalid {what}: {reason}")]
    Invalid { what: &'static str, reason: String },
}

/// Result alias of the crate.
pub type Result<T> = std::result::Result<T, AnalyticError>;

/// `value` must be finite and > 0.
pub(crate) fn positive(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value > 0.0 {
        Ok(value)
    } else {
        Err(AnalyticError::OutOfRange { name, value, allowed: "finite and > 0" })
    }
}

/// `value` must be finite and ≥ 0.
pub(crate) fn non_negative(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() && value >= 0.0 {
        Ok(value)
    } else {
        Err(AnalyticError::OutOfRange { name, value, allowed: "finite and >= 0" })
    }
}

/// `value` must be finite.
pub(crate) fn finite(name: &'static str, value: f64) -> Result<f64> {
    if value.is_finite() {
        Ok(value)
    } else {
        Err(AnalyticError::OutOfRange { name, value, allowed: "a finite number" })
    }
}

/// `value` must lie in the closed interval [lower, upper].
pub(crate) fn in_closed(name: &'static str, value: f64, lower: f64, upper: f64, allowed: &'static str) -> Result<f64> {
    if value.is_finite() && value >= lower && value <= upper {
        Ok(value)
    } else {
        Err(AnalyticError::OutOfRange { name, value, allowed })
    }
}

/// `value` must lie in the open interval (lower, upper).
pub(crate) fn in_open(name: &'static str, value: f64, lower: f64, upper: f64, allowed: &'static str) -> Result<f64> {
    if value.is_finite() && value > lower && value < upper {
        Ok(value)
    } else {
        Err(AnalyticError::OutOfRange { name, value, allowed })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn messages_name_parameter_value_and_range() {
        let err = in_open("alpha", 1.5, 0.0, 1.0, "in (0, 1)").unwrap_err();
        let text = err.to_string();
        assert!(text.contains("alpha") && text.contains("1.5") && text.contains("(0, 1)"), "{text}");
        assert!(positive("d", f64::NAN).is_err());
        assert!(non_negative("q", -1e-30).is_err());
        assert_eq!(non_negative("q", 0.0), Ok(0.0));
    }
}

//! Closed-form answers.

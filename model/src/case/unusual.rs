//! Values a case may hold but rarely means: `spillage check` warns about them.

use super::Case;

/// Warnings about allowed but unusual values, each naming the key, the value and why.
pub fn warnings(_case: &Case) -> Vec<String> {
    Vec::new()
}

//! Differences between two states, field by field, for the solver-equivalence tests.
//!
//! The walk goes through the serialised form of [`State`], so every field any model adds is
//! compared without this file knowing about it. Array indices are folded into the field name
//! (`fluid.velocity[]`), so each row is the worst entry of one field; the index of that worst
//! entry is kept so a failing test can say which cell or particle diverged.

use std::collections::BTreeMap;

use serde_json::Value;

use crate::state::State;

/// Largest difference found in one field.
#[derive(Clone, Debug, PartialEq)]
pub struct FieldDiff {
    /// Largest |a − b|.
    pub max_abs: f64,
    /// Largest |a − b| / max(|a|, |b|, floor) where `floor` is 1e-300 (pure relative).
    pub max_rel: f64,
    /// Largest |a − b| / max|a| over the field: the difference relative to the field's scale,
    /// which is what "agree to 1e-8" means for fields that pass through zero.
    pub max_rel_to_scale: f64,
    /// Flattened index (position among the numbers of this field) of the largest |a − b|.
    pub worst_index: usize,
    /// Numbers compared.
    pub count: usize,
}

/// Per-field differences, keyed by the folded path.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct StateDiff {
    pub fields: BTreeMap<String, FieldDiff>,
    /// Paths whose structure differs (array lengths, missing fields): never "close".
    pub mismatches: Vec<String>,
}

impl StateDiff {
    /// Largest scale-relative difference over all fields (∞ when the structures differ).
    pub fn worst_relative(&self) -> f64 {
        if !self.mismatches.is_empty() {
            return f64::INFINITY;
        }
        self.fields.values().map(|f| f.max_rel_to_scale).fold(0.0, f64::max)
    }

    /// True when every field agrees to `tolerance` relative to its scale.
    pub fn within(&self, tolerance: f64) -> bool {
        self.worst_relative() <= tolerance
    }

    /// One line per field, worst first: for messages of failing tests.
    pub fn report(&self) -> String {
        let mut rows: Vec<_> = self.fields.iter().collect();
        rows.sort_by(|a, b| b.1.max_rel_to_scale.total_cmp(&a.1.max_rel_to_scale));
        let mut out = String::new();
        for m in &self.mismatches {
            out.push_str(&format!("structure differs: {m}\n"));
        }
        for (name, d) in rows {
            out.push_str(&format!(
                "{name}: max abs {:.3e}, max rel to scale {:.3e} (worst at #{} of {})\n",
                d.max_abs, d.max_rel_to_scale, d.worst_index, d.count
            ));
        }
        out
    }
}

/// Compares two states field by field.
pub fn diff(a: &State, b: &State) -> StateDiff {
    let va = serde_json::to_value(a).expect("a State always serialises");
    let vb = serde_json::to_value(b).expect("a State always serialises");
    let mut acc: BTreeMap<String, (Vec<f64>, Vec<f64>)> = BTreeMap::new();
    let mut out = StateDiff::default();
    collect(&va, &vb, String::new(), &mut acc, &mut out.mismatches);
    for (name, (xs, ys)) in acc {
        let scale = xs.iter().fold(0.0_f64, |m, x| m.max(x.abs()));
        let mut d = FieldDiff { max_abs: 0.0, max_rel: 0.0, max_rel_to_scale: 0.0, worst_index: 0, count: xs.len() };
        for (i, (x, y)) in xs.iter().zip(&ys).enumerate() {
            let abs = if x == y { 0.0 } else { (x - y).abs() };
            let abs = if abs.is_nan() { f64::INFINITY } else { abs };
            if abs > d.max_abs {
                d.max_abs = abs;
                d.worst_index = i;
            }
            d.max_rel = d.max_rel.max(abs / x.abs().max(y.abs()).max(1e-300));
        }
        d.max_rel_to_scale = if d.max_abs == 0.0 { 0.0 } else { d.max_abs / scale.max(1e-300) };
        out.fields.insert(name, d);
    }
    out
}

fn collect(a: &Value, b: &Value, path: String, acc: &mut BTreeMap<String, (Vec<f64>, Vec<f64>)>, mismatches: &mut Vec<String>) {
    match (a, b) {
        (Value::Number(x), Value::Number(y)) => {
            let entry = acc.entry(path).or_default();
            entry.0.push(x.as_f64().unwrap_or(f64::NAN));
            entry.1.push(y.as_f64().unwrap_or(f64::NAN));
        }
        (Value::Array(xs), Value::Array(ys)) => {
            if xs.len() != ys.len() {
                mismatches.push(format!("{path}: {} vs {} entries", xs.len(), ys.len()));
                return;
            }
            for (x, y) in xs.iter().zip(ys) {
                collect(x, y, format!("{path}[]"), acc, mismatches);
            }
        }
        (Value::Object(xs), Value::Object(ys)) => {
            for (k, x) in xs {
                let sub = if path.is_empty() { k.clone() } else { format!("{path}.{k}") };
                match ys.get(k) {
                    Some(y) => collect(x, y, sub, acc, mismatches),
                    None => mismatches.push(format!("{sub}: missing in the second state")),
                }
            }
            for k in ys.keys().filter(|k| !xs.contains_key(*k)) {
                mismatches.push(format!("{path}.{k}: missing in the first state"));
            }
        }
        (x, y) if x == y => {}
        (x, y) => mismatches.push(format!("{path}: {x} vs {y}")),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn identical_states_have_zero_difference() {
        let s = State { time: 1.5, step: 3, dt: 0.5, ..State::default() };
        let d = diff(&s, &s.clone());
        assert_eq!(d.worst_relative(), 0.0);
        assert!(d.within(0.0));
    }

    #[test]
    fn reports_the_field_and_size_of_a_difference() {
        let a = State { time: 2.0, dt: 0.5, ..State::default() };
        let b = State { time: 2.0 + 2e-6, dt: 0.5, ..State::default() };
        let d = diff(&a, &b);
        let t = &d.fields["time"];
        assert!((t.max_abs - 2e-6).abs() < 1e-15);
        assert!((t.max_rel_to_scale - 1e-6).abs() < 1e-12);
        assert!(!d.within(1e-7) && d.within(1e-5));
        assert!(d.report().starts_with("time:"), "{}", d.report());
    }

    #[test]
    fn structural_differences_are_never_close() {
        let a = State { fluid: Some(Default::default()), ..State::default() };
        let b = State::default();
        let d = diff(&a, &b);
        assert!(!d.mismatches.is_empty());
        assert!(!d.within(f64::MAX));
    }
}

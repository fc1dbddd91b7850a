//! Conservative area-weighted mapping across a non-conformal interface whose faces overlap in
//! one coordinate (the θ direction of a cylindrical sliding interface).
//!
//! spillage-and-flow-verification.md §3.6 (thesis Eqs. 3.33–3.36) and fluid-dem-model.md §4.2,
//! U-17, U-18: q_t^j = Σ_i (A_s^i ∩ A_t^j)/A_t^j q_s^i.
//! Erratum [E]: the thesis prints q_t = [3, 5, 8, 9] for its example; its own weights give
//! [3, 5, 7, 9] (§9 item 17), which is the oracle here.

use crate::error::{AnalyticError, Result};

fn check_edges(name: &'static str, edges: &[f64]) -> Result<()> {
    if edges.len() < 2 {
        return Err(AnalyticError::Invalid { what: name, reason: format!("needs at least 2 edges, got {}", edges.len()) });
    }
    for pair in edges.windows(2) {
        if !(pair[1] > pair[0]) || !pair[1].is_finite() || !pair[0].is_finite() {
            return Err(AnalyticError::Invalid { what: name, reason: format!("edges must increase strictly; {} follows {}", pair[1], pair[0]) });
        }
    }
    Ok(())
}

/// Weight matrix m[j][i] = |I_s^i ∩ I_t^j| / |I_t^j| (Eq. 3.36) for source faces between
/// consecutive `source_edges` and target faces between consecutive `target_edges` (unit depth).
pub fn overlap_weights(source_edges: &[f64], target_edges: &[f64]) -> Result<Vec<Vec<f64>>> {
    check_edges("source edges", source_edges)?;
    check_edges("target edges", target_edges)?;
    let mut weights = Vec::with_capacity(target_edges.len() - 1);
    for target in target_edges.windows(2) {
        let width = target[1] - target[0];
        let row = source_edges.windows(2).map(|source| (target[1].min(source[1]) - target[0].max(source[0])).max(0.0) / width).collect();
        weights.push(row);
    }
    Ok(weights)
}

/// Overlap weights of a periodic interface of period `period`: `source_count` equal source faces
/// rotated by `shift` against `target_count` equal target faces starting at 0 (a rotor/stator
/// interface whose rotor has turned by `shift`, U-18).
pub fn periodic_overlap_weights(source_count: usize, target_count: usize, period: f64, shift: f64) -> Result<Vec<Vec<f64>>> {
    if source_count == 0 || target_count == 0 {
        return Err(AnalyticError::Invalid { what: "periodic interface", reason: "face counts must be > 0".into() });
    }
    crate::error::positive("period", period)?;
    crate::error::finite("shift", shift)?;
    let (ps, pt) = (period / source_count as f64, period / target_count as f64);
    let shift = shift.rem_euclid(period);
    let mut weights = vec![vec![0.0; source_count]; target_count];
    for (j, row) in weights.iter_mut().enumerate() {
        let (t0, t1) = (j as f64 * pt, (j + 1) as f64 * pt);
        for (i, w) in row.iter_mut().enumerate() {
            let s0 = i as f64 * ps + shift;
            // The shifted source face may wrap; test it and its images one period away.
            let mut overlap = 0.0;
            for image in [-period, 0.0, period] {
                overlap += (t1.min(s0 + ps + image) - t0.max(s0 + image)).max(0.0);
            }
            *w = overlap / pt;
        }
    }
    Ok(weights)
}

/// Applies the map q_t = M q_s (Eq. 3.34).
pub fn map_values(weights: &[Vec<f64>], source_values: &[f64]) -> Result<Vec<f64>> {
    weights
        .iter()
        .map(|row| {
            if row.len() != source_values.len() {
                return Err(AnalyticError::Invalid {
                    what: "mapping",
                    reason: format!("weight row has {} entries but there are {} source values", row.len(), source_values.len()),
                });
            }
            Ok(row.iter().zip(source_values).map(|(w, q)| w * q).sum())
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn thesis_example_with_erratum() {
        // §3.6: 3 faces of 2/3 → 4 faces of 1/2; q_s = [3, 6, 9] → [3, 5, 7, 9] (not 8).
        let source = [0.0, 2.0 / 3.0, 4.0 / 3.0, 2.0];
        let target = [0.0, 0.5, 1.0, 1.5, 2.0];
        let m = overlap_weights(&source, &target).unwrap();
        let expected = [[1.0, 0.0, 0.0], [1.0 / 3.0, 2.0 / 3.0, 0.0], [0.0, 2.0 / 3.0, 1.0 / 3.0], [0.0, 0.0, 1.0]];
        for (row, exp) in m.iter().zip(expected) {
            for (w, e) in row.iter().zip(exp) {
                assert!((w - e).abs() < 1e-15);
            }
            assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-15, "row sums are 1");
        }
        let q_t = map_values(&m, &[3.0, 6.0, 9.0]).unwrap();
        for (got, want) in q_t.iter().zip([3.0, 5.0, 7.0, 9.0]) {
            assert!((got - want).abs() < 1e-14, "{q_t:?}");
        }
        // U-17: Σ A q = 12 on both sides.
        let total_t: f64 = q_t.iter().map(|q| 0.5 * q).sum();
        assert!((total_t - 12.0).abs() < 1e-14);
    }

    #[test]
    fn periodic_interface_properties() {
        // U-18: uniform fields map exactly, the integral is conserved for any rotor angle, and a
        // rotation by one source pitch turns the map into a permutation.
        let period = 2.0 * std::f64::consts::PI;
        for shift in [0.0, 0.1234, 1.0, -2.5, 7.0] {
            let m = periodic_overlap_weights(12, 8, period, shift).unwrap();
            for row in &m {
                assert!((row.iter().sum::<f64>() - 1.0).abs() < 1e-13, "shift {shift}");
            }
            let q_s: Vec<f64> = (0..12).map(|i| (i as f64).sin() + 2.0).collect();
            let q_t = map_values(&m, &q_s).unwrap();
            let (a_s, a_t) = (period / 12.0, period / 8.0);
            let source_integral: f64 = q_s.iter().map(|q| q * a_s).sum();
            let target_integral: f64 = q_t.iter().map(|q| q * a_t).sum();
            assert!((source_integral - target_integral).abs() < 1e-12);
        }
        let pitch = period / 8.0;
        let m = periodic_overlap_weights(8, 8, period, pitch).unwrap();
        for (j, row) in m.iter().enumerate() {
            for (i, w) in row.iter().enumerate() {
                let expected = if i == (j + 7) % 8 { 1.0 } else { 0.0 };
                assert!((w - expected).abs() < 1e-12, "({j},{i}) = {w}");
            }
        }
    }

    #[test]
    fn bad_inputs_are_rejected() {
        assert!(overlap_weights(&[0.0, 1.0, 1.0], &[0.0, 1.0]).is_err());
        assert!(overlap_weights(&[0.0], &[0.0, 1.0]).is_err());
        assert!(map_values(&[vec![1.0, 0.0]], &[1.0]).is_err());
        assert!(periodic_overlap_weights(0, 4, 1.0, 0.0).is_err());
    }
}

//! Drag coefficient of a single sphere, C_d(Re).
//!
//! fluid-dem-model.md §5.2 (thesis Eqs. 3.39–3.41) and wear-model.md §3 (Eq. 2.17, §4.5.1).

use serde::{Deserialize, Serialize};

use crate::error::{AnalyticError, Result};

/// Brown–Lawler upper validity limit Re_s ≤ 2·10⁵ (Eq. 3.41).
pub const BROWN_LAWLER_MAX_REYNOLDS: f64 = 2.0e5;

/// A single-sphere drag law.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize, Deserialize)]
pub enum DragLaw {
    /// C_d = 24/Re (wear-model.md §12.2, Eq. 4.23: F = 6πμRv).
    Stokes,
    /// C_d = 24/Re (1 + 0.150 Re^0.687) for Re ≤ 1000, 0.44 above
    /// (fluid-dem-model.md Eq. 3.40; wear-model.md Eq. 2.17).
    SchillerNaumann,
    /// C_d = 24/Re (1 + 0.150 Re^0.681) + 0.407/(1 + 8710/Re), Re ≤ 2·10⁵
    /// (fluid-dem-model.md Eq. 3.41; the law the thesis uses everywhere).
    BrownLawler,
    /// C_d = (0.63 + 4.8/√Re)² (fluid-dem-model.md Eq. 3.39; used by Di Felice 1994).
    Dallavalle,
}

impl DragLaw {
    /// All laws, in a fixed order.
    pub const ALL: [DragLaw; 4] = [DragLaw::Stokes, DragLaw::SchillerNaumann, DragLaw::BrownLawler, DragLaw::Dallavalle];

    /// Short name used on the command line.
    pub fn name(self) -> &'static str {
        match self {
            DragLaw::Stokes => "stokes",
            DragLaw::SchillerNaumann => "schiller-naumann",
            DragLaw::BrownLawler => "brown-lawler",
            DragLaw::Dallavalle => "dallavalle",
        }
    }

    /// Parses a command-line name (see [`DragLaw::name`]).
    pub fn from_name(name: &str) -> Option<DragLaw> {
        DragLaw::ALL.into_iter().find(|law| law.name() == name)
    }

    /// Drag coefficient at Reynolds number `re` (> 0; ≤ 2·10⁵ for Brown–Lawler).
    pub fn drag_coefficient(self, re: f64) -> Result<f64> {
        if !(re.is_finite() && re > 0.0) {
            return Err(AnalyticError::OutOfRange { name: "reynolds", value: re, allowed: "finite and > 0" });
        }
        Ok(match self {
            DragLaw::Stokes => 24.0 / re,
            DragLaw::SchillerNaumann => {
                if re <= 1000.0 {
                    24.0 / re * (1.0 + 0.150 * re.powf(0.687))
                } else {
                    0.44
                }
            }
            DragLaw::BrownLawler => {
                if re > BROWN_LAWLER_MAX_REYNOLDS {
                    return Err(AnalyticError::OutOfRange { name: "reynolds", value: re, allowed: "<= 2e5 for the Brown–Lawler law (Eq. 3.41)" });
                }
                24.0 / re * (1.0 + 0.150 * re.powf(0.681)) + 0.407 / (1.0 + 8710.0 / re)
            }
            DragLaw::Dallavalle => (0.63 + 4.8 / re.sqrt()).powi(2),
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn rel(a: f64, b: f64) -> f64 {
        ((a - b) / b).abs()
    }

    /// particle-verification.md §8 check 1 and fluid-dem-model.md U-01 (printed to 6–7 digits).
    #[test]
    fn brown_lawler_matches_spec_values() {
        let cases = [
            (1.0, 27.600047),
            (10.0, 4.127507),
            (100.0, 1.073139),
            (1000.0, 0.463384),
            (7332.78, 0.399818),
            (7000.0, 0.398435),
            (1.0e4, 0.41061),
            (1.0e5, 0.466106),
        ];
        for (re, cd) in cases {
            let got = DragLaw::BrownLawler.drag_coefficient(re).unwrap();
            // Printed values carry 6–7 significant digits: 2e-6 relative covers rounding.
            assert!(rel(got, cd) < 2e-6, "Re={re}: {got} vs {cd}");
        }
        assert!(DragLaw::BrownLawler.drag_coefficient(2.1e5).is_err());
    }

    /// particle-verification.md §8 check 2, fluid-dem-model.md U-02/U-03.
    #[test]
    fn alternative_laws_and_ratios_match_spec() {
        let dv = DragLaw::Dallavalle.drag_coefficient(7000.0).unwrap();
        let sn = DragLaw::SchillerNaumann.drag_coefficient(7000.0).unwrap();
        let bl = DragLaw::BrownLawler.drag_coefficient(7000.0).unwrap();
        assert!(rel(dv, 0.472479) < 2e-6);
        assert_eq!(sn, 0.44);
        assert!((dv / bl - 1.1858).abs() < 1e-4, "thesis: 18 % larger");
        assert!((dv / sn - 1.0738).abs() < 1e-4, "thesis: 7 % larger");
        assert!(rel(DragLaw::Dallavalle.drag_coefficient(1.0).unwrap(), 29.48490) < 1e-6);
        assert!(rel(DragLaw::Dallavalle.drag_coefficient(100.0).unwrap(), 1.23210) < 1e-6);
        // Branch switch (U-02 and wear-model.md §3.2, A29): 0.438288 just below 1000.
        let below = DragLaw::SchillerNaumann.drag_coefficient(1000.0).unwrap();
        assert!((below - 0.438288).abs() < 1e-6);
        assert_eq!(DragLaw::SchillerNaumann.drag_coefficient(1000.0001).unwrap(), 0.44);
    }

    #[test]
    fn stokes_limit_is_shared_at_low_reynolds() {
        assert_eq!(DragLaw::Stokes.drag_coefficient(0.5).unwrap(), 48.0);
        for law in [DragLaw::SchillerNaumann, DragLaw::BrownLawler] {
            let ratio = law.drag_coefficient(1e-6).unwrap() / DragLaw::Stokes.drag_coefficient(1e-6).unwrap();
            assert!((ratio - 1.0).abs() < 1e-4, "{law:?}");
        }
        assert!(DragLaw::Stokes.drag_coefficient(0.0).is_err());
        assert_eq!(DragLaw::from_name("brown-lawler"), Some(DragLaw::BrownLawler));
    }
}

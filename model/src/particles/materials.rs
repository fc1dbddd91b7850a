//! Contact constants of every material pair, resolved once from `[[particles.materials]]`.

use super::settings::MaterialSection;
use crate::closure::contact::{effective_shear_modulus, effective_youngs_modulus, harmonic, normal_stiffness, tangential_stiffness, PairConstants, SlipTest};
use crate::closure::restitution::{stokes_number, wet_restitution};

/// What the contact law needs of one pair of materials.
#[derive(Clone, Copy, Debug)]
pub struct MaterialPair {
    pub effective_youngs: f64,
    pub effective_shear: f64,
    /// ε_dry of the pair: the mean of the two materials' values [R: the spec gives one value
    /// per material and tests identical materials only].
    pub dry_restitution: f64,
    /// μ_f of the pair: the mean of the two (spec §7.5 treats μ_f as a pair input) [R].
    pub friction: f64,
}

/// Pair table indexed `[i][j]`.
#[derive(Clone, Debug)]
pub struct MaterialTable {
    pub pairs: Vec<Vec<MaterialPair>>,
    pub slip_test: SlipTest,
}

impl MaterialTable {
    pub fn new(materials: &[MaterialSection], slip_test: SlipTest) -> Self {
        let pairs = materials
            .iter()
            .map(|a| {
                materials
                    .iter()
                    .map(|b| {
                        let (ea, eb) = (a.contact_youngs_modulus(), b.contact_youngs_modulus());
                        MaterialPair {
                            effective_youngs: effective_youngs_modulus(ea, a.poisson_ratio, eb, b.poisson_ratio),
                            effective_shear: effective_shear_modulus(ea, a.poisson_ratio, eb, b.poisson_ratio),
                            dry_restitution: 0.5 * (a.restitution + b.restitution),
                            friction: 0.5 * (a.friction + b.friction),
                        }
                    })
                    .collect()
            })
            .collect();
        Self { pairs, slip_test }
    }

    /// Contact constants for radii/masses of the two sides (infinite for a wall, §7.4).
    pub fn constants(&self, material_i: usize, material_j: usize, radius_i: f64, radius_j: f64, mass_i: f64, mass_j: f64) -> PairConstants {
        let pair = &self.pairs[material_i][material_j];
        let r_eff = harmonic(radius_i, radius_j);
        let (k_n, m_eff) = (normal_stiffness(r_eff, pair.effective_youngs), harmonic(mass_i, mass_j));
        PairConstants {
            normal_stiffness: k_n,
            tangential_stiffness: tangential_stiffness(r_eff, pair.effective_shear),
            effective_mass: m_eff,
            damping_scale: (m_eff * k_n).sqrt(),
            friction: pair.friction,
            slip_test: self.slip_test,
        }
    }

    /// The restitution of a new contact (§7.8 step 3): ε_wet from St_AM at first touch when
    /// `wet_fluid` (ρ_f, ν) is given (T3.103–104), else ε_dry. Its damping ratio α_η is
    /// [`crate::closure::contact::damping_ratio`] of it (T3.101).
    pub fn first_touch_restitution(
        &self,
        material_i: usize,
        material_j: usize,
        wet_fluid: Option<(f64, f64)>,
        approach_speed: f64,
        density: f64,
        diameter: f64,
    ) -> f64 {
        let dry = self.pairs[material_i][material_j].dry_restitution;
        match wet_fluid {
            Some((rho_f, nu)) => wet_restitution(dry, stokes_number(density, rho_f, approach_speed.max(0.0), diameter, nu)),
            None => dry,
        }
    }

    /// The largest E* of any pair (for the worst-case collision time, §7.6).
    pub fn stiffest(&self) -> f64 {
        self.pairs.iter().flatten().map(|p| p.effective_youngs).fold(0.0, f64::max)
    }
}

//! Walton (1993) / Foerster et al. (1994) hard-sphere oblique impact on a wall.
//!
//! particle-verification.md §1.6 and §8 checks 24–25; spillage-and-flow-verification.md §8
//! (thesis Eqs. 2.13–2.15); fluid-dem-model.md §7.7 and U-29/U-30.
//! Ψ values are tangential contact-point speeds normalised by the incoming normal speed:
//! Ψ_in = u_t,in/u_n,in, Ψ_out = u_t,out/u_n,in.

use serde::Serialize;

use crate::error::{in_closed, non_negative, positive, AnalyticError, Result};

/// Moment-of-inertia factor of a solid sphere, K₀ = 2/5 (I₀ = K₀ m r², Eq. 2.14).
pub const SOLID_SPHERE_INERTIA_FACTOR: f64 = 0.4;

/// Parameters of Walton's two-regime model.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaltonModel {
    /// Coulomb friction coefficient μ_f.
    pub friction: f64,
    /// Normal restitution ε_n.
    pub normal_restitution: f64,
    /// Tangential restitution ε_t of the stick regime (−1 … 1).
    pub tangential_restitution: f64,
    /// K₀ (2/5 for a solid sphere).
    pub inertia_factor: f64,
}

/// Which branch of Eq. 2.13 applies.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub enum ImpactRegime {
    Stick,
    Slip,
}

/// Rebound of one impact.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct WaltonRebound {
    pub psi_out: f64,
    pub regime: ImpactRegime,
}

impl WaltonModel {
    /// Validates μ_f ≥ 0, ε_n in [0, 1], ε_t in [−1, 1], K₀ > 0.
    pub fn new(friction: f64, normal_restitution: f64, tangential_restitution: f64, inertia_factor: f64) -> Result<Self> {
        non_negative("friction", friction)?;
        in_closed("normal_restitution", normal_restitution, 0.0, 1.0, "in [0, 1]")?;
        in_closed("tangential_restitution", tangential_restitution, -1.0, 1.0, "in [-1, 1]")?;
        positive("inertia_factor", inertia_factor)?;
        Ok(Self { friction, normal_restitution, tangential_restitution, inertia_factor })
    }

    /// Slip-branch offset μ_f (1 + ε_n)(1 + 1/K₀) (Eq. 2.13; 3.5 μ_f (1 + ε_n) for a sphere).
    pub fn slip_offset(&self) -> f64 {
        self.friction * (1.0 + self.normal_restitution) * (1.0 + 1.0 / self.inertia_factor)
    }

    /// Critical Ψ* = μ_f (1 + ε_n)/(1 + ε_t) (1 + 1/K₀) (Eq. 2.14). Infinite if ε_t = −1.
    pub fn critical_psi(&self) -> f64 {
        self.slip_offset() / (1.0 + self.tangential_restitution)
    }

    /// Ψ_out for incoming Ψ_in ≥ 0 (Eq. 2.13): −ε_t Ψ_in if Ψ_in ≤ Ψ*, else Ψ_in − offset.
    pub fn rebound(&self, psi_in: f64) -> Result<WaltonRebound> {
        non_negative("psi_in", psi_in)?;
        Ok(if psi_in <= self.critical_psi() {
            WaltonRebound { psi_out: -self.tangential_restitution * psi_in, regime: ImpactRegime::Stick }
        } else {
            WaltonRebound { psi_out: psi_in - self.slip_offset(), regime: ImpactRegime::Slip }
        })
    }
}

/// Friction coefficient backed out of a slip-regime rebound, μ_f = (Ψ_in − Ψ_out)/((1 + ε_n)(1 + 1/K₀))
/// (Eq. 2.15: (2/7)(Ψ_in − Ψ_out)/(1 + ε_n) for a solid sphere).
pub fn friction_from_rebound(psi_in: f64, psi_out: f64, normal_restitution: f64, inertia_factor: f64) -> Result<f64> {
    in_closed("normal_restitution", normal_restitution, 0.0, 1.0, "in [0, 1]")?;
    positive("inertia_factor", inertia_factor)?;
    Ok((psi_in - psi_out) / ((1.0 + normal_restitution) * (1.0 + 1.0 / inertia_factor)))
}

/// Tangential restitution backed out of a stick-regime rebound, ε_t = −Ψ_out/Ψ_in (Eq. 2.15).
pub fn tangential_restitution_from_rebound(psi_in: f64, psi_out: f64) -> Result<f64> {
    if !(psi_in.is_finite() && psi_in != 0.0) {
        return Err(AnalyticError::OutOfRange { name: "psi_in", value: psi_in, allowed: "finite and non-zero" });
    }
    Ok(-psi_out / psi_in)
}

/// Velocities of a sphere after a wall impact, from impulses (independent of Eq. 2.13).
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct SphereRebound {
    /// Normal speed away from the wall.
    pub normal_speed: f64,
    /// Tangential centre-of-mass velocity.
    pub tangential_velocity: f64,
    /// Spin contribution to the contact-point velocity, ω r (same sign convention as u_t).
    pub contact_spin_velocity: f64,
}

impl SphereRebound {
    /// Contact-point tangential velocity u_t + ω r.
    pub fn contact_velocity(&self) -> f64 {
        self.tangential_velocity + self.contact_spin_velocity
    }
}

/// Impulse solution of a sphere (mass m, I = K₀ m r²) hitting a wall with normal speed u_n > 0,
/// tangential centre velocity u_t and contact-point spin velocity ω r. Normal impulse
/// J_n = m (1 + ε_n) u_n; the tangential impulse is the one that would bring the contact point to
/// −ε_t times its incoming velocity, capped by Coulomb μ_f J_n.
pub fn sphere_wall_rebound(model: &WaltonModel, normal_speed: f64, tangential_velocity: f64, contact_spin_velocity: f64) -> Result<SphereRebound> {
    positive("normal_speed", normal_speed)?;
    let mobility = 1.0 + 1.0 / model.inertia_factor; // contact-point Δv per unit J_t/m
    let contact_in = tangential_velocity + contact_spin_velocity;
    let stick_impulse = (1.0 + model.tangential_restitution) * contact_in / mobility; // J_t/m
    let coulomb = model.friction * (1.0 + model.normal_restitution) * normal_speed;
    let impulse = stick_impulse.clamp(-coulomb, coulomb);
    Ok(SphereRebound {
        normal_speed: model.normal_restitution * normal_speed,
        tangential_velocity: tangential_velocity - impulse,
        contact_spin_velocity: contact_spin_velocity - impulse / model.inertia_factor,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn slip_offsets_match_spec() {
        // particle-verification.md §8 check 24: glass μ = 0.15, ε_n = 0.88013 → 0.98707;
        // steel μ = 0.02, ε_n = 0.93861 → 0.13570. U-29: μ = 0.02, ε_n = 0.97 → 0.1379.
        let glass = WaltonModel::new(0.15, 0.88013, 0.3, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        let steel = WaltonModel::new(0.02, 0.93861, 0.3, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        assert!((glass.slip_offset() - 0.98707).abs() < 5e-6);
        assert!((steel.slip_offset() - 0.13570).abs() < 5e-6);
        let u29 = WaltonModel::new(0.02, 0.97, 0.0, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        assert!((u29.slip_offset() - 0.1379).abs() < 5e-5);
        let r = glass.rebound(2.0).unwrap();
        assert_eq!(r.regime, ImpactRegime::Slip);
        assert!((r.psi_out - (2.0 - 0.98707)).abs() < 5e-6);
    }

    #[test]
    fn friction_back_out_matches_spec() {
        // Check 25: Ψ_in = 2, Ψ_out = 1.01293, ε_n = 0.88013 → μ_f = 0.15.
        let mu = friction_from_rebound(2.0, 1.01293, 0.88013, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        assert!((mu - 0.15).abs() < 1e-5);
        // U-30 round trip in both regimes.
        let model = WaltonModel::new(0.1, 0.8, 0.4, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        let slip = model.rebound(3.0).unwrap();
        assert!((friction_from_rebound(3.0, slip.psi_out, 0.8, 0.4).unwrap() - 0.1).abs() < 1e-14);
        let stick = model.rebound(0.2).unwrap();
        assert_eq!(stick.regime, ImpactRegime::Stick);
        assert!((tangential_restitution_from_rebound(0.2, stick.psi_out).unwrap() - 0.4).abs() < 1e-14);
    }

    #[test]
    fn branches_meet_at_critical_angle_and_impulses_agree() {
        let model = WaltonModel::new(0.15, 0.88, 0.35, SOLID_SPHERE_INERTIA_FACTOR).unwrap();
        let critical = model.critical_psi();
        let below = model.rebound(critical).unwrap().psi_out;
        let above = model.rebound(critical * (1.0 + 1e-12)).unwrap().psi_out;
        assert!((below - above).abs() < 1e-10, "Eq. 2.13 is continuous at Ψ*");
        // Independent impulse derivation for a non-spinning sphere: Ψ_out = contact velocity out / u_n.
        for psi_in in [0.05, 0.3, critical, 1.0, 2.1445] {
            let rebound = sphere_wall_rebound(&model, 0.37, psi_in * 0.37, 0.0).unwrap();
            let psi_out = rebound.contact_velocity() / 0.37;
            assert!((psi_out - model.rebound(psi_in).unwrap().psi_out).abs() < 1e-12, "Ψ_in={psi_in}");
            assert!((rebound.normal_speed - 0.88 * 0.37).abs() < 1e-15);
        }
        // Backspin: in stick with ε_t > 0 the contact point reverses (Ψ_out < 0), as in Fig. 7.7.
        assert!(model.rebound(0.1).unwrap().psi_out < 0.0);
        assert!(WaltonModel::new(-0.1, 0.9, 0.0, 0.4).is_err());
    }
}

//! What each verification check checks and against which reference, for the report of
//! `spillage verify --report` (issue 20). Keyed by the `[verify] check` name; a check without an
//! entry here still appears in the report, with its case's `[case] description` only.

/// A check's description for a reader of the report.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct About {
    /// What the check measures.
    pub checks: &'static str,
    /// The exact solution, formula or published data it is compared with.
    pub reference: &'static str,
    /// Where the spec states it.
    pub spec: &'static str,
}

/// The description of `check`, if one is registered.
pub fn about(check: &str) -> Option<About> {
    ABOUT.iter().find(|(name, _)| *name == check).map(|(_, a)| *a)
}

const fn a(checks: &'static str, reference: &'static str, spec: &'static str) -> About {
    About { checks, reference, spec }
}

const ABOUT: &[(&str, About)] = &[
    (
        "fluid_couette",
        a(
            "steady circular Couette flow between a turning inner and a fixed outer cylinder, on a ladder of meshes: rms errors of u_θ and of dp/dr, their observed orders, the radial velocity where a sliding interface joins rotor and stator cells",
            "exact solution u_θ = A r + B/r, (1/ρ) dp/dr = u_θ²/r",
            "spillage-and-flow-verification.md §3.2 (U-32), §3.4",
        ),
    ),
    (
        "fluid_free_stream",
        a(
            "a uniform stream through a (turning) non-conformal sliding interface must stay uniform: velocity deviation, pressure spread, interface flux imbalance",
            "u = U exactly (free-stream preservation), to round-off",
            "fluid-dem-model.md §4.2 (T3.33–T3.36); spillage-and-flow-verification.md §3.6",
        ),
    ),
    (
        "fluid_poiseuille",
        a(
            "plane Poiseuille flow (periodic with a body force, or inlet/outlet): on uniform meshes the closed-form discrete solution to solver tolerance, on graded meshes the observed order",
            "u = g/(2ν) η(H − η) (or 6U η(H − η)/H²) and its exact discrete counterpart",
            "textbook channel flow; fluid-dem-model.md §8.2, §8.8",
        ),
    ),
    (
        "fluid_taylor_green",
        a(
            "decaying 2-D Taylor–Green vortex, space and time refined together: kinetic-energy decay and velocity errors, observed orders",
            "u = U sin(x/L) cos(y/L) e^(−2νt/L²), KE ∝ e^(−4νt/L²)",
            "textbook; fluid-dem-model.md §8.1–§8.5 (second-order schemes)",
        ),
    ),
    (
        "coupling_settling",
        a(
            "one 10 mm sphere settling in still water, two-way coupled, per mapping method (kernel, diffusion, centroid) and mesh: terminal velocity and the transient",
            "the particle equation of motion solved independently (analytic crate, Brown–Lawler drag, added mass 0.5); the centroid method's documented failure at d_p/Δx = 1.5",
            "particle-verification.md §2 (case P1, Tables 6.1–6.3); fluid-dem-model.md §6.1",
        ),
    ),
    (
        "coupling_stokes",
        a(
            "a 400 µm sphere settling under Stokes drag at several Δt: largest velocity error and its order in Δt",
            "exact Stokes transient u(t) = u_t (1 − e^(−t/τ)); the source's largest error 7.84e-3 m/s",
            "particle-verification.md §1.1, §8; fluid-dem-model.md §5.2, §5.9",
        ),
    ),
    (
        "coupling_hindered",
        a(
            "settling of a cloud of spheres at particle fraction α_p: median settling velocity over a time window",
            "thesis Table 6.3 (Di Felice closure), shown with Richardson–Zaki (Rowe exponent)",
            "particle-verification.md §4 (case P3); fluid-dem-model.md §5.6",
        ),
    ),
    (
        "coupling_hydrostatic",
        a(
            "a suspension settling in a closed box: the vertical pressure gradient in the cloud must carry the mixture weight; the literal T3.2 feedback must miss it",
            "ρ_m g = (α_p ρ_p + (1 − α_p) ρ_c) g",
            "fluid-dem-model.md §2.6, §12 (U-33); wear-model.md §12.2",
        ),
    ),
    (
        "coupling_held",
        a(
            "a uniform suspension held at its hindered terminal settling velocity in a closed column (one sphere per cell, [particles] motion = \"held\"): the pressure gradient, bottom to top and cell by cell, and the fluid speed, per mapping; the kernel mapping asserted non-uniform; the literal T3.2 feedback must give ρ_c g",
            "ρ_m g = (α_p ρ_p + (1 − α_p) ρ_c) g to solver tolerance, the water at rest",
            "fluid-dem-model.md §2.6, §12 (U-33)",
        ),
    ),
    (
        "coupling_budgets",
        a(
            "a settling suspension in a closed box, step by step: fluid + particle momentum against gravity, the walls' pressure and viscous force and the §8.4 split; Σ α_c V + Σ V_p against the box volume; particles in the box or logged; the literal T3.2 feedback must break the momentum budget",
            "momentum conservation of the discrete equations (exact up to the PIMPLE outer-loop convergence with the split counted); the box volume",
            "fluid-dem-model.md §2.1, §2.6, §8.4; issue 13 verification item 6",
        ),
    ),
    (
        "coupling_interface",
        a(
            "a sphere settling through a stationary sliding interface, with and without the interface mask: velocity disturbance and continuity errors",
            "the same run without an interface; thesis Table 6.4",
            "particle-verification.md §3 (case P2)",
        ),
    ),
    (
        "coupling_turning_cells",
        a(
            "a rock held at rest in still water inside a turning rotor zone: the water must stay at rest while the cells slide under the rock's footprint",
            "water at rest: the rock may see at most 1e-2 of the speed it would displace the water with sweeping against the cells (4.7e-2 without the mesh-flux share), on this mesh and one twice as fine",
            "fluid-dem-model.md §2.3 (T3.89) in the ALE form of §4.1",
        ),
    ),
    (
        "dem_hertz_elastic",
        a(
            "elastic normal impacts at several speeds: peak overlap, peak force, contact time, energy conservation",
            "Hertz contact theory (closed form)",
            "fluid-dem-model.md §7.1–§7.2; particle-verification.md §1.5",
        ),
    ),
    (
        "dem_dry_restitution",
        a(
            "damped normal impacts in vacuum: rebound/approach speed for several input restitutions and speeds",
            "the input restitution e (T3.101 is exact for Hertz damping)",
            "fluid-dem-model.md §7.3",
        ),
    ),
    (
        "dem_wet_restitution",
        a(
            "a sphere approaching a wall through still fluid (drag, added mass, buoyancy) over a range of Stokes numbers: effective restitution",
            "Legendre et al. wet-restitution law e_wet(St) = e_dry exp(−35/St)",
            "fluid-dem-model.md §7.5 (T3.103–T3.104); particle-verification.md §5.2 (case C2)",
        ),
    ),
    (
        "dem_oblique",
        a(
            "oblique impacts (sphere–wall or sphere–sphere) over impact angles: rebound tangential velocity, spin and rebound angle in the stick and gross-slip regimes",
            "Walton's hard-sphere model (Foerster et al. 1994)",
            "particle-verification.md §1.6, §5.3, §5.5; fluid-dem-model.md §7.7",
        ),
    ),
    (
        "dem_moving_wall",
        a(
            "a sphere on a rotating disc, or hit by a rotating blade: contact-point velocity and rebound speed",
            "rigid-wall kinematics: sticking contact moves with the wall; rebound at (1 + e) × blade speed",
            "fluid-dem-model.md §7.4",
        ),
    ),
    (
        "dem_tessellated_plane",
        a("impacts on a plane made of triangles, on edges and vertices: the same rebound as on the analytic plane", "the analytic plane", "fluid-dem-model.md §7.4, §7.8"),
    ),
    (
        "dem_pile",
        a("particles poured into a pile: settles to rest without overlap growth or energy gain", "static equilibrium (bounded overlap, kinetic energy → 0)", "fluid-dem-model.md §7.6, §7.8"),
    ),
    (
        "cutter_head_flow",
        a(
            "water through the back-plate cutter head at 60 rpm and 0.12 m³/s: out-flowing flux through the contour hull and the net flux (`--full`: 30–90 rpm and two finer meshes)",
            "thesis CFD: out-flowing flux ≈ half the suction discharge, rising with rpm (Fig. 8.1); continuity: net inflow = suction discharge (Eq. 8.3); shown with the analytic spillage model's Q₁",
            "spillage-and-flow-verification.md §4, §5.1, §5.2; §2 (analytic model)",
        ),
    ),
    (
        "cutter_head_twenty_rpm",
        a(
            "water through the case's head at 20 rpm with its own suction, the thesis' eccentric mouth at rest, and axial suction: the mean flow through the contour at fixed places (maps with `--plots`)",
            "thesis CFD: the axial head draws water in over its whole contour at 20 rpm; the back-plate head lets water out already, far from its mouth (Fig. 8.2)",
            "spillage-and-flow-verification.md §5.2",
        ),
    ),
    (
        "wear_stream",
        a(
            "a stream of particles against a plate at impact angles 15–90°: removed volume per particle mass and the volume bookkeeping of smoothing and recession",
            "the erosion law evaluated by the analytic crate; exact volume identities",
            "wear-model.md §6 (Arabnejad), §7.1–§7.3, §15",
        ),
    ),
    (
        "wear_profile",
        a(
            "the Coriolis tester arm at 3000 rpm: wear profile along the coupon, position of the first peak, second region ratio, bookkeeping",
            "thesis Ch. 5 (Tables 5.1–5.2): deepest wear ≈ 10 ± 3 mm after the step, second region 0.4–0.75 of the first",
            "wear-model.md §12.4",
        ),
    ),
    (
        "wear_jet",
        a(
            "a jet of garnet at 30° on a plate that recedes as it wears, against the same plate held still (a dry stand-in: a retarding field slows the particles instead of water): wear at first impact, the wear rate's trend, the profile's relief, bookkeeping",
            "thesis §4.5.2 (qualitative): identical wear at first impact; afterwards the receding wall's wear rate falls and flattens while the still wall's stays; exact volume identities",
            "wear-model.md §12.3, §7.4, §15",
        ),
    ),
    (
        "rotating_frame_free_particle",
        a(
            "free particles seen from the turning frame: position errors against the exact trajectory, observed order in Δt, A39 and A40",
            "rigid-rotation kinematics: A39 (Ω, Ω²r at 3000 rpm), A40 |r|² = |r₀|²(1 + Ω²t²)",
            "wear-model.md §2.6, §15 (A39–A40)",
        ),
    ),
    (
        "rotating_frame_fluid_at_rest",
        a(
            "water at rest in the rotating frame, both fluid solvers: spurious velocity and the centrifugal pressure (and its order on annulus meshes)",
            "p − p_in = ½ρΩ²(r² − r_in²), u = 0",
            "wear-model.md §2.6 [R], §13 row 16",
        ),
    ),
    (
        "rotating_frame_equivalence",
        a(
            "a channel flow in the rotating frame (Coriolis acting): fast vs reference fluid step by step; the cross-duct pressure carries the Coriolis force",
            "the reference solver (≤ 1e-8); ΔP = −2Ω_z ∫u dy",
            "wear-model.md §2.6; issue #6 (equivalence bound)",
        ),
    ),
    (
        "rotating_frame_settling",
        a(
            "a grain drifting outwards through water at rest in the frame: position error, observed order in Δt, drift rates",
            "the exact solution of the linear drift equation (complex exponential), centrifugal terminal velocity u_t/(1 + a²)",
            "wear-model.md §2.6, §12.2",
        ),
    ),
    (
        "turbulent_channel",
        a(
            "the fully developed turbulent half channel (realizable k–ε, standard wall functions), driven by a body force, run to steady state by both fluid solvers: U⁺(y⁺) against the log law, C_f against Dean, the wall shear stress against u_τ² (momentum balance), U_b under mesh and Δt refinement",
            "log law U⁺ = ln(y⁺)/0.41 + 5.2; Dean (1978) C_f = 0.073 Re_m^(−1/4); OpenFOAM v1912 realizableKE on the same mesh (benches/peers/openfoam_channel)",
            "fluid-dem-model.md §3.1–3.2 (T3.13–T3.21), §8.10",
        ),
    ),
    (
        "backward_facing_step",
        a(
            "the separated flow behind a backward-facing step (expansion 9/8, Re_H = 37 500, realizable k–ε with wall functions): the mean reattachment length from the sign change of the wall-cell velocity, and its spread over the last steps",
            "Driver & Seegmiller (1985), measured x_r = 6.26 H",
            "fluid-dem-model.md §3.2, §8.10",
        ),
    ),
];

#[cfg(test)]
mod tests {
    use super::*;

    /// Every description names a known check (a check without one still appears in the
    /// report, marked as undescribed).
    #[test]
    fn every_description_names_a_known_check() {
        let known = super::super::known_checks();
        for (name, _) in ABOUT {
            assert!(known.contains(name), "about.rs describes an unknown check `{name}`");
        }
    }
}

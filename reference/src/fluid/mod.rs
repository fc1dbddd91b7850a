//! Reference fluid solver: collocated finite volumes on the face-addressed mesh, PIMPLE,
//! BDF2, direct sparse solves. Written to be read against spec fluid-dem-model.md §8; the fast
//! solver reproduces it step by step, so every choice is spelled out here.
//!
//! # Unknowns and storage
//! Cell velocity u (absolute frame), kinematic pressure P = p/ρ, and one absolute volumetric
//! flux φ = u_f·S_f per *link* (internal face or sliding-interface overlap, [`geometry`]) and per
//! boundary face. Volume-averaged form throughout: α_c per cell (1 without particles), face
//! values α_f by linear interpolation, α_b = α_P on boundaries.
//!
//! # One time step (Algorithm 1 of spec §8.7, fluid part)
//! 1. Δt from `[time] dt` (the previous Δt is `State::dt`). Time coefficients
//!    d/dt q ≈ (c₀qⁿ + c₁qᵒ + c₂qᵒᵒ)/Δt: implicit Euler (1, −1, 0) on the first step or with
//!    `time_scheme = "euler"`, else variable-step BDF2 with r = Δt/Δtᵒ:
//!    c₀ = (1+2r)/(1+r), c₁ = −(1+r), c₂ = r²/(1+r).
//! 2. Rotor: angle += ω Δt; the mesh zone is set to the new angle from its reference geometry.
//!    Links are rebuilt ([`geometry::Geometry::build`]): internal faces, then the interface
//!    overlaps ([`interface`]: one link per rotor/stator face overlap, owner = rotor cell, area
//!    = chord of the true circle over the overlap). Mesh flux of a face of the rotor zone:
//!    (ω×(x_f − x_axis))·S_f (exact for planar faces, so Σ_faces = 0 per cell: geometric
//!    conservation).
//! 3. Starting values: u* = uᵒ, P* = Pᵒ, boundary P from the state; flux φ* = φᵒ on internal
//!    faces of static cells, interpolated (w u_P + (1−w) u_N)·S (new geometry) on faces of the
//!    moving zone and on overlap links (their geometry changed: old fluxes there would leave the
//!    cells open in the first outer iteration), the prescribed flux on velocity boundaries and
//!    φᵒ on pressure boundaries.
//! 4. Outer (SIMPLE) loop k = 1..`max_outer_iterations`:
//!    a. ∇u* (Gauss, linear face values, boundary values from the conditions).
//!    b. Momentum matrix ([`momentum::assemble`]): time term c₀αV/Δt on the diagonal, old
//!       levels in the source; convection Σ α_f u_f (φ* − φ_mesh) implicit with the scheme's
//!       owner weight (linear: w; upwind; blended; limitedLinearV 1 with the limiter from u*
//!       and ∇u*); diffusion Σ (αν)_f [|S|²/(d·S)](u_N − u_P) implicit plus
//!       (αν)_f (∇u)_f·(S − |S|²/(d·S) d) explicit, (∇u)_f linearly interpolated; explicit
//!       Σ (αν)_f[(∇u)_fᵀ − ⅔tr(∇u)_f I]·S (cell gradient on boundary faces); body force
//!       (g + `body_force`)V; in a rotating frame α(−2Ω×u* − Ω×(Ω×(x_c − x₀)))V, Coriolis in
//!       the latest iterate u* ([`momentum`] doc, wear-model.md §2.6); in a frozen-rotor
//!       start-up step (the pose of step 2 keeps its angle, ω stays) −α Ω×u* V in the rotor
//!       zone's cells (spillage_model::fluid::frozen_rotor, OpenFOAM's MRF); fixed-velocity faces:
//!       −α_P(φ_b − φ_mesh)u_b in the source and ν α_P|S|/d_n on the diagonal, ν α_P|S|/d_n u_b
//!       in the source; pressure-outlet faces: α_P(φ_b − φ_mesh) on the diagonal; symmetry:
//!       viscous flux towards the slip value of u*.
//!       Then implicit under-relaxation a_P ← a_P/α_u, b ← b + (a_P/α_u − a_P)u*.
//!    c. Predictor: solve M u = b − V ∇P* (∇P* Gauss with linear face values and the boundary
//!       pressures) for every solved component (components along empty-patch normals stay 0).
//!    d. PISO corrector, `piso_correctors` times ([`pressure::correct`]):
//!       HbyA = (b − Σ_N a_N u_N)/a_P, rAU = V/a_P with the latest u; face values by linear
//!       interpolation, on overlap links plus the skewness correction (k·∇u)_f of HbyA_f
//!       (k = overlap centre − interpolation point, ∇u of the momentum assembly; issue 12);
//!       pressure equation
//!       Σ α_f rAU_f |S|²/(d·S) (P_N − P_P) = Σ α_f [HbyA_f·S − rAU_f (∇P)_f·T] + Σ_b α_P φ_b
//!       + ∂α/∂t V − Σ_f (α_f − 1) φ_mesh,f (the rate at the cell's place: α's time levels follow
//!       turning cells, spillage_model::fluid::moving_cells), with (∇P)_f·T the explicit
//!       non-orthogonal part from the previous pressure,
//!       repeated `non_orthogonal_correctors` extra times. Prescribed-flux boundaries (walls,
//!       velocity inlets, symmetry) contribute their flux; their boundary pressure is
//!       P_b = P_P + d_n (HbyA_P·S − φ_b)/(rAU_P|S|) (spec §8.8 T4.42, A⁻¹H extrapolated), or
//!       P_P with `pressure_wall = "zero_gradient"`. Pressure outlets are Dirichlet. Without a
//!       Dirichlet boundary, cell 0 is pinned to P = 0 (diagonal doubled). The initial residual
//!       (OpenFOAM normalisation, [`pressure::normalised_residual`]) of the first corrector is
//!       the outer convergence measure. The direct solve is exact.
//!       Fluxes φ = HbyA_f·S − rAU_f (∇P)_f·T − rAU_f |S|²/(d·S)(P_N − P_P) from the solved P
//!       (exactly conservative). P ← P* + α_p (P_new − P*); boundary pressures from the
//!       relaxed P; u = HbyA − rAU ∇P.
//!       Time-derivative flux correction (OpenFOAM `fvc::ddtCorr`, coupling coefficient 1;
//!       `[numerics] ddt_flux_correction`, default off, see below): the momentum source carries the old
//!       levels −(c₁αᵒuᵒ + c₂αᵒᵒuᵒᵒ)V/Δt, so HbyA_f·S carries the interpolated old velocities.
//!       The predicted face flux gets rAU_f·(−1/Δt)[c₁(α_fᵒ φᵒ − (αᵒuᵒ)_f·S)
//!       + c₂(α_fᵒᵒ φᵒᵒ − (αᵒᵒuᵒᵒ)_f·S)] added, so that its old-time part is the old flux.
//!       Zero on boundary faces, on faces of the moving zone and on overlap links (their
//!       geometry changed since φᵒ, φᵒᵒ were stored). Without it φ differs from the
//!       interpolated u by rAU_f[(∇P)_f interpolated − compact ∇P]·S ≈ (Δt/c₀)·O(h²), an error
//!       of order Δt·h²: first order in Δt at fixed h, O(h³) along Δt ∝ h. On Taylor–Green
//!       at Courant 0.25 it cancels the spatial h² error on 16²–64² (observed KE order 1.4),
//!       so the verification refines at Courant 0.03 (measured decomposition in
//!       cases/verification/fluid/taylor_green.toml). With the correction the mismatch
//!       X = φ − u_f·S obeys X ≈ (rAU_f/Δt)(−c₁Xᵒ − c₂Xᵒᵒ) + D (D the instantaneous term
//!       above): a recursion with a root near 1 when νΔt/h² is small, so X accumulates to
//!       ≈ D/(diffusion number) instead of staying D. Measured on Taylor–Green (Δt ∝ h):
//!       |KE error| 1.12e-3 → 1.46e-2 (16²), 4.14e-4 → 9.04e-4 (32²); velocity rms 3.13e-3 →
//!       2.16e-2, 3.73e-4 → 1.37e-3. The KE "order" 16→32 rises to 4.0 only because the coarse
//!       error grows, so the correction stays off by default (OpenFOAM's ddtCouplingCoeff
//!       1 − min(|X|/|φᵒ|, 1) would be ≈ 1 here and not change this).
//!       With one corrector and no under-relaxation the outer loop may not converge at
//!       diffusion numbers νΔt/h² ≳ 0.2; use `piso_correctors = 2` or relaxation there.
//!    e. Stop when the initial pressure residual of this outer iteration < `p_initial_residual`.
//! 5. uᵒᵒ ← uᵒ, uᵒ ← u, Pᵒ ← P, φᵒᵒ ← φᵒ, φᵒ ← φ (overlap fluxes summed onto their rotor and stator
//!    faces), α levels shifted, continuity errors accumulated.
//!
//! # Diagnostics (per step, `StepReport::values`)
//! Continuity error per cell e_c = ∂α/∂t V + Σ α_f φ_f − Σ (α_f − 1) φ_mesh,f [m³/s]; local = Δt Σ|e_c|, global =
//! Δt Σ e_c, cumulative = Σ_steps global [m³] (spec U-31); Courant number
//! max_c ½Δt Σ_f |φ_f − φ_mesh,f| / V (T4.44); kinetic energy ½ Σ α|u|²V [m⁵/s²]; outer
//! iterations; last initial pressure residual; interface flux imbalance
//! |Σ_rotor-side φ + Σ_stator-side φ| / Σ_overlaps |φ|.

pub mod boundary;
pub mod diagnostics;
pub mod geometry;
pub mod gradient;
pub mod interface;
pub mod linear;
pub mod momentum;
pub mod pressure;
pub mod schemes;
mod solver;
pub mod turbulence;

pub use solver::ReferenceFluid;

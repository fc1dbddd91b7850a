//! One PISO corrector (spec §8.5, T4.24–T4.33, Algorithm 1 lines 15–20) with the flux-based
//! pressure condition at prescribed-flux boundaries (spec §8.8, T4.42).

use spillage_model::fluid::settings::PressureWallCondition;
use spillage_model::mesh::Vec3;
use spillage_model::solver::SolverError;

use super::boundary::Condition;
use super::geometry::BoundaryFace;
use super::gradient::{directional, scalar_gradient};
use super::linear::SparseMatrix;
use super::momentum::{interpolate_tensor, MomentumSystem, StepInputs};

/// The pressure-velocity fields the corrector updates.
pub struct CorrectorFields<'a> {
    pub u: &'a mut Vec<Vec3>,
    pub p: &'a mut Vec<f64>,
    /// Pressure on each boundary face (index into `geo.boundary`).
    pub p_boundary: &'a mut Vec<f64>,
    pub link_flux: &'a mut Vec<f64>,
    pub boundary_flux: &'a mut Vec<f64>,
}

/// H/A and V/A of the latest velocity: HbyA = (b − Σ_N a_N u_N)/a_P (T4.24, T4.40), rAU = V/a_P.
pub fn h_by_a(inputs: &StepInputs, system: &MomentumSystem, u: &[Vec3]) -> (Vec<Vec3>, Vec<f64>) {
    let n = u.len();
    let mut hbya = vec![Vec3::zeros(); n];
    for j in 0..3 {
        if !inputs.geo.solved_components[j] {
            continue;
        }
        let component: Vec<f64> = u.iter().map(|v| v[j]).collect();
        let offdiag = system.matrix.multiply_off_diagonal(&component);
        for c in 0..n {
            hbya[c][j] = (system.source[c][j] - offdiag[c]) / system.matrix.diagonal[c];
        }
    }
    let rau = (0..n).map(|c| inputs.volumes[c] / system.matrix.diagonal[c]).collect();
    (hbya, rau)
}

/// Normal pressure gradient at a prescribed-flux boundary face (spec §8.8, T4.42):
/// ∂P/∂n = (HbyA·S − φ_b) / (rAU |S|), with HbyA/rAU taken from the cell
/// (`fixed_flux_extrapolated`, OpenFOAM's choice) or extrapolated linearly from the cell and the
/// neighbour across it (`fixed_flux_linear`); zero for the `zero_gradient` option.
fn boundary_normal_gradient(inputs: &StepInputs, face: &BoundaryFace, hbya: &[Vec3], rau: &[f64], flux: f64) -> f64 {
    let from_cell = |c: usize| (hbya[c].dot(&face.area) - flux) / (rau[c] * face.area.norm());
    match (inputs.numerics.pressure_wall, face.across) {
        (PressureWallCondition::ZeroGradient, _) => 0.0,
        (PressureWallCondition::FixedFluxLinear, Some((across, ratio))) => {
            let (at_cell, at_across) = (from_cell(face.cell), from_cell(across));
            at_cell + ratio * (at_cell - at_across)
        }
        (PressureWallCondition::FixedFluxExtrapolated | PressureWallCondition::FixedFluxLinear, _) => from_cell(face.cell),
    }
}

/// Boundary pressures for cell pressure `p`.
pub fn boundary_pressures(inputs: &StepInputs, hbya: &[Vec3], rau: &[f64], p: &[f64], prescribed: &[Option<f64>]) -> Vec<f64> {
    inputs
        .geo
        .boundary
        .iter()
        .enumerate()
        .map(|(b, face)| match (&inputs.conditions.conditions[face.patch], prescribed[b]) {
            (Condition::FixedPressure { pressure }, _) => *pressure,
            (_, Some(flux)) => p[face.cell] + face.normal_distance * boundary_normal_gradient(inputs, face, hbya, rau, flux),
            (_, None) => p[face.cell],
        })
        .collect()
}

/// Runs one corrector; returns the initial residual of the pressure equation (the residual of
/// the pressure before this solve, normalised as OpenFOAM does).
pub fn correct(inputs: &StepInputs, system: &MomentumSystem, prescribed: &[Option<f64>], fields: CorrectorFields) -> Result<f64, SolverError> {
    let geo = inputs.geo;
    let n = geo.n_cells();
    let (hbya, rau) = h_by_a(inputs, system, fields.u);
    let alpha = inputs.alpha;

    // prescribed-flux boundaries keep their flux
    for (b, flux) in prescribed.iter().enumerate() {
        if let Some(flux) = flux {
            fields.boundary_flux[b] = *flux;
        }
    }

    let p_start = fields.p.clone();
    let mut p_work = fields.p.clone();
    let mut initial_residual = 0.0;
    let mut link_h_flux = vec![0.0; geo.links.len()];
    for corrector in 0..=inputs.numerics.non_orthogonal_correctors {
        let p_bnd = boundary_pressures(inputs, &hbya, &rau, &p_work, prescribed);
        let grad_p = scalar_gradient(geo, inputs.volumes, &p_work, &p_bnd);
        let mut lap = SparseMatrix::new(n);
        let mut rhs = vec![0.0; n];
        for (l, link) in geo.links.iter().enumerate() {
            let (p, nb) = (link.owner, link.neighbour);
            let alpha_f = link.interpolate(alpha[p], alpha[nb]);
            let rau_f = link.interpolate(rau[p], rau[nb]);
            // (A⁻¹H) at the face centre: linear interpolation plus the skewness correction
            // (k·∇)(A⁻¹H)_f, k = 0 on mesh faces. On an overlap link the rotor and stator
            // centres lie at different θ, so the linearly interpolated value belongs to a point
            // O(h) beside the overlap centre, and a swirling field's Cartesian components turn
            // with θ: without the correction the predicted flux of a pure rotation carries a
            // spurious normal part u_θ·O(Δθ), first order (issue 12). [R, our construction; the
            // spec's Rhie–Chow flux, fluid-dem-model.md §8.5 T4.27, interpolates linearly:
            // OpenFOAM's skewCorrected scheme, with ∇u of the momentum assembly of this outer
            // iteration in place of ∇(A⁻¹H) = ∇u + ∇(A⁻¹∇P), A⁻¹ ≈ Δt/c₀, so the difference is
            // O(Δt·|k|) = O(h²) with Δt ∝ h.]
            let hbya_f =
                link.interpolate_vec(hbya[p], hbya[nb]) + directional(&interpolate_tensor(link.weight, &system.grad_u[p], &system.grad_u[nb]), &link.skew);
            let grad_f = link.interpolate_vec(grad_p[p], grad_p[nb]);
            // predicted flux (A⁻¹H)_f·S minus the explicit non-orthogonal pressure part, plus
            // the time-derivative flux correction (old fluxes in place of interpolated old
            // velocities)
            let h_flux = hbya_f.dot(&link.area) - rau_f * grad_f.dot(&link.non_orthogonal_part()) + rau_f * inputs.ddt_flux_correction[l];
            link_h_flux[l] = h_flux;
            let c = alpha_f * rau_f * link.laplacian_coefficient();
            lap.add_diagonal(p, c);
            lap.add_diagonal(nb, c);
            lap.add_off_diagonal(p, nb, -c);
            lap.add_off_diagonal(nb, p, -c);
            rhs[p] -= alpha_f * h_flux;
            rhs[nb] += alpha_f * h_flux;
        }
        for (b, face) in geo.boundary.iter().enumerate() {
            let p = face.cell;
            match (&inputs.conditions.conditions[face.patch], prescribed[b]) {
                (Condition::FixedPressure { pressure }, _) => {
                    let c = alpha[p] * rau[p] * face.area.norm() / face.normal_distance;
                    lap.add_diagonal(p, c);
                    rhs[p] += c * pressure - alpha[p] * hbya[p].dot(&face.area);
                }
                (_, Some(flux)) => rhs[p] -= alpha[p] * flux,
                (_, None) => {}
            }
        }
        for (r, rate) in rhs.iter_mut().zip(inputs.alpha_rates_volume_in_pressure()) {
            *r -= rate;
        }
        if !inputs.conditions.has_fixed_pressure {
            // reference level P = 0 in cell 0 (OpenFOAM setReference): exact for a compatible
            // right-hand side, since the columns of the Laplacian sum to zero
            let d = lap.diagonal[0];
            lap.add_diagonal(0, d);
        }
        if corrector == 0 {
            initial_residual = normalised_residual(&lap, &rhs, &p_start);
        }
        p_work = lap.solve_on_cells(&[rhs], "pressure equation", inputs.cell_centres)?.remove(0);
    }

    // conservative fluxes from the final pressure (T4.28)
    for (l, link) in geo.links.iter().enumerate() {
        let rau_f = link.interpolate(rau[link.owner], rau[link.neighbour]);
        fields.link_flux[l] = link_h_flux[l] - rau_f * link.laplacian_coefficient() * (p_work[link.neighbour] - p_work[link.owner]);
    }
    for (b, face) in geo.boundary.iter().enumerate() {
        if let Condition::FixedPressure { pressure } = &inputs.conditions.conditions[face.patch] {
            let p = face.cell;
            fields.boundary_flux[b] = hbya[p].dot(&face.area) - rau[p] * face.area.norm() / face.normal_distance * (pressure - p_work[p]);
        }
    }

    // pressure under-relaxation, then the velocity corrector u = HbyA − rAU ∇P (T4.26)
    let relax = inputs.numerics.relax_pressure;
    for c in 0..n {
        fields.p[c] = p_start[c] + relax * (p_work[c] - p_start[c]);
    }
    *fields.p_boundary = boundary_pressures(inputs, &hbya, &rau, fields.p, prescribed);
    let grad_p = scalar_gradient(geo, inputs.volumes, fields.p, fields.p_boundary);
    for c in 0..n {
        for j in 0..3 {
            fields.u[c][j] = if geo.solved_components[j] { hbya[c][j] - rau[c] * grad_p[c][j] } else { 0.0 };
        }
    }
    Ok(initial_residual)
}

/// OpenFOAM's normalised residual Σ|b − Ax| / (Σ|Ax − A x̄| + Σ|b − A x̄| + 10⁻²⁰), x̄ the mean of x.
pub fn normalised_residual(a: &SparseMatrix, b: &[f64], x: &[f64]) -> f64 {
    let n = x.len() as f64;
    let mean = x.iter().sum::<f64>() / n;
    let ax = a.multiply(x);
    let a_mean = a.multiply(&vec![mean; x.len()]);
    let mut residual = 0.0;
    let mut norm = 0.0;
    for i in 0..x.len() {
        residual += (b[i] - ax[i]).abs();
        norm += (ax[i] - a_mean[i]).abs() + (b[i] - a_mean[i]).abs();
    }
    residual / (norm + 1e-20)
}

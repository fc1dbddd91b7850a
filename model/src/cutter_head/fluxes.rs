//! The head's fluid fluxes of one step, as `series.csv` columns (spillage-and-flow-verification.md
//! §5.1): the face hull's exact fluxes ([`HullFaces`]: `hull_*`, `suction_flux`,
//! `outflow_ratio`) and the thesis' interpolated contour surface ([`HullSurface`]:
//! `contour_*`).

use super::hull_surface::HullSurface;
use super::spillage::HullFaces;
use super::CutterHead;
use crate::case::Case;
use crate::fluid::conditions::Conditions;
use crate::fluid::state::FluidState;
use crate::fluid::velocity_gradient::{boundary_velocities, gauss_velocity_gradient};
use crate::mesh::{Mesh, Vec3};
use crate::solver::StepReport;
use crate::step::RotorPose;

/// Both hulls of a head and the boundary conditions its interpolation needs.
#[derive(Clone, Debug)]
pub struct HeadFluxes {
    pub faces: HullFaces,
    pub surface: HullSurface,
    conditions: Conditions,
}

impl HeadFluxes {
    pub fn new(case: &Case, head: &CutterHead, mesh: &Mesh) -> Result<HeadFluxes, String> {
        let density = case.fluid.as_ref().ok_or("a cutter head needs a [fluid]")?.density;
        Ok(HeadFluxes {
            faces: HullFaces::new(head, mesh),
            surface: HullSurface::new(head, mesh)?,
            conditions: Conditions::from_case(case, mesh, density).map_err(|e| e.to_string())?,
        })
    }

    /// The head with its fluxes (what the coupled driver keeps).
    pub fn with_head(case: &Case, head: CutterHead, mesh: &Mesh) -> Result<(CutterHead, HeadFluxes), String> {
        let fluxes = HeadFluxes::new(case, &head, mesh)?;
        Ok((head, fluxes))
    }

    /// Appends the fluxes of `fluid` (at the end of a step, `mesh` and `pose` at its time).
    pub fn report(&self, head: &CutterHead, mesh: &Mesh, fluid: &FluidState, pose: Option<&RotorPose>, report: &mut StepReport) {
        let q = self.faces.flux(&fluid.flux);
        let s = self.surface.flux(mesh, &fluid.velocity, &self.velocity_gradient(mesh, fluid, pose));
        report.values.extend([
            ("hull_outflow", q.outflow),
            ("hull_net_flux", q.net),
            ("suction_flux", q.suction),
            ("outflow_ratio", q.outflow / head.suction_discharge),
            ("hull_outflow_top", q.outflow_top_bin),
            ("contour_outflow", s.outflow),
            ("contour_net_flux", s.net),
            ("contour_outflow_top", s.outflow_top_bin),
        ]);
    }

    /// The contour surface's fluxes per element fixed in the laboratory
    /// ([`HullSurface::laboratory_fluxes`]), for time means of the flow through fixed places.
    pub fn laboratory_contour_fluxes(&self, mesh: &Mesh, fluid: &FluidState, pose: Option<&RotorPose>) -> Vec<f64> {
        self.surface.laboratory_fluxes(mesh, &fluid.velocity, &self.velocity_gradient(mesh, fluid, pose))
    }

    /// The cells' Gauss velocity gradients with the assembly's boundary values (the blades'
    /// faces bring the rotor's velocity), which the contour's interpolation takes.
    fn velocity_gradient(&self, mesh: &Mesh, fluid: &FluidState, pose: Option<&RotorPose>) -> Vec<[Vec3; 3]> {
        let conditions = self.conditions.with_solved_suction(mesh, &fluid.flux);
        let boundary_u = boundary_velocities(mesh, &conditions, &fluid.velocity, pose);
        gauss_velocity_gradient(mesh, &fluid.velocity, |f, _| Some(boundary_u[f - mesh.n_internal_faces]))
    }
}

//! What a particle phase reads from the case, resolved once and the same for both solvers: the
//! `[particles]` section, the material-pair table, the non-contact forces and the fluid of the
//! wet restitution law; and the particle and wall states of a fresh run.

use super::materials::MaterialTable;
use super::non_contact::NonContactForces;
use super::settings::ParticlesSection;
use super::state::Vec3;
use crate::case::Case;
use crate::closure::drag::DragLaw;
use crate::closure::rotating_frame::RotatingFrame;
use crate::state::State;
use crate::walls::geometry::WallMesh;
use crate::walls::state::WallState;

/// The case's constants of a DEM.
#[derive(Clone, Debug)]
pub struct DemSetup {
    pub section: ParticlesSection,
    pub materials: MaterialTable,
    pub forces: NonContactForces,
    /// Fluid density and viscosity for the wet restitution (T3.103), if wet.
    pub wet_fluid: Option<(f64, f64)>,
}

impl DemSetup {
    /// Resolves `case`; missing particle or wall states in `state` are built from the case
    /// (walls with STL paths relative to the case file's folder). Errors are sentences.
    pub fn new(case: &Case, state: &mut State) -> Result<Self, String> {
        let section = case.particles.clone().ok_or("a DEM needs a [particles] section")?;
        if state.particles.is_none() {
            let initial = super::initial_state(case).map_err(|e| format!("initial particles: key `{}` = {}: expected {}", e.key, e.value, e.allowed))?;
            state.particles = Some(initial);
        }
        if state.walls.is_none() {
            let dir = case.path.parent().map(|p| p.to_path_buf()).unwrap_or_default();
            state.walls = Some(crate::walls::build(case, &dir).map_err(|e| format!("walls: {e}"))?);
        }
        let materials = MaterialTable::new(&section.materials, section.slip_test);
        let wet_fluid = match (&case.fluid, &section.ambient) {
            (Some(f), _) => Some((f.density, f.kinematic_viscosity)),
            (None, Some(a)) if a.wet_restitution => Some((a.density, a.kinematic_viscosity)),
            _ => None,
        };
        let drag_law = match (&case.coupling, &section.ambient) {
            (Some(c), _) => c.drag,
            (None, Some(a)) => a.drag,
            (None, None) => DragLaw::default(),
        };
        let forces = NonContactForces {
            drag_law,
            gravity: Vec3::from(case.physics.gravity),
            rotating_frame: RotatingFrame::of_physics(&case.physics).map_err(|e| format!("`{}` = {}: expected {}", e.key, e.value, e.allowed))?,
            feedback: case.coupling.as_ref().map(|c| c.feedback),
            motion: section.motion,
        };
        Ok(Self { section, materials, forces, wet_fluid })
    }
}

/// The collision mesh of every wall, rebuilt when the wall's vertices move (a receding wall,
/// wear-model.md §7.4) so contacts see its worn shape.
pub struct WallMeshes {
    pub meshes: Vec<WallMesh>,
    /// The wall revision each mesh was built from.
    revisions: Vec<u64>,
    /// How often each mesh was built (1 at the start): what a particle phase keeps about a mesh
    /// (near triangles) is stale once this changes.
    pub generations: Vec<u64>,
}

impl WallMeshes {
    pub fn new(walls: &WallState) -> Result<Self, String> {
        let meshes =
            walls.walls.iter().map(|w| WallMesh::new(&w.vertices, &w.triangles).map_err(|m| format!("wall `{}`: {m}", w.name))).collect::<Result<_, _>>()?;
        Ok(Self { meshes, revisions: walls.walls.iter().map(|w| w.revision).collect(), generations: vec![1; walls.walls.len()] })
    }

    /// Rebuilds the mesh of every wall whose revision moved on since.
    pub fn refresh(&mut self, walls: &WallState) -> Result<(), String> {
        for (i, w) in walls.walls.iter().enumerate() {
            if self.revisions[i] != w.revision {
                self.meshes[i] = WallMesh::new(&w.vertices, &w.triangles).map_err(|m| format!("worn wall `{}`: {m}", w.name))?;
                self.revisions[i] = w.revision;
                self.generations[i] += 1;
            }
        }
        Ok(())
    }
}

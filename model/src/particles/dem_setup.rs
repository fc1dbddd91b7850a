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
    /// Per wall: whether its contacts book sliding wear (`crate::wear::sliding`).
    pub sliding_walls: Vec<bool>,
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
        let wet_fluid = section.wet_fluid(case.fluid.as_ref().map(|f| (f.density, f.kinematic_viscosity)));
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
            fluid_forces: section.fluid_forces,
        };
        let sliding_walls = crate::wear::setup::sliding_walls(case, state.walls.as_ref().expect("built above"))?;
        Ok(Self { section, materials, forces, wet_fluid, sliding_walls })
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

#[cfg(test)]
mod tests {
    use super::DemSetup;
    use crate::case::Case;
    use crate::state::State;

    const COUPLED: &str = include_str!("../../../cases/verification/coupling/hydrostatic_held.toml");

    fn wet_fluid(text: &str) -> Option<(f64, f64)> {
        let case = Case::from_toml(text, std::path::Path::new("held.toml")).unwrap();
        DemSetup::new(&case, &mut State::default()).unwrap().wet_fluid
    }

    /// In a fluid the contacts start wet (the case's water) unless `[particles] restitution =
    /// "dry"` keeps ε_dry; another value is refused at its line, naming what is allowed.
    #[test]
    fn restitution_is_wet_in_a_fluid_unless_the_case_says_dry() {
        let case = Case::from_toml(COUPLED, std::path::Path::new("held.toml")).unwrap();
        let fluid = case.fluid.as_ref().unwrap();
        assert_eq!(wet_fluid(COUPLED), Some((fluid.density, fluid.kinematic_viscosity)));
        let dry = COUPLED.replacen("[particles]\n", "[particles]\nrestitution = \"dry\"\n", 1);
        assert_ne!(dry, COUPLED);
        assert_eq!(wet_fluid(&dry), None);
        let bad = COUPLED.replacen("[particles]\n", "[particles]\nrestitution = \"damp\"\n", 1);
        let e = Case::from_toml(&bad, std::path::Path::new("held.toml")).unwrap_err();
        let line = bad.lines().position(|l| l.starts_with("restitution = \"damp\"")).unwrap() + 1;
        assert_eq!(e.line, Some(line), "{e}");
        let text = e.to_string();
        assert!(text.contains("damp") && text.contains("wet") && text.contains("dry"), "{text}");
    }
}

//! ParaView output of a run: one `.vtu` of the fluid mesh (the rotor turned to its current
//! angle), one `.vtp` of the particles and one `.vtp` of the wall triangles per written step,
//! each series indexed by a `.pvd` file that ParaView opens as a time series. A two-way coupled
//! run adds the exchange of its last step ([`CouplingFrame`]).

use std::path::{Path, PathBuf};

use spillage_model::mesh::Mesh;
use spillage_model::output::vtk::{self, Encoding, Field, FieldValues, PolyCells, PolyData, PvdCollection, UnstructuredCells, UnstructuredGrid};
use spillage_model::output::OutputError;
use spillage_model::state::State;

/// Above this many numbers a file is written in raw binary rather than ASCII.
const BINARY_ABOVE: usize = 20_000;

/// The fields a two-way coupled run adds to a frame, from its last step; all `None` otherwise
/// (and before the first step). A field whose length does not match the cells or particles is
/// left out.
#[derive(Debug, Default)]
pub struct CouplingFrame {
    /// The particles' force density on the fluid per cell, f = (F − C u)/V [N/m³].
    pub force_density: Option<Vec<[f64; 3]>>,
    /// Per particle: the fluid velocity it saw, u_c|p [m/s] (zero where it saw no fluid).
    pub fluid_velocity: Option<Vec<[f64; 3]>>,
    /// Per particle: the drag force on it [N].
    pub drag_force: Option<Vec<[f64; 3]>>,
    /// Per particle: its slip Reynolds number |u_c|p − u_p| d_p/ν.
    pub slip_reynolds: Option<Vec<f64>>,
}

/// How many numbers `fields` hold (three per vector entry).
fn numbers(fields: &[Field]) -> usize {
    fields.iter().map(|f| f.values.len() * if matches!(f.values, FieldValues::Vector(_)) { 3 } else { 1 }).sum()
}

/// `values` when there is one per item of `n`.
fn matching<T>(values: &Option<Vec<T>>, n: usize) -> Option<&[T]> {
    values.as_deref().filter(|v| v.len() == n)
}

pub struct Frames {
    dir: PathBuf,
    fluid: Option<PvdCollection>,
    particles: Option<PvdCollection>,
    walls: Option<PvdCollection>,
    resume_time: Option<f64>,
}

impl Frames {
    /// Frames under `out/`; `resume_time` continues the `.pvd` indexes of an earlier run,
    /// dropping frames written after that time.
    pub fn new(out: &Path, resume_time: Option<f64>) -> Result<Self, OutputError> {
        let dir = out.join("vtk");
        std::fs::create_dir_all(&dir).map_err(|source| OutputError::Io { path: dir.clone(), source })?;
        Ok(Self { dir, fluid: None, particles: None, walls: None, resume_time })
    }

    fn collection<'a>(slot: &'a mut Option<PvdCollection>, path: PathBuf, resume_time: Option<f64>) -> Result<&'a mut PvdCollection, OutputError> {
        if slot.is_none() {
            *slot = Some(match resume_time {
                Some(t) if path.exists() => PvdCollection::resume(&path, t)?,
                _ => PvdCollection::create(&path)?,
            });
        }
        Ok(slot.as_mut().expect("just set"))
    }

    /// Writes the state at its current time, with the coupling fields of its last step.
    pub fn write(&mut self, mesh: Option<&Mesh>, state: &State, coupling: &CouplingFrame) -> Result<(), OutputError> {
        let out = self.dir.parent().expect("vtk folder has a parent").to_path_buf();
        let step = state.step;
        if let (Some(mesh), Some(fluid)) = (mesh, &state.fluid) {
            let name = format!("fluid_{step:08}.vtu");
            let points: Vec<[f64; 3]> = mesh.points.iter().map(|p| [p.x, p.y, p.z]).collect();
            let cells = UnstructuredCells::hexahedra(&mesh.cell_points);
            let zone: Vec<i64> = mesh.cell_zone.iter().map(|&z| z as i64).collect();
            let mut cell_data = vec![
                Field::vector("velocity", &fluid.velocity),
                Field::scalar("kinematic_pressure", &fluid.pressure),
                Field::scalar("alpha_c", &fluid.alpha),
                Field::int("zone", &zone),
            ];
            if let Some(f) = matching(&coupling.force_density, mesh.n_cells()) {
                cell_data.push(Field::vector("particle_force_density", f));
            }
            // the k–ε fields, and y⁺ of each wall cell (the largest over its wall faces; 0 away
            // from walls) so that ParaView shows where the wall functions are valid
            let wall_y_plus = state.fluid.as_ref().and_then(|f| f.turbulence.as_ref()).map(|t| {
                let mut cell = vec![0.0f64; mesh.n_cells()];
                for (index, y_plus) in t.y_plus.iter().enumerate() {
                    let owner = mesh.face_owner[mesh.n_internal_faces + index];
                    cell[owner] = cell[owner].max(*y_plus);
                }
                cell
            });
            if let (Some(t), Some(y_plus)) = (&fluid.turbulence, &wall_y_plus) {
                cell_data.push(Field::scalar("k", &t.k));
                cell_data.push(Field::scalar("epsilon", &t.epsilon));
                cell_data.push(Field::scalar("nu_t", &t.nu_t));
                cell_data.push(Field::scalar("y_plus", y_plus));
            }
            let values = points.len() * 3 + numbers(&cell_data);
            let grid = UnstructuredGrid { points: &points, cells: &cells, point_data: vec![], cell_data };
            let encoding = Encoding::by_size(values, BINARY_ABOVE);
            vtk::write_vtu(&self.dir.join(&name), &grid, encoding)?;
            Self::collection(&mut self.fluid, out.join("fluid.pvd"), self.resume_time)?.add(state.time, &format!("vtk/{name}"))?;
        }
        if let Some(particles) = &state.particles {
            let name = format!("particles_{step:08}.vtp");
            let ps = &particles.particles;
            let centres: Vec<[f64; 3]> = ps.iter().map(|p| p.position.into()).collect();
            let ids: Vec<i64> = ps.iter().map(|p| p.id as i64).collect();
            let diameter: Vec<f64> = ps.iter().map(|p| p.diameter).collect();
            let velocity: Vec<[f64; 3]> = ps.iter().map(|p| p.velocity.into()).collect();
            let spin: Vec<[f64; 3]> = ps.iter().map(|p| p.spin.into()).collect();
            let contacts: Vec<i64> = ps.iter().map(|p| i64::from(p.contacts)).collect();
            let mut fields = vec![
                Field::int("id", &ids),
                Field::scalar("diameter", &diameter),
                Field::vector("velocity", &velocity),
                Field::vector("angular_velocity", &spin),
                Field::int("contacts", &contacts),
            ];
            if let Some(u) = matching(&coupling.fluid_velocity, ps.len()) {
                fields.push(Field::vector("fluid_velocity", u));
            }
            if let Some(f) = matching(&coupling.drag_force, ps.len()) {
                fields.push(Field::vector("drag_force", f));
            }
            if let Some(re) = matching(&coupling.slip_reynolds, ps.len()) {
                fields.push(Field::scalar("slip_reynolds", re));
            }
            let values = centres.len() * 3 + numbers(&fields);
            let poly = PolyData::particles(&centres, fields);
            vtk::write_vtp(&self.dir.join(&name), &poly, Encoding::by_size(values, BINARY_ABOVE))?;
            Self::collection(&mut self.particles, out.join("particles.pvd"), self.resume_time)?.add(state.time, &format!("vtk/{name}"))?;
        }
        if let Some(walls) = state.walls.as_ref().filter(|w| !w.walls.is_empty()) {
            let name = format!("walls_{step:08}.vtp");
            let mut points = Vec::new();
            let mut triangles = Vec::new();
            let mut wall_index = Vec::new();
            let mut wear = WallWearFields::default();
            for (w, wall) in walls.walls.iter().enumerate() {
                let base = points.len();
                points.extend(wall.vertices.iter().map(|&v| <[f64; 3]>::from(wall.to_world(v))));
                for t in &wall.triangles {
                    triangles.push(t.map(|i| base + i as usize));
                    wall_index.push(w as i64);
                }
                if let Some(state) = &state.wear {
                    wear.push(state.walls.iter().find(|x| x.wall == w), wall);
                }
            }
            let mut cell_data = vec![Field::int("wall", &wall_index)];
            let mut point_data = vec![];
            if state.wear.is_some() {
                cell_data.extend([
                    Field::scalar("wear_depth", &wear.depth),
                    Field::scalar("wear_rate", &wear.rate),
                    Field::scalar("wear_volume", &wear.volume),
                    Field::int("impacts", &wear.impacts),
                ]);
                point_data.push(Field::scalar("wear_depth", &wear.vertex_depth));
            }
            let poly = PolyData { points: &points, cells: PolyCells::Triangles(&triangles), point_data, cell_data };
            vtk::write_vtp(&self.dir.join(&name), &poly, Encoding::by_size(points.len() * 3 + triangles.len() * 4, BINARY_ABOVE))?;
            Self::collection(&mut self.walls, out.join("walls.pvd"), self.resume_time)?.add(state.time, &format!("vtk/{name}"))?;
        }
        Ok(())
    }
}

/// The wear fields of the walls' `.vtp`: per triangle the depth receded [m] and the recession
/// rate [m/s] (node values averaged over its corners; accelerated, as the wall moves), the
/// volume deposited on it [m³] and its impacts; per vertex the depth. Walls that do not erode
/// get zeros.
#[derive(Default)]
struct WallWearFields {
    depth: Vec<f64>,
    rate: Vec<f64>,
    volume: Vec<f64>,
    impacts: Vec<i64>,
    vertex_depth: Vec<f64>,
}

impl WallWearFields {
    fn push(&mut self, wear: Option<&spillage_model::wear::state::WallWear>, wall: &spillage_model::walls::state::Wall) {
        match wear {
            Some(w) => {
                self.depth.extend(w.on_triangles(&w.node_depth, &wall.triangles));
                self.rate.extend(w.on_triangles(&w.node_rate, &wall.triangles));
                self.volume.extend(&w.triangle_volume);
                self.impacts.extend(w.triangle_impacts.iter().map(|&n| n as i64));
                self.vertex_depth.extend(w.at_vertices(&w.node_depth));
            }
            None => {
                let n = wall.triangles.len();
                self.depth.extend(std::iter::repeat(0.0).take(n));
                self.rate.extend(std::iter::repeat(0.0).take(n));
                self.volume.extend(std::iter::repeat(0.0).take(n));
                self.impacts.extend(std::iter::repeat(0).take(n));
                self.vertex_depth.extend(std::iter::repeat(0.0).take(wall.vertices.len()));
            }
        }
    }
}

//! The particles as struct-of-arrays, in cell order: copied in from the state (sorted by id)
//! at the start of a step, sorted so that neighbours in space are neighbours in memory, and
//! copied back in the state's order at its end.

use spillage_model::particles::state::Vec3;
use spillage_model::particles::Particle;

/// Every per-particle quantity the sub-steps touch, indexed by the internal (cell) order.
#[derive(Default)]
pub struct ParticleArrays {
    /// Index in `ParticleState::particles` of each internal particle.
    pub state_index: Vec<usize>,
    pub id: Vec<u64>,
    pub material: Vec<usize>,
    pub diameter: Vec<f64>,
    pub density: Vec<f64>,
    /// r = d/2, m, I₀ and V as [`Particle`]'s methods compute them (the same bits).
    pub radius: Vec<f64>,
    pub mass: Vec<f64>,
    pub inertia: Vec<f64>,
    pub volume: Vec<f64>,
    pub position: Vec<Vec3>,
    pub velocity: Vec<Vec3>,
    pub spin: Vec<Vec3>,
    pub force: Vec<Vec3>,
    pub torque: Vec<Vec3>,
    pub contacts: Vec<u32>,
}

impl ParticleArrays {
    pub fn len(&self) -> usize {
        self.id.len()
    }

    pub fn is_empty(&self) -> bool {
        self.id.is_empty()
    }

    /// Loads `particles` in the order of the cells of width `cell` (x fastest), ties by id,
    /// reusing the arrays' memory.
    pub fn load(&mut self, particles: &[Particle], cell: f64) {
        let keys = cell_keys(particles.iter().map(|p| p.position), cell);
        self.state_index.clear();
        self.state_index.extend(0..particles.len());
        self.state_index.sort_unstable_by_key(|&i| (keys[i], i));
        let order = &self.state_index;
        macro_rules! fill {
            ($field:ident, $value:expr) => {{
                self.$field.clear();
                self.$field.extend(order.iter().map(|&i| {
                    let p = &particles[i];
                    $value(p)
                }));
            }};
        }
        fill!(id, |p: &Particle| p.id);
        fill!(material, |p: &Particle| p.material);
        fill!(diameter, |p: &Particle| p.diameter);
        fill!(density, |p: &Particle| p.density);
        fill!(radius, |p: &Particle| p.radius());
        fill!(mass, |p: &Particle| p.mass());
        fill!(inertia, |p: &Particle| p.moment_of_inertia());
        fill!(volume, |p: &Particle| p.volume());
        fill!(position, |p: &Particle| p.position);
        fill!(velocity, |p: &Particle| p.velocity);
        fill!(spin, |p: &Particle| p.spin);
        fill!(force, |p: &Particle| p.contact_force);
        fill!(torque, |p: &Particle| p.contact_torque);
        fill!(contacts, |p: &Particle| p.contacts);
    }

    /// Writes the moving quantities back into `particles` (the slice they were loaded from).
    pub fn store(&self, particles: &mut [Particle]) {
        for (k, &i) in self.state_index.iter().enumerate() {
            let p = &mut particles[i];
            p.position = self.position[k];
            p.velocity = self.velocity[k];
            p.spin = self.spin[k];
            p.contact_force = self.force[k];
            p.contact_torque = self.torque[k];
            p.contacts = self.contacts[k];
        }
    }

    /// Particle `k` as the shared model functions take it (for the rare events: first
    /// touches, faults), without its contact force, torque and count (being evaluated).
    pub fn particle(&self, k: usize) -> Particle {
        self.properties().particle(k, self.position[k], self.velocity[k], self.spin[k])
    }

    /// What the particles are, apart from how they move: read while a pass moves them.
    pub fn properties(&self) -> ParticleProperties<'_> {
        ParticleProperties { id: &self.id, material: &self.material, diameter: &self.diameter, density: &self.density, radius: &self.radius, mass: &self.mass }
    }
}

/// The arrays of [`ParticleArrays`] a sub-step does not change, borrowed apart from the moving
/// ones (a pass that evaluates a particle's wall contacts just before it moves it reads these
/// for the whole bed while each thread writes the positions of its own block).
#[derive(Clone, Copy)]
pub struct ParticleProperties<'a> {
    pub id: &'a [u64],
    pub material: &'a [usize],
    pub diameter: &'a [f64],
    pub density: &'a [f64],
    pub radius: &'a [f64],
    pub mass: &'a [f64],
}

impl ParticleProperties<'_> {
    /// Particle `k` at this motion, as [`ParticleArrays::particle`] gives it.
    pub fn particle(&self, k: usize, position: Vec3, velocity: Vec3, spin: Vec3) -> Particle {
        Particle {
            id: self.id[k],
            material: self.material[k],
            diameter: self.diameter[k],
            density: self.density[k],
            position,
            velocity,
            spin,
            contact_force: Vec3::zeros(),
            contact_torque: Vec3::zeros(),
            contacts: 0,
        }
    }
}

/// Linear cell index of each point on a [`Grid`] of width `cell` spanning the points.
pub fn cell_keys(points: impl Iterator<Item = Vec3> + Clone, cell: f64) -> Vec<u64> {
    let grid = Grid::spanning(points.clone(), cell);
    points.map(|p| grid.key(grid.cell_of(p))).collect()
}

/// A grid of cubic cells over the bounding box of some points, with one empty cell of margin
/// on each side (neighbour lookups never wrap); keys are linear with x fastest, so a row of
/// three neighbouring cells is one range of keys.
#[derive(Clone, Copy, Debug)]
pub struct Grid {
    lo: Vec3,
    cell: f64,
    pub dims: [u64; 3],
}

/// Most cells along an axis: a cloud spread over kilometres gets wider cells (any width of at
/// least the contact reach finds every contact) instead of keys that overflow.
const MAX_CELLS_PER_AXIS: f64 = (1u64 << 20) as f64;

impl Grid {
    /// Cells at least `cell` wide over the bounding box of `points`.
    pub fn spanning(points: impl Iterator<Item = Vec3>, cell: f64) -> Grid {
        let mut lo = Vec3::repeat(f64::INFINITY);
        let mut hi = Vec3::repeat(f64::NEG_INFINITY);
        for p in points {
            lo = lo.inf(&p);
            hi = hi.sup(&p);
        }
        let extent = (hi - lo).max();
        let cell = if extent.is_finite() { cell.max(extent / MAX_CELLS_PER_AXIS) } else { cell };
        let dims = [0, 1, 2].map(|a| (((hi[a] - lo[a]) / cell).floor().clamp(0.0, MAX_CELLS_PER_AXIS) as u64) + 3);
        Grid { lo, cell, dims }
    }

    /// The cell (1-based: cell 0 is the margin) holding `p`; points outside the box (or not
    /// finite) go to the nearest cell of the box.
    pub fn cell_of(&self, p: Vec3) -> [u64; 3] {
        [0, 1, 2].map(|a| ((p[a] - self.lo[a]) / self.cell).floor().clamp(0.0, (self.dims[a] - 3) as f64) as u64 + 1)
    }

    pub fn key(&self, c: [u64; 3]) -> u64 {
        (c[2] * self.dims[1] + c[1]) * self.dims[0] + c[0]
    }
}

//! Step 1 of wear: impacts → removed volume on the triangle hit and its nodes (wear-model.md
//! §5.3, §6, §7.1, §7.3 "per-face accumulation"), in parallel with a fixed summation order.
//!
//! The order of every sum is that of the impacts, not of the threads:
//! - the wall's totals (deposited volume, the law's parts) are summed over its impacts in time
//!   order, as the reference phase does: the same bits;
//! - each triangle sums its own impacts in time order (a stable counting sort groups them), so
//!   its volume has the reference's bits too;
//! - each node gathers the shares of its triangle corners in triangle order (one addition
//!   order for any number of threads; the reference adds in impact order instead, so node
//!   volumes agree to round-off).

use spillage_model::particles::ImpactRecord;
use spillage_model::walls::state::Vec3;
use spillage_model::wear::laws::{ErosionLaw, ImpactInput};
use spillage_model::wear::state::{WallWear, ANGLE_BINS, SPEED_BINS};
use spillage_model::wear::surface::{barycentric_weights, WearSurface};

use super::topology::Topology;
use crate::linear::{par_range, par_update, Out};

/// One impact's contribution, computed independently of the others.
#[derive(Clone, Copy, Debug, Default)]
struct Booking {
    /// Deposited volume [m³] and the law's parts (per real particle, unscaled).
    volume: f64,
    cutting: f64,
    deformation: f64,
    /// Hat functions of the triangle's corners at the contact point.
    phi: [f64; 3],
    angle_bin: u8,
    speed_bin: u8,
    /// Sliding wear's equivalent impact: deposits, but is not counted as an impact.
    sliding: bool,
}

/// Work arrays of the deposit (sized once; the impact lists grow to the largest step seen).
pub struct DepositWork {
    /// Indices into the step's impacts of those on this wall, in time order.
    mine: Vec<u32>,
    bookings: Vec<Booking>,
    /// Counting sort by triangle: triangle t's impacts are `order[start[t]..start[t + 1]]`
    /// (positions in `mine`, ascending).
    start: Vec<u32>,
    order: Vec<u32>,
    /// Per triangle: Σ volume·φ_k over its impacts of this step, corner k.
    corner: Vec<[f64; 3]>,
    /// Deposited volume per node this step [m³] (Σ_i modifier·A·W_i φ_j(x_i)).
    pub node_volume: Vec<f64>,
}

impl DepositWork {
    pub fn new(surface: &WearSurface) -> Self {
        let n_triangles = surface.triangles.len();
        DepositWork {
            mine: Vec::new(),
            bookings: Vec::new(),
            start: vec![0; n_triangles + 1],
            order: Vec::new(),
            corner: vec![[0.0; 3]; n_triangles],
            node_volume: vec![0.0; surface.n_nodes],
        }
    }
}

/// Books the impacts on wall `w` (the others are skipped) and returns how many there were
/// (sliding wear's equivalent impacts deposit but do not count). The
/// impact speed is the particle centre's speed relative to the wall surface and the angle is
/// measured from the surface (§5.3): both taken at first touch by the DEM. An impact on a
/// triangle the wall does not have is an error (an impact log of another mesh).
#[allow(clippy::too_many_arguments)]
pub fn deposit(
    law: &ErosionLaw,
    scale: f64,
    max_speed: f64,
    surface: &WearSurface,
    topology: &Topology,
    nodes: &[Vec3],
    impacts: &[ImpactRecord],
    w: &mut WallWear,
    work: &mut DepositWork,
) -> Result<u64, String> {
    let n_triangles = surface.triangles.len();
    let DepositWork { mine, bookings, start, order, corner, node_volume } = work;
    mine.clear();
    for (k, impact) in impacts.iter().enumerate() {
        if impact.wall as usize == w.wall {
            if impact.triangle as usize >= n_triangles {
                return Err(format!("wall `{}`: an impact on triangle {} of {n_triangles}", w.name, impact.triangle));
            }
            mine.push(k as u32);
        }
    }
    match mine.first() {
        Some(&first) if w.material_side == 0.0 => {
            // an open wall: the material is on the side the particles move into
            let impact = &impacts[first as usize];
            let [a, b, c] = surface.triangles[impact.triangle as usize].map(|n| nodes[n as usize]);
            let side = impact.normal.dot(&(b - a).cross(&(c - a)));
            w.material_side = if side < 0.0 { -1.0 } else { 1.0 };
        }
        _ => {}
    }

    // the law, once per impact (independent: in parallel)
    bookings.resize(mine.len(), Booking::default());
    par_update(bookings, |k, booking| {
        let impact = &impacts[mine[k] as usize];
        let [a, b, c] = surface.triangles[impact.triangle as usize].map(|n| nodes[n as usize]);
        let speed = impact.normal_speed.hypot(impact.tangential_speed);
        let angle = impact.angle.clamp(0.0, std::f64::consts::FRAC_PI_2);
        let removed = law.removed_volume(&ImpactInput { speed, angle, mass: impact.mass, diameter: impact.diameter, density: impact.density });
        *booking = Booking {
            volume: scale * removed.total(),
            cutting: removed.cutting,
            deformation: removed.deformation,
            phi: barycentric_weights(a, b, c, impact.point),
            angle_bin: ((angle / std::f64::consts::FRAC_PI_2 * ANGLE_BINS as f64) as usize).min(ANGLE_BINS - 1) as u8,
            speed_bin: ((speed / max_speed * SPEED_BINS as f64) as usize).min(SPEED_BINS - 1) as u8,
            sliding: impact.sliding,
        };
    });
    // the wall's totals in time order (a few additions per impact: not worth a thread)
    for b in bookings.iter() {
        w.law_cutting += b.cutting;
        w.law_deformation += b.deformation;
        w.deposited += b.volume;
        if b.sliding {
            w.sliding_deposited += b.volume;
        }
    }

    // group by triangle, keeping time order within a triangle
    start.iter_mut().for_each(|s| *s = 0);
    for &k in mine.iter() {
        start[impacts[k as usize].triangle as usize + 1] += 1;
    }
    for t in 0..n_triangles {
        start[t + 1] += start[t];
    }
    order.resize(mine.len(), 0);
    for (k, &i) in mine.iter().enumerate() {
        let slot = &mut start[impacts[i as usize].triangle as usize];
        order[*slot as usize] = k as u32;
        *slot += 1;
    }
    // the fill moved every start one triangle on: shift back
    for t in (1..=n_triangles).rev() {
        start[t] = start[t - 1];
    }
    start[0] = 0;

    // each triangle books its own impacts (disjoint writes)
    let volume = Out::of(&mut w.triangle_volume);
    let count = Out::of(&mut w.triangle_impacts);
    let angles = Out::of(&mut w.angle_histogram);
    let speeds = Out::of(&mut w.speed_histogram);
    let corners = Out::of(corner);
    let (start, order, bookings) = (&*start, &*order, &*bookings);
    par_range(n_triangles, |t| {
        let mine = &order[start[t] as usize..start[t + 1] as usize];
        let mut shares = [0.0; 3];
        if !mine.is_empty() {
            // SAFETY: entries of triangle t (its volume, count and histogram rows, its corner
            // shares) are written by this task only; the arrays were sized in `FastWear::new`
            unsafe {
                let mut v = *volume.ptr(t);
                let mut impacts = 0;
                for &k in mine {
                    let b = &bookings[k as usize];
                    v += b.volume;
                    if !b.sliding {
                        *angles.ptr(t * ANGLE_BINS + b.angle_bin as usize) += 1;
                        *speeds.ptr(t * SPEED_BINS + b.speed_bin as usize) += 1;
                        impacts += 1;
                    }
                    for (s, phi) in shares.iter_mut().zip(b.phi) {
                        *s += b.volume * phi;
                    }
                }
                volume.set(t, v);
                *count.ptr(t) += impacts;
            }
        }
        // SAFETY: as above
        unsafe { corners.set(t, shares) };
    });
    let corner = &*corner;
    par_update(node_volume, |j, v| *v = topology.corners(j).iter().map(|&c| corner[c as usize / 3][c as usize % 3]).sum());
    Ok(bookings.iter().filter(|b| !b.sliding).count() as u64)
}

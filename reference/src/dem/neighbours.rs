//! Neighbour search: a cell list with cells as wide as the largest particle, so every pair in
//! contact (centre distance < r_i + r_j ≤ d_max) lies in the same or an adjacent cell, whatever
//! the size distribution.

use std::collections::BTreeMap;

use spillage_model::particles::Particle;

/// Index pairs (i < j) of particles whose spheres overlap, in ascending order.
pub fn overlapping_pairs(particles: &[Particle]) -> Vec<(usize, usize)> {
    let Some(cell) = particles.iter().map(|p| p.diameter).reduce(f64::max) else {
        return Vec::new();
    };
    let key = |p: &Particle| -> [i64; 3] { [0, 1, 2].map(|k| (p.position[k] / cell).floor() as i64) };
    let mut cells: BTreeMap<[i64; 3], Vec<usize>> = BTreeMap::new();
    for (i, p) in particles.iter().enumerate() {
        cells.entry(key(p)).or_default().push(i);
    }
    let mut pairs = Vec::new();
    for (i, p) in particles.iter().enumerate() {
        let [cx, cy, cz] = key(p);
        for dx in -1..=1 {
            for dy in -1..=1 {
                for dz in -1..=1 {
                    let Some(members) = cells.get(&[cx + dx, cy + dy, cz + dz]) else { continue };
                    for &j in members {
                        if j > i {
                            let q = &particles[j];
                            if (q.position - p.position).norm() < p.radius() + q.radius() {
                                pairs.push((i, j));
                            }
                        }
                    }
                }
            }
        }
    }
    pairs.sort_unstable();
    pairs
}

#[cfg(test)]
mod tests {
    use super::*;
    use spillage_model::particles::random::SplitMix64;
    use spillage_model::particles::state::Vec3;

    /// The cell list finds exactly the pairs that all-pairs finds, for a wide size range.
    #[test]
    fn cell_list_matches_all_pairs_for_polydisperse_spheres() {
        let mut random = SplitMix64::new(7);
        let particles: Vec<Particle> = (0..300)
            .map(|id| Particle {
                id,
                material: 0,
                diameter: random.uniform(0.01, 0.1),
                density: 1.0,
                position: Vec3::new(random.uniform(-0.3, 0.3), random.uniform(-0.3, 0.3), random.uniform(-0.3, 0.3)),
                velocity: Vec3::zeros(),
                spin: Vec3::zeros(),
                contact_force: Vec3::zeros(),
                contact_torque: Vec3::zeros(),
                contacts: 0,
            })
            .collect();
        let mut brute = Vec::new();
        for i in 0..particles.len() {
            for j in i + 1..particles.len() {
                if (particles[j].position - particles[i].position).norm() < particles[i].radius() + particles[j].radius() {
                    brute.push((i, j));
                }
            }
        }
        assert!(brute.len() > 50);
        assert_eq!(overlapping_pairs(&particles), brute);
    }
}

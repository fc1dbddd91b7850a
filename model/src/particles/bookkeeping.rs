//! Particle bookkeeping shared by every particle phase: feeding new particles at an inlet region
//! and classifying the ones that leave (DESIGN.md "Particles", "Spillage bookkeeping").
//!
//! Every particle ever created is either in [`ParticleState::particles`] or in
//! [`ParticleState::exits`], so `created = particles.len() + exits.len()` at every step.

use serde::{Deserialize, Serialize};

use super::initial::{new_particle, place_without_overlap};
use super::settings::{Diameter, ParticlesSection};
use super::state::{ParticleState, Partner, Vec3};

/// Where a particle left the domain.
#[derive(Clone, Debug, PartialEq, Eq, Serialize, Deserialize)]
pub enum ExitRoute {
    /// Its centre left the box `[particles] domain`.
    Domain,
    /// Its centre left the fluid mesh through the named boundary patch (the patch of the
    /// boundary face nearest to its last position).
    Patch(String),
    /// Its centre rose into a cutter head's suction pipe (`capture_height` above the mouth).
    Sucked,
    /// Its centre left a cutter head's contour hull (spillage, Eq. 8.6).
    Spilled,
}

/// One particle that left, with when and where.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct ExitRecord {
    pub particle: u64,
    /// End of the step in which it left [s].
    pub time: f64,
    pub position: [f64; 3],
    pub velocity: [f64; 3],
    pub diameter: f64,
    pub route: ExitRoute,
}

/// Creates the particles owed by each feed for a step of `dt` from `time`: the rate times the
/// part of [time, time + dt] inside the feed's [start, end) accumulates as a debt and whole
/// particles are placed at random in the feed's region, never overlapping other particles and
/// only where `clear(centre, radius)` says the sphere is clear of the walls (a cutter head's
/// blades, spillage-and-flow-verification.md §6.1 item 1); a particle that cannot be placed now
/// stays owed. Returns how many were created.
pub fn feed(section: &ParticlesSection, state: &mut ParticleState, time: f64, dt: f64, clear: impl Fn(&Vec3, f64) -> bool) -> u64 {
    let mut created = 0;
    for (f, feed) in section.feed.iter().enumerate() {
        let active = (time + dt).min(feed.end.unwrap_or(f64::INFINITY)) - time.max(feed.start);
        if active <= 0.0 {
            continue;
        }
        state.feed_debt[f] += feed.rate * active;
        let material = section.material_index(&feed.material).expect("validated feed material");
        while state.feed_debt[f] >= 1.0 {
            let d = match feed.diameter {
                Diameter::Fixed(d) => d,
                Diameter::Uniform { min, max } => state.feed_random[f].uniform(min, max),
            };
            let mut random = state.feed_random[f].clone();
            let Some(position) = place_without_overlap(&feed.region, d, &state.particles, &mut random, &clear) else { break };
            state.feed_random[f] = random;
            let shape = feed.velocity_profile.as_ref().map_or(1.0, |p| p.factor([position.x, position.y, position.z]));
            let particle = new_particle(section, state, material, d, position, shape * Vec3::from(feed.velocity));
            state.particles.push(particle);
            state.counts.created += 1;
            state.feed_debt[f] -= 1.0;
            created += 1;
        }
    }
    created
}

/// Removes the particles for which `route` names an exit, logs them with `time`, drops their
/// contact history and their entries of `load` (which is per particle, in particle order).
/// Particle order (by id) is kept. `route` is called once per particle, in particle order.
/// Returns how many left.
pub fn remove_exited(
    state: &mut ParticleState,
    load: Option<&mut crate::step::ParticleLoad>,
    time: f64,
    mut route: impl FnMut(&super::Particle) -> Option<ExitRoute>,
) -> u64 {
    let mut gone = Vec::new();
    let mut exits = Vec::new();
    let keep: Vec<bool> = state
        .particles
        .iter()
        .map(|p| match route(p) {
            Some(route) => {
                gone.push(p.id);
                exits.push(ExitRecord { particle: p.id, time, position: p.position.into(), velocity: p.velocity.into(), diameter: p.diameter, route });
                false
            }
            None => true,
        })
        .collect();
    if gone.is_empty() {
        return 0;
    }
    fn retain<T>(values: &mut Vec<T>, keep: &[bool]) {
        let mut index = 0;
        values.retain(|_| {
            index += 1;
            keep[index - 1]
        });
    }
    retain(&mut state.particles, &keep);
    if let Some(load) = load {
        retain(&mut load.volume, &keep);
        retain(&mut load.implicit_drag, &keep);
        retain(&mut load.explicit_force, &keep);
        retain(&mut load.drag, &keep);
        retain(&mut load.slip_reynolds, &keep);
    }
    if !gone.is_empty() {
        state.contacts.retain(|r| !gone.contains(&r.particle) && !matches!(r.partner, Partner::Particle(j) if gone.contains(&j)));
    }
    let n = gone.len() as u64;
    state.exits.extend(exits);
    n
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::particles::{ContactRecord, Particle};

    fn particle(id: u64, x: f64) -> Particle {
        Particle {
            id,
            material: 0,
            diameter: 0.01,
            density: 2650.0,
            position: Vec3::new(x, 0.0, 0.0),
            velocity: Vec3::new(1.0, 0.0, 0.0),
            spin: Vec3::zeros(),
            contact_force: Vec3::zeros(),
            contact_torque: Vec3::zeros(),
            contacts: 0,
        }
    }

    #[test]
    fn exits_are_logged_counted_and_lose_their_contacts() {
        let record = |a: u64, b: u64| ContactRecord {
            particle: a,
            partner: Partner::Particle(b),
            tangential_overlap: Vec3::zeros(),
            damping_ratio: 0.1,
            approach_speed: 1.0,
            normal: Vec3::x(),
            start_time: 0.0,
            restitution: 0.5,
            normal_impulse: 0.0,
        };
        let mut state = ParticleState {
            particles: vec![particle(0, 0.0), particle(1, 2.0), particle(2, 0.5)],
            contacts: vec![record(0, 1), record(0, 2)],
            ..Default::default()
        };
        state.counts.created = 3;
        let mut load = crate::step::ParticleLoad {
            volume: vec![1.0, 2.0, 3.0],
            implicit_drag: vec![0.1, 0.2, 0.3],
            explicit_force: vec![[0.0; 3], [1.0; 3], [2.0; 3]],
            drag: vec![[0.0; 3], [1.0; 3], [2.0; 3]],
            slip_reynolds: vec![1.0, 2.0, 3.0],
        };
        let n = remove_exited(&mut state, Some(&mut load), 1.5, |p| (p.position.x > 1.0).then_some(ExitRoute::Domain));
        assert_eq!(n, 1);
        assert_eq!(state.particles.iter().map(|p| p.id).collect::<Vec<_>>(), vec![0, 2]);
        assert_eq!(state.contacts.len(), 1);
        assert_eq!(state.exits.len(), 1);
        assert_eq!(state.exits[0].particle, 1);
        assert_eq!(state.exits[0].time, 1.5);
        assert_eq!(state.counts.created, state.particles.len() as u64 + state.exits.len() as u64);
        // the load follows its particles
        assert_eq!(load.volume, vec![1.0, 3.0]);
        assert_eq!(load.implicit_drag, vec![0.1, 0.3]);
        assert_eq!(load.explicit_force, vec![[0.0; 3], [2.0; 3]]);
    }

    /// A feed switched on or off inside a step owes only the part of the step it was on.
    #[test]
    fn a_feed_owes_the_part_of_the_step_it_is_on() {
        use crate::particles::settings::{BoxRegion, FeedSection};
        let text = r#"
[case]
name = "feed"
[time]
dt = 0.125
steps = 1
[particles]
[[particles.materials]]
name = "rock"
density = 2650.0
youngs_modulus = 1e7
poisson_ratio = 0.25
restitution = 0.5
friction = 0.5
[[particles.feed]]
material = "rock"
diameter = 0.01
region = { min = [0.0, 0.0, 0.0], max = [1.0, 1.0, 1.0] }
rate = 100.0
start = 0.0625
end = 0.3125
"#;
        let case = crate::case::Case::from_toml(text, std::path::Path::new("feed.toml")).unwrap();
        let section = case.particles.clone().unwrap();
        let _: (&BoxRegion, &FeedSection) = (&section.feed[0].region, &section.feed[0]);
        let mut state = crate::particles::initial_state(&case).unwrap();
        // (binary-exact times) [0, 0.125): on for 0.0625 s → 6.25 owed, 6 placed; [0.125, 0.25):
        // 12.5 + 0.25 → 12; [0.25, 0.375): 6.25 + 0.75 → 7; [0.375, 0.5): off. 25 = rate × 0.25 s.
        let created: Vec<u64> = [0.0, 0.125, 0.25, 0.375].iter().map(|&t| feed(&section, &mut state, t, 0.125, |_, _| true)).collect();
        assert_eq!(created, vec![6, 12, 7, 0]);
        assert_eq!(state.counts.created, 25);
        // walls that leave only x < 0.5 clear: every new particle lands there, none is lost
        let mut state = crate::particles::initial_state(&case).unwrap();
        let clear = |p: &Vec3, r: f64| p.x + r < 0.5;
        let created: u64 = [0.0, 0.125, 0.25, 0.375].iter().map(|&t| feed(&section, &mut state, t, 0.125, clear)).sum();
        assert_eq!(created, 25);
        assert!(state.particles.iter().all(|p| clear(&p.position, p.radius())));
    }
}

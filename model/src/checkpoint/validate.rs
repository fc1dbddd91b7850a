//! A state read from a checkpoint is checked before any step: every number finite, every array
//! the size the case and the rest of the state say (issue 14: a payload replaced under a
//! recomputed checksum loaded a NaN time and failed only when the summary was written).
//!
//! The check is one pass over the state at a restart, never during a run.

use crate::case::{Case, MeshSection};
use crate::state::State;

/// The first thing wrong with `state` as a state of `case`, in words naming the field and the
/// cell, face or particle.
pub fn state_for_case(case: &Case, state: &State) -> Result<(), String> {
    // a frozen-rotor start-up runs before t = 0 (crate::fluid::frozen_rotor)
    let start = crate::fluid::frozen_rotor::StartUp::of_case(case).map_or(0.0, |s| s.start_time());
    scalar("time", state.time, start)?;
    scalar("dt", state.dt, 0.0)?;
    scalar("courant", state.courant, 0.0)?;
    if let Some(limit) = state.dt_limit {
        if !(limit.is_finite() && limit > 0.0) {
            return Err(format!("dt_limit = {limit} s: expected a finite step > 0"));
        }
    }
    if !state.rotor_angle.is_finite() {
        return Err(format!("rotor_angle = {} rad: expected a finite angle", state.rotor_angle));
    }
    if state.step > 0 && !(state.time > start && state.dt > 0.0) {
        return Err(format!("step {} at time {} s with dt {} s: a state after step 0 has t > {start} s and dt > 0", state.step, state.time, state.dt));
    }
    if let Some(fluid) = &state.fluid {
        let n = fluid.velocity.len();
        for (name, len) in [("velocity_old", fluid.velocity_old.len()), ("pressure", fluid.pressure.len()), ("alpha", fluid.alpha.len())] {
            same_size(name, len, n)?;
        }
        same_size("alpha_old", fluid.alpha_old.len(), n)?;
        same_size("alpha_old_old", fluid.alpha_old_old.len(), n)?;
        if !fluid.flux_old.is_empty() {
            same_size("flux_old (per face)", fluid.flux_old.len(), fluid.flux.len())?;
        }
        if fluid.boundary_pressure.len() > fluid.flux.len() {
            return Err(format!("fluid boundary_pressure has {} faces, more than the {} faces of flux", fluid.boundary_pressure.len(), fluid.flux.len()));
        }
        // A box with solid blocks has fewer cells than its `cells` product; a cutter head's
        // count follows from its generator: both are left to the fluid phase's exact mesh check.
        let expected = match &case.mesh {
            Some(MeshSection::Box { solids, .. }) if !solids.is_empty() => None,
            Some(mesh) => Some(mesh.cell_count()),
            None => None,
        };
        if let Some(cells) = expected.filter(|&c| c != n) {
            return Err(format!("the fluid state has {n} cells, the case's [mesh] makes {cells}"));
        }
        vectors("fluid velocity", "cell", &fluid.velocity)?;
        vectors("fluid velocity_old", "cell", &fluid.velocity_old)?;
        for (name, what, values) in [
            ("fluid pressure", "cell", &fluid.pressure),
            ("fluid alpha", "cell", &fluid.alpha),
            ("fluid alpha_old", "cell", &fluid.alpha_old),
            ("fluid alpha_old_old", "cell", &fluid.alpha_old_old),
            ("fluid flux", "face", &fluid.flux),
            ("fluid flux_old", "face", &fluid.flux_old),
            ("fluid boundary_pressure", "boundary face", &fluid.boundary_pressure),
        ] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!("{name} of {what} {i} is {}: expected a finite number", values[i]));
            }
        }
        if let Some(t) = &fluid.turbulence {
            for (name, values) in [("turbulence k", &t.k), ("turbulence epsilon", &t.epsilon), ("turbulence nu_t", &t.nu_t)] {
                same_size(name, values.len(), n)?;
                if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                    return Err(format!("fluid {name} of cell {i} is {}: expected a finite number", values[i]));
                }
            }
        }
        if !fluid.cumulative_continuity_error.is_finite() {
            return Err(format!("fluid cumulative_continuity_error is {}", fluid.cumulative_continuity_error));
        }
        for (name, values) in [("mesh_displacement", &fluid.mesh_displacement), ("mesh_displacement_old", &fluid.mesh_displacement_old)] {
            if let Some(i) = values.iter().position(|v| !v.is_finite()) {
                return Err(format!("fluid {name} of point {i} is {}: expected a finite number", values[i]));
            }
        }
    }
    let n_walls = state.walls.as_ref().map_or(0, |w| w.walls.len());
    if let (Some(section), Some(p)) = (&case.particles, &state.particles) {
        let materials = section.materials.len();
        let mut previous: Option<u64> = None;
        for q in &p.particles {
            let at = |what: &str| format!("particle {} at {:?}: {what}", q.id, [q.position.x, q.position.y, q.position.z]);
            if previous.is_some_and(|id| id >= q.id) {
                return Err(at("ids not increasing (the particle list is kept sorted by id)"));
            }
            previous = Some(q.id);
            if q.id >= p.next_id {
                return Err(at(&format!("id not below the next id {}", p.next_id)));
            }
            if q.material >= materials {
                return Err(at(&format!("material {} of the case's {materials} materials", q.material)));
            }
            if !(q.diameter.is_finite() && q.diameter > 0.0 && q.density.is_finite() && q.density > 0.0) {
                return Err(at(&format!("diameter {} m, density {} kg/m³: expected finite numbers > 0", q.diameter, q.density)));
            }
            for (name, v) in [
                ("position", &q.position),
                ("velocity", &q.velocity),
                ("spin", &q.spin),
                ("contact_force", &q.contact_force),
                ("contact_torque", &q.contact_torque),
            ] {
                if !v.iter().all(|x| x.is_finite()) {
                    return Err(at(&format!("{name} {:?} not finite", [v.x, v.y, v.z])));
                }
            }
        }
        if p.feed_debt.len() != section.feed.len() || p.feed_random.len() != section.feed.len() {
            return Err(format!("the state has {} feeds, the case {}", p.feed_debt.len(), section.feed.len()));
        }
        if let Some(d) = p.feed_debt.iter().find(|d| !d.is_finite()) {
            return Err(format!("a feed's debt is {d}: expected a finite number"));
        }
        for c in &p.contacts {
            let finite = c.tangential_overlap.iter().chain(c.normal.iter()).all(|x| x.is_finite())
                && c.damping_ratio.is_finite()
                && c.approach_speed.is_finite()
                && c.start_time.is_finite();
            if !finite {
                return Err(format!("the contact of particle {} with {:?} holds a non-finite value", c.particle, c.partner));
            }
            if let crate::particles::Partner::Wall(w) = c.partner {
                if w as usize >= n_walls {
                    return Err(format!("the contact of particle {} names wall {w}, but there are {n_walls} walls", c.particle));
                }
            }
        }
        // the DEM phases walk the history in this order (a new neighbour list's pieces start
        // their walks by bisection), and a pair's or wall's contact is kept once
        if let Some(w) = p.contacts.windows(2).find(|w| (w[0].particle, w[0].partner) >= (w[1].particle, w[1].partner)) {
            return Err(format!(
                "the contact history lists particle {} with {:?} before particle {} with {:?}: expected each contact once, sorted by particle, then partner",
                w[0].particle, w[0].partner, w[1].particle, w[1].partner
            ));
        }
        if let Some(e) = p.exits.iter().find(|e| !(e.time.is_finite() && e.position.iter().chain(&e.velocity).all(|x| x.is_finite()))) {
            return Err(format!("the exit record of particle {} holds a non-finite value", e.particle));
        }
    }
    if let (Some(section), Some(walls)) = (&case.particles, &state.walls) {
        let mut expected: Vec<String> = case.walls.iter().map(|w| w.name.clone()).collect();
        if let Some(head) = case.cutter_head.as_ref().filter(|h| h.material.is_some()) {
            expected.extend(crate::cutter_head::walls::head_wall_names(head));
        }
        let names: Vec<&str> = walls.walls.iter().map(|w| w.name.as_str()).collect();
        if names != expected.iter().map(|n| n.as_str()).collect::<Vec<_>>() {
            return Err(format!("the state has walls {names:?}, the case {expected:?}"));
        }
        for w in &walls.walls {
            if w.material >= section.materials.len() {
                return Err(format!("wall `{}` has material {} of the case's {}", w.name, w.material, section.materials.len()));
            }
            if let Some(i) = w.vertices.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
                return Err(format!("wall `{}` vertex {i} is not finite", w.name));
            }
            let n = w.vertices.len() as u32;
            if let Some(t) = w.triangles.iter().position(|t| t.iter().any(|&v| v >= n)) {
                return Err(format!("wall `{}` triangle {t} names a vertex beyond its {n} vertices", w.name));
            }
        }
    }
    if let Some(wear) = &state.wear {
        for w in &wear.walls {
            if w.wall >= n_walls {
                return Err(format!("the wear of wall `{}` names wall {}, but there are {n_walls} walls", w.name, w.wall));
            }
            let scalars = [w.material_side, w.deposited, w.law_cutting, w.law_deformation, w.sliding_deposited, w.receded, w.pending, w.initial_volume];
            if !(scalars.iter().chain(&w.volume_origin).chain(&w.triangle_volume).chain(&w.node_rate).chain(&w.node_depth).all(|x| x.is_finite())) {
                return Err(format!("the wear of wall `{}` holds a non-finite value", w.name));
            }
        }
    }
    Ok(())
}

fn scalar(name: &str, value: f64, min: f64) -> Result<(), String> {
    if value.is_finite() && value >= min {
        Ok(())
    } else {
        Err(format!("{name} = {value}: expected a finite number ≥ {min}"))
    }
}

fn same_size(name: &str, len: usize, cells: usize) -> Result<(), String> {
    if len == cells {
        Ok(())
    } else {
        Err(format!("fluid {name} has {len} entries, fluid velocity {cells}"))
    }
}

fn vectors(name: &str, what: &str, values: &[[f64; 3]]) -> Result<(), String> {
    match values.iter().position(|v| !v.iter().all(|x| x.is_finite())) {
        Some(i) => Err(format!("{name} of {what} {i} is {:?}: expected finite numbers", values[i])),
        None => Ok(()),
    }
}

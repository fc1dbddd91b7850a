//! The time-mean flow through the cutter head's contour at fixed places in the laboratory
//! (spillage-and-flow-verification.md §5.2): where the water leaves the head on average and
//! where it enters, with the blades' passing averaged out. The thesis describes its heads in
//! such terms ("the axial head has inflow over the whole contour at 20 rpm", the back-plate
//! head "outflow already at 20 rpm, far from the eccentric suction mouth"), from contour maps
//! (its Fig. 8.2) that the spec does not reproduce.
//!
//! Q_out of the mean flow, Σ pos(φ̄), differs from the mean of Q_out, (Σ pos(φ))‾ (Eq. 8.4
//! sampled and averaged, §5.1, the thesis' Fig. 8.1): each blade pushes water out through the
//! contour ahead of it and draws it in behind, which the mean of Q_out counts and the mean flow
//! does not. Σ pos(φ̄) ≤ (Σ pos(φ))‾ always.

use anyhow::{bail, Context, Result};
use spillage_model::cutter_head::hull_surface::{HullSurface, LaboratoryElement};
use spillage_model::cutter_head::spillage::EXIT_BIN;
use spillage_model::output::heat_map::{write_heat_map_png, HeatCell, HeatMapLabels};
use spillage_model::output::{format_f64, write_atomically, OutputError};
use std::path::Path;

/// The time-weighted mean of the contour's laboratory fluxes
/// ([`HullSurface::laboratory_fluxes`]).
#[derive(Clone, Debug)]
pub struct ContourMeanFlow {
    elements: Vec<LaboratoryElement>,
    points_around: usize,
    /// Σ φ dt per element [m³], and Σ dt [s].
    sums: Vec<f64>,
    weight: f64,
}

impl ContourMeanFlow {
    /// An empty mean over the laboratory elements of `surface`.
    pub fn new(surface: &HullSurface) -> Self {
        Self::of_elements(surface.laboratory_elements().collect(), surface.points_around())
    }

    fn of_elements(elements: Vec<LaboratoryElement>, points_around: usize) -> Self {
        let sums = vec![0.0; elements.len()];
        ContourMeanFlow { elements, points_around, sums, weight: 0.0 }
    }

    /// Adds one step's fluxes (one per element), weighted by its step size `dt`.
    pub fn add(&mut self, fluxes: &[f64], dt: f64) {
        debug_assert_eq!(fluxes.len(), self.sums.len(), "one flux per laboratory element");
        for (sum, phi) in self.sums.iter_mut().zip(fluxes) {
            *sum += phi * dt;
        }
        self.weight += dt;
    }

    fn means(&self) -> impl Iterator<Item = f64> + '_ {
        let w = self.weight;
        self.sums.iter().map(move |s| if w > 0.0 { s / w } else { 0.0 })
    }

    /// Q_out of the mean flow, Σ pos(φ̄) [m³/s], over the whole contour and over its top
    /// `EXIT_BIN` under the ring.
    pub fn outflow(&self) -> (f64, f64) {
        self.means()
            .zip(&self.elements)
            .filter(|(phi, _)| *phi > 0.0)
            .fold((0.0, 0.0), |(all, top), (phi, e)| (all + phi, top + if e.z >= -EXIT_BIN { phi } else { 0.0 }))
    }

    /// The fraction of the contour's area through which the mean flow leaves (0 for an empty
    /// contour).
    pub fn outflow_area_fraction(&self) -> f64 {
        let total: f64 = self.elements.iter().map(|e| e.area.norm()).sum();
        // folded from +0 (an empty f64 sum is −0)
        let out = self.means().zip(&self.elements).filter(|(phi, _)| *phi > 0.0).fold(0.0, |sum, (_, e)| sum + e.area.norm());
        if total > 0.0 {
            out / total
        } else {
            0.0
        }
    }

    /// Per azimuth (in the order of the elements around the axis): the depth under the ring
    /// [m] down to which the mean flow leaves, i.e. to the first element, going down from the
    /// ring, through which it enters (the whole contour's height where there is none).
    pub fn outflow_depths(&self) -> Vec<f64> {
        let n = self.points_around.max(1);
        let means: Vec<f64> = self.means().collect();
        let bottom = self.elements.iter().map(|e| -e.z).fold(0.0, f64::max);
        (0..n.min(self.elements.len())).map(|j| (j..self.elements.len()).step_by(n).find(|&i| means[i] < 0.0).map_or(bottom, |i| -self.elements[i].z)).collect()
    }

    /// The azimuth [rad, in −π…π] where the mean inflow reaches toward the ring: the weighted
    /// centre of the notch in the outflow zone under the ring, the circular mean of the
    /// azimuths weighted by how much shallower the outflow is there than where it is deepest.
    /// `None` when the outflow is equally deep all round. The thesis speaks of the centre of
    /// the "inflow region" of its contour maps, 30–45° from the eccentric mouth toward the
    /// under-cut side at 60 rpm (spillage-and-flow-verification.md §5.2); this is our reading
    /// of it (the depths come in steps of the surface's rings, 6.5 mm).
    pub fn inflow_centre(&self) -> Option<f64> {
        let depths = self.outflow_depths();
        let deepest = depths.iter().copied().fold(0.0, f64::max);
        let (x, y) =
            depths.iter().zip(&self.elements).fold((0.0, 0.0), |(x, y), (d, e)| (x + (deepest - d) * e.azimuth.cos(), y + (deepest - d) * e.azimuth.sin()));
        (x != 0.0 || y != 0.0).then(|| y.atan2(x))
    }

    /// Writes the map as CSV to `path`: per element its azimuth [°], height z [m], area [m²],
    /// mean flux φ̄ [m³/s] and mean outward velocity φ̄/|A| [m/s].
    fn write_csv(&self, path: &Path) -> Result<()> {
        use std::io::Write;
        if let Some((index, value)) = self.means().enumerate().find(|(_, m)| !m.is_finite()) {
            bail!(OutputError::NonFinite { path: path.to_path_buf(), field: "mean_flux".into(), index, value });
        }
        write_atomically(path, |out| {
            let io = |e: std::io::Error| OutputError::Io { path: path.to_path_buf(), source: e };
            writeln!(out, "azimuth_deg,z,area,mean_flux,mean_outward_velocity").map_err(io)?;
            for (phi, e) in self.means().zip(&self.elements) {
                let area = e.area.norm();
                let row = [e.azimuth.to_degrees(), e.z, area, phi, phi / area].map(format_f64).join(",");
                writeln!(out, "{row}").map_err(io)?;
            }
            Ok(())
        })?;
        Ok(())
    }

    /// Draws the mean outward velocity φ̄/|A| (normal to the contour) over the unrolled contour, azimuth in the
    /// laboratory against height, to `dir/name.png`, with its numbers in `dir/name.csv`.
    pub fn draw(&self, dir: &Path, name: &str, title: &str) -> Result<()> {
        std::fs::create_dir_all(dir).with_context(|| format!("cannot create {}", dir.display()))?;
        let n = self.points_around.max(1);
        let dtheta = 360.0 / n as f64;
        let bands = ring_bands(&self.elements.iter().step_by(n).map(|e| e.z).collect::<Vec<_>>());
        let cells: Vec<HeatCell> = self
            .means()
            .zip(&self.elements)
            .enumerate()
            .map(|(i, (phi, e))| {
                let degrees = e.azimuth.to_degrees();
                HeatCell { x: (degrees - 0.5 * dtheta, degrees + 0.5 * dtheta), y: bands[i / n], value: phi / e.area.norm() }
            })
            .collect();
        let labels = HeatMapLabels {
            title,
            x: "azimuth in the laboratory [°] (0 = +x, turning with +z)",
            y: "height z [m] (ring at 0)",
            value: "mean outward velocity [m/s]",
        };
        write_heat_map_png(&labels, &cells, &dir.join(format!("{name}.png")))?;
        self.write_csv(&dir.join(format!("{name}.csv")))
    }
}

/// The height band (lower, upper) [m] each ring of heights `rings` (ring to hub) covers on the
/// map: halfway to its neighbours, the end rings as far beyond as halfway to their one
/// neighbour (5 mm each way for a lone ring).
fn ring_bands(rings: &[f64]) -> Vec<(f64, f64)> {
    let middles: Vec<f64> = rings.windows(2).map(|w| 0.5 * (w[0] + w[1])).collect();
    let (first, last) = (middles.first().map_or(0.005, |m| rings[0] - m), middles.last().map_or(0.005, |m| m - rings[rings.len() - 1]));
    (0..rings.len())
        .map(|k| {
            let above = if k == 0 { rings[0] + first } else { middles[k - 1] };
            let below = if k + 1 == rings.len() { rings[k] - last } else { middles[k] };
            (below, above)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Two rings of two elements, the upper in the top bin: a blade-like pattern that swaps
    /// out- and inflow between two equal steps has outflow at every instant and none on
    /// average; a steady outflow through one element stays, weighted by the step sizes.
    #[test]
    fn the_mean_flow_leaves_out_what_passes_and_keeps_what_stays() {
        let element = |z: f64, azimuth: f64, area: f64| LaboratoryElement { z, radius: 0.3, azimuth, area: spillage_model::mesh::Vec3::new(area, 0.0, 0.0) };
        let elements = vec![element(-0.01, 1.0, 2.0), element(-0.01, 4.0, 2.0), element(-0.2, 1.0, 1.0), element(-0.2, 4.0, 1.0)];
        let mut passing = ContourMeanFlow::of_elements(elements.clone(), 2);
        passing.add(&[0.3, -0.3, -0.1, -0.1], 0.5);
        passing.add(&[-0.3, 0.3, -0.1, -0.1], 0.5);
        assert_eq!(passing.outflow(), (0.0, 0.0));
        assert_eq!(passing.outflow_area_fraction(), 0.0);
        let mut steady = ContourMeanFlow::of_elements(elements, 2);
        steady.add(&[0.3, -0.3, 0.4, -0.1], 1.0);
        steady.add(&[0.0, -0.3, 0.1, -0.1], 3.0);
        // element 0: (0.3 + 0) / 4; element 2: (0.4 + 0.3) / 4
        // 1e-15 and 1e-12 (the atan2 of summed sines and cosines): round-off of a few terms
        let (all, top) = steady.outflow();
        assert!((all - 0.25).abs() < 1e-15 && (top - 0.075).abs() < 1e-15, "{all} {top}");
        assert!((steady.outflow_area_fraction() - 0.5).abs() < 1e-15);
        // the water leaves down to the lower ring at azimuth 1 (element 2 is outflow too, so
        // the whole height) and enters at the ring at azimuth 4: the notch is there
        assert_eq!(steady.outflow_depths(), vec![0.2, 0.01]);
        assert!((steady.inflow_centre().unwrap() - (4.0 - std::f64::consts::TAU)).abs() < 1e-12);
        // the passing pattern's mean enters nowhere under the ring and everywhere below it:
        // equally deep all round
        assert_eq!(passing.inflow_centre(), None);
    }

    /// The map's bands tile the contour's height without gaps: each ends where the next begins.
    #[test]
    fn ring_bands_tile_the_height() {
        // 1e-15: sums of a few centimetres
        let close = |a: Vec<(f64, f64)>, b: Vec<(f64, f64)>| {
            a.len() == b.len() && a.iter().zip(&b).all(|(p, q)| (p.0 - q.0).abs() < 1e-15 && (p.1 - q.1).abs() < 1e-15)
        };
        assert!(close(ring_bands(&[-0.01, -0.03, -0.07]), vec![(-0.02, 0.0), (-0.05, -0.02), (-0.09, -0.05)]));
        assert!(close(ring_bands(&[-0.2]), vec![(-0.205, -0.195)]));
    }
}

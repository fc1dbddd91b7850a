//! TEMPORARY stand-in for the erosion laws (replaced by the wear-laws branch).
use super::settings::WearSection;
use crate::case::FieldError;

#[derive(Clone, Copy, Debug, PartialEq)]
pub struct ImpactInput {
    pub speed: f64,
    pub angle: f64,
    pub mass: f64,
    pub diameter: f64,
    pub density: f64,
}
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RemovedVolume {
    pub cutting: f64,
    pub deformation: f64,
}
impl RemovedVolume {
    pub fn total(&self) -> f64 {
        self.cutting + self.deformation
    }
}
#[derive(Clone, Debug, PartialEq)]
pub struct ErosionLaw {
    c: super::settings::MaterialConstants,
}
impl ErosionLaw {
    pub fn from_section(section: &WearSection) -> Result<ErosionLaw, FieldError> {
        Ok(ErosionLaw { c: section.material.constants()? })
    }
    pub fn removed_volume(&self, i: &ImpactInput) -> RemovedVolume {
        let c = &self.c;
        let theta = i.angle.clamp(0.0, std::f64::consts::FRAC_PI_2);
        let k = c.contact_ratio;
        let f = if theta <= k.atan() {
            (k * (2.0 * theta).sin() - theta.sin().powi(2)) / (2.0 * k * k)
        } else {
            (std::f64::consts::FRAC_PI_2 - theta).sin().powi(2)
        };
        let pre = i.mass * c.sharpness / 2.0;
        RemovedVolume {
            cutting: pre * c.cutting_coefficient * i.speed.powf(2.41) * f / c.vickers_hardness.sqrt(),
            deformation: pre * (i.speed * theta.sin() - c.threshold_velocity).max(0.0).powi(2) / c.deformation_factor,
        }
    }
    pub fn wall_density(&self) -> f64 {
        self.c.density
    }
    pub fn name(&self) -> &'static str {
        "arabnejad"
    }
}

//! Test helpers shared by the erosion-law tests: a `[wear]` section and its law from TOML text.

use super::laws::ErosionLaw;
use super::settings::WearSection;

pub fn section(text: &str) -> WearSection {
    toml::from_str(text).unwrap()
}

pub fn law(text: &str) -> ErosionLaw {
    ErosionLaw::from_section(&section(text)).unwrap()
}

/// The Arabnejad law on a material `preset`, with `extra` lines of the `[wear]` table.
pub fn arabnejad(preset: &str, extra: &str) -> ErosionLaw {
    law(&format!("law = \"arabnejad\"\n{extra}\n[material]\npreset = \"{preset}\"\n"))
}

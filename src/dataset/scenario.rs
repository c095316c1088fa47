//! The four ContPhy scenarios and their names on disk, on the command line and in reports.
//!
//! This is the one list of the benchmark's scenarios; what each scenario brings (its engine,
//! scene backend, generator, writer, vocabulary and models) is its row in the scenario table
//! (`scenarios`).

use std::fmt;
use std::str::FromStr;

use serde::{Deserialize, Serialize};

/// One of the four ContPhy scenarios.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "lowercase")]
pub enum Scenario {
    /// Rope–pulley systems (`pulley_group`).
    Rope,
    /// Fluids flowing down ramps into containers (`fluid_slides`).
    Fluid,
    /// Cloth pulled over pillars and plates (`cloth_collision`).
    Cloth,
    /// Elastic, rigid and plastic balls falling into pits (`soft_body`).
    Ball,
}

impl Scenario {
    /// All scenarios, in the paper's table order.
    pub const ALL: [Scenario; 4] = [
        Scenario::Rope,
        Scenario::Fluid,
        Scenario::Cloth,
        Scenario::Ball,
    ];

    /// The short name used on the command line and in reports (`rope`).
    pub fn name(self) -> &'static str {
        match self {
            Scenario::Rope => "rope",
            Scenario::Fluid => "fluid",
            Scenario::Cloth => "cloth",
            Scenario::Ball => "ball",
        }
    }

    /// The folder name of the public release (`pulley_group`).
    pub fn folder_name(self) -> &'static str {
        match self {
            Scenario::Rope => "pulley_group",
            Scenario::Fluid => "fluid_slides",
            Scenario::Cloth => "cloth_collision",
            Scenario::Ball => "soft_body",
        }
    }

    /// The report label used in the paper's Table 2 (`Rope`).
    pub fn label(self) -> &'static str {
        match self {
            Scenario::Rope => "Rope",
            Scenario::Fluid => "Fluid",
            Scenario::Cloth => "Cloth",
            Scenario::Ball => "Ball",
        }
    }

    /// The scenario whose folder name is `folder` (`pulley_group` → rope).
    pub fn from_folder_name(folder: &str) -> Option<Scenario> {
        Scenario::ALL
            .into_iter()
            .find(|s| s.folder_name() == folder)
    }
}

impl fmt::Display for Scenario {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(self.name())
    }
}

/// A scenario name that is none of the four.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
#[error("unknown scenario `{0}`: expected one of {names}", names = Scenario::names())]
pub struct UnknownScenario(pub String);

impl Scenario {
    /// The short names, comma separated (`rope, fluid, cloth, ball`).
    pub fn names() -> String {
        Scenario::ALL.map(Scenario::name).join(", ")
    }

    /// The release folder names, comma separated.
    pub fn folder_names() -> String {
        Scenario::ALL.map(Scenario::folder_name).join(", ")
    }
}

/// Accepts the short name or the release folder name.
impl FromStr for Scenario {
    type Err = UnknownScenario;

    fn from_str(text: &str) -> Result<Self, Self::Err> {
        let lower = text.trim().to_ascii_lowercase();
        Scenario::ALL
            .into_iter()
            .find(|s| s.name() == lower || s.folder_name() == lower)
            .ok_or_else(|| UnknownScenario(text.to_string()))
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for scenario in Scenario::ALL {
            assert_eq!(scenario.name().parse::<Scenario>().unwrap(), scenario);
            assert_eq!(
                scenario.folder_name().parse::<Scenario>().unwrap(),
                scenario
            );
            assert_eq!(
                Scenario::from_folder_name(scenario.folder_name()),
                Some(scenario)
            );
        }
        assert_eq!(
            "pulleys".parse::<Scenario>().unwrap_err().to_string(),
            "unknown scenario `pulleys`: expected one of rope, fluid, cloth, ball"
        );
    }
}

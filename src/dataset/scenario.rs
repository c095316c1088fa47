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

/// A row of the paper's Table 2 (ContPhy, ICML 2024) for comparison: ContPRO's and the humans'
/// accuracy, %, on the release's test split.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct PaperRow {
    /// `Prop.`, `C-Opt.`, `C-Ques.`, `G-Opt.`, `G-Ques.`, `P-Opt.` or `P-Ques.`.
    pub setting: &'static str,
    /// ContPRO, the paper's oracle model.
    pub contpro: f64,
    /// The paper's human study.
    pub human: f64,
}

impl Scenario {
    /// The scenario's rows of the paper's Table 2 (the ContPRO and Human columns), in its order.
    pub fn paper_rows(self) -> &'static [PaperRow] {
        const fn row(setting: &'static str, contpro: f64, human: f64) -> PaperRow {
            PaperRow {
                setting,
                contpro,
                human,
            }
        }
        const ROPE: &[PaperRow] = &[
            row("Prop.", 71.4, 84.7),
            row("C-Opt.", 75.6, 90.2),
            row("C-Ques.", 48.8, 75.0),
            row("G-Opt.", 55.8, 91.9),
            row("G-Ques.", 2.3, 84.0),
        ];
        const FLUID: &[PaperRow] = &[
            row("Prop.", 78.0, 75.8),
            row("C-Opt.", 75.7, 82.5),
            row("C-Ques.", 36.2, 60.6),
            row("G-Opt.", 77.3, 75.0),
            row("G-Ques.", 60.0, 64.3),
            row("P-Opt.", 90.1, 73.9),
            row("P-Ques.", 68.3, 42.9),
        ];
        const CLOTH: &[PaperRow] = &[
            row("Prop.", 60.0, 81.4),
            row("P-Opt.", 64.7, 79.6),
            row("P-Ques.", 60.0, 77.3),
        ];
        const BALL: &[PaperRow] = &[
            row("Prop.", 54.0, 76.9),
            row("C-Opt.", 71.6, 93.9),
            row("C-Ques.", 57.4, 90.9),
            row("G-Opt.", 68.1, 89.7),
            row("G-Ques.", 52.2, 84.6),
            row("P-Opt.", 92.4, 72.5),
            row("P-Ques.", 88.6, 58.8),
        ];
        match self {
            Scenario::Rope => ROPE,
            Scenario::Fluid => FLUID,
            Scenario::Cloth => CLOTH,
            Scenario::Ball => BALL,
        }
    }

    /// The paper's Table-2 row of `setting`, if the paper reports one.
    pub fn paper_row(self, setting: &str) -> Option<&'static PaperRow> {
        self.paper_rows().iter().find(|row| row.setting == setting)
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

    #[test]
    fn the_paper_rows_are_table_2s() {
        // Spot checks against the paper's Table 2, one per scenario, and the row counts.
        let counts: Vec<usize> = Scenario::ALL.map(|s| s.paper_rows().len()).to_vec();
        assert_eq!(counts, [5, 7, 3, 7]);
        let rope = Scenario::Rope.paper_row("G-Ques.").unwrap();
        assert_eq!(
            (rope.contpro.to_bits(), rope.human.to_bits()),
            (2.3_f64.to_bits(), 84.0_f64.to_bits())
        );
        let cloth = Scenario::Cloth.paper_row("P-Opt.").unwrap();
        assert_eq!(
            (cloth.contpro.to_bits(), cloth.human.to_bits()),
            (64.7_f64.to_bits(), 79.6_f64.to_bits())
        );
        assert!(Scenario::Cloth.paper_row("C-Opt.").is_none());
        assert_eq!(
            Scenario::Ball.paper_row("P-Ques.").unwrap().human.to_bits(),
            58.8_f64.to_bits()
        );
    }
}

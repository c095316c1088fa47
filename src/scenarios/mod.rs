//! The scenario table: one row per ContPhy scenario, mapping it to its parts in every layer.
//!
//! Each scenario's code lives in sibling folders of the layers (`dataset/<scenario>/`,
//! `dataset/engine/<scenario>/`, `scene_api/<scenario>/`, `synth/<scenario>/`,
//! `program/builtin/<scenario>.rs`, `perception/<scenario>/`); shared code names no scenario and
//! reaches a scenario's parts through [`parts`]. A part a scenario does not have yet is `None`,
//! and the shared code says so in its own words. Adding a scenario is its folders plus one row
//! here (`docs/adding-a-scenario.md`).
//!
//! This module sits above every layer whose parts it lists and below the ones that use it
//! (`sandbox`, `app`).

use std::sync::OnceLock;

use crate::dataset::engine::{self, QuestionEngine};
use crate::dataset::{self, FamilyIndex, Scenario, Vocabulary};
use crate::program::builtin::{self, Writer};

/// One scenario's parts.
#[derive(Debug, Clone, Copy)]
pub struct ScenarioParts {
    /// The scenario.
    pub scenario: Scenario,
    /// The words of its scenes: what `find` understands, what objects carry, what the prompt
    /// lists.
    pub vocabulary: &'static Vocabulary,
    /// Its question engine (`questions`, `generate`).
    pub engine: Option<&'static QuestionEngine>,
    /// The builtin writer's programs for its questions.
    pub writer: Option<&'static Writer>,
}

/// The table, in the paper's order.
static TABLE: [ScenarioParts; 4] = [
    ScenarioParts {
        scenario: Scenario::Rope,
        vocabulary: &dataset::rope::VOCABULARY,
        engine: Some(&engine::rope::ENGINE),
        writer: Some(&builtin::rope::WRITER),
    },
    ScenarioParts {
        scenario: Scenario::Fluid,
        vocabulary: &dataset::fluid::VOCABULARY,
        engine: None,
        writer: None,
    },
    ScenarioParts {
        scenario: Scenario::Cloth,
        vocabulary: &dataset::cloth::VOCABULARY,
        engine: None,
        writer: None,
    },
    ScenarioParts {
        scenario: Scenario::Ball,
        vocabulary: &dataset::ball::VOCABULARY,
        engine: None,
        writer: None,
    },
];

/// Every row, in the paper's order.
pub fn all() -> &'static [ScenarioParts] {
    &TABLE
}

/// The parts of `scenario`.
pub fn parts(scenario: Scenario) -> &'static ScenarioParts {
    TABLE
        .iter()
        .find(|row| row.scenario == scenario)
        .expect("the table has a row for every scenario (a test checks it)")
}

/// Every scenario's question families, for telling a question file's scenario from its records.
pub fn families() -> FamilyIndex<'static> {
    static FAMILIES: OnceLock<Vec<(Scenario, &'static [&'static str])>> = OnceLock::new();
    FAMILIES.get_or_init(|| {
        TABLE
            .iter()
            .filter_map(|row| row.engine.map(|engine| (row.scenario, engine.families)))
            .collect()
    })
}

/// The scenarios that have `part`, by name, comma separated (`rope`): for messages about the
/// others.
pub fn names_with(part: impl Fn(&ScenarioParts) -> bool) -> String {
    TABLE
        .iter()
        .filter(|row| part(row))
        .map(|row| row.scenario.name())
        .collect::<Vec<_>>()
        .join(", ")
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_scenario_has_exactly_one_row_in_the_paper_order() {
        let order: Vec<Scenario> = all().iter().map(|row| row.scenario).collect();
        assert_eq!(order, Scenario::ALL.to_vec());
    }
}

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
use crate::dataset::{ChoiceOption, Question};
use crate::perception::{self, ScenarioPerception};
use crate::physics::{self, bench::PhysicsBench};
use crate::program::builtin::{self, Writer};
use crate::prompt::{PromptError, PromptMode, PromptSet, RenderedPrompt, SceneWords, error_chain};
use crate::scene_api::{self, BackendLoader, InferenceBench, ReadingCheck, SceneParts};
use crate::synth::{self, ScenarioSynth};

/// One scenario's parts.
#[derive(Clone, Copy)]
pub struct ScenarioParts {
    /// The scenario.
    pub scenario: Scenario,
    /// Its demo video in the repository (relative to its root), for commands that need one
    /// video by default (`bench sandbox`).
    pub demo: Option<&'static str>,
    /// The words of its scenes: what `find` understands, what objects carry, what the prompt
    /// lists.
    pub vocabulary: &'static Vocabulary,
    /// Its question engine (`questions`, `generate`).
    pub engine: Option<&'static QuestionEngine>,
    /// Its generator of synthetic videos (`generate`).
    pub synth: Option<&'static dyn ScenarioSynth>,
    /// The builtin writer's programs for its questions.
    pub writer: Option<&'static Writer>,
    /// Its scene API backend (`scene_api/<scenario>/`).
    pub scene: Option<BackendLoader>,
    /// Its detector classes and default model files, for `--perception maskrcnn`.
    pub perception: Option<&'static ScenarioPerception>,
    /// Its check of what perception reads of a scene against the annotations (`bench
    /// perception`).
    pub reading_check: Option<ReadingCheck>,
    /// Its check of properties inferred from the video (`bench inference`).
    pub inference_bench: Option<InferenceBench>,
    /// Its simulator's error-against-run-time benchmark (`bench physics`).
    pub physics_bench: Option<&'static PhysicsBench>,
}

impl std::fmt::Debug for ScenarioParts {
    fn fmt(&self, formatter: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        formatter
            .debug_struct("ScenarioParts")
            .field("scenario", &self.scenario)
            .field("engine", &self.engine.is_some())
            .field("synth", &self.synth.is_some())
            .field("writer", &self.writer.is_some())
            .field("scene", &self.scene.is_some())
            .field("perception", &self.perception.is_some())
            .finish_non_exhaustive()
    }
}

impl ScenarioParts {
    /// A scenario that so far has only its words: every other part is `None`.
    const fn words_only(scenario: Scenario, vocabulary: &'static Vocabulary) -> ScenarioParts {
        ScenarioParts {
            scenario,
            demo: None,
            vocabulary,
            engine: None,
            synth: None,
            writer: None,
            scene: None,
            perception: None,
            reading_check: None,
            inference_bench: None,
            physics_bench: None,
        }
    }
}

/// The table, in the paper's order.
static TABLE: [ScenarioParts; 4] = [
    ScenarioParts {
        scenario: Scenario::Rope,
        demo: Some("eval/demo/pulley_group/0"),
        vocabulary: &dataset::rope::VOCABULARY,
        engine: Some(&engine::rope::ENGINE),
        synth: Some(&synth::rope::RopeSynth),
        writer: Some(&builtin::rope::WRITER),
        scene: Some(scene_api::rope::load),
        perception: Some(&perception::rope::PERCEPTION),
        reading_check: Some(scene_api::rope::mechanism_report),
        inference_bench: Some(scene_api::rope::inference_report),
        physics_bench: Some(&physics::rope::bench::BENCH),
    },
    ScenarioParts {
        scenario: Scenario::Fluid,
        demo: Some("eval/demo/fluid_slides/0"),
        vocabulary: &dataset::fluid::VOCABULARY,
        engine: Some(&engine::fluid::ENGINE),
        synth: Some(&synth::fluid::FLUID_SYNTH),
        writer: Some(&builtin::fluid::WRITER),
        scene: Some(scene_api::fluid::load),
        perception: Some(&perception::fluid::PERCEPTION),
        reading_check: Some(scene_api::fluid::scene_report),
        inference_bench: Some(scene_api::fluid::infer::inference_report),
        physics_bench: Some(&scene_api::fluid::physics_bench::BENCH),
    },
    ScenarioParts {
        demo: Some("eval/demo/cloth_collision/0"),
        engine: Some(&engine::cloth::ENGINE),
        synth: Some(&synth::cloth::CLOTH_SYNTH),
        writer: Some(&builtin::cloth::WRITER),
        scene: Some(scene_api::cloth::load),
        perception: Some(&perception::cloth::PERCEPTION),
        reading_check: Some(scene_api::cloth::scene_report),
        inference_bench: Some(scene_api::cloth::inference_report),
        physics_bench: Some(&scene_api::cloth::physics_bench::BENCH),
        ..ScenarioParts::words_only(Scenario::Cloth, &dataset::cloth::VOCABULARY)
    },
    ScenarioParts {
        demo: Some("eval/demo/soft_body/0"),
        engine: Some(&engine::ball::ENGINE),
        synth: Some(&synth::ball::BALL_SYNTH),
        writer: Some(&builtin::ball::WRITER),
        scene: Some(scene_api::ball::load),
        perception: Some(&perception::ball::PERCEPTION),
        reading_check: Some(scene_api::ball::scene_report),
        inference_bench: Some(scene_api::ball::infer::inference_report),
        physics_bench: Some(&scene_api::ball::physics_bench::BENCH),
        ..ScenarioParts::words_only(Scenario::Ball, &dataset::ball::VOCABULARY)
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

/// What the scene API needs of `scenario`: its vocabulary, every scenario's vocabulary, and its
/// backend.
pub fn scene_parts(scenario: Scenario) -> SceneParts {
    static VOCABULARIES: OnceLock<Vec<&'static Vocabulary>> = OnceLock::new();
    let row = parts(scenario);
    SceneParts {
        vocabulary: row.vocabulary,
        all_vocabularies: VOCABULARIES.get_or_init(|| TABLE.iter().map(|r| r.vocabulary).collect()),
        backend: row.scene,
    }
}

/// Every scenario's words as the prompt's guidelines list them, in the paper's order.
pub fn scene_words() -> &'static [SceneWords] {
    static WORDS: OnceLock<Vec<SceneWords>> = OnceLock::new();
    WORDS.get_or_init(|| {
        TABLE
            .iter()
            .map(|row| SceneWords {
                name: row.scenario.name(),
                objects: row.vocabulary.kinds,
            })
            .collect()
    })
}

/// The embedded prompt set with every scenario's words, built once per process.
pub fn prompts() -> Result<&'static PromptSet, PromptError> {
    static SHARED: OnceLock<Result<PromptSet, String>> = OnceLock::new();
    SHARED
        .get_or_init(|| PromptSet::embedded(scene_words()).map_err(|error| error_chain(&error)))
        .as_ref()
        .map_err(|message| PromptError::Embedded(message.clone()))
}

/// Renders one unit's prompt with the embedded prompt set (see [`PromptSet::render`]).
pub fn render_prompt(
    question: &Question,
    option: Option<&ChoiceOption>,
    mode: PromptMode,
) -> Result<RenderedPrompt, PromptError> {
    prompts()?.render(question, option, mode)
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

/// The one scenario that has `part`, when exactly one has it: what a command that needs the part
/// uses when no scenario is named.
pub fn only_with(part: impl Fn(&ScenarioParts) -> bool) -> Option<Scenario> {
    let mut with = TABLE.iter().filter(|row| part(row)).map(|row| row.scenario);
    match (with.next(), with.next()) {
        (Some(only), None) => Some(only),
        _ => None,
    }
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

//! What a run saves per unit ([`Prediction`], one line of `predictions.jsonl`) and per question
//! ([`EvalQuestion`], in `questions.json`), so a run directory can be re-scored on its own.

use serde::{Deserialize, Serialize};

use super::Priors;
use crate::dataset::{AnswerType, Category, ChoiceOption, Question, Scenario};
use crate::scene_api::WorkCounters;

/// The pipeline stage where a unit failed (`docs/architecture.md`, pipeline).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum Stage {
    /// Rendering the prompt.
    Prompt,
    /// Calling the LLM.
    Llm,
    /// Extracting code from a completion.
    Extract,
    /// Getting a program from its source (builtin writer, cache replay).
    Program,
    /// Running the program (syntax, Python errors, limits, worker crashes).
    Sandbox,
    /// A scene API call failed (misuse, unavailable data, broken annotations).
    SceneApi,
    /// Turning the program's value into an answer.
    Answer,
}

impl Stage {
    /// All stages in pipeline order.
    pub const ALL: [Stage; 7] = [
        Stage::Prompt,
        Stage::Llm,
        Stage::Extract,
        Stage::Program,
        Stage::Sandbox,
        Stage::SceneApi,
        Stage::Answer,
    ];

    /// The snake-case name.
    pub fn name(self) -> &'static str {
        match self {
            Stage::Prompt => "prompt",
            Stage::Llm => "llm",
            Stage::Extract => "extract",
            Stage::Program => "program",
            Stage::Sandbox => "sandbox",
            Stage::SceneApi => "scene_api",
            Stage::Answer => "answer",
        }
    }
}

/// Why a unit failed.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct UnitError {
    /// Where.
    pub stage: Stage,
    /// A short stable kind (`timeout`, `misuse`, `cache_miss`, `NameError`...).
    pub kind: String,
    /// The message for humans.
    pub message: String,
}

/// One unit's result: a line of `predictions.jsonl`. Fields ending in `_ms` are timings, the
/// only fields that may differ between two runs of the same inputs.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct Prediction {
    /// `<question>` or `<question>:<letter>`.
    pub unit: String,
    /// The question.
    pub question_id: String,
    /// The option letter, for choice questions.
    pub option: Option<char>,
    /// The scenario.
    pub scenario: Scenario,
    /// The family key.
    pub family: String,
    /// The video.
    pub video_id: String,
    /// blake3 of the program text, when a program was obtained.
    pub program_hash: Option<String>,
    /// The program-cache key of the program (what `cache export` collects).
    #[serde(default)]
    pub program_key: Option<String>,
    /// Where the program came from (`builtin`, `cache`, ...).
    pub program_origin: Option<String>,
    /// The program's value as JSON, when it produced one.
    pub value: Option<serde_json::Value>,
    /// The normalised answer (`yes`, `no`, `can not answer`, `3`); for options, `yes`/`no` means
    /// the program judged the option true/false.
    pub answer: Option<String>,
    /// Whether the unit is correct against the gold answer.
    pub correct: bool,
    /// The failure, if the unit failed.
    pub error: Option<UnitError>,
    /// Programs tried for this unit: every sample and every repair attempt, in order.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub attempts: Vec<Attempt>,
    /// Answers of the samples and their counts, when more than one sample was drawn.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub votes: Vec<(String, u32)>,
    /// Tokens and cost of the LLM completions behind the unit (on the first unit of a
    /// per-question program only, so totals do not count a completion twice).
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub usage: Option<Usage>,
    /// Work done by the scene API for this unit (for a per-question program: on its first unit).
    pub work: WorkCounters,
    /// Program time outside the scene API, ms.
    pub own_ms: u64,
    /// Time inside scene API calls, ms.
    pub api_ms: u64,
    /// Wall time of the unit in the sandbox, ms.
    pub wall_ms: u64,
}

/// One program tried for a unit.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Attempt {
    /// Sample index (self-consistency draws), from 0.
    pub sample: u32,
    /// Attempt within the sample: 0, then 1.. for repair turns.
    pub attempt: u32,
    /// blake3 of the program, when one was obtained.
    pub program_hash: Option<String>,
    /// The program's cache key (also of a completion that held no program), which a replay
    /// and `cache export` need.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub program_key: Option<String>,
    /// Why the attempt failed, if it did.
    pub error: Option<UnitError>,
}

/// LLM usage behind a unit.
#[derive(Debug, Clone, Copy, PartialEq, Default, Serialize, Deserialize)]
pub struct Usage {
    /// Prompt tokens, as the server reported them.
    pub prompt_tokens: u64,
    /// Completion tokens.
    pub completion_tokens: u64,
    /// Cost in USD from the price table, when the model is priced.
    pub cost_usd: Option<f64>,
    /// HTTP requests made in this run (0 when every completion came from the cache).
    pub requests: u32,
}

impl Usage {
    /// Adds `other` to `self`.
    pub fn add(&mut self, other: &Usage) {
        self.prompt_tokens += other.prompt_tokens;
        self.completion_tokens += other.completion_tokens;
        self.cost_usd = match (self.cost_usd, other.cost_usd) {
            (Some(a), Some(b)) => Some(a + b),
            (a, b) => a.or(b),
        };
        self.requests += other.requests;
    }
}

/// A question as the scorer needs it (gold included), saved in the run's `questions.json`.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct EvalQuestion {
    /// The question id.
    pub id: String,
    /// The scenario.
    pub scenario: Scenario,
    /// The family key.
    pub family: String,
    /// The Table-2 category.
    pub category: Category,
    /// Open-ended or choice.
    pub answer_type: AnswerType,
    /// The video.
    pub video_id: String,
    /// The full question text (options included).
    pub text: String,
    /// The gold answer (normalised text, or sorted letters).
    pub answer: String,
    /// The options with their gold truth (empty for open-ended questions).
    pub options: Vec<ChoiceOption>,
}

impl EvalQuestion {
    /// The scorer's view of a dataset question.
    pub fn from_question(question: &Question) -> EvalQuestion {
        EvalQuestion {
            id: question.id.0.clone(),
            scenario: question.scenario,
            family: question.family.0.clone(),
            category: question.category(),
            answer_type: question.answer_type,
            video_id: question.video_id.0.clone(),
            text: question.record.question.clone(),
            answer: question.answer.clone(),
            options: question.options.clone(),
        }
    }

    /// Unit ids, as [`Question::units`] names them.
    pub fn unit_ids(&self) -> Vec<String> {
        if self.options.is_empty() {
            vec![self.id.clone()]
        } else {
            self.options
                .iter()
                .map(|o| format!("{}:{}", self.id, o.letter))
                .collect()
        }
    }
}

/// The content of a run's `questions.json`: what was evaluated and the baseline priors.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
pub struct RunQuestions {
    /// The evaluated questions, in run order.
    pub questions: Vec<EvalQuestion>,
    /// Answer statistics of the train split, for the FRQ and RND baselines.
    pub priors: Priors,
}

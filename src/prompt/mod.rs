//! Prompts: what the LLM sees, rendered from `prompts/` (minijinja templates) and `api_spec/`
//! (the scene API listing, worked examples, its version).
//!
//! Input: a [`Question`](crate::dataset::Question), the unit's option (per-option mode) and a
//! [`PromptMode`]. Output: a [`RenderedPrompt`] (system and user message, the hash of the
//! templates and api_spec files used, the api_spec version: all of it enters program-cache keys,
//! `docs/architecture.md`, program cache), or a [`PromptError`] naming the template and the
//! variable.
//!
//! The prompt follows the paper's listing `tb:oracle_prompt`: the API, "Write a function using
//! Python and the SoftScene class ...", the guidelines (with the objects of every scenario),
//! examples of the question's family, and the query.
//!
//! * **Per option** (the paper's): a choice question is one program per "question | option"
//!   unit, each answering yes or no; open questions are one program each.
//! * **Per question**: a choice question is one program returning the letters of its correct
//!   options (`"A C"`). Open questions render the same prompt in both modes.
//!
//! Templates use `UndefinedBehavior::Strict`: a variable the context lacks is an error, never an
//! empty string. The files are compiled in ([`PromptSet::embedded`]) so the binary works
//! anywhere; [`PromptSet::load`] lays a directory of edited files over them.
//!
//! Layer 2 (`docs/architecture.md`, layers): this module uses only `dataset` and `util`.

mod context;
mod error;
mod example;
mod files;
mod render;

pub use context::{PromptMode, SceneWords};
pub use error::PromptError;
pub use example::{Example, ExampleCheck};
pub use render::{ChatMessage, PromptSet, RenderedPrompt, error_chain};

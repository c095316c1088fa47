//! Program sources of a run: where each program request gets its Python program.
//!
//! A request is one program for one task (an open question, an option of a choice question, or
//! a whole choice question in per-question mode), for one sample and one attempt (repair turns
//! carry the earlier program and the error it met). Sources: the builtin writer and, in the
//! `llm` source, a model behind an OpenAI-compatible endpoint. Both go through the program cache:
//! with `--cache` every program is recorded, with `--offline` it is only replayed.

use serde_json::{Value, json};

use super::error::{AppError, Classify as _};
use crate::dataset::{ChoiceOption, Question};
use crate::program::{CacheEntry, Program, ProgramCache, ProgramOrigin, builtin, cache_key};
use crate::scenarios;
use crate::score::{Stage, UnitError, Usage};

/// One earlier attempt shown to the model in a repair turn.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(crate) struct RepairTurn {
    /// The completion text the model wrote (or the program, when there is no completion).
    pub(crate) completion: String,
    /// What went wrong, in words for the model.
    pub(crate) feedback: String,
}

/// One program to obtain.
#[derive(Debug, Clone, Copy)]
pub(crate) struct ProgramRequest<'a> {
    /// The question.
    pub(crate) question: &'a Question,
    /// The option, for a per-option unit.
    pub(crate) option: Option<&'a ChoiceOption>,
    /// One program for the whole choice question (per-question mode).
    pub(crate) whole_question: bool,
    /// Sample index (self-consistency).
    pub(crate) sample: u32,
    /// Earlier attempts of this sample, oldest first.
    pub(crate) repairs: &'a [RepairTurn],
    /// The first unit of the task, recorded with new cache entries.
    pub(crate) unit: &'a str,
}

/// A program obtained for a request.
#[derive(Debug, Clone)]
pub(crate) struct Obtained {
    /// The program.
    pub(crate) program: Program,
    /// The completion text it came from (LLM sources), for repair turns.
    pub(crate) completion: Option<String>,
    /// Tokens, cost and requests.
    pub(crate) usage: Option<Usage>,
}

/// A request that yielded no program: why, and what there is of it (an LLM completion that held
/// no code is cached, costs tokens and is shown to the model in a repair turn).
#[derive(Debug, Clone)]
pub(crate) struct Failed {
    /// Why.
    pub(crate) error: UnitError,
    /// The cache key of the completion, when there is one (a replay needs it).
    pub(crate) key: Option<String>,
    /// The completion text, when there is one.
    pub(crate) completion: Option<String>,
    /// Tokens, cost and requests spent on it.
    pub(crate) usage: Option<Usage>,
}

impl From<UnitError> for Box<Failed> {
    fn from(error: UnitError) -> Box<Failed> {
        Box::new(Failed {
            error,
            key: None,
            completion: None,
            usage: None,
        })
    }
}

/// What a source gives for one request (the failure boxed: it is rare and large).
pub(crate) type Obtain = Result<Obtained, Box<Failed>>;

/// Where a run's programs come from.
pub(crate) trait ProgramSource {
    /// The name shown in reports and manifests (`builtin`, the model).
    fn name(&self) -> String;
    /// Whether failed programs may be repaired (a model can read the error; the builtin writer
    /// would write the same program again).
    fn can_repair(&self) -> bool;
    /// Obtains programs for `requests`, in order. A unit's failure is an `Err` inside the vector;
    /// an error that must stop the run (a rejected API key, an unknown model) is the outer `Err`.
    fn obtain_batch(&self, requests: &[ProgramRequest<'_>]) -> Result<Vec<Obtain>, AppError>;
    /// What the manifest records about the source.
    fn describe(&self) -> Value;
}

/// The cache as seen by a source: optional, possibly replay-only.
#[derive(Debug, Clone)]
pub(crate) struct CacheAccess {
    /// The cache, if any.
    pub(crate) cache: Option<ProgramCache>,
    /// Replay only: a miss fails the unit.
    pub(crate) offline: bool,
}

/// What the cache says about a key.
pub(crate) enum Lookup {
    /// Cached.
    Hit(Box<CacheEntry>),
    /// Not cached; the source may produce it.
    Miss,
    /// Not cached and the run is offline: the unit fails.
    OfflineMiss(UnitError),
}

impl CacheAccess {
    /// Looks `key` up.
    pub(crate) fn lookup(&self, key: &str, unit: &str) -> Result<Lookup, AppError> {
        let entry = match &self.cache {
            Some(cache) => cache.get(key).user()?,
            None => None,
        };
        Ok(match entry {
            Some(entry) => Lookup::Hit(Box::new(entry)),
            None if self.offline => Lookup::OfflineMiss(UnitError {
                stage: Stage::Program,
                kind: "cache_miss".to_string(),
                message: format!(
                    "no cached program for unit `{unit}` (key {key}); run once without --offline to record it"
                ),
            }),
            None => Lookup::Miss,
        })
    }

    /// Records an entry (immutable: an existing entry is kept).
    pub(crate) fn record(&self, entry: CacheEntry) -> Result<(), AppError> {
        if let Some(cache) = &self.cache {
            cache.put(entry).internal()?;
        }
        Ok(())
    }
}

/// The versions of every scenario's writer, in table order, joined by `+` (`builtin-rope-v1`):
/// a run's identity changes when any of them does.
fn writer_versions() -> String {
    scenarios::all()
        .iter()
        .filter_map(|row| row.writer.map(|w| w.version))
        .collect::<Vec<_>>()
        .join("+")
}

/// The builtin writer as a program source.
#[derive(Debug, Clone)]
pub(crate) struct BuiltinSource {
    /// The program cache.
    pub(crate) cache: CacheAccess,
}

/// The source name of builtin programs.
pub(crate) const BUILTIN_SOURCE: &str = "builtin";

impl BuiltinSource {
    fn obtain(&self, request: &ProgramRequest<'_>) -> Result<Obtain, AppError> {
        let question = request.question;
        let writer = scenarios::parts(question.scenario).writer;
        let key_material = json!({
            "source": BUILTIN_SOURCE,
            "writer": writer.map_or("", |w| w.version),
            "scenario": question.scenario,
            "question": question.title,
            "option": request.option.map(|o| o.text.as_str()),
            "whole_question": request.whole_question.then_some(question.record.question.as_str()),
        });
        let key = cache_key(&key_material);
        match self.cache.lookup(&key, request.unit)? {
            Lookup::Hit(entry) => {
                return Ok(Ok(Obtained {
                    program: Program {
                        source: entry.program,
                        origin: ProgramOrigin::Cache,
                        key: Some(key),
                    },
                    completion: None,
                    usage: None,
                }));
            }
            Lookup::OfflineMiss(error) => return Ok(Err(error.into())),
            Lookup::Miss => {}
        }
        let written = match writer {
            None => Err(builtin::WriterError::Scenario(question.scenario)),
            Some(writer) if request.whole_question => {
                builtin::write_question_program(question, writer)
            }
            Some(writer) => builtin::write_program(question, request.option, writer),
        };
        let source = match written {
            Ok(source) => source,
            Err(error) => {
                return Ok(Err(UnitError {
                    stage: Stage::Program,
                    kind: "unrecognised".to_string(),
                    message: error.to_string(),
                }
                .into()));
            }
        };
        self.cache.record(CacheEntry {
            key: key.clone(),
            key_material,
            program: source.clone(),
            raw_completion: None,
            source: BUILTIN_SOURCE.to_string(),
            first_unit: request.unit.to_string(),
            details: Value::Null,
        })?;
        Ok(Ok(Obtained {
            program: Program {
                source,
                origin: ProgramOrigin::Builtin,
                key: Some(key),
            },
            completion: None,
            usage: None,
        }))
    }
}

impl ProgramSource for BuiltinSource {
    fn name(&self) -> String {
        BUILTIN_SOURCE.to_string()
    }

    fn can_repair(&self) -> bool {
        false
    }

    fn obtain_batch(&self, requests: &[ProgramRequest<'_>]) -> Result<Vec<Obtain>, AppError> {
        requests
            .iter()
            .map(|request| self.obtain(request))
            .collect()
    }

    fn describe(&self) -> Value {
        json!({ "source": BUILTIN_SOURCE, "writer": writer_versions() })
    }
}

//! Program sources: where each unit's Python program comes from, and the program cache.
//!
//! Input: a [`Question`](crate::dataset::Question) and, for choice questions, one option (the
//! paper's "question | option" unit). Output: a [`Program`] (Python text plus its origin and
//! hash). Sources are the deterministic [`builtin`] writer, the content-addressed
//! [`ProgramCache`] (replay), and, in a later issue, an LLM.

pub mod builtin;
mod cache;
mod extract;

pub use cache::{CacheEntry, CacheError, ProgramCache, cache_key};
pub use extract::{ExtractError, extract_program};

use serde::{Deserialize, Serialize};

/// A Python program for one unit.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
pub struct Program {
    /// The Python source.
    pub source: String,
    /// Where it came from.
    pub origin: ProgramOrigin,
    /// The program-cache key it is (or would be) stored under.
    pub key: Option<String>,
}

/// Where a program came from.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Hash, Serialize, Deserialize)]
#[serde(rename_all = "snake_case")]
pub enum ProgramOrigin {
    /// The built-in deterministic writer.
    Builtin,
    /// Replayed from the program cache.
    Cache,
    /// A program file given on the command line.
    File,
    /// Written by an LLM in this run.
    Llm,
}

impl Program {
    /// blake3 of the source text: identifies the program in predictions.
    pub fn hash(&self) -> String {
        crate::util::content_hash(self.source.as_bytes())
    }
}

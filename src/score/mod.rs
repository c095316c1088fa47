//! Scoring: per-option and per-question accuracy per scenario × category and per family, the RND
//! and FRQ baselines on the same questions, and failures counted by stage.
//!
//! Input: the evaluated questions ([`EvalQuestion`], gold included), the saved [`Prediction`]s of
//! a run and the baseline [`Priors`] (answer statistics of the train split). Output: [`Scores`],
//! integer counts from which every percentage is derived at render time. Scoring is a pure
//! function of its inputs, so `score RUN...` re-scores saved runs exactly.
//!
//! Conventions (paper §Experimental Setup; CLEVRER/ComPhy precedent): an option is correct iff
//! its predicted truth equals the gold truth; a question is correct iff all its options are; a
//! failed or missing unit is wrong and is also counted by stage.

mod baseline;
mod metrics;
mod prediction;

pub use baseline::{FamilyPrior, Priors};
pub use metrics::{ExpectedTally, GroupScore, Scores, Tally, score};
pub use prediction::{Attempt, EvalQuestion, Prediction, RunQuestions, Stage, UnitError, Usage};

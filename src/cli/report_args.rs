//! The arguments of the commands that read saved runs: `score` and `view`.

use std::path::PathBuf;

use clap::Args;

use crate::app::{ScoreSettings, ViewSettings};

/// `score` arguments.
#[derive(Debug, Args)]
pub struct ScoreArgs {
    /// Run directories to score. The shards of one sharded run (`--shard I/N`, same settings)
    /// are merged into one column.
    #[arg(value_name = "RUN", required = true)]
    runs: Vec<PathBuf>,
    /// Print the scores as JSON instead of the table.
    #[arg(long)]
    json: bool,
}

/// `view` arguments.
#[derive(Debug, Args)]
pub struct ViewArgs {
    /// Run directories to show. The shards of one sharded run are merged into one column, as
    /// `score` does.
    #[arg(value_name = "RUN", required = true)]
    runs: Vec<PathBuf>,
    /// The site's folder: new, empty, or one an earlier `view` wrote (it is replaced). Open
    /// `index.html` in a browser; no server is needed.
    #[arg(long, value_name = "DIR")]
    out: PathBuf,
    /// The program cache the runs used (`run --cache`), to show each unit's program text and
    /// LLM completion; each run's own `cache/` is read too.
    #[arg(long, value_name = "DIR")]
    cache: Option<PathBuf>,
}

impl ScoreArgs {
    pub(super) fn into_settings(self) -> ScoreSettings {
        ScoreSettings {
            runs: self.runs,
            json: self.json,
        }
    }
}

impl ViewArgs {
    pub(super) fn into_settings(self) -> ViewSettings {
        ViewSettings {
            runs: self.runs,
            out: self.out,
            cache: self.cache,
        }
    }
}

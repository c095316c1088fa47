//! `score RUN...` (re-score saved runs into one leaderboard) and `cache ls`.

use std::collections::BTreeSet;
use std::io::Write as _;
use std::path::PathBuf;
use std::process::ExitCode;

use serde_json::json;

use super::error::{AppError, Classify as _, user_error};
use super::run_dir::{Manifest, RunDir, RunIdentity};
use super::settings::{CacheExportSettings, CacheImportSettings, CacheSettings, ScoreSettings};
use crate::program::{CacheEntry, ProgramCache, cache_key};
use crate::report::render_leaderboard;
use crate::score::{EvalQuestion, Prediction, Priors, RunQuestions, Scores, score};
use crate::util::canonical_json;

/// One loaded run directory.
struct LoadedRun {
    dir: PathBuf,
    name: String,
    identity: Option<RunIdentity>,
    manifest: Option<Manifest>,
    questions: RunQuestions,
    predictions: Vec<Prediction>,
}

/// A leaderboard column: one run, or the complete set of shards of one sharded run.
pub(crate) struct Column {
    /// The column's name (the run's folder, or the shards' parent with their count).
    pub(crate) name: String,
    /// The run directories behind it.
    pub(crate) dirs: Vec<PathBuf>,
    /// The first directory's manifest, if it has one.
    pub(crate) manifest: Option<Manifest>,
    /// The evaluated questions.
    pub(crate) questions: Vec<EvalQuestion>,
    priors: Priors,
    /// The predictions.
    pub(crate) predictions: Vec<Prediction>,
}

/// Runs loaded, their shards merged into columns and scored, with notes for the user.
pub(crate) struct ScoredRuns {
    /// One per leaderboard column, in the order given.
    pub(crate) columns: Vec<Column>,
    /// Each column's name and scores.
    pub(crate) scored: Vec<(String, Scores)>,
    /// What the user should know (missing units, merged or unmerged shards, other questions).
    pub(crate) notes: Vec<String>,
}

/// Loads the run directories `runs`, merges the complete shard sets and scores every column.
pub(crate) fn load_and_score(runs: &[PathBuf]) -> Result<ScoredRuns, AppError> {
    let mut loaded = Vec::new();
    for dir in runs {
        let run = RunDir::new(dir);
        if !run.questions_path().is_file() {
            return Err(user_error(format!(
                "`{}` is not a run directory (no `questions.json`)",
                dir.display()
            )));
        }
        let manifest = if run.manifest_path().is_file() {
            Some(run.read_manifest()?)
        } else {
            None
        };
        loaded.push(LoadedRun {
            dir: dir.clone(),
            name: dir.file_name().map_or_else(
                || dir.display().to_string(),
                |n| n.to_string_lossy().into_owned(),
            ),
            identity: manifest.as_ref().map(|m| m.identity.clone()),
            manifest,
            questions: run.read_questions()?,
            predictions: run.read_predictions()?,
        });
    }
    let mut notes = Vec::new();
    let columns = merge_shards(loaded, &mut notes);
    let mut scored = Vec::with_capacity(columns.len());
    for column in &columns {
        let scores = score(&column.questions, &column.predictions, &column.priors);
        let label = column
            .dirs
            .iter()
            .map(|d| d.display().to_string())
            .collect::<Vec<_>>()
            .join(", ");
        if scores.missing_units > 0 {
            notes.push(format!(
                "{label}: {} of {} units have no prediction (an unfinished run?); they count as wrong",
                scores.missing_units, scores.units
            ));
        }
        if scores.unknown_units > 0 || scores.duplicate_units > 0 {
            notes.push(format!(
                "{label}: {} predictions for unknown units and {} duplicates were ignored",
                scores.unknown_units, scores.duplicate_units
            ));
        }
        scored.push((column.name.clone(), scores));
    }
    let question_sets: Vec<BTreeSet<&str>> = columns
        .iter()
        .map(|c| c.questions.iter().map(|q| q.id.as_str()).collect())
        .collect();
    if question_sets.windows(2).any(|pair| pair[0] != pair[1]) {
        notes.push(
            "the runs evaluated different questions; RND and FRQ are those of the first run"
                .to_string(),
        );
    }
    Ok(ScoredRuns {
        columns,
        scored,
        notes,
    })
}

pub(crate) fn score_runs(settings: &ScoreSettings) -> Result<ExitCode, AppError> {
    let ScoredRuns {
        columns,
        scored,
        notes,
    } = load_and_score(&settings.runs)?;
    let mut stdout = std::io::stdout().lock();
    if settings.json {
        let runs: Vec<serde_json::Value> = columns
            .iter()
            .zip(&scored)
            .map(|(column, (name, scores))| {
                json!({
                    "name": name,
                    "dirs": column.dirs.iter().map(|d| d.display().to_string()).collect::<Vec<_>>(),
                    "scores": scores,
                })
            })
            .collect();
        let _ = writeln!(
            stdout,
            "{}",
            serde_json::to_string_pretty(&json!({ "runs": runs })).unwrap_or_default()
        );
    } else {
        let _ = write!(stdout, "{}", render_leaderboard(&scored));
    }
    let mut stderr = std::io::stderr().lock();
    for note in notes {
        let _ = writeln!(stderr, "note: {note}");
    }
    Ok(ExitCode::SUCCESS)
}

/// Groups the shards of one run (same settings and data, shards `0..N` of `N`, all present) into
/// one column; everything else stays a column of its own. Scores are sums over questions, so a
/// merged column scores exactly as the unsharded run would.
fn merge_shards(runs: Vec<LoadedRun>, notes: &mut Vec<String>) -> Vec<Column> {
    let single = |run: LoadedRun| Column {
        name: run.name,
        dirs: vec![run.dir],
        manifest: run.manifest,
        questions: run.questions.questions,
        priors: run.questions.priors,
        predictions: run.predictions,
    };
    // Group key: the identity without its shard, as canonical JSON.
    let mut groups: Vec<(String, usize, Vec<LoadedRun>)> = Vec::new();
    let mut columns: Vec<(usize, Column)> = Vec::new();
    for (position, run) in runs.into_iter().enumerate() {
        match run
            .identity
            .as_ref()
            .and_then(|identity| identity.shard.map(|shard| (identity, shard)))
        {
            Some((identity, _)) => {
                let mut unsharded = identity.clone();
                unsharded.shard = None;
                let key = serde_json::to_value(&unsharded)
                    .map(|v| canonical_json(&v))
                    .unwrap_or_default();
                match groups.iter_mut().find(|(k, _, _)| *k == key) {
                    Some((_, _, members)) => members.push(run),
                    None => groups.push((key, position, vec![run])),
                }
            }
            None => columns.push((position, single(run))),
        }
    }
    for (_, position, mut members) in groups {
        let count = members
            .first()
            .and_then(|m| m.identity.as_ref())
            .and_then(|i| i.shard)
            .map_or(0, |(_, n)| n);
        members.sort_by_key(|m| {
            m.identity
                .as_ref()
                .and_then(|i| i.shard)
                .map_or(usize::MAX, |(i, _)| i)
        });
        let indices: Vec<usize> = members
            .iter()
            .filter_map(|m| m.identity.as_ref().and_then(|i| i.shard))
            .map(|(i, _)| i)
            .collect();
        let complete = indices == (0..count).collect::<Vec<_>>()
            && members.iter().all(|m| {
                m.identity
                    .as_ref()
                    .and_then(|i| i.shard)
                    .is_some_and(|(_, n)| n == count)
            });
        if !complete {
            notes.push(format!(
                "shards {} of a {count}-shard run are not a complete set (0..{count}); scored separately",
                indices.iter().map(ToString::to_string).collect::<Vec<_>>().join(", ")
            ));
            for (offset, member) in members.into_iter().enumerate() {
                columns.push((position + offset, single(member)));
            }
            continue;
        }
        let parent = members.first().and_then(|m| {
            m.dir
                .parent()
                .and_then(|p| p.file_name())
                .map(|n| n.to_string_lossy().into_owned())
        });
        let name = match parent {
            Some(parent) if !parent.is_empty() => format!("{parent} ({count} shards)"),
            _ => format!(
                "{} ({count} shards)",
                members.first().map_or("run", |m| m.name.as_str())
            ),
        };
        let mut column = Column {
            name,
            dirs: Vec::new(),
            manifest: members.first().and_then(|m| m.manifest.clone()),
            questions: Vec::new(),
            priors: Priors::default(),
            predictions: Vec::new(),
        };
        for member in members {
            column.dirs.push(member.dir);
            column.priors = member.questions.priors;
            column.questions.extend(member.questions.questions);
            column.predictions.extend(member.predictions);
        }
        columns.push((position, column));
    }
    columns.sort_by_key(|(position, _)| *position);
    columns.into_iter().map(|(_, column)| column).collect()
}

pub(crate) fn cache_list(settings: &CacheSettings) -> Result<ExitCode, AppError> {
    if !settings.cache.is_dir() {
        return Err(user_error(format!(
            "program cache `{}` does not exist",
            settings.cache.display()
        )));
    }
    let entries = ProgramCache::new(&settings.cache).list().user()?;
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(
        stdout,
        "| key | source | first unit | lines | program hash |"
    );
    let _ = writeln!(stdout, "|---|---|---|---:|---|");
    for entry in &entries {
        let hash = crate::util::content_hash(entry.program.as_bytes());
        let _ = writeln!(
            stdout,
            "| {} | {} | {} | {} | {} |",
            entry.key.get(..16).unwrap_or(&entry.key),
            entry.source,
            entry.first_unit,
            entry.program.lines().count(),
            hash.get(..16).unwrap_or(&hash)
        );
    }
    let _ = writeln!(stdout, "\n{} programs", entries.len());
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn cache_export(settings: &CacheExportSettings) -> Result<ExitCode, AppError> {
    let run = RunDir::new(&settings.run);
    if !run.predictions_path().is_file() {
        return Err(user_error(format!(
            "`{}` is not a run directory (no `predictions.jsonl`)",
            settings.run.display()
        )));
    }
    let cache = ProgramCache::new(&settings.cache);
    let mut keys: Vec<String> = Vec::new();
    let mut seen = BTreeSet::new();
    // Every attempt's key: the voted program, the other samples, the repaired-away attempts
    // and completions that held no program; an offline replay asks for all of them.
    for prediction in run.read_predictions()? {
        let attempt_keys = prediction
            .attempts
            .iter()
            .filter_map(|a| a.program_key.clone());
        for key in prediction.program_key.into_iter().chain(attempt_keys) {
            if seen.insert(key.clone()) {
                keys.push(key);
            }
        }
    }
    let mut lines = String::new();
    let mut missing = 0;
    for key in &keys {
        match cache.get(key).user()? {
            Some(entry) => {
                lines.push_str(&serde_json::to_string(&entry).internal()?);
                lines.push('\n');
            }
            None => missing += 1,
        }
    }
    match &settings.out {
        Some(path) => crate::util::write_atomic(path, lines.as_bytes()).internal()?,
        None => {
            let _ = write!(std::io::stdout().lock(), "{lines}");
        }
    }
    let mut stderr = std::io::stderr().lock();
    let _ = writeln!(stderr, "exported {} programs", keys.len() - missing);
    if missing > 0 {
        let _ = writeln!(
            stderr,
            "note: {missing} programs of the run are not in `{}`",
            settings.cache.display()
        );
    }
    Ok(ExitCode::SUCCESS)
}

pub(crate) fn cache_import(settings: &CacheImportSettings) -> Result<ExitCode, AppError> {
    let cache = ProgramCache::new(&settings.cache);
    let mut imported = 0;
    for path in &settings.files {
        let text = fs_err::read_to_string(path).user()?;
        for (index, line) in text
            .lines()
            .enumerate()
            .filter(|(_, l)| !l.trim().is_empty())
        {
            let entry: CacheEntry = serde_json::from_str(line).map_err(|error| {
                user_error(format!(
                    "`{}` line {}: not a cache entry: {error}",
                    path.display(),
                    index + 1
                ))
            })?;
            if cache_key(&entry.key_material) != entry.key {
                return Err(user_error(format!(
                    "`{}` line {}: the entry's key does not match its key material",
                    path.display(),
                    index + 1
                )));
            }
            cache.put(entry).internal()?;
            imported += 1;
        }
    }
    let _ = writeln!(
        std::io::stdout().lock(),
        "imported {imported} programs into {}",
        settings.cache.display()
    );
    Ok(ExitCode::SUCCESS)
}

//! `score RUN...` (re-score saved runs into one leaderboard) and `cache ls`.

use std::io::Write as _;
use std::process::ExitCode;

use super::error::{AppError, Classify as _, user_error};
use super::run_dir::RunDir;
use super::settings::{CacheSettings, ScoreSettings};
use crate::program::ProgramCache;
use crate::report::render_leaderboard;
use crate::score::score;

pub(crate) fn score_runs(settings: &ScoreSettings) -> Result<ExitCode, AppError> {
    let mut runs = Vec::new();
    let mut question_sets = Vec::new();
    let mut notes = Vec::new();
    for dir in &settings.runs {
        let run = RunDir::new(dir);
        if !run.questions_path().is_file() {
            return Err(user_error(format!(
                "`{}` is not a run directory (no `questions.json`)",
                dir.display()
            )));
        }
        let questions = run.read_questions()?;
        let predictions = run.read_predictions()?;
        let scores = score(&questions.questions, &predictions, &questions.priors);
        if scores.missing_units > 0 {
            notes.push(format!(
                "{}: {} of {} units have no prediction (an unfinished run?); they count as wrong",
                dir.display(),
                scores.missing_units,
                scores.units
            ));
        }
        if scores.unknown_units > 0 || scores.duplicate_units > 0 {
            notes.push(format!(
                "{}: {} predictions for unknown units and {} duplicates were ignored",
                dir.display(),
                scores.unknown_units,
                scores.duplicate_units
            ));
        }
        let ids: Vec<String> = questions.questions.iter().map(|q| q.id.clone()).collect();
        question_sets.push(ids);
        let name = dir.file_name().map_or_else(
            || dir.display().to_string(),
            |n| n.to_string_lossy().into_owned(),
        );
        runs.push((name, scores));
    }
    if question_sets.windows(2).any(|pair| pair[0] != pair[1]) {
        notes.push(
            "the runs evaluated different questions; RND and FRQ are those of the first run"
                .to_string(),
        );
    }
    let mut stdout = std::io::stdout().lock();
    let _ = write!(stdout, "{}", render_leaderboard(&runs));
    let mut stderr = std::io::stderr().lock();
    for note in notes {
        let _ = writeln!(stderr, "note: {note}");
    }
    Ok(ExitCode::SUCCESS)
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

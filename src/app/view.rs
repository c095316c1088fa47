//! `view RUN... --out DIR`: writes the static viewer site of saved runs (the leaderboard, and per
//! run every unit with its program, answer and error), built by `report::site`.
//!
//! Input: run directories (shards merged as `score` merges them) and, optionally, the program
//! cache they used, for the programs' texts. Output: the site's files under `--out`, which must be
//! new, empty, or a folder an earlier `view` wrote (then its files are replaced).

use std::collections::BTreeMap;
use std::io::Write as _;
use std::path::Path;
use std::process::ExitCode;

use super::error::{AppError, Classify as _, user_error};
use super::run::backends_line;
use super::score::{Column, ScoredRuns, load_and_score};
use super::settings::ViewSettings;
use crate::program::ProgramCache;
use crate::report::run_plots;
use crate::report::site::{ProgramText, SITE_MARKER, SiteFile, SiteRun, build_site};
use crate::util::write_atomic;

pub(crate) fn view(settings: &ViewSettings) -> Result<ExitCode, AppError> {
    prepare_out(&settings.out)?;
    if let Some(dir) = &settings.cache
        && !dir.is_dir()
    {
        return Err(user_error(format!(
            "program cache `{}` does not exist",
            dir.display()
        )));
    }
    let ScoredRuns {
        columns,
        scored,
        mut notes,
    } = load_and_score(&settings.runs)?;
    let mut runs = Vec::with_capacity(columns.len());
    let mut images = Vec::new();
    for (index, (column, (name, scores))) in columns.iter().zip(&scored).enumerate() {
        let model = column.manifest.as_ref().map_or_else(
            || name.clone(),
            |manifest| manifest.identity.program_source.clone(),
        );
        runs.push(SiteRun {
            name: name.clone(),
            facts: facts(column, scores),
            scores,
            questions: &column.questions,
            predictions: &column.predictions,
            plots: run_plots(&model, scores, &column.questions, &column.predictions).internal()?,
            frames: perception_frames(column, index + 1, &mut images, &mut notes),
        });
    }
    // The cache given, then each run's own (`RUN/cache`, where an LLM run keeps its completions
    // when no --cache was given): keys are content hashes, so any cache holding one is right.
    let caches: Vec<ProgramCache> = settings
        .cache
        .iter()
        .cloned()
        .chain(
            columns
                .iter()
                .flat_map(|column| column.dirs.iter().map(|dir| dir.join("cache")))
                .filter(|dir| dir.is_dir()),
        )
        .map(|dir| ProgramCache::new(&dir))
        .collect();
    if caches.is_empty() {
        notes.push(
            "no program cache (--cache, or a run's own cache/): the units show their programs' hashes, not their texts"
                .to_string(),
        );
    }
    let unreadable = std::cell::Cell::new(0_usize);
    let find = |key: &str| -> Option<ProgramText> {
        for cache in &caches {
            match cache.get(key) {
                Ok(Some(entry)) => {
                    return Some(ProgramText {
                        source: entry.source,
                        program: entry.program,
                        completion: entry.raw_completion,
                    });
                }
                Ok(None) => {}
                Err(_) => unreadable.set(unreadable.get() + 1),
            }
        }
        None
    };
    // A key is read once: the options of a per-question program and a unit's last repair turn
    // name the same program.
    let read: std::cell::RefCell<BTreeMap<String, Option<ProgramText>>> =
        std::cell::RefCell::default();
    let programs = |key: &str| -> Option<ProgramText> {
        if let Some(known) = read.borrow().get(key) {
            return known.clone();
        }
        let found = find(key);
        read.borrow_mut().insert(key.to_string(), found.clone());
        found
    };
    let mut files = build_site(&runs, &programs, &notes);
    files.extend(images);
    let mut bytes = 0_usize;
    for file in &files {
        bytes += file.bytes.len();
        write_atomic(&settings.out.join(&file.path), &file.bytes).user()?;
    }
    let mut stderr = std::io::stderr().lock();
    for note in &notes {
        let _ = writeln!(stderr, "note: {note}");
    }
    if unreadable.get() > 0 {
        let _ = writeln!(
            stderr,
            "note: {} program-cache entries could not be read; those units show no program text",
            unreadable.get()
        );
    }
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(
        stdout,
        "wrote {} files ({:.1} MB) for {} run(s); open {} in a browser",
        files.len(),
        bytes as f64 / 1e6,
        runs.len(),
        settings.out.join("index.html").display()
    );
    Ok(ExitCode::SUCCESS)
}

/// Makes `out` ready: created when missing; an earlier site's files removed; anything else that
/// is not empty refused, so no user file is overwritten.
fn prepare_out(out: &Path) -> Result<(), AppError> {
    if out.exists() && !out.is_dir() {
        return Err(user_error(format!(
            "--out `{}` is a file; give a folder for the site",
            out.display()
        )));
    }
    if out.is_dir() {
        let marked = out.join(SITE_MARKER).is_file();
        let empty = fs_err::read_dir(out).user()?.next().is_none();
        if !marked && !empty {
            return Err(user_error(format!(
                "--out `{}` is not empty and was not written by `view`; give a new or empty folder",
                out.display()
            )));
        }
        for folder in ["runs", "assets"] {
            let path = out.join(folder);
            if path.is_dir() {
                fs_err::remove_dir_all(&path).user()?;
            }
        }
    }
    fs_err::create_dir_all(out).user()?;
    Ok(())
}

/// The run's facts for its page header.
fn facts(column: &Column, scores: &crate::score::Scores) -> Vec<(String, String)> {
    let mut facts = vec![(
        "run directories".to_string(),
        column
            .dirs
            .iter()
            .map(|dir| dir.display().to_string())
            .collect::<Vec<_>>()
            .join(", "),
    )];
    let Some(manifest) = &column.manifest else {
        facts.push(("manifest".into(), "none (an unfinished run?)".into()));
        return facts;
    };
    let identity = &manifest.identity;
    facts.push(("program source".into(), identity.program_source.clone()));
    facts.push((
        "backends".into(),
        backends_line(identity.perception, identity.dynamics),
    ));
    facts.push((
        "questions".into(),
        identity
            .question_files
            .iter()
            .map(|(path, _)| path.as_str())
            .collect::<Vec<_>>()
            .join(", "),
    ));
    facts.push(("data root".into(), manifest.data_root.clone()));
    let failed = scores.failed_units();
    facts.push((
        "units".into(),
        format!(
            "{} of {} questions: {} answered, {} failed, {} missing",
            scores.units,
            column.questions.len(),
            scores.units_answered,
            failed,
            scores.missing_units
        ),
    ));
    facts.push((
        "tool".into(),
        format!(
            "{} {}{}",
            manifest.tool,
            manifest.tool_version,
            manifest
                .git_revision
                .as_ref()
                .map_or_else(String::new, |rev| format!(" ({rev})"))
        ),
    ));
    if manifest.finished_unix_ms > manifest.started_unix_ms {
        facts.push((
            "run time".into(),
            format!(
                "{:.1} s",
                (manifest.finished_unix_ms - manifest.started_unix_ms) as f64 / 1000.0
            ),
        ));
    }
    if let Some(usage) = &manifest.usage {
        facts.push((
            "LLM usage".into(),
            format!(
                "{} requests, {} prompt + {} completion tokens{}",
                usage.requests,
                usage.prompt_tokens,
                usage.completion_tokens,
                usage
                    .cost_usd
                    .map_or_else(String::new, |usd| format!(", ${usd:.4}"))
            ),
        ));
    }
    facts
}

/// The frames perception kept in the column's run directories (`frames/<scenario>/<video>/`,
/// with `detections.json`), by `<scenario>/<video>`; their images are added to `images` under
/// `runs/<run>/frames/`. An unreadable listing is noted and skipped.
fn perception_frames(
    column: &Column,
    run: usize,
    images: &mut Vec<SiteFile>,
    notes: &mut Vec<String>,
) -> BTreeMap<String, serde_json::Value> {
    let mut frames = BTreeMap::new();
    for dir in &column.dirs {
        let root = dir.join("frames");
        for scenario in sorted_folders(&root) {
            for video in sorted_folders(&root.join(&scenario)) {
                let folder = root.join(&scenario).join(&video);
                let listing = folder.join("detections.json");
                let Some(list) = fs_err::read(&listing)
                    .ok()
                    .and_then(|bytes| serde_json::from_slice::<serde_json::Value>(&bytes).ok())
                    .and_then(|value| value.get("frames").cloned())
                    .and_then(|value| value.as_array().cloned())
                else {
                    notes.push(format!(
                        "`{}` is missing or not a frames listing; that video's frames are not shown",
                        listing.display()
                    ));
                    continue;
                };
                let mut kept = Vec::new();
                for frame in list {
                    // Only plain file names beside the listing: a run directory is data, and
                    // the site must not copy files from elsewhere.
                    let Some(image) = frame["image"].as_str().filter(|name| {
                        !name.is_empty()
                            && !name.starts_with('.')
                            && name.chars().all(|c| {
                                c.is_ascii_alphanumeric() || c == '.' || c == '_' || c == '-'
                            })
                    }) else {
                        continue;
                    };
                    let Ok(bytes) = fs_err::read(folder.join(image)) else {
                        continue;
                    };
                    images.push(SiteFile {
                        path: format!("runs/{run}/frames/{scenario}/{video}/{image}"),
                        bytes,
                    });
                    kept.push(frame);
                }
                frames.insert(
                    format!("{scenario}/{video}"),
                    serde_json::Value::Array(kept),
                );
            }
        }
    }
    frames
}

/// The names of the folders in `dir`, sorted; none when it cannot be read.
fn sorted_folders(dir: &Path) -> Vec<String> {
    let Ok(entries) = fs_err::read_dir(dir) else {
        return Vec::new();
    };
    let mut names: Vec<String> = entries
        .filter_map(Result::ok)
        .filter(|entry| entry.path().is_dir())
        .map(|entry| entry.file_name().to_string_lossy().into_owned())
        .collect();
    names.sort();
    names
}

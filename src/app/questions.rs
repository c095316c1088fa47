//! `questions`: each scenario's question engine over a data root, writing per-video files and the
//! sampled train/val/test files.
//!
//! Every scenario folder of the data root whose scenario has an engine in the scenario table is
//! processed; the others are named on stderr and skipped.

use std::io::Write as _;
use std::process::ExitCode;

use indexmap::IndexMap;

use super::error::{AppError, Classify as _, user_error};
use super::settings::QuestionsSettings;
use crate::dataset::engine::{QuestionEngine, SamplerConfig, sample_and_split};
use crate::dataset::{
    DataRoot, Scenario, Split, questions_file_name, write_per_video_file, write_sampled_file,
};
use crate::scenarios;

pub(crate) fn questions(settings: &QuestionsSettings) -> Result<ExitCode, AppError> {
    let root = DataRoot::open(&settings.data).user()?;
    let present = root.scenarios();
    if present.is_empty() {
        return Err(user_error(format!(
            "data root `{}` has no scenario folder ({})",
            settings.data.display(),
            Scenario::folder_names()
        )));
    }
    let mut with_engine = Vec::new();
    let mut stderr = std::io::stderr().lock();
    for scenario in present {
        match scenarios::parts(scenario).engine {
            Some(engine) => with_engine.push((scenario, engine)),
            None => {
                let _ = writeln!(
                    stderr,
                    "note: skipping {}: there is no {scenario} question engine yet",
                    scenario.folder_name()
                );
            }
        }
    }
    drop(stderr);
    if with_engine.is_empty() {
        return Err(user_error(format!(
            "data root `{}` has no folder of a scenario with a question engine ({})",
            settings.data.display(),
            scenarios::names_with(|row| row.engine.is_some())
        )));
    }
    for (scenario, engine) in with_engine {
        scenario_questions(&root, scenario, engine, settings)?;
    }
    Ok(ExitCode::SUCCESS)
}

/// One scenario's questions: per-video files, the sampled splits and a summary on stdout.
fn scenario_questions(
    root: &DataRoot,
    scenario: Scenario,
    engine: &QuestionEngine,
    settings: &QuestionsSettings,
) -> Result<(), AppError> {
    let listing = root.list_videos(scenario).user()?;
    if listing.valid.is_empty() {
        return Err(user_error(format!(
            "`{}` has no valid video folder",
            root.scenario_dir(scenario).display()
        )));
    }
    let mut per_video = Vec::with_capacity(listing.valid.len());
    for video in &listing.valid {
        let questions = (engine.generate)(video, settings.seed).user()?;
        let path = settings
            .out
            .join(scenario.folder_name())
            .join(format!("{}.json", video.id));
        write_per_video_file(&path, &questions).internal()?;
        per_video.push(questions);
    }
    let config = SamplerConfig {
        fact_per_video: settings
            .fact_per_video
            .unwrap_or(engine.per_video.fact_per_video),
        dynamics_per_video: settings
            .dynamics_per_video
            .unwrap_or(engine.per_video.dynamics_per_video),
    };
    let splits = sample_and_split(scenario, &per_video, &config, settings.seed);
    // Families in the engine's template order.
    let mut family_counts: IndexMap<String, usize> = IndexMap::new();
    for questions in &per_video {
        for (family, records) in &questions.question_dict {
            *family_counts.entry(family.clone()).or_insert(0) += records.len();
        }
    }
    let mut stdout = std::io::stdout().lock();
    let _ = writeln!(
        stdout,
        "{} videos ({} invalid skipped) -> {}",
        listing.valid.len(),
        listing.invalid.len(),
        settings.out.join(scenario.folder_name()).display()
    );
    let _ = writeln!(stdout, "\n| family | questions |\n|---|---:|");
    for (family, count) in &family_counts {
        let _ = writeln!(stdout, "| {family} | {count} |");
    }
    let _ = writeln!(
        stdout,
        "\n| split | file | sampled questions |\n|---|---|---:|"
    );
    for split in Split::ALL {
        let records = splits.get(split);
        let name = questions_file_name(scenario, split);
        write_sampled_file(&settings.out.join(&name), records).internal()?;
        let _ = writeln!(
            stdout,
            "| {} | {name} | {} |",
            split.as_str(),
            records.len()
        );
    }
    Ok(())
}

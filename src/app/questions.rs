//! `questions`: the rope question engine over a data root, writing per-video files and the
//! sampled train/val/test files.

use std::io::Write as _;
use std::process::ExitCode;

use super::error::{AppError, Classify as _, user_error};
use super::settings::QuestionsSettings;
use crate::dataset::engine::{SamplerConfig, generate_rope_questions, sample_and_split};
use crate::dataset::{
    DataRoot, RopeAnnotation, Scenario, Split, questions_file_name, write_per_video_file,
    write_sampled_file,
};

pub(crate) fn questions(settings: &QuestionsSettings) -> Result<ExitCode, AppError> {
    let root = DataRoot::open(&settings.data).user()?;
    let scenarios = root.scenarios();
    if scenarios.is_empty() {
        return Err(user_error(format!(
            "data root `{}` has no scenario folder (pulley_group, fluid_slides, cloth_collision or soft_body)",
            settings.data.display()
        )));
    }
    let mut stderr = std::io::stderr().lock();
    for scenario in scenarios.iter().filter(|s| **s != Scenario::Rope) {
        let _ = writeln!(
            stderr,
            "note: skipping {}: only the rope question engine is public",
            scenario.folder_name()
        );
    }
    if !scenarios.contains(&Scenario::Rope) {
        return Err(user_error(format!(
            "data root `{}` has no `pulley_group` folder",
            settings.data.display()
        )));
    }
    let listing = root.list_videos(Scenario::Rope).user()?;
    if listing.valid.is_empty() {
        return Err(user_error(format!(
            "`{}` has no valid video folder",
            root.scenario_dir(Scenario::Rope).display()
        )));
    }
    let mut per_video = Vec::with_capacity(listing.valid.len());
    for video in &listing.valid {
        let annotation = RopeAnnotation::load(&video.outputs_json()).user()?;
        let questions = generate_rope_questions(&video.id, &annotation, settings.seed).user()?;
        let path = settings
            .out
            .join(Scenario::Rope.folder_name())
            .join(format!("{}.json", video.id));
        write_per_video_file(&path, &questions).internal()?;
        per_video.push(questions);
    }
    let config = SamplerConfig {
        fact_per_video: settings.fact_per_video,
        dynamics_per_video: settings.dynamics_per_video,
    };
    let splits = sample_and_split(&per_video, &config, settings.seed);
    // Families in the engine's template order.
    let mut family_counts: indexmap::IndexMap<String, usize> = indexmap::IndexMap::new();
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
        settings.out.join(Scenario::Rope.folder_name()).display()
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
        let name = questions_file_name(Scenario::Rope, split);
        write_sampled_file(&settings.out.join(&name), records).internal()?;
        let _ = writeln!(
            stdout,
            "| {} | {name} | {} |",
            split.as_str(),
            records.len()
        );
    }
    Ok(ExitCode::SUCCESS)
}

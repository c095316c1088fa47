//! End-to-end fluid runs: the builtin programs with annotation backends answer every question
//! the fluid engine asks, every option of every family, of the hand-made video
//! `tests/data/fluid_slides/0` (several engine seeds, per option and per question) and of a
//! short generated video. A wrong answer means the engine, the writer or the scene API disagree.

use std::collections::BTreeMap;
use std::path::Path;

use crate::support::{assert_perfect, contphy, fixture_data_root, stderr};

/// The fluid engine's families.
const FLUID_FAMILIES: [&str; 7] = [
    "density",
    "stick_number",
    "fluid_predictive_pass",
    "fluid_predictive_container",
    "fluid_counterfactual_pass",
    "fluid_counterfactual_container",
    "fluid_goaldriven_container",
];

/// Writes the engine's questions of every video of `data` with `seed`, then runs the builtin
/// programs on video `0`'s question file into `run` with `extra` options.
fn questions_and_run(data: &Path, seed: &str, run: &Path, extra: &[&str]) {
    let output = contphy(data, &["questions", "--data", ".", "--seed", seed]);
    assert!(output.status.success(), "{}", stderr(&output));
    let mut args = vec![
        "--data",
        ".",
        "--questions",
        "fluid_slides/0.json",
        "--out",
        run.to_str().unwrap(),
        "--quiet",
    ];
    args.extend_from_slice(extra);
    let output = contphy(data, &args);
    assert!(output.status.success(), "seed {seed}: {}", stderr(&output));
}

#[test]
fn builtin_programs_answer_every_fluid_family_of_the_fixture() {
    let data = fixture_data_root("fluid_slides", 1);
    let mut totals: BTreeMap<String, [u64; 4]> = BTreeMap::new();
    for seed in ["0", "1", "2", "3", "4"] {
        let run = data.path().join(format!("run-{seed}"));
        questions_and_run(data.path(), seed, &run, &[]);
        for (family, counts) in assert_perfect(&run, &FLUID_FAMILIES) {
            let total = totals.entry(family).or_default();
            for (sum, count) in total.iter_mut().zip(counts) {
                *sum += count;
            }
        }
    }
    // Every family is asked (and answered) over the seeds; the fixture's fixed counts: six
    // ordered density pairs, one stick count, one predictive question of each kind (the
    // yellow fluid's later emitter) per seed.
    assert_eq!(
        totals.keys().map(String::as_str).collect::<Vec<_>>(),
        {
            let mut sorted = FLUID_FAMILIES.to_vec();
            sorted.sort_unstable();
            sorted
        },
        "{totals:?}"
    );
    assert_eq!(totals["density"][1], 30);
    assert_eq!(totals["stick_number"][1], 5);
    assert_eq!(totals["fluid_predictive_pass"][1], 5);
    assert_eq!(totals["fluid_predictive_container"][1], 5);

    // One program per choice question answers all its options the same way.
    let run = data.path().join("per-question");
    questions_and_run(data.path(), "0", &run, &["--per-question"]);
    let per_question = assert_perfect(&run, &FLUID_FAMILIES);
    assert_eq!(per_question.len(), FLUID_FAMILIES.len(), "{per_question:?}");
}

/// A fluid trial long enough for the fluids to reach the containers, short enough for a debug
/// build (about 6 s a video): 400 updates, 300 captured, later emitters at 200, 80 particles an
/// emitter.
const REACHES_THE_CONTAINERS: contphy_eval::synth::fluid::FluidSynth =
    contphy_eval::synth::fluid::FluidSynth {
        timeline: contphy_eval::synth::fluid::simulate::Timeline {
            factual_updates: 400,
            capture_updates: 300,
            emitters_open: 2,
            later_emitters_open: 200,
            capacity: 80,
        },
    };

#[test]
fn builtin_programs_answer_every_question_of_generated_fluid_videos() {
    use contphy_eval::dataset::Scenario;
    use contphy_eval::synth::{
        GenerateOptions, appearance::Appearance, generate, video::FrameOutput,
    };
    let data = tempfile::tempdir().unwrap();
    let options = GenerateOptions {
        scenario: Scenario::Fluid,
        videos: 2,
        seed: 4,
        out: data.path().to_path_buf(),
        jobs: 1,
        frames: FrameOutput::None,
        width: 96,
        height: 54,
        appearance: Appearance::Release,
    };
    generate(&REACHES_THE_CONTAINERS, &options, &|_| {}).unwrap();
    let output = contphy(data.path(), &["questions", "--data", ".", "--seed", "0"]);
    assert!(output.status.success(), "{}", stderr(&output));
    let mut asked = BTreeMap::new();
    for video in ["0", "1"] {
        let run = data.path().join(format!("run-{video}"));
        let output = contphy(
            data.path(),
            &[
                "--data",
                ".",
                "--questions",
                &format!("fluid_slides/{video}.json"),
                "--out",
                run.to_str().unwrap(),
                "--quiet",
            ],
        );
        assert!(
            output.status.success(),
            "video {video}: {}",
            stderr(&output)
        );
        for (family, [_, questions, _, options]) in assert_perfect(&run, &FLUID_FAMILIES) {
            let total: &mut [u64; 2] = asked.entry(family).or_default();
            total[0] += questions;
            total[1] += options;
        }
    }
    // These short runs leave no question where removing a stick decides which container holds
    // most of a fluid; the fixture asks the goal-driven family.
    assert_eq!(
        asked.len(),
        FLUID_FAMILIES.len() - 1,
        "every other family is asked: {asked:?}"
    );
}

//! `generate`: synthetic rope videos in the release format. They load through the same loader
//! as the real video, their boxes and masks agree with their pixels and with the 4-D data, the
//! same seed gives the same bytes whatever the job count, an interrupted generation resumes,
//! and bad requests fail with one line.

use std::fmt::Write as _;
use std::path::Path;
use std::process::Command;

use contphy_eval::dataset::rope::RopeAnnotation;
use contphy_eval::dataset::{DataRoot, FourDData, Scenario};
use contphy_eval::perception::camera::CameraModel;
use contphy_eval::perception::frames::FrameSource;
use contphy_eval::synth::palette::instance_color;
use contphy_eval::synth::video::FrameOutput;
use contphy_eval::synth::{
    GenerateOptions, ScenarioSynth, appearance::Appearance, generate as generate_in_process,
};

use crate::support::{contphy, root, stderr, stdout};

fn generate(out: &Path, videos: &str, seed: &str, jobs: &str) -> std::process::Output {
    generate_with(out, videos, seed, jobs, &[])
}

/// [`generate`] with more options (`extra`).
fn generate_with(
    out: &Path,
    videos: &str,
    seed: &str,
    jobs: &str,
    extra: &[&str],
) -> std::process::Output {
    let mut args = vec![
        "generate",
        "--scenario",
        "rope",
        "--videos",
        videos,
        "--seed",
        seed,
        "--frames",
        "png",
        "--resolution",
        "192x108",
        "--jobs",
        jobs,
        "--quiet",
        "--out",
        out.to_str().unwrap(),
    ];
    args.extend_from_slice(extra);
    contphy(&root(), &args)
}

/// The boxes of one capture: instance id → (x0, y0, width, height).
fn boxes(capture: &serde_json::Value) -> Vec<(u32, [f64; 4])> {
    let annotations = capture[0]["annotations"].as_array().unwrap();
    let boxes = annotations
        .iter()
        .find(|a| a["@type"] == "type.unity.com/unity.solo.BoundingBox2DAnnotation")
        .unwrap();
    boxes["values"]
        .as_array()
        .unwrap()
        .iter()
        .map(|v| {
            let id = u32::try_from(v["instanceId"].as_u64().unwrap()).unwrap();
            let origin = v["origin"].as_array().unwrap();
            let size = v["dimension"].as_array().unwrap();
            (
                id,
                [
                    origin[0].as_f64().unwrap(),
                    origin[1].as_f64().unwrap(),
                    size[0].as_f64().unwrap(),
                    size[1].as_f64().unwrap(),
                ],
            )
        })
        .collect()
}

#[test]
fn generated_videos_load_and_their_boxes_masks_and_tracks_agree() {
    let out = tempfile::tempdir().unwrap();
    let output = generate(out.path(), "2", "3", "2");
    assert!(output.status.success(), "{}", stderr(&output));
    let text = stdout(&output);
    assert!(text.starts_with("generated 2 rope videos"), "{text}");
    assert!(text.contains("| rope_counterfactual2 |"), "{text}");
    let data = DataRoot::open(out.path()).unwrap();
    let listing = data.list_videos(Scenario::Rope).unwrap();
    assert_eq!(listing.valid.len(), 2);
    for file in [
        "pulley_group/0.json",
        "pulley_group/1.json",
        "pulley_group_train.json",
        "pulley_group_test.json",
        "generate.json",
    ] {
        assert!(out.path().join(file).is_file(), "{file}");
    }
    let mut boxes_checked = 0;
    for video in &listing.valid {
        let annotation = RopeAnnotation::load(&video.outputs_json()).unwrap();
        let four_d = FourDData::load(&video.outputs_4d_json()).unwrap();
        assert_eq!(annotation.frame_count, 150);
        assert_eq!(four_d.frame_count(), 150);
        assert!(!annotation.counterfactuals.is_empty());
        let camera_record = annotation.camera.clone().unwrap();
        let camera = CameraModel::from_unity_euler(
            camera_record.position,
            camera_record.rotation_deg,
            camera_record.vertical_fov_deg,
            192,
            108,
        );
        let raw: serde_json::Value =
            serde_json::from_slice(&fs_err::read(video.outputs_json()).unwrap()).unwrap();
        let per_frame = &raw["imgAnnotationDescriptions"]["perFrameAnnotations"];
        let names = &raw["imgAnnotationDescriptions"]["Id2ObjectNameDict"];
        let segmentation = FrameSource::open(&video.dir.join("frames/output_Full_seg")).unwrap();
        let frames = [0_usize, 75, 149];
        let images = segmentation.read(&frames).unwrap();
        for (frame, image) in frames.iter().zip(&images) {
            let capture = &per_frame[(frame + 1).to_string()];
            for (id, [x0, y0, width, height]) in boxes(capture) {
                // The mask's pixels span exactly the box.
                let color = &instance_color(id)[..3];
                let (mut low_x, mut low_y, mut high_x, mut high_y) = (u32::MAX, u32::MAX, 0, 0);
                let mut count = 0;
                for y in 0..image.height {
                    for x in 0..image.width {
                        if image.pixel(x, y).unwrap() == [color[0], color[1], color[2]] {
                            count += 1;
                            low_x = low_x.min(x);
                            low_y = low_y.min(y);
                            high_x = high_x.max(x);
                            high_y = high_y.max(y);
                        }
                    }
                }
                let name = names[id.to_string()].as_str().unwrap();
                assert!(count > 0, "{name} has a box but no mask in frame {frame}");
                let mask_box = [
                    f64::from(low_x),
                    f64::from(low_y),
                    f64::from(high_x - low_x + 1),
                    f64::from(high_y - low_y + 1),
                ];
                // Whole pixels on both sides: equal means equal.
                assert!(
                    mask_box
                        .iter()
                        .zip([x0, y0, width, height])
                        .all(|(a, b)| (a - b).abs() < 1e-9),
                    "{name}, frame {frame}: mask spans {mask_box:?}, box {:?}",
                    [x0, y0, width, height]
                );
                // A load's tracked centroid projects inside its box.
                if let Some(track) = four_d.rigid_bodies.get(name)
                    && (name.ends_with("Cube") || name.ends_with("Sphere"))
                {
                    let p = camera.project(track.poses[*frame].0).unwrap();
                    assert!(
                        p.x >= x0 && p.x <= x0 + width && p.y >= y0 && p.y <= y0 + height,
                        "{name} frame {frame}: centroid ({}, {}) outside its box",
                        p.x,
                        p.y
                    );
                }
                boxes_checked += 1;
            }
        }
    }
    assert!(boxes_checked > 30, "{boxes_checked}");
}

#[test]
fn the_same_seed_gives_the_same_bytes_and_an_interrupted_generation_resumes() {
    let one = tempfile::tempdir().unwrap();
    let two = tempfile::tempdir().unwrap();
    assert!(generate(one.path(), "1", "5", "1").status.success());
    assert!(generate(two.path(), "2", "5", "2").status.success());
    for file in [
        "outputs.json",
        "outputs4D.json",
        "frames/output_Full_ori/frame_00000.png",
        "frames/output_Full_seg/frame_00149.png",
    ] {
        let a = fs_err::read(one.path().join("pulley_group/0").join(file)).unwrap();
        let b = fs_err::read(two.path().join("pulley_group/0").join(file)).unwrap();
        assert!(a == b, "{file} differs between runs");
    }
    // Folders already written are kept: a second run only makes the questions again.
    let again = generate(two.path(), "2", "5", "2");
    assert!(again.status.success(), "{}", stderr(&again));
    assert!(
        stdout(&again).starts_with("generated 2 rope videos (2 kept from an earlier run)"),
        "{}",
        stdout(&again)
    );
    assert!(
        !two.path().join("pulley_group/.partial-0").exists(),
        "no half-written folder is left"
    );
    // Another seed into the same data root would mix two datasets: refused.
    let mixed = generate(two.path(), "3", "6", "2");
    assert_eq!(mixed.status.code(), Some(1));
    assert!(
        stderr(&mixed).contains("holds videos generated with"),
        "{}",
        stderr(&mixed)
    );
    assert!(!two.path().join("pulley_group/2").exists());
}

#[test]
fn bad_generate_requests_fail_with_one_line() {
    let out = tempfile::tempdir().unwrap();
    let target = out.path().join("data");
    let target = target.to_str().unwrap();
    let cases: [(&str, Vec<&str>, i32); 6] = [
        ("no_videos", vec!["--videos", "0"], 1),
        ("no_scenario", vec!["--videos", "1"], 1),
        (
            "into_a_data_root_it_did_not_make",
            vec!["--videos", "1", "--scenario", "fluid", "--frames", "none"],
            1,
        ),
        (
            "tiny_resolution",
            vec!["--videos", "1", "--resolution", "12x8"],
            1,
        ),
        (
            "mp4_without_ffmpeg",
            vec!["--videos", "1", "--scenario", "rope", "--frames", "mp4"],
            1,
        ),
        (
            "malformed_resolution",
            vec!["--videos", "1", "--resolution", "wide"],
            2,
        ),
    ];
    let mut transcript = String::new();
    for (name, args, code) in cases {
        // A release data root (a rope video folder, no generate manifest) for the one case.
        let _ = fs_err::remove_dir_all(out.path().join("data"));
        if name == "into_a_data_root_it_did_not_make" {
            fs_err::create_dir_all(out.path().join("data/pulley_group/0")).unwrap();
        }
        let mut command = Command::new(env!("CARGO_BIN_EXE_contphy-eval"));
        command
            .arg("generate")
            .args(&args)
            .args(["--out", target, "--quiet"])
            .env("NO_COLOR", "1")
            // No ffmpeg here, whatever the machine has.
            .env("CONTPHY_FFMPEG_DIR", out.path().join("no-ffmpeg"));
        let output = command.output().unwrap();
        assert_eq!(
            output.status.code(),
            Some(code),
            "{name}: {}",
            stderr(&output)
        );
        let message = stderr(&output).replace(target, "[OUT]");
        assert!(!message.contains("panicked"), "{name}: {message}");
        if code == 1 {
            assert_eq!(message.lines().count(), 1, "{name}: {message}");
        }
        let _ = writeln!(transcript, "## {name}\n{message}");
    }
    insta::assert_snapshot!("generate_errors", transcript);
}

#[test]
fn a_randomised_appearance_changes_the_pixels_only() {
    // The same seed with `--appearance randomized`: the same annotations, 4-D data and
    // segmentation (geometry and simulation are untouched), other colours in the frames, and the
    // same bytes again on a second run. A data root keeps one appearance.
    let release = tempfile::tempdir().unwrap();
    let randomized = tempfile::tempdir().unwrap();
    let again = tempfile::tempdir().unwrap();
    assert!(generate(release.path(), "1", "8", "1").status.success());
    let randomize = |out: &Path, seed: &str| {
        generate_with(out, "1", seed, "1", &["--appearance", "randomized"])
    };
    assert!(randomize(randomized.path(), "8").status.success());
    assert!(randomize(again.path(), "8").status.success());
    let read =
        |root: &Path, file: &str| fs_err::read(root.join("pulley_group/0").join(file)).unwrap();
    for file in [
        "outputs.json",
        "outputs4D.json",
        "frames/output_Full_seg/frame_00000.png",
        "frames/output_Full_seg/frame_00100.png",
    ] {
        assert!(
            read(release.path(), file) == read(randomized.path(), file),
            "{file} changed with the appearance"
        );
    }
    let frame = "frames/output_Full_ori/frame_00000.png";
    assert!(read(release.path(), frame) != read(randomized.path(), frame));
    assert!(read(randomized.path(), frame) == read(again.path(), frame));
    // The release's look into a randomised data root is refused.
    let mixed = generate(randomized.path(), "2", "8", "1");
    assert_eq!(mixed.status.code(), Some(1), "{}", stderr(&mixed));
    assert!(
        stderr(&mixed).contains("\"appearance\":\"randomized\""),
        "{}",
        stderr(&mixed)
    );
}

/// Checks, for each of `frames` of `video`, that every annotated box spans exactly the pixels of
/// its instance's colour in the segmentation frames; returns the names of the boxed objects.
fn boxes_match_masks(video: &contphy_eval::dataset::VideoFolder, frames: &[usize]) -> Vec<String> {
    let raw: serde_json::Value =
        serde_json::from_slice(&fs_err::read(video.outputs_json()).unwrap()).unwrap();
    let per_frame = &raw["imgAnnotationDescriptions"]["perFrameAnnotations"];
    let names = &raw["imgAnnotationDescriptions"]["Id2ObjectNameDict"];
    let segmentation = FrameSource::open(&video.dir.join("frames/output_Full_seg")).unwrap();
    let images = segmentation.read(frames).unwrap();
    let mut boxed = Vec::new();
    for (frame, image) in frames.iter().zip(&images) {
        for (id, [x0, y0, width, height]) in boxes(&per_frame[(frame + 1).to_string()]) {
            let color = &instance_color(id)[..3];
            let (mut low_x, mut low_y, mut high_x, mut high_y) = (u32::MAX, u32::MAX, 0, 0);
            for y in 0..image.height {
                for x in 0..image.width {
                    if image.pixel(x, y).unwrap() == [color[0], color[1], color[2]] {
                        low_x = low_x.min(x);
                        low_y = low_y.min(y);
                        high_x = high_x.max(x);
                        high_y = high_y.max(y);
                    }
                }
            }
            let name = names[id.to_string()].as_str().unwrap();
            assert!(
                low_x != u32::MAX,
                "{name} has a box but no mask in frame {frame}"
            );
            let mask_box = [low_x, low_y, high_x - low_x + 1, high_y - low_y + 1].map(f64::from);
            // Whole pixels on both sides: equal means equal.
            assert!(
                mask_box
                    .iter()
                    .zip([x0, y0, width, height])
                    .all(|(a, b)| (a - b).abs() < 1e-9),
                "{name}, frame {frame}: mask spans {mask_box:?}, box {:?}",
                [x0, y0, width, height]
            );
            boxed.push(name.to_string());
        }
    }
    boxed
}

/// Generates video 0 of `scenario` in process (seed 4, 192×108 PNG frames, one job) into a new
/// folder; returns the folder and the options.
fn generate_one(
    synth: &dyn ScenarioSynth,
    scenario: Scenario,
) -> (tempfile::TempDir, GenerateOptions) {
    let out = tempfile::tempdir().unwrap();
    let options = GenerateOptions {
        scenario,
        videos: 1,
        seed: 4,
        out: out.path().to_path_buf(),
        jobs: 1,
        frames: FrameOutput::Png,
        width: 192,
        height: 108,
        appearance: Appearance::Release,
    };
    generate_in_process(synth, &options, &|_| {}).unwrap();
    (out, options)
}

/// Generates two videos with two jobs from `options` (as [`generate_one`] made them) and checks
/// that video 0's `files` have the same bytes as in `options.out`: the job count changes nothing.
fn assert_same_bytes_with_two_jobs(
    synth: &dyn ScenarioSynth,
    options: &GenerateOptions,
    files: &[&str],
) {
    let again = tempfile::tempdir().unwrap();
    let two_jobs = GenerateOptions {
        videos: 2,
        jobs: 2,
        out: again.path().to_path_buf(),
        ..options.clone()
    };
    generate_in_process(synth, &two_jobs, &|_| {}).unwrap();
    let video = Path::new(options.scenario.folder_name()).join("0");
    for file in files {
        let read = |root: &Path| fs_err::read(root.join(&video).join(file)).unwrap();
        assert!(read(&options.out) == read(again.path()), "{file} differs");
    }
}

/// A short fluid trial (the release's timeline would take minutes in a debug build): 120
/// updates, 80 captured, later emitters at 50, 80 particles an emitter.
const SHORT_FLUID: contphy_eval::synth::fluid::FluidSynth =
    contphy_eval::synth::fluid::FluidSynth {
        timeline: contphy_eval::synth::fluid::simulate::Timeline {
            factual_updates: 120,
            capture_updates: 80,
            emitters_open: 2,
            later_emitters_open: 50,
            capacity: 80,
        },
    };

#[test]
fn generated_fluid_videos_load_ask_questions_and_their_boxes_match_their_masks() {
    use contphy_eval::dataset::engine::fluid::ENGINE;
    use contphy_eval::dataset::fluid::FluidAnnotation;
    let (out, options) = generate_one(&SHORT_FLUID, Scenario::Fluid);
    let data = DataRoot::open(out.path()).unwrap();
    let listing = data.list_videos(Scenario::Fluid).unwrap();
    let video = &listing.valid[0];
    let annotation = FluidAnnotation::load(&video.outputs_json()).unwrap();
    assert_eq!(annotation.frame_count, 40);
    assert!((3..=4).contains(&annotation.layout.fluids.len()));
    assert!(
        !annotation.counterfactuals.is_empty(),
        "the release always removes a stick"
    );
    // The engine reads what the generator wrote: every family is present.
    let questions = (ENGINE.generate)(video, 0).unwrap();
    assert_eq!(questions.question_dict.len(), ENGINE.families.len());
    let stick_number = &questions.question_dict["stick_number"];
    let sticks = annotation.layout.sticks.len().to_string();
    assert!(stick_number.iter().all(|record| record.answer == sticks));
    let fluids_seen = boxes_match_masks(video, &[0, 39])
        .iter()
        .filter(|name| name.ends_with("Fluid"))
        .count();
    assert!(
        fluids_seen >= 3,
        "the fluids are drawn and labelled: {fluids_seen}"
    );
    // The same seed gives the same bytes whatever the job count.
    assert_same_bytes_with_two_jobs(
        &SHORT_FLUID,
        &options,
        &[
            "outputs.json",
            "outputs4D.json",
            "frames/output_Full_ori/frame_00039.png",
        ],
    );
}

#[test]
fn generated_ball_videos_load_ask_questions_and_their_boxes_match_their_masks() {
    use contphy_eval::dataset::ball::BallAnnotation;
    use contphy_eval::dataset::engine::ball::ENGINE;
    use contphy_eval::synth::ball::BALL_SYNTH;
    let (out, options) = generate_one(&BALL_SYNTH, Scenario::Ball);
    let data = DataRoot::open(out.path()).unwrap();
    let listing = data.list_videos(Scenario::Ball).unwrap();
    let video = &listing.valid[0];
    let annotation = BallAnnotation::load(&video.outputs_json()).unwrap();
    assert_eq!(annotation.frame_count, 120);
    assert_eq!(annotation.counterfactuals.len(), 6);
    let questions = (ENGINE.generate)(video, 0).unwrap();
    assert_eq!(questions.question_dict.len(), ENGINE.families.len());
    assert_eq!(questions.question_dict["elasticity"].len(), 4);
    // The 4-D data reads back: static slabs with their first pose and voxels, 91 tracked
    // particles a ball in each of the 120 frames.
    let four_d = FourDData::load(&video.dir.join("outputs4D.json")).unwrap();
    assert_eq!(four_d.frame_count(), 120);
    assert_eq!(four_d.rigid_bodies.len(), 7);
    for (name, slab) in &four_d.rigid_bodies {
        assert!(slab.is_static && slab.first_pose.is_some(), "{name}");
        assert!(!slab.voxels.is_empty(), "{name}");
    }
    for ball in &annotation.layout.balls {
        let track = &four_d.soft_bodies[&ball.name];
        assert!(track.particles.iter().all(|frame| frame.len() == 91));
    }
    let balls_seen = boxes_match_masks(video, &[0, 60])
        .iter()
        .filter(|name| name.ends_with(" Ball"))
        .count();
    assert!(
        balls_seen >= 4,
        "the balls are drawn and labelled: {balls_seen}"
    );
    // The same seed gives the same bytes whatever the job count.
    assert_same_bytes_with_two_jobs(
        &BALL_SYNTH,
        &options,
        &[
            "outputs.json",
            "outputs4D.json",
            "frames/output_Full_ori/frame_00060.png",
        ],
    );
}

#[test]
fn generated_cloth_videos_load_ask_questions_and_their_boxes_match_their_masks() {
    use contphy_eval::dataset::cloth::ClothAnnotation;
    use contphy_eval::dataset::engine::cloth::ENGINE;
    use contphy_eval::synth::cloth::CLOTH_SYNTH;
    let (out, options) = generate_one(&CLOTH_SYNTH, Scenario::Cloth);
    let data = DataRoot::open(out.path()).unwrap();
    let listing = data.list_videos(Scenario::Cloth).unwrap();
    let video = &listing.valid[0];
    let annotation = ClothAnnotation::load(&video.outputs_json()).unwrap();
    assert_eq!(annotation.frame_count, 145);
    let questions = (ENGINE.generate)(video, 0).unwrap();
    assert_eq!(questions.question_dict["elasticity"].len(), 2);
    assert_eq!(questions.question_dict["bending"].len(), 2);
    // The 4-D data reads back: every pillar and plate with its poses, 961 tracked particles a
    // cloth in each of the 115 frames from the cloth's spawn.
    let four_d = FourDData::load(&video.dir.join("outputs4D.json")).unwrap();
    assert_eq!(four_d.frame_count(), 115);
    let names: Vec<&str> = annotation.boxes().map(|(_, b)| b.name.as_str()).collect();
    for name in &names {
        let track = &four_d.rigid_bodies[*name];
        assert!(!track.voxels.is_empty(), "{name}");
    }
    for cloth in ["Cloth (Left)", "Cloth (Right)"] {
        let track = &four_d.soft_bodies[cloth];
        assert!(track.particles.iter().all(|frame| frame.len() == 961));
    }
    // Before the cloths spawn every box is in view; at the end both cloths are.
    let first = boxes_match_masks(video, &[0]);
    for name in &names {
        assert!(first.iter().any(|seen| seen == name), "{name} not boxed");
    }
    let last = boxes_match_masks(video, &[144]);
    for cloth in ["Cloth (Left)", "Cloth (Right)"] {
        assert!(last.iter().any(|seen| seen == cloth), "{cloth} not boxed");
    }
    // The same seed gives the same bytes whatever the job count.
    assert_same_bytes_with_two_jobs(
        &CLOTH_SYNTH,
        &options,
        &[
            "outputs.json",
            "outputs4D.json",
            "frames/output_Full_ori/frame_00144.png",
            "frames/output_Full_seg/frame_00144.png",
        ],
    );
}

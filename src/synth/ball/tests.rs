//! The ball generator against the release's format and rules: its `outputs.json` reads back
//! through the typed reader, every ball has a factual record and six counterfactual runs exist
//! (each wall removed, each ball alone), labels agree with the simulated tracks, and a seed
//! always gives the same video.

use std::path::Path;

use serde_json::Value;

use super::*;
use crate::dataset::ball::BallAnnotation;
use crate::dataset::ball::outcome::{CAPTURE_UPDATES, PitResult};

fn outputs_json(video: &SynthesizedVideo) -> Value {
    let mut all = video.annotations.clone();
    all.extend(video.trailing.clone());
    Value::Object(all)
}

#[test]
fn a_generated_video_reads_back_with_the_releases_keys_and_runs() {
    let video = BALL_SYNTH.synthesize(7, 96, 54).unwrap();
    let annotation =
        BallAnnotation::from_json(Path::new("soft_body/0/outputs.json"), &outputs_json(&video))
            .unwrap();
    assert_eq!(annotation.layout.balls.len(), 3);
    assert_eq!(annotation.tracking.len(), 3);
    assert_eq!(annotation.layout.floating_walls.len(), 2);
    assert_eq!(annotation.layout.floor_pieces.len(), 3);
    assert_eq!(annotation.counterfactuals.len(), 6);
    for wall in &annotation.layout.floating_walls {
        for ball in &annotation.layout.balls {
            let run = annotation.counterfactual(&wall.name, &ball.name).unwrap();
            assert!(!matches!(run.record.result, PitResult::ToPredict(_)));
        }
    }
    // Frame numbers agree with the results: observed drops within the video's 120 frames,
    // predicted ones after it, no pit at frame 0.
    for record in annotation.tracking.values() {
        let last_frame = u32::try_from(CAPTURE_UPDATES / 2).unwrap();
        match record.result {
            PitResult::Observed(_) => assert!(record.frame >= 1 && record.frame <= last_frame),
            PitResult::ToPredict(_) => assert!(record.frame > last_frame),
            PitResult::NoPit => assert_eq!(record.frame, 0),
        }
    }
    assert_eq!(video.frames.len(), 120);
    // Each frame draws the 7 slabs and the 3 balls; the labels name them all.
    assert_eq!(video.frames[0].len(), 10);
    assert_eq!(video.labels.len(), 10);
    let four_d = &video.four_d["softbody4D"]["softbodyTrackedParticles"];
    for ball in &annotation.layout.balls {
        let frames = four_d[&ball.name].as_array().unwrap();
        assert_eq!(frames.len(), 120);
        assert_eq!(frames[0].as_array().unwrap().len(), 91);
    }
}

#[test]
fn a_seed_gives_the_same_video() {
    let a = BALL_SYNTH.synthesize(3, 64, 36).unwrap();
    let b = BALL_SYNTH.synthesize(3, 64, 36).unwrap();
    assert_eq!(outputs_json(&a), outputs_json(&b));
    assert_eq!(a.four_d, b.four_d);
    let c = BALL_SYNTH.synthesize(4, 64, 36).unwrap();
    assert_ne!(outputs_json(&a), outputs_json(&c));
}

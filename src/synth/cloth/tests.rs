//! The cloth generator against the release's format and rules: its `outputs.json` reads back
//! through the typed reader; the two cloths differ in all three properties; masses come from the
//! half's pools; records agree with each other (a box that fell moved, touchers are neighbours in
//! its half, events are in time order within the run); 145 frames and 115 4-D frames of 961
//! particles per cloth; and a seed always gives the same bytes (a golden hash).

use std::path::Path;

use serde_json::Value;

use super::*;
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::{ClothAnnotation, Friction};

fn outputs_json(video: &SynthesizedVideo) -> Value {
    let mut all = video.annotations.clone();
    all.extend(video.trailing.clone());
    Value::Object(all)
}

#[test]
fn a_generated_video_reads_back_with_consistent_records_and_a_golden_hash() {
    let video = CLOTH_SYNTH.synthesize(5, 64, 36).unwrap();
    let json = outputs_json(&video);
    let annotation =
        ClothAnnotation::from_json(Path::new("cloth_collision/0/outputs.json"), &json).unwrap();
    let (left, right) = (&annotation.left_cloth, &annotation.right_cloth);
    assert!(left.stretching_compliance.to_bits() != right.stretching_compliance.to_bits());
    assert!(left.bending_compliance.to_bits() != right.bending_compliance.to_bits());
    assert_ne!(left.friction, right.friction);
    for side in Side::BOTH {
        let friction = annotation.cloth(side).friction;
        let objects = annotation.objects(side);
        let names: Vec<&str> = objects.boxes().map(|b| b.name.as_str()).collect();
        assert!((2..=4).contains(&names.len()), "{names:?}");
        for record in objects.boxes() {
            let heavy = record.mass > 99000.0;
            let light = match (friction, record.name.ends_with("Plate")) {
                (Friction::Low, true) => (2.0..2.003).contains(&record.mass),
                (Friction::Low, false) => (6.5..6.5003).contains(&record.mass),
                (Friction::High, true) => (4.0..4.003).contains(&record.mass),
                (Friction::High, false) => (12.0..12.003).contains(&record.mass),
            };
            assert!(heavy || light, "{} weighs {}", record.name, record.mass);
            if record.end_pose.fell_over() == Some(true) {
                assert!(
                    record.start_moving_update.is_some(),
                    "{} fell unmoved",
                    record.name
                );
            }
            let updates: Vec<u32> = record.collision_events.iter().map(|e| e.update).collect();
            assert!(updates.windows(2).all(|w| w[0] <= w[1]), "{updates:?}");
            assert!(
                updates.iter().all(|u| (60..=290).contains(u)),
                "{updates:?}"
            );
            for other in record.collision_events.iter().map(|e| e.other.as_str()) {
                assert!(
                    other == side.cloth_name() || names.contains(&other),
                    "{other}"
                );
            }
            for other in &record.touchers {
                assert!(other == side.cloth_name() || names.contains(&other.as_str()));
                if other != side.cloth_name() {
                    assert!(annotation.in_touch(&record.name, other));
                }
            }
        }
    }
    assert_eq!(video.frames.len(), 145);
    // The table and the boxes before the cloth spawns; both cloths as well at the end.
    let boxes = annotation.boxes().count();
    assert_eq!(video.frames[0].len(), 1 + boxes);
    assert_eq!(video.frames[144].len(), 3 + boxes);
    assert_eq!(video.labels.len(), boxes + 3);
    let tracked = &video.four_d["softbody4D"]["softbodyTrackedParticles"];
    for side in Side::BOTH {
        let frames = tracked[side.cloth_name()].as_array().unwrap();
        assert_eq!(frames.len(), 115);
        assert_eq!(frames[0].as_array().unwrap().len(), 961);
    }
    let hash = blake3::hash(json.to_string().as_bytes())
        .to_hex()
        .to_string();
    assert_eq!(
        hash,
        "1718da8b46c21b57cac4b7cc548b9ec7b051eabd35b73db1d9f0a6dc3a90058e"
    );
}

/// Halves (seed of the layout, half) in which a cloth at the release's unscaled friction carried
/// a pillar 2.6–4 units into the air (seed 3 left, 12 right, 26 left), before the boxes' edges
/// met the cloth's triangles and the friction was scaled (`FRICTION_SCALE`).
#[test]
fn a_dragged_cloth_pushes_pillars_without_carrying_them() {
    for (seed, side) in [(3, 0), (12, 1), (26, 0)] {
        let mut rng = crate::util::seeded_rng(seed);
        let layout = loop {
            if let Some(layout) = sample_layout(&mut rng) {
                break layout;
            }
        };
        let half = &layout.halves[side];
        let run = run_half(half).unwrap();
        for (index, entry) in half.boxes.iter().enumerate() {
            let start = run.frames[0].boxes[index].0[1];
            let highest = run
                .frames
                .iter()
                .map(|frame| frame.boxes[index].0[1])
                .fold(f64::NEG_INFINITY, f64::max);
            assert!(
                highest - start < 0.3,
                "seed {seed}: {} rose {:.2} units",
                entry.name,
                highest - start
            );
        }
        // The cloth still pushes the pillar it used to carry (or the plate it falls on).
        let moved = run
            .outcomes
            .iter()
            .filter(|o| o.start_moving.is_some())
            .count();
        assert!(moved >= 1, "seed {seed}: nothing moved");
    }
}

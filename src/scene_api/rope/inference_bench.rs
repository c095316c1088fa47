//! Rope's part of `bench inference --data DIR`: how well the rope masses inferred from tracked
//! motion (what `--dynamics simulate` answers mass and tension questions with) match the masses
//! the videos were made with, pair by pair, as a JSON report.
//!
//! With `--noise σ,…` the tracked centroid heights are perturbed by seeded Gaussian noise of
//! standard deviation σ (units) before inference, one sweep per level, to show how the decision
//! rule trades coverage for accuracy as tracking gets worse (the release's own tracks are exact
//! simulator states; a detector's are not).
//!
//! Every ordered pair of loads of a video is scored. A pair in one related group is *decided*
//! or *undecidable* (with the reason); a decided pair is *correct* when its ratio class (the
//! first mass against the second, twice it and half of it, as the questions ask) equals the
//! class of the nominal masses in `outputMass` (`ceil(m·100)/100`). Pairs in different groups
//! are counted apart: the benchmark answers "can not answer" for them, and inference must not
//! decide them.

use std::time::Instant;

use indexmap::IndexMap;
use serde_json::{Value, json};

use super::simulation::infer_rope_masses;
use crate::dataset::rope::RopeAnnotation;
use crate::dataset::{FourDData, VideoFolder};
use crate::physics::rope::identify::{PairVerdict, RatioClass, Undecidable};
use crate::scene_api::ApiError;
use crate::util::{derive_seed, seeded_rng, standard_normal};

/// A short key for an undecidable reason.
fn reason_key(reason: &Undecidable) -> &'static str {
    match reason {
        Undecidable::DifferentMechanisms => "different_mechanisms",
        Undecidable::Untracked { .. } => "untracked",
        Undecidable::NoCleanWindow { .. } => "no_clean_window",
        Undecidable::Unexplained { .. } => "unexplained",
        Undecidable::RestsAgainstStop { .. } => "rests_against_stop",
        Undecidable::FreeFall { .. } => "free_fall",
        Undecidable::MassHidden { .. } => "mass_hidden",
        Undecidable::MotionTooSmall { .. } => "motion_too_small",
        Undecidable::Ambiguous { .. } => "ambiguous",
    }
}

fn nominal(mass: f64) -> f64 {
    (mass * 100.0).ceil() / 100.0
}

fn describe(class: RatioClass) -> String {
    format!(
        "{:?} / twice {:?} / half {:?}",
        class.to_other, class.to_twice, class.to_half
    )
}

/// The report over `videos` (valid rope videos), one sweep per noise level (non-negative
/// standard deviations, units; the caller checks them).
pub fn inference_report(videos: &[VideoFolder], noise_levels: &[f64]) -> Result<Value, ApiError> {
    let mut loaded = Vec::with_capacity(videos.len());
    for video in videos {
        loaded.push((
            video.id.0.clone(),
            RopeAnnotation::load(&video.outputs_json())?,
            FourDData::load(&video.outputs_4d_json())?,
        ));
    }
    let sweeps: Vec<Value> = noise_levels
        .iter()
        .map(|&noise| sweep(&loaded, noise))
        .collect();
    Ok(if let [only] = sweeps.as_slice() {
        only.clone()
    } else {
        json!({"bench": "inference", "scenario": "rope", "sweeps": sweeps})
    })
}

/// Scores every pair of loads of `videos` with their tracked heights perturbed by `noise`.
fn sweep(videos: &[(String, RopeAnnotation, FourDData)], noise: f64) -> Value {
    let started = Instant::now();
    let mut within = 0_u64;
    let mut decided = 0_u64;
    let mut correct = 0_u64;
    let mut across = 0_u64;
    let mut across_decided = 0_u64;
    let mut reasons: IndexMap<&'static str, u64> = IndexMap::new();
    let mut undecided_cases = Vec::new();
    let mut wrong_cases = Vec::new();
    let mut failed_videos = Vec::new();
    for (id, annotation, tracked) in videos {
        let mut four_d = tracked.clone();
        if noise > 0.0 {
            let mut rng = seeded_rng(derive_seed(0, &format!("bench/inference/{id}/{noise}")));
            for track in four_d.rigid_bodies.values_mut() {
                for (position, _) in &mut track.poses {
                    position[1] += noise * standard_normal(&mut rng);
                }
            }
        }
        let inference = match infer_rope_masses(annotation, &four_d) {
            Ok(inference) => inference,
            Err(error) => {
                failed_videos.push(json!({"video": id, "error": error.to_string()}));
                continue;
            }
        };
        let loads: Vec<&String> = annotation.output_mass_kg.keys().collect();
        let group_of = |name: &str| {
            annotation
                .related_groups
                .iter()
                .position(|g| g.iter().any(|n| n == name))
        };
        for first in &loads {
            for second in &loads {
                if first == second {
                    continue;
                }
                let same_group = group_of(first).is_some() && group_of(first) == group_of(second);
                let verdict = inference.pair(first, second);
                if !same_group {
                    across += 1;
                    if matches!(verdict, Some(PairVerdict::Decided { .. })) {
                        across_decided += 1;
                    }
                    continue;
                }
                within += 1;
                let truth = RatioClass::of(
                    nominal(annotation.output_mass_kg[*first]),
                    nominal(annotation.output_mass_kg[*second]),
                );
                match verdict {
                    Some(PairVerdict::Decided { class, masses }) => {
                        decided += 1;
                        if class == truth {
                            correct += 1;
                        } else {
                            wrong_cases.push(json!({
                                "video": id,
                                "first": first,
                                "second": second,
                                "inferred_kg": masses,
                                "true_kg": [annotation.output_mass_kg[*first], annotation.output_mass_kg[*second]],
                                "inferred": describe(class),
                                "true": describe(truth),
                            }));
                        }
                    }
                    Some(PairVerdict::Undecidable(reason)) => {
                        *reasons.entry(reason_key(&reason)).or_insert(0) += 1;
                        undecided_cases.push(json!({
                            "video": id,
                            "first": first,
                            "second": second,
                            "reason": reason.to_string(),
                        }));
                    }
                    None => {
                        *reasons.entry("not_in_mechanism").or_insert(0) += 1;
                        undecided_cases.push(json!({
                            "video": id,
                            "first": first,
                            "second": second,
                            "reason": "a load the rebuilt mechanism does not hold",
                        }));
                    }
                }
            }
        }
    }
    let ratio = |a: u64, b: u64| {
        if b == 0 {
            Value::Null
        } else {
            #[expect(clippy::cast_precision_loss, reason = "counts of pairs")]
            let value = a as f64 / b as f64;
            json!((value * 10_000.0).round() / 10_000.0)
        }
    };
    json!({
        "bench": "inference",
        "scenario": "rope",
        "what": "mass relations of load pairs inferred from tracked motion, against outputMass",
        "track_noise_sd": noise,
        "videos": videos.len(),
        "videos_failed": failed_videos,
        "pairs_in_one_group": within,
        "decided": decided,
        "correct": correct,
        "wrong": decided - correct,
        "undecided": within - decided,
        "accuracy_of_decided": ratio(correct, decided),
        "coverage": ratio(decided, within),
        "accuracy_counting_undecided_as_wrong": ratio(correct, within),
        "undecided_by_reason": reasons,
        "pairs_across_groups": across,
        "pairs_across_groups_decided": across_decided,
        "wrong_cases": wrong_cases,
        "undecided_cases": undecided_cases,
        "wall_ms": u64::try_from(started.elapsed().as_millis()).unwrap_or(u64::MAX),
    })
}

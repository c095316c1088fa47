//! `bench inference` for cloth videos: the properties `--dynamics simulate` reads from the
//! cloths' tracked particles ([`super::infer`]) against the values the videos were made with,
//! counted right, wrong and not told per property, with each video's measures; and the boxes
//! the cloth never goes through (given the immovable mass) against their true masses and end
//! poses.
//!
//! Input: valid cloth video folders (`outputs.json`, `outputs4D.json`) and track-noise levels
//! (Gaussian, standard deviation in units, added to every particle coordinate). Output: JSON.

use serde_json::{Value, json};

use super::infer::{ClothReading, ClothVerdict, goes_through, read_cloths};
use super::simulate::SeenBox;
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{ClothAnnotation, Friction, VALUES};
use crate::dataset::{FourDData, VideoFolder};
use crate::scene_api::ApiError;
use crate::util::{derive_seed, seeded_rng, standard_normal};

/// A property the bench scores: its name, the verdict's side, and the annotated side with more
/// of it (friction: the high-friction cloth).
pub(super) struct Scored {
    pub(super) name: &'static str,
    pub(super) told: Option<Side>,
    pub(super) truth: Side,
}

/// The report (see the module's doc).
pub fn inference_report(videos: &[VideoFolder], noise_levels: &[f64]) -> Result<Value, ApiError> {
    let mut loaded = Vec::with_capacity(videos.len());
    for video in videos {
        loaded.push((
            video.id.0.clone(),
            ClothAnnotation::load(&video.outputs_json())?,
            FourDData::load(&video.outputs_4d_json())?,
        ));
    }
    let sweeps = noise_levels
        .iter()
        .map(|&noise| -> Result<Value, ApiError> {
            let mut counts: Vec<(&'static str, [u64; 3])> = Vec::new();
            let mut boxes = BoxCounts::default();
            let mut per_video = Vec::with_capacity(loaded.len());
            for (id, annotation, tracked) in &loaded {
                let mut four_d = tracked.clone();
                if noise > 0.0 {
                    let mut rng =
                        seeded_rng(derive_seed(0, &format!("bench/inference/cloth/{id}/{noise}")));
                    for body in four_d.soft_bodies.values_mut() {
                        for value in body.particles.iter_mut().flatten().flatten() {
                            *value += noise * standard_normal(&mut rng);
                        }
                    }
                }
                let readings = read_cloths(&four_d)?;
                let verdict = ClothVerdict::of(&readings);
                let scored = scored(annotation, verdict);
                boxes.add(annotation, &readings);
                for property in &scored {
                    let column = match property.told {
                        Some(side) if side == property.truth => 0,
                        Some(_) => 1,
                        None => 2,
                    };
                    if let Some((_, row)) =
                        counts.iter_mut().find(|(name, _)| *name == property.name)
                    {
                        row[column] += 1;
                    } else {
                        let mut row = [0; 3];
                        row[column] = 1;
                        counts.push((property.name, row));
                    }
                }
                per_video.push(json!({
                    "video": id,
                    "cloths": readings.iter().map(reading_json).collect::<Vec<_>>(),
                    "verdicts": scored.iter().map(|property| json!({
                        "property": property.name,
                        "truth": property.truth.word(),
                        "told": property.told.map(Side::word),
                    })).collect::<Vec<_>>(),
                }));
            }
            let per_property: serde_json::Map<String, Value> = counts
                .into_iter()
                .map(|(name, [right, wrong, undecided])| {
                    (
                        name.to_string(),
                        json!({"right": right, "wrong": wrong, "not_told": undecided}),
                    )
                })
                .collect();
            Ok(json!({
                "bench": "inference",
                "scenario": "cloth",
                "what": "which cloth of each video stretches more, which bends more and which has the high friction, read from the cloths' tracked particles (--dynamics simulate), against the annotations",
                "track_noise_sd": noise,
                "videos": loaded.len(),
                "per_property": per_property,
                "boxes": boxes.to_json(),
                "per_video": per_video,
            }))
        })
        .collect::<Result<Vec<Value>, ApiError>>()?;
    Ok(if let [only] = sweeps.as_slice() {
        only.clone()
    } else {
        json!({"bench": "inference", "scenario": "cloth", "sweeps": sweeps})
    })
}

/// Boxes by whether the cloth goes through their place (`moved`) or never does
/// (`undisturbed`), against the truth: immovable (a 99999-class mass), light and upright at the
/// end, or light and not.
#[derive(Debug, Default)]
struct BoxCounts {
    /// Undisturbed, then moved; each immovable, light upright, light fallen.
    counts: [[u64; 3]; 2],
}

impl BoxCounts {
    fn add(&mut self, annotation: &ClothAnnotation, readings: &[ClothReading; 2]) {
        for (side, reading) in Side::BOTH.into_iter().zip(readings) {
            for record in annotation.objects(side).boxes() {
                let seen = SeenBox::from_record(record, None);
                let moved =
                    goes_through(&reading.track, seen.position, seen.orientation, seen.size);
                let truth = if record.mass >= IMMOVABLE {
                    0
                } else if record.end_pose == Pose::Upright {
                    1
                } else {
                    2
                };
                self.counts[usize::from(moved)][truth] += 1;
            }
        }
    }

    fn to_json(&self) -> Value {
        let row = |[immovable, upright, fallen]: [u64; 3]| json!({"immovable": immovable, "light_upright": upright, "light_not_upright": fallen});
        json!({
            "what": "boxes whose start place the cloth never goes through (the simulation gives them their pool's immovable mass) and the others, by their true mass and end pose",
            "undisturbed": row(self.counts[0]),
            "moved": row(self.counts[1]),
        })
    }
}

/// Masses from this on are the release's immovable draws (99998 and 99999 kg), kg.
pub(crate) const IMMOVABLE: f64 = 99998.0;

/// Each property's verdict next to the annotation's cloth with more of it.
pub(super) fn scored(annotation: &ClothAnnotation, verdict: ClothVerdict) -> Vec<Scored> {
    let high_friction = if annotation.cloth(Side::Left).friction == Friction::High {
        Side::Left
    } else {
        Side::Right
    };
    let more = |value: fn(&crate::dataset::cloth::ClothProperties) -> f64, high: f64| {
        // The release's values are written as they are drawn: the larger is the one with more.
        if value(annotation.cloth(Side::Left)) >= high {
            Side::Left
        } else {
            Side::Right
        }
    };
    vec![
        Scored {
            name: "elasticity",
            told: verdict.stretches,
            truth: more(|c| c.stretching_compliance, VALUES.stretch_compliance[0]),
        },
        Scored {
            name: "bending",
            told: verdict.bends,
            truth: more(|c| c.bending_compliance, VALUES.max_bending[0]),
        },
        Scored {
            name: "friction",
            told: verdict.friction,
            truth: high_friction,
        },
        Scored {
            name: "friction, every pair (what the simulation assumes)",
            told: verdict.friction_guess,
            truth: high_friction,
        },
    ]
}

fn reading_json(reading: &ClothReading) -> Value {
    let round = |value: f64| (value * 1e6).round() / 1e6;
    json!({
        "cloth": reading.side.cloth_name(),
        "bend_offset": round(reading.bend_offset),
        "stretch_strain": round(reading.stretch_strain),
        "landing_friction": reading.landing_friction.map(round),
        "table_fraction": round(reading.table_fraction),
        "friction_score": round(reading.friction_score()),
        "pull_distance": round(reading.pull_distance),
    })
}

//! Fluid's part of `bench inference --data DIR`: how well the properties inferred from the
//! video ([`infer_fluid_properties`]) match the annotations, per video and in total, as JSON.
//!
//! * Density pairs, every unordered pair of base fluids, against the truth relations
//!   (`allDensityRelations` closed, [`DensityOrdering`]): a pair the truth orders is decided
//!   correctly, decided wrongly or left undecided; a pair the truth leaves unrelated ("can not
//!   answer") is either left undecided, as it should be, or wrongly decided (a false relation;
//!   whether it at least agrees with the layout densities is counted too).
//! * Viscosity classes against the layout's `viscosity`: correct, wrong, undecided.
//! * The rank order (the total order a simulator uses) against the layout densities: the
//!   fraction of fluid pairs it orders as the densities do.
//!
//! With `--noise σ,…` every tracked particle's x and y are perturbed by seeded Gaussian noise of
//! standard deviation σ (units), one sweep per level, as rope's bench does.

use std::time::Instant;

use indexmap::IndexMap;
use serde_json::{Value, json};

use super::{FluidInference, PerceivedFluidScene, infer_fluid_properties};
use crate::dataset::fluid::FluidAnnotation;
use crate::dataset::fluid::outcome::{DensityOrder, DensityOrdering};
use crate::dataset::{FourDData, VideoFolder};
use crate::scene_api::ApiError;
use crate::util::{derive_seed, seeded_rng, standard_normal};

/// Counts of one sweep (or one video).
#[derive(Debug, Clone, Copy, Default)]
struct Tally {
    /// Pairs the truth orders.
    related: u64,
    /// ... decided as the truth orders them.
    correct: u64,
    /// ... decided the other way.
    wrong: u64,
    /// ... left undecided.
    undecided: u64,
    /// Pairs the truth leaves unrelated.
    unrelated: u64,
    /// ... which inference decides anyway.
    false_relation: u64,
    /// ... of which the decision agrees with the layout densities.
    false_relation_agreeing: u64,
    /// Fluids.
    fluids: u64,
    /// Viscosity classes decided right.
    viscosity_correct: u64,
    /// ... decided wrong.
    viscosity_wrong: u64,
    /// ... left undecided.
    viscosity_undecided: u64,
    /// Fluid pairs the rank order places.
    rank_pairs: u64,
    /// ... as the densities order them.
    rank_correct: u64,
}

impl Tally {
    fn add(&mut self, other: &Tally) {
        self.related += other.related;
        self.correct += other.correct;
        self.wrong += other.wrong;
        self.undecided += other.undecided;
        self.unrelated += other.unrelated;
        self.false_relation += other.false_relation;
        self.false_relation_agreeing += other.false_relation_agreeing;
        self.fluids += other.fluids;
        self.viscosity_correct += other.viscosity_correct;
        self.viscosity_wrong += other.viscosity_wrong;
        self.viscosity_undecided += other.viscosity_undecided;
        self.rank_pairs += other.rank_pairs;
        self.rank_correct += other.rank_correct;
    }

    fn json(&self) -> Value {
        json!({
            "density_pairs": {
                "truth_related": self.related,
                "correct": self.correct,
                "wrong": self.wrong,
                "undecided": self.undecided,
                "truth_unrelated": self.unrelated,
                "false_relation": self.false_relation,
                "false_relation_agreeing_with_densities": self.false_relation_agreeing,
                "accuracy_of_decided": ratio(self.correct, self.correct + self.wrong),
                "coverage": ratio(self.correct + self.wrong, self.related),
            },
            "viscosity": {
                "fluids": self.fluids,
                "correct": self.viscosity_correct,
                "wrong": self.viscosity_wrong,
                "undecided": self.viscosity_undecided,
                "accuracy_of_decided": ratio(
                    self.viscosity_correct,
                    self.viscosity_correct + self.viscosity_wrong
                ),
            },
            "rank_order": {
                "pairs": self.rank_pairs,
                "ordered_as_densities": self.rank_correct,
                "accuracy": ratio(self.rank_correct, self.rank_pairs),
            },
        })
    }
}

/// Inferences scored against their videos' annotations, video by video (the reading check
/// scores what is inferred from the detector's masks with it).
#[derive(Debug, Default)]
pub(crate) struct InferenceScore {
    total: Tally,
    per_video: Vec<Value>,
}

impl InferenceScore {
    /// Scores `inference` of video `id` against `annotation`.
    pub(crate) fn add(
        &mut self,
        id: &str,
        annotation: &FluidAnnotation,
        inference: &FluidInference,
    ) {
        let (tally, report) = score_video(id, annotation, inference);
        self.total.add(&tally);
        self.per_video.push(report);
    }

    /// The totals and the per-video reports.
    pub(crate) fn json(&self) -> Value {
        json!({"total": self.total.json(), "per_video": self.per_video})
    }
}

/// `a / b` rounded to 4 decimals, `null` when `b` is 0.
fn ratio(a: u64, b: u64) -> Value {
    if b == 0 {
        Value::Null
    } else {
        #[expect(clippy::cast_precision_loss, reason = "counts of pairs and fluids")]
        let value = a as f64 / b as f64;
        json!((value * 10_000.0).round() / 10_000.0)
    }
}

/// The report over `videos` (valid fluid videos), one sweep per noise level (non-negative
/// standard deviations, units; the caller checks them).
pub(crate) fn inference_report(
    videos: &[VideoFolder],
    noise_levels: &[f64],
) -> Result<Value, ApiError> {
    let mut loaded = Vec::with_capacity(videos.len());
    for video in videos {
        loaded.push((
            video.id.0.clone(),
            FluidAnnotation::load(&video.outputs_json())?,
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
        json!({"bench": "inference", "scenario": "fluid", "sweeps": sweeps})
    })
}

/// Scores every video with its tracked particles perturbed by `noise`.
fn sweep(videos: &[(String, FluidAnnotation, FourDData)], noise: f64) -> Value {
    let started = Instant::now();
    let mut total = Tally::default();
    let mut per_video = Vec::new();
    let mut failed_videos = Vec::new();
    for (id, annotation, tracked) in videos {
        let mut four_d = tracked.clone();
        if noise > 0.0 {
            let mut rng = seeded_rng(derive_seed(0, &format!("bench/inference/{id}/{noise}")));
            for body in four_d.soft_bodies.values_mut() {
                for point in body.particles.iter_mut().flatten() {
                    point[0] += noise * standard_normal(&mut rng);
                    point[1] += noise * standard_normal(&mut rng);
                }
            }
        }
        let scene = PerceivedFluidScene::from_layout(&annotation.layout);
        match infer_fluid_properties(id, &scene, &four_d) {
            Ok(inference) => {
                let (tally, report) = score_video(id, annotation, &inference);
                total.add(&tally);
                per_video.push(report);
            }
            Err(error) => failed_videos.push(json!({"video": id, "error": error.to_string()})),
        }
    }
    json!({
        "bench": "inference",
        "scenario": "fluid",
        "what": "fluid density order (layering in the containers), viscosity class (speed on the sticks) and density ranks inferred from tracked particles of the video's frames, against the annotations",
        "track_noise_sd": noise,
        "videos": videos.len(),
        "videos_failed": failed_videos,
        "total": total.json(),
        "per_video": per_video,
        "wall_ms": u64::try_from(started.elapsed().as_millis()).unwrap_or(u64::MAX),
    })
}

fn order_word(order: DensityOrder) -> &'static str {
    match order {
        DensityOrder::Heavier => "heavier",
        DensityOrder::Lighter => "lighter",
        DensityOrder::Unknown => "unknown",
        DensityOrder::Contradictory => "contradictory",
    }
}

/// One video's counts and report.
fn score_video(
    id: &str,
    annotation: &FluidAnnotation,
    inference: &FluidInference,
) -> (Tally, Value) {
    let truth: DensityOrdering = annotation.tracking.density_ordering();
    let fluids = &annotation.layout.fluids;
    let mut tally = Tally::default();
    let mut pairs = Vec::new();
    for (index, first) in fluids.iter().enumerate() {
        for second in fluids.iter().skip(index + 1) {
            let (a, b) = (first.name.as_str(), second.name.as_str());
            let truth_order = truth.order(a, b);
            let inferred = inference.density.order(a, b);
            let decided = matches!(inferred, DensityOrder::Heavier | DensityOrder::Lighter);
            let outcome = match truth_order {
                DensityOrder::Heavier | DensityOrder::Lighter => {
                    tally.related += 1;
                    if !decided {
                        tally.undecided += 1;
                        "undecided"
                    } else if inferred == truth_order {
                        tally.correct += 1;
                        "correct"
                    } else {
                        tally.wrong += 1;
                        "wrong"
                    }
                }
                DensityOrder::Unknown | DensityOrder::Contradictory => {
                    tally.unrelated += 1;
                    if decided {
                        tally.false_relation += 1;
                        let agrees =
                            (inferred == DensityOrder::Heavier) == (first.density > second.density);
                        if agrees {
                            tally.false_relation_agreeing += 1;
                        }
                        "false_relation"
                    } else {
                        "unrelated_undecided"
                    }
                }
            };
            pairs.push(json!({
                "first": a,
                "second": b,
                "truth": order_word(truth_order),
                "inferred": order_word(inferred),
                "outcome": outcome,
            }));
        }
    }
    let mut fluid_rows = Vec::new();
    let rank_of: IndexMap<&str, usize> = inference
        .ranks
        .iter()
        .map(|rank| (rank.fluid.as_str(), rank.rank))
        .collect();
    for (index, fluid) in fluids.iter().enumerate() {
        tally.fluids += 1;
        let evidence = inference.viscosity.iter().find(|v| v.fluid == fluid.name);
        match evidence.and_then(|v| v.class) {
            None => tally.viscosity_undecided += 1,
            Some(class) if class == fluid.viscosity => tally.viscosity_correct += 1,
            Some(_) => tally.viscosity_wrong += 1,
        }
        for other in fluids.iter().skip(index + 1) {
            if let (Some(&mine), Some(&theirs)) = (
                rank_of.get(fluid.name.as_str()),
                rank_of.get(other.name.as_str()),
            ) {
                tally.rank_pairs += 1;
                if (mine > theirs) == (fluid.density > other.density) {
                    tally.rank_correct += 1;
                }
            }
        }
        fluid_rows.push(json!({
            "fluid": fluid.name,
            "true_density": fluid.density,
            "true_viscosity": fluid.viscosity,
            "viscosity": evidence,
            "rank": inference.ranks.iter().find(|r| r.fluid == fluid.name),
        }));
    }
    let report = json!({
        "video": id,
        "totals": tally.json(),
        "fluids": fluid_rows,
        "pairs": pairs,
        "layering": inference.density.comparisons,
        "conflicts": inference.density.conflicts,
    });
    (tally, report)
}

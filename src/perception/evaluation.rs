//! Perception metrics against ground truth: how well the detector finds and labels objects, and
//! how well the tracker keeps their identities.
//!
//! Input: [`Detection`]s grouped by frame, [`TruthInstance`]s grouped by frame (from the
//! release's segmentation frames), and for identities the [`Track`]s built from those
//! detections. Output: serialisable reports ([`ApReport`], [`AttributeReport`],
//! [`IdentityReport`]) for JSON and tables.
//!
//! Only frames that have ground truth are scored: detections and track observations in other
//! frames are ignored (the truth may be annotated on a subset of frames). A frame whose truth
//! list is empty is annotated and has no objects, so everything found there is a false positive.
//!
//! # Average precision
//!
//! COCO-style per class, at one IoU threshold: all detections of the class across frames are
//! sorted by score (descending; ties by frame, then index in the frame; non-finite scores last),
//! and each in turn takes the still-unmatched truth of its class in its frame with the best IoU,
//! if that IoU is at least the threshold (a true positive); otherwise it is a false positive
//! (duplicates of a matched truth included). AP is the area under the precision-recall curve
//! after making precision monotone (each point takes the best precision at its recall or
//! higher), summed over every recall step: the all-point interpolation of PASCAL VOC 2010+ and
//! of COCO's definition, without COCO's sampling at 101 recall points (which differs from it by
//! at most about 1%). A class with no truth has no AP and is left out of the mean; a class with
//! truth and no detections has AP 0. Mask AP uses mask IoU; box AP uses the IoU of the
//! detection's box with the tight box of the truth mask.

use std::collections::{BTreeMap, BTreeSet};

use serde::Serialize;

use super::assignment::assign;
use super::classes::{Class, ClassTable};
use super::detection::{Detection, InstanceMask, box_iou};
use super::tracking::Track;

/// IoU at which a detection counts as the same object as a truth instance, for attribute and
/// identity matching (the usual CLEAR-MOT / COCO 0.5).
pub const MATCH_IOU: f64 = 0.5;

/// Fraction of its frames a truth instance must be matched in to count as mostly tracked (the
/// usual 80%).
pub const MOSTLY_TRACKED: f64 = 0.8;

/// Below this fraction of matched frames a truth instance is mostly lost (the usual 20%).
pub const MOSTLY_LOST: f64 = 0.2;

/// One ground-truth object in one frame.
#[derive(Debug, Clone, PartialEq)]
pub struct TruthInstance {
    /// The release's instance id (stable across frames).
    pub instance_id: u32,
    /// Its class.
    pub class: Class,
    /// Its palette colour id; `None` when the object has no palette colour.
    pub color: Option<u8>,
    /// Its pixels in the frame.
    pub mask: InstanceMask,
}

/// Why an evaluation could not run.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum EvaluationError {
    /// A frame appears twice in one input list.
    #[error("frame `{frame}` appears twice in the {list}")]
    DuplicateFrame {
        /// The frame.
        frame: usize,
        /// Which list: `detections` or `truth`.
        list: &'static str,
    },
    /// An instance id appears twice in one truth frame.
    #[error("instance `{instance_id}` appears twice in truth frame `{frame}`")]
    DuplicateInstance {
        /// The frame.
        frame: usize,
        /// The instance id.
        instance_id: u32,
    },
    /// A track observation points at a detection that is not there.
    #[error(
        "track `{track}` refers to detection `{detection}` of frame `{frame}`, which does not exist"
    )]
    MissingDetection {
        /// The track id.
        track: u32,
        /// The frame.
        frame: usize,
        /// The detection index in that frame.
        detection: usize,
    },
    /// The IoU threshold is not in `(0, 1]`.
    #[error("IoU threshold `{threshold}` is not in (0, 1]")]
    Threshold {
        /// The threshold given.
        threshold: f64,
    },
}

/// Which overlap AP was computed with.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Overlap {
    /// Mask IoU.
    Mask,
    /// IoU of the detection box with the truth mask's tight box.
    Box,
}

/// Average precision per class and their mean.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ApReport {
    /// The overlap measure.
    pub overlap: Overlap,
    /// The IoU a true positive needs.
    pub iou_threshold: f64,
    /// One row per class, in label order.
    pub classes: Vec<ClassAp>,
    /// Mean AP over the classes with truth; `None` when no class has any.
    pub mean_ap: Option<f64>,
}

impl ApReport {
    /// The row of `class`.
    pub fn class(&self, class: Class) -> Option<&ClassAp> {
        self.classes.iter().find(|row| row.class == class)
    }
}

/// Average precision of one class.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct ClassAp {
    /// The class (its label).
    pub class: Class,
    /// The class name.
    pub name: &'static str,
    /// AP in `[0, 1]`; `None` when the class has no truth.
    pub ap: Option<f64>,
    /// Truth instances of the class (summed over frames).
    pub truths: usize,
    /// Detections of the class (summed over scored frames).
    pub detections: usize,
    /// Detections that matched a truth.
    pub true_positives: usize,
}

/// Detections grouped by frame with duplicate frames refused.
fn by_frame<'a, T>(
    groups: &'a [(usize, Vec<T>)],
    list: &'static str,
) -> Result<BTreeMap<usize, &'a [T]>, EvaluationError> {
    let mut map = BTreeMap::new();
    for (frame, items) in groups {
        if map.insert(*frame, items.as_slice()).is_some() {
            return Err(EvaluationError::DuplicateFrame {
                frame: *frame,
                list,
            });
        }
    }
    Ok(map)
}

/// Truth grouped by frame, with duplicate frames and instance ids refused.
fn truth_by_frame(
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
) -> Result<BTreeMap<usize, &[TruthInstance]>, EvaluationError> {
    let map = by_frame(truth_per_frame, "truth")?;
    for (frame, truths) in &map {
        let mut seen = BTreeSet::new();
        for truth in *truths {
            if !seen.insert(truth.instance_id) {
                return Err(EvaluationError::DuplicateInstance {
                    frame: *frame,
                    instance_id: truth.instance_id,
                });
            }
        }
    }
    Ok(map)
}

fn check_threshold(threshold: f64) -> Result<(), EvaluationError> {
    if threshold > 0.0 && threshold <= 1.0 {
        Ok(())
    } else {
        Err(EvaluationError::Threshold { threshold })
    }
}

/// Mask IoU from two masks and their known areas.
fn mask_iou(a: &InstanceMask, area_a: u64, b: &InstanceMask, area_b: u64) -> f64 {
    let intersection = a.intersection(b);
    let union = area_a + area_b - intersection;
    if union == 0 {
        0.0
    } else {
        intersection as f64 / union as f64
    }
}

/// A truth instance with its area and box computed once.
struct PreparedTruth<'a> {
    truth: &'a TruthInstance,
    area: u64,
    /// The tight box of the mask, `None` when empty.
    bounds: Option<[f64; 4]>,
}

impl<'a> PreparedTruth<'a> {
    fn new(truth: &'a TruthInstance) -> Self {
        PreparedTruth {
            truth,
            area: truth.mask.area(),
            bounds: truth.mask.bounds().map(|b| b.map(f64::from)),
        }
    }
}

/// A detection with its mask area computed once.
struct PreparedDetection<'a> {
    detection: &'a Detection,
    area: u64,
}

impl<'a> PreparedDetection<'a> {
    fn new(detection: &'a Detection) -> Self {
        PreparedDetection {
            detection,
            area: detection.mask.area(),
        }
    }

    fn mask_iou(&self, truth: &PreparedTruth<'_>) -> f64 {
        mask_iou(
            &self.detection.mask,
            self.area,
            &truth.truth.mask,
            truth.area,
        )
    }

    fn iou(&self, truth: &PreparedTruth<'_>, overlap: Overlap) -> f64 {
        match overlap {
            Overlap::Mask => self.mask_iou(truth),
            Overlap::Box => truth.bounds.map_or(0.0, |bounds| {
                box_iou(self.detection.bbox.map(f64::from), bounds)
            }),
        }
    }
}

/// The score used for ranking: non-finite scores rank last.
fn rank_score(score: f32) -> f32 {
    if score.is_finite() {
        score
    } else {
        f32::NEG_INFINITY
    }
}

/// All-point interpolated AP of a ranked list of hits (true positive or not) against `truths`
/// truth instances; `None` when there is no truth.
fn all_point_ap(hits: &[bool], truths: usize) -> Option<f64> {
    if truths == 0 {
        return None;
    }
    let mut precision = Vec::with_capacity(hits.len());
    let mut recall = Vec::with_capacity(hits.len());
    let mut true_positives = 0_usize;
    for (rank, hit) in hits.iter().enumerate() {
        if *hit {
            true_positives += 1;
        }
        precision.push(true_positives as f64 / (rank + 1) as f64);
        recall.push(true_positives as f64 / truths as f64);
    }
    // Monotone precision: the best precision at this recall or any higher one.
    for i in (0..precision.len().saturating_sub(1)).rev() {
        precision[i] = precision[i].max(precision[i + 1]);
    }
    let mut ap = 0.0;
    let mut previous_recall = 0.0;
    for (p, r) in precision.iter().zip(&recall) {
        ap += (r - previous_recall) * p;
        previous_recall = *r;
    }
    Some(ap)
}

/// Mask AP per class at `iou_threshold` (COCO's AP50 at 0.5); see the module docs.
pub fn mask_average_precision(
    classes: &ClassTable,
    detections_per_frame: &[(usize, Vec<Detection>)],
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
    iou_threshold: f64,
) -> Result<ApReport, EvaluationError> {
    average_precision(
        classes,
        detections_per_frame,
        truth_per_frame,
        iou_threshold,
        Overlap::Mask,
    )
}

/// Box AP per class at `iou_threshold`: the detection's `bbox` against the tight box of the
/// truth mask; otherwise as [`mask_average_precision`].
pub fn box_average_precision(
    classes: &ClassTable,
    detections_per_frame: &[(usize, Vec<Detection>)],
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
    iou_threshold: f64,
) -> Result<ApReport, EvaluationError> {
    average_precision(
        classes,
        detections_per_frame,
        truth_per_frame,
        iou_threshold,
        Overlap::Box,
    )
}

fn average_precision(
    table: &ClassTable,
    detections_per_frame: &[(usize, Vec<Detection>)],
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
    iou_threshold: f64,
    overlap: Overlap,
) -> Result<ApReport, EvaluationError> {
    check_threshold(iou_threshold)?;
    let truth = truth_by_frame(truth_per_frame)?;
    let detections = by_frame(detections_per_frame, "detections")?;

    let mut classes = Vec::new();
    for class in table.all() {
        // Truth of the class per scored frame, with a matched flag each.
        let mut truths: BTreeMap<usize, Vec<(PreparedTruth<'_>, bool)>> = BTreeMap::new();
        let mut truth_count = 0;
        for (frame, instances) in &truth {
            let of_class: Vec<_> = instances
                .iter()
                .filter(|t| t.class == class)
                .map(|t| (PreparedTruth::new(t), false))
                .collect();
            truth_count += of_class.len();
            truths.insert(*frame, of_class);
        }
        // Detections of the class in scored frames, ranked.
        let mut ranked: Vec<(usize, usize, PreparedDetection<'_>)> = Vec::new();
        for (frame, list) in &detections {
            if !truth.contains_key(frame) {
                continue;
            }
            for (index, detection) in list.iter().enumerate() {
                if detection.class == class {
                    ranked.push((*frame, index, PreparedDetection::new(detection)));
                }
            }
        }
        ranked.sort_by(|a, b| {
            rank_score(b.2.detection.score)
                .total_cmp(&rank_score(a.2.detection.score))
                .then(a.0.cmp(&b.0))
                .then(a.1.cmp(&b.1))
        });

        let mut hits = Vec::with_capacity(ranked.len());
        for (frame, _, detection) in &ranked {
            let mut hit = false;
            if let Some(candidates) = truths.get_mut(frame) {
                let mut best: Option<(usize, f64)> = None;
                for (i, (prepared, matched)) in candidates.iter().enumerate() {
                    if *matched {
                        continue;
                    }
                    let iou = detection.iou(prepared, overlap);
                    if iou >= iou_threshold && best.is_none_or(|(_, b)| iou > b) {
                        best = Some((i, iou));
                    }
                }
                if let Some(entry) = best.and_then(|(i, _)| candidates.get_mut(i)) {
                    entry.1 = true;
                    hit = true;
                }
            }
            hits.push(hit);
        }
        classes.push(ClassAp {
            class,
            name: table.name(class),
            ap: all_point_ap(&hits, truth_count),
            truths: truth_count,
            detections: ranked.len(),
            true_positives: hits.iter().filter(|h| **h).count(),
        });
    }
    let with_truth: Vec<f64> = classes.iter().filter_map(|c| c.ap).collect();
    let mean_ap =
        (!with_truth.is_empty()).then(|| with_truth.iter().sum::<f64>() / with_truth.len() as f64);
    Ok(ApReport {
        overlap,
        iou_threshold,
        classes,
        mean_ap,
    })
}

/// A count of correct answers out of a total.
#[derive(Debug, Clone, Copy, PartialEq, Serialize)]
pub struct Accuracy {
    /// Correct answers.
    pub correct: usize,
    /// Answers judged.
    pub total: usize,
    /// `correct / total`; `None` when nothing was judged.
    pub accuracy: Option<f64>,
}

impl Accuracy {
    fn new(correct: usize, total: usize) -> Self {
        Accuracy {
            correct,
            total,
            accuracy: (total > 0).then(|| correct as f64 / total as f64),
        }
    }
}

/// How well matched detections are labelled.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct AttributeReport {
    /// Detection–truth pairs (mask IoU ≥ [`MATCH_IOU`], class-agnostic).
    pub matched: usize,
    /// Truth instances no detection matched.
    pub unmatched_truth: usize,
    /// Detections (at or above the score floor) that matched no truth.
    pub unmatched_detections: usize,
    /// Same palette colour (both unknown counts as the same).
    pub color: Accuracy,
    /// The same, per true colour (palette name; `unknown` when the truth has none).
    pub color_per_color: BTreeMap<&'static str, Accuracy>,
    /// Same class.
    pub class: Accuracy,
    /// Same kind (rope: cube, sphere, rope, fixed point, pulley).
    pub kind: Accuracy,
    /// Per attribute of the classes (rope: pulley `shape`, `dynamic`), the same value, over the
    /// pairs whose truth has the attribute.
    pub attributes: BTreeMap<&'static str, Accuracy>,
}

/// Match detections (score ≥ `min_score`) to truth in each scored frame, class-agnostically, by
/// the assignment with the largest number of pairs at mask IoU ≥ [`MATCH_IOU`] and then the
/// least summed `1 − IoU`; then count how often the matched detection's colour, class, kind
/// and attribute values are right.
pub fn attribute_accuracy(
    classes: &ClassTable,
    detections_per_frame: &[(usize, Vec<Detection>)],
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
    min_score: f32,
) -> Result<AttributeReport, EvaluationError> {
    let truth = truth_by_frame(truth_per_frame)?;
    let detections = by_frame(detections_per_frame, "detections")?;
    let (mut matched, mut unmatched_truth, mut unmatched_detections) = (0, 0, 0);
    let (mut color, mut class, mut kind) = (0, 0, 0);
    // Per true colour: (right, judged).
    let mut per_color: BTreeMap<&'static str, (usize, usize)> = BTreeMap::new();
    let attribute_names = classes.attribute_names();
    // Per attribute: (right, judged).
    let mut attributes: Vec<(usize, usize)> = vec![(0, 0); attribute_names.len()];
    for (frame, instances) in &truth {
        let truths: Vec<PreparedTruth<'_>> = instances.iter().map(PreparedTruth::new).collect();
        let found: Vec<PreparedDetection<'_>> = detections
            .get(frame)
            .into_iter()
            .flat_map(|list| list.iter())
            .filter(|d| d.score >= min_score)
            .map(PreparedDetection::new)
            .collect();
        let pairs = assign(truths.len(), found.len(), |t, d| {
            let iou = found[d].mask_iou(&truths[t]);
            (iou >= MATCH_IOU).then_some(1.0 - iou)
        });
        for (prepared, pair) in truths.iter().zip(&pairs) {
            let Some(detection) = pair.and_then(|d| found.get(d)) else {
                unmatched_truth += 1;
                continue;
            };
            let (truth, detection) = (prepared.truth, detection.detection);
            matched += 1;
            let right_color = detection.color == truth.color;
            color += usize::from(right_color);
            let name = truth
                .color
                .and_then(super::palette::palette_color)
                .map_or("unknown", |c| c.name);
            let entry = per_color.entry(name).or_default();
            entry.0 += usize::from(right_color);
            entry.1 += 1;
            class += usize::from(detection.class == truth.class);
            kind += usize::from(detection.class.same_kind(truth.class));
            for (name, (right, judged)) in attribute_names.iter().zip(&mut attributes) {
                if let Some(value) = classes.attribute(truth.class, name) {
                    *judged += 1;
                    *right += usize::from(classes.attribute(detection.class, name) == Some(value));
                }
            }
        }
        unmatched_detections += found.len() - pairs.iter().flatten().count();
    }
    Ok(AttributeReport {
        matched,
        unmatched_truth,
        unmatched_detections,
        color: Accuracy::new(color, matched),
        color_per_color: per_color
            .into_iter()
            .map(|(name, (right, judged))| (name, Accuracy::new(right, judged)))
            .collect(),
        class: Accuracy::new(class, matched),
        kind: Accuracy::new(kind, matched),
        attributes: attribute_names
            .into_iter()
            .zip(attributes)
            .map(|(name, (right, judged))| (name, Accuracy::new(right, judged)))
            .collect(),
    })
}

/// Identity statistics of tracks against truth (CLEAR-MOT counts and track coverage).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct IdentityReport {
    /// Distinct truth instances.
    pub truth_instances: usize,
    /// Tracks given.
    pub tracks: usize,
    /// Truth instances matched in at least [`MOSTLY_TRACKED`] of the frames they are in.
    pub mostly_tracked: usize,
    /// Truth instances matched in less than [`MOSTLY_LOST`] of the frames they are in.
    pub mostly_lost: usize,
    /// Truth objects summed over scored frames (MOTA's denominator).
    pub truth_objects: usize,
    /// Truth–track pairs summed over scored frames.
    pub matches: usize,
    /// Truth objects without a track, summed over scored frames.
    pub misses: usize,
    /// Track observations without a truth, summed over scored frames.
    pub false_positives: usize,
    /// Times a truth instance was matched to another track than the one it was last matched to.
    pub switches: usize,
    /// `1 − (misses + false positives + switches) / truth objects`; `None` without truth.
    pub mota: Option<f64>,
    /// One row per truth instance, by id.
    pub instances: Vec<InstanceIdentity>,
}

/// How one truth instance was tracked.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct InstanceIdentity {
    /// The truth instance id.
    pub instance_id: u32,
    /// Scored frames it is in.
    pub frames: usize,
    /// Of those, frames a track matched it in.
    pub matched_frames: usize,
    /// Its identity switches.
    pub switches: usize,
    /// The track ids it was matched to, in order of first match.
    pub track_ids: Vec<u32>,
}

/// Count identity switches and track coverage, CLEAR-MOT style (Bernardin & Stiefelhagen
/// 2008).
///
/// In each scored frame, a truth instance keeps the track it was last matched to if that track
/// has an observation there with mask IoU ≥ [`MATCH_IOU`]; the others are paired by the
/// assignment with the most pairs at IoU ≥ [`MATCH_IOU`], then the least summed `1 − IoU`. A
/// switch is counted each time a truth instance is matched to a track other than the one it was
/// last matched to (across frames where it was not matched). Observations refer to
/// `detections_per_frame` by frame and index, as [`super::tracking::track`] made them.
pub fn id_switches(
    tracks: &[Track],
    detections_per_frame: &[(usize, Vec<Detection>)],
    truth_per_frame: &[(usize, Vec<TruthInstance>)],
) -> Result<IdentityReport, EvaluationError> {
    let truth = truth_by_frame(truth_per_frame)?;
    let detections = by_frame(detections_per_frame, "detections")?;

    // The track observations in scored frames: frame → (track id, detection).
    let mut observed: BTreeMap<usize, Vec<(u32, PreparedDetection<'_>)>> = BTreeMap::new();
    for track in tracks {
        for point in &track.observations {
            if !truth.contains_key(&point.frame) {
                continue;
            }
            let detection = detections
                .get(&point.frame)
                .and_then(|list| list.get(point.detection))
                .ok_or(EvaluationError::MissingDetection {
                    track: track.id,
                    frame: point.frame,
                    detection: point.detection,
                })?;
            observed
                .entry(point.frame)
                .or_default()
                .push((track.id, PreparedDetection::new(detection)));
        }
    }

    let mut instances: BTreeMap<u32, InstanceIdentity> = BTreeMap::new();
    let mut last_track: BTreeMap<u32, u32> = BTreeMap::new();
    let (mut truth_objects, mut matches, mut misses, mut false_positives, mut switches) =
        (0, 0, 0, 0, 0);
    let no_observations = Vec::new();
    for (frame, list) in &truth {
        let truths: Vec<PreparedTruth<'_>> = list.iter().map(PreparedTruth::new).collect();
        let hypotheses = observed.get(frame).unwrap_or(&no_observations);
        let mut track_of: Vec<Option<usize>> = vec![None; truths.len()];
        let mut taken = vec![false; hypotheses.len()];

        // Keep last frame's correspondences that still hold.
        for (t, prepared) in truths.iter().enumerate() {
            let Some(previous) = last_track.get(&prepared.truth.instance_id) else {
                continue;
            };
            let kept = hypotheses.iter().enumerate().find(|(h, (id, detection))| {
                !taken[*h] && id == previous && detection.mask_iou(prepared) >= MATCH_IOU
            });
            if let Some((h, _)) = kept {
                track_of[t] = Some(h);
                taken[h] = true;
            }
        }
        // Pair the rest optimally.
        let open_truths: Vec<usize> = (0..truths.len())
            .filter(|t| track_of[*t].is_none())
            .collect();
        let open_hypotheses: Vec<usize> = (0..hypotheses.len()).filter(|h| !taken[*h]).collect();
        let pairs = assign(open_truths.len(), open_hypotheses.len(), |t, h| {
            let iou = hypotheses[open_hypotheses[h]]
                .1
                .mask_iou(&truths[open_truths[t]]);
            (iou >= MATCH_IOU).then_some(1.0 - iou)
        });
        for (t, h) in pairs.iter().enumerate() {
            if let Some(h) = h {
                track_of[open_truths[t]] = Some(open_hypotheses[*h]);
                taken[open_hypotheses[*h]] = true;
            }
        }

        // Count.
        for (prepared, hypothesis) in truths.iter().zip(&track_of) {
            let instance_id = prepared.truth.instance_id;
            let row = instances
                .entry(instance_id)
                .or_insert_with(|| InstanceIdentity {
                    instance_id,
                    frames: 0,
                    matched_frames: 0,
                    switches: 0,
                    track_ids: Vec::new(),
                });
            row.frames += 1;
            truth_objects += 1;
            let Some((track_id, _)) = hypothesis.and_then(|h| hypotheses.get(h)) else {
                misses += 1;
                continue;
            };
            matches += 1;
            row.matched_frames += 1;
            if let Some(previous) = last_track.insert(instance_id, *track_id)
                && previous != *track_id
            {
                row.switches += 1;
                switches += 1;
            }
            if !row.track_ids.contains(track_id) {
                row.track_ids.push(*track_id);
            }
        }
        false_positives += taken.iter().filter(|t| !**t).count();
    }

    let coverage = |row: &InstanceIdentity| row.matched_frames as f64 / row.frames.max(1) as f64;
    let instances: Vec<InstanceIdentity> = instances.into_values().collect();
    Ok(IdentityReport {
        truth_instances: instances.len(),
        tracks: tracks.len(),
        mostly_tracked: instances
            .iter()
            .filter(|r| coverage(r) >= MOSTLY_TRACKED)
            .count(),
        mostly_lost: instances
            .iter()
            .filter(|r| coverage(r) < MOSTLY_LOST)
            .count(),
        truth_objects,
        matches,
        misses,
        false_positives,
        switches,
        mota: (truth_objects > 0)
            .then(|| 1.0 - (misses + false_positives + switches) as f64 / truth_objects as f64),
        instances,
    })
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::rope::{PERCEPTION, test_class as class};
    use crate::perception::tracking::TrackPoint;

    fn table() -> ClassTable {
        ClassTable::of_scenario(PERCEPTION.classes)
    }

    const RED: Option<u8> = Some(0);
    const BLUE: Option<u8> = Some(5);
    const GREEN: Option<u8> = Some(7);

    /// The pixels `x0..x1 × y0..y1` of a 100×100 frame.
    fn rect(x0: u32, y0: u32, x1: u32, y1: u32) -> InstanceMask {
        InstanceMask::from_predicate(100, 100, |x, y| {
            (x0..x1).contains(&x) && (y0..y1).contains(&y)
        })
    }

    /// A detection whose box is its mask's tight box.
    fn det(class: Class, color: Option<u8>, score: f32, mask: InstanceMask) -> Detection {
        let bbox = mask.bounds().unwrap().map(|v| v as f32);
        Detection {
            frame: 0,
            class,
            score,
            bbox,
            mask,
            color,
        }
    }

    fn truth(
        instance_id: u32,
        class: Class,
        color: Option<u8>,
        mask: InstanceMask,
    ) -> TruthInstance {
        TruthInstance {
            instance_id,
            class,
            color,
            mask,
        }
    }

    fn close(a: Option<f64>, b: f64) -> bool {
        a.is_some_and(|a| (a - b).abs() < 1e-12)
    }

    #[test]
    fn all_point_ap_of_ranked_hits() {
        let cases: &[(&[bool], usize, Option<f64>)] = &[
            // Precision 1, 1/2, 2/3 at recall 1/2, 1/2, 1: 1/2·1 + 1/2·2/3.
            (&[true, false, true], 2, Some(5.0 / 6.0)),
            (&[true, true], 2, Some(1.0)),
            // Monotone precision is 1/2 everywhere; recall reaches 1/2.
            (&[false, true, false, true], 4, Some(0.25)),
            (&[], 3, Some(0.0)),
            (&[false], 0, None),
        ];
        for (hits, truths, expected) in cases {
            let ap = all_point_ap(hits, *truths);
            match expected {
                Some(e) => assert!(close(ap, *e), "{hits:?} {truths}: {ap:?}"),
                None => assert_eq!(ap, None),
            }
        }
    }

    #[test]
    fn mask_ap_of_three_ranked_cube_detections() {
        let truth_frames = vec![(
            0,
            vec![
                truth(1, class("cube"), RED, rect(0, 0, 10, 10)),
                truth(2, class("cube"), BLUE, rect(20, 0, 30, 10)),
                truth(3, class("sphere"), GREEN, rect(50, 50, 60, 60)),
            ],
        )];
        let detection_frames = vec![
            (
                0,
                vec![
                    // IoU 0.6 with truth 2: a true positive, ranked third.
                    det(class("cube"), BLUE, 0.7, rect(20, 0, 26, 10)),
                    // Exactly truth 1: a true positive, ranked first.
                    det(class("cube"), RED, 0.9, rect(0, 0, 10, 10)),
                    // IoU 0.3 with truth 2: a false positive, ranked second.
                    det(class("cube"), BLUE, 0.8, rect(20, 0, 23, 10)),
                    // A rope where there is no rope.
                    det(class("rope"), GREEN, 0.6, rect(0, 80, 90, 82)),
                ],
            ),
            // Frame 7 has no truth: not scored.
            (7, vec![det(class("cube"), RED, 0.95, rect(70, 70, 80, 80))]),
        ];
        for report in [
            mask_average_precision(&table(), &detection_frames, &truth_frames, 0.5).unwrap(),
            box_average_precision(&table(), &detection_frames, &truth_frames, 0.5).unwrap(),
        ] {
            let cube = report.class(class("cube")).unwrap();
            assert!(close(cube.ap, 5.0 / 6.0), "{cube:?}");
            assert_eq!(
                (cube.truths, cube.detections, cube.true_positives),
                (2, 3, 2)
            );
            let sphere = report.class(class("sphere")).unwrap();
            assert_eq!(
                (sphere.ap, sphere.truths, sphere.detections),
                (Some(0.0), 1, 0)
            );
            let rope = report.class(class("rope")).unwrap();
            assert_eq!((rope.ap, rope.truths, rope.detections), (None, 0, 1));
            assert!(close(report.mean_ap, 5.0 / 12.0));
            assert_eq!(report.classes.len(), 8);
            assert_eq!(report.classes[0].class, class("cube"));
        }
    }

    #[test]
    fn duplicates_are_false_positives_and_the_threshold_matters() {
        let truth_frames = vec![(3, vec![truth(1, class("cube"), RED, rect(0, 0, 10, 10))])];
        let detection_frames = vec![(
            3,
            vec![
                det(class("cube"), RED, 0.9, rect(0, 0, 10, 6)), // IoU 0.6
                det(class("cube"), RED, 0.8, rect(0, 0, 10, 10)), // IoU 1
            ],
        )];
        // At 0.5 the first takes the truth and the second is a duplicate: precision 1 at
        // recall 1, AP 1.
        let report =
            mask_average_precision(&table(), &detection_frames, &truth_frames, 0.5).unwrap();
        let cube = report.class(class("cube")).unwrap();
        assert!(close(cube.ap, 1.0));
        assert_eq!(cube.true_positives, 1);
        // At 0.75 the first misses and the second hits: precision 1/2 at recall 1.
        let report =
            mask_average_precision(&table(), &detection_frames, &truth_frames, 0.75).unwrap();
        assert!(close(report.class(class("cube")).unwrap().ap, 0.5));
    }

    #[test]
    fn box_ap_uses_the_box_and_mask_ap_the_pixels() {
        // The box covers the truth exactly, the mask only 40% of it.
        let truth_frames = vec![(0, vec![truth(1, class("cube"), RED, rect(0, 0, 10, 10))])];
        let mut partial = det(class("cube"), RED, 0.9, rect(0, 0, 10, 4));
        partial.bbox = [0.0, 0.0, 10.0, 10.0];
        let detection_frames = vec![(0, vec![partial])];
        let mask = mask_average_precision(&table(), &detection_frames, &truth_frames, 0.5).unwrap();
        let boxed = box_average_precision(&table(), &detection_frames, &truth_frames, 0.5).unwrap();
        assert_eq!(mask.overlap, Overlap::Mask);
        assert_eq!(boxed.overlap, Overlap::Box);
        assert!(close(mask.mean_ap, 0.0));
        assert!(close(boxed.mean_ap, 1.0));
        assert!(close(
            Some(box_iou([0.0, 0.0, 10.0, 10.0], [5.0, 0.0, 15.0, 10.0])),
            1.0 / 3.0
        ));
        assert!(close(
            Some(box_iou([0.0, 0.0, f64::NAN, 1.0], [0.0, 0.0, 1.0, 1.0])),
            0.0
        ));
    }

    #[test]
    fn bad_inputs_are_errors() {
        let cube = || truth(1, class("cube"), RED, rect(0, 0, 10, 10));
        for threshold in [0.0, 1.5, f64::NAN] {
            assert!(matches!(
                mask_average_precision(&table(), &[], &[], threshold),
                Err(EvaluationError::Threshold { .. })
            ));
        }
        assert_eq!(
            mask_average_precision(&table(), &[], &[(2, vec![]), (2, vec![])], 0.5),
            Err(EvaluationError::DuplicateFrame {
                frame: 2,
                list: "truth"
            })
        );
        assert_eq!(
            attribute_accuracy(&table(), &[], &[(4, vec![cube(), cube()])], 0.0),
            Err(EvaluationError::DuplicateInstance {
                frame: 4,
                instance_id: 1
            })
        );
        let track = Track {
            id: 3,
            class: class("cube"),
            color: RED,
            observations: vec![TrackPoint {
                frame: 4,
                detection: 1,
                centroid: [5.0, 5.0],
                bbox: [0.0, 0.0, 10.0, 10.0],
            }],
        };
        let detection_frames = vec![(4, vec![det(class("cube"), RED, 0.9, rect(0, 0, 10, 10))])];
        assert_eq!(
            id_switches(&[track], &detection_frames, &[(4, vec![cube()])]),
            Err(EvaluationError::MissingDetection {
                track: 3,
                frame: 4,
                detection: 1
            })
        );
    }

    #[test]
    fn attributes_of_matched_detections() {
        let truth_frames = vec![
            (
                0,
                vec![
                    truth(1, class("cube"), RED, rect(0, 0, 10, 10)),
                    truth(2, class("solid static pulley"), BLUE, rect(20, 0, 30, 10)),
                    truth(
                        3,
                        class("hollow dynamic pulley"),
                        GREEN,
                        rect(40, 0, 50, 10),
                    ),
                    truth(4, class("rope"), Some(2), rect(0, 50, 100, 52)),
                ],
            ),
            (2, vec![truth(1, class("cube"), RED, rect(0, 0, 10, 10))]),
        ];
        let detection_frames = vec![
            (
                0,
                vec![
                    // Everything right.
                    det(class("cube"), RED, 0.9, rect(0, 0, 10, 10)),
                    // Right kind and colour, wrong shape (so wrong class).
                    det(
                        class("hollow static pulley"),
                        BLUE,
                        0.9,
                        rect(20, 0, 30, 10),
                    ),
                    // Right class, colour not read.
                    det(
                        class("hollow dynamic pulley"),
                        None,
                        0.9,
                        rect(40, 0, 50, 10),
                    ),
                    // Nothing there.
                    det(class("sphere"), RED, 0.9, rect(80, 80, 90, 90)),
                    // Under the score floor: the rope counts as missed.
                    det(class("rope"), Some(2), 0.05, rect(0, 50, 100, 52)),
                ],
            ),
            // Not scored: no truth for frame 1.
            (1, vec![det(class("cube"), RED, 0.9, rect(0, 0, 10, 10))]),
            // Class-agnostic matching: a sphere on the cube (IoU 0.6) is matched, wrong kind.
            (2, vec![det(class("sphere"), RED, 0.9, rect(0, 0, 10, 6))]),
        ];
        let report = attribute_accuracy(&table(), &detection_frames, &truth_frames, 0.1).unwrap();
        assert_eq!(
            (
                report.matched,
                report.unmatched_truth,
                report.unmatched_detections
            ),
            (4, 1, 1)
        );
        let counts = |a: Accuracy| (a.correct, a.total);
        assert_eq!(counts(report.color), (3, 4));
        assert_eq!(counts(report.class), (2, 4));
        assert_eq!(counts(report.kind), (3, 4));
        assert_eq!(counts(report.attributes["shape"]), (1, 2));
        assert!(close(report.attributes["shape"].accuracy, 0.5));
        assert!(close(report.color.accuracy, 0.75));
        // Per true colour: both red cubes right, the blue pulley right, the green one unread.
        let name = |id: Option<u8>| {
            crate::perception::palette::palette_color(id.unwrap())
                .unwrap()
                .name
        };
        let per_color: Vec<(&str, (usize, usize))> = report
            .color_per_color
            .iter()
            .map(|(name, accuracy)| (*name, counts(*accuracy)))
            .collect();
        let mut expected = vec![
            (name(RED), (2, 2)),
            (name(BLUE), (1, 1)),
            (name(GREEN), (0, 1)),
        ];
        expected.sort_unstable();
        assert_eq!(per_color, expected);
        let empty = attribute_accuracy(&table(), &[], &[], 0.0).unwrap();
        assert_eq!(empty.color.accuracy, None);
    }

    fn point(frame: usize, detection: usize) -> TrackPoint {
        TrackPoint {
            frame,
            detection,
            centroid: [0.0, 0.0],
            bbox: [0.0; 4],
        }
    }

    fn track_of(id: u32, points: Vec<TrackPoint>) -> Track {
        Track {
            id,
            class: class("cube"),
            color: RED,
            observations: points,
        }
    }

    #[test]
    fn two_tracks_that_swap_truths_make_two_switches() {
        // Truth 10 on the left, 20 on the right, frames 0..4; detection 0 is on 10, 1 on 20.
        let truth_frames: Vec<_> = (0..4)
            .map(|f| {
                (
                    f,
                    vec![
                        truth(10, class("cube"), RED, rect(0, 0, 10, 10)),
                        truth(20, class("cube"), BLUE, rect(30, 0, 40, 10)),
                    ],
                )
            })
            .collect();
        let detection_frames: Vec<_> = (0..4)
            .map(|f| {
                (
                    f,
                    vec![
                        det(class("cube"), RED, 0.9, rect(0, 0, 10, 10)),
                        det(class("cube"), BLUE, 0.9, rect(30, 0, 40, 10)),
                    ],
                )
            })
            .collect();
        // Track 0 follows 10 then jumps to 20 at frame 2; track 1 the other way round.
        let tracks = vec![
            track_of(0, vec![point(0, 0), point(1, 0), point(2, 1), point(3, 1)]),
            track_of(1, vec![point(0, 1), point(1, 1), point(2, 0), point(3, 0)]),
        ];
        let report = id_switches(&tracks, &detection_frames, &truth_frames).unwrap();
        assert_eq!(report.switches, 2);
        assert_eq!(
            (
                report.truth_objects,
                report.matches,
                report.misses,
                report.false_positives
            ),
            (8, 8, 0, 0)
        );
        assert!(close(report.mota, 0.75));
        assert_eq!((report.truth_instances, report.tracks), (2, 2));
        assert_eq!((report.mostly_tracked, report.mostly_lost), (2, 0));
        let rows: Vec<_> = report
            .instances
            .iter()
            .map(|r| {
                (
                    r.instance_id,
                    r.frames,
                    r.matched_frames,
                    r.switches,
                    r.track_ids.clone(),
                )
            })
            .collect();
        assert_eq!(
            rows,
            vec![(10, 4, 4, 1, vec![0, 1]), (20, 4, 4, 1, vec![1, 0])]
        );
    }

    #[test]
    fn a_kept_correspondence_is_not_a_switch_and_misses_and_extras_are_counted() {
        // Truth 1 is in frames 0..5, truth 2 (never tracked) too.
        let truth_frames: Vec<_> = (0..5)
            .map(|f| {
                (
                    f,
                    vec![
                        truth(1, class("cube"), RED, rect(0, 0, 10, 10)),
                        truth(2, class("sphere"), BLUE, rect(50, 50, 60, 60)),
                    ],
                )
            })
            .collect();
        let mut detection_frames: Vec<_> = (0..5)
            .map(|f| (f, vec![det(class("cube"), RED, 0.9, rect(0, 0, 10, 10))]))
            .collect();
        // Frame 4: detection 0 overlaps truth 1 at IoU 0.6, detection 1 exactly.
        detection_frames[4].1 = vec![
            det(class("cube"), RED, 0.9, rect(0, 0, 10, 6)),
            det(class("cube"), RED, 0.9, rect(0, 0, 10, 10)),
        ];
        detection_frames.push((5, vec![det(class("cube"), RED, 0.9, rect(0, 0, 10, 10))]));
        let tracks = vec![
            // Unseen in frame 3 (a miss); frame 4 keeps the 0.6 overlap, as CLEAR-MOT keeps a
            // correspondence that still holds (the optimum alone would take track 1's 1.0).
            track_of(0, vec![point(0, 0), point(1, 0), point(2, 0), point(4, 0)]),
            // Frame 4: an extra hypothesis, a false positive. Frame 5 has no truth.
            track_of(1, vec![point(4, 1), point(5, 0)]),
        ];
        let report = id_switches(&tracks, &detection_frames, &truth_frames).unwrap();
        assert_eq!(report.switches, 0);
        assert_eq!(
            (
                report.truth_objects,
                report.matches,
                report.misses,
                report.false_positives
            ),
            (10, 4, 6, 1)
        );
        // 1 − (6 + 1 + 0) / 10.
        assert!(close(report.mota, 0.3));
        // Truth 1 matched in 4 of 5 frames (80%): mostly tracked; truth 2 in none: mostly lost.
        assert_eq!((report.mostly_tracked, report.mostly_lost), (1, 1));
        assert_eq!(report.instances[0].track_ids, vec![0]);
        assert_eq!(report.instances[1].matched_frames, 0);
        let json = serde_json::to_value(&report).unwrap();
        assert_eq!(json["switches"], 0);
        assert_eq!(json["instances"][0]["instance_id"], 1);
    }
}

//! Which of a track's masks a perceived object is read from, and the second-choice colours of
//! sticks and containers (`--perception maskrcnn`).
//!
//! Input: first-pass tracks and their detections, and for the colours the frames of the chosen
//! masks and the [`Perceiver`]'s colour model. Output: `(frame, mask)` per track, and per named
//! stick and container its next-likeliest colour words, which `find` falls back on
//! ([`SceneObjectInfo::other_colors`](crate::scene_api::object::SceneObjectInfo::other_colors)).

use std::collections::BTreeMap;

use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::frames::RgbFrame;
use crate::perception::palette::palette_color;
use crate::perception::tracking::Track;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::Perceiver;

/// How many second-choice colours an object keeps.
const SECOND_CHOICES: usize = 2;

/// The kinds whose objects keep second-choice colours: those questions name by a colour of the
/// twelve-colour pool, where the colour model confuses red with brown and white with grey under
/// some lights (held-out colour accuracy, `docs/data/fluid.md`). Fluids and emitters take the
/// fluids' seven colours, which it reads right.
pub(super) const SECOND_CHOICE_KINDS: [&str; 2] = ["stick", "container"];

/// The frames of the masks [`second_colors`] reads: each second-choice object's earliest
/// full-size mask.
pub(super) fn second_color_frames(perceiver: &Perceiver) -> Vec<usize> {
    let Some(classes) = perceiver.classes() else {
        return Vec::new();
    };
    perceiver
        .first_tracks()
        .iter()
        .filter(|track| SECOND_CHOICE_KINDS.contains(&classes.kind(track.class)))
        .filter_map(|track| earliest_full_mask(track, perceiver.first_detections()))
        .map(|(frame, _)| frame)
        .collect::<std::collections::BTreeSet<usize>>()
        .into_iter()
        .collect()
}

/// Each named stick's and container's second-choice colours, likeliest first: the colours
/// other than its own that the colour model's Gaussians find likeliest for the pixels of its
/// earliest full-size mask (for a container, before fluid fills it).
pub(super) fn second_colors(
    perceiver: &Perceiver,
    names: &[Option<String>],
    frames: &BTreeMap<usize, RgbFrame>,
) -> Result<BTreeMap<String, Vec<String>>, ApiError> {
    let mut second = BTreeMap::new();
    let Some(classes) = perceiver.classes() else {
        return Ok(second);
    };
    let detections = perceiver.first_detections();
    for (track, name) in perceiver.first_tracks().iter().zip(names) {
        let Some(name) = name else { continue };
        if !SECOND_CHOICE_KINDS.contains(&classes.kind(track.class)) {
            continue;
        }
        let Some((frame, mask)) = earliest_full_mask(track, detections) else {
            continue;
        };
        let Some(rgb) = frames.get(&frame) else {
            continue;
        };
        let masks: Vec<&InstanceMask> = detections
            .get(&frame)
            .map(|found| found.iter().map(|d| &d.mask).collect())
            .unwrap_or_default();
        let others: Vec<String> = perceiver
            .color_ranking(rgb, mask, &masks, track.class)?
            .into_iter()
            .filter(|color| Some(*color) != track.color)
            .take(SECOND_CHOICES)
            .filter_map(|color| palette_color(color).map(|c| c.word.to_string()))
            .collect();
        if !others.is_empty() {
            second.insert(name.clone(), others);
        }
    }
    Ok(second)
}

/// The largest mask among a track's observations.
pub(super) fn largest_mask<'a>(
    track: &Track,
    detections: &'a BTreeMap<usize, Vec<Detection>>,
) -> Option<(usize, &'a InstanceMask)> {
    track
        .observations
        .iter()
        .filter_map(|point| {
            let mask = &detections.get(&point.frame)?.get(point.detection)?.mask;
            Some((point.frame, mask))
        })
        .max_by_key(|(_, mask)| mask.area())
}

/// A stick's mask at its earliest observation that is nearly full size (at least
/// [`FULL_MASK_SHARE`] of the median mask area): before fluid reaches the stick. Later masks
/// take in the fluid running along it and dripping off its ends, so the largest mask is the
/// longest and lengthens the stick.
pub(super) fn earliest_full_mask<'a>(
    track: &Track,
    detections: &'a BTreeMap<usize, Vec<Detection>>,
) -> Option<(usize, &'a InstanceMask)> {
    let masks: Vec<(usize, &InstanceMask)> = track
        .observations
        .iter()
        .filter_map(|point| {
            let mask = &detections.get(&point.frame)?.get(point.detection)?.mask;
            Some((point.frame, mask))
        })
        .collect();
    let mut areas: Vec<u64> = masks.iter().map(|(_, mask)| mask.area()).collect();
    areas.sort_unstable();
    let median = *areas.get(areas.len() / 2)?;
    masks
        .into_iter()
        .filter(|(_, mask)| mask.area() as f64 >= FULL_MASK_SHARE * median as f64)
        .min_by_key(|(frame, _)| *frame)
}

/// See [`earliest_full_mask`].
const FULL_MASK_SHARE: f64 = 0.8;

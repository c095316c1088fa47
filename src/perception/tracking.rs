//! Tracking: linking one frame's detections to the next so each object keeps one id through the
//! video, through occlusions by ropes and other objects.
//!
//! Input: [`Detection`]s grouped by frame, frames in increasing order (they may be sparse, e.g.
//! every 5th frame), and a [`TrackerConfig`]. Output: [`Track`]s, each with a stable id, a voted
//! class and colour, and the observations (frame, index of the detection in that frame's list,
//! centroid, box) it was built from. The group's frame number is the one used; the detections'
//! own `frame` fields are not read.
//!
//! # Method
//!
//! Frames are processed in order. Each frame's detections are first put in a canonical order
//! (centroid x, then y, then class, colour, score), so the result does not depend on the order
//! the detector listed them in. Then two optimal assignments ([`super::assignment::assign`]) run:
//!
//! 1. **Compatible pairs.** A live track and a detection are *compatible* when their kinds
//!    ([`Class::same_kind`]) are equal and their colours do not contradict (equal, or one of
//!    them unknown). A compatible pair is *in the gate* when the detection's mask overlaps the
//!    track's last mask with IoU ≥ [`TrackerConfig::min_iou`], or when its centroid lies within
//!    the distance gate of the track's position: the smaller distance to the constant-velocity
//!    prediction (velocity from the track's last two observations) or to the last centroid,
//!    against `distance_gate × object radius + speed_slack_px × frames since last seen` (the
//!    object radius is half the larger box diagonal of the two, at least `min_radius_px`). The
//!    cost is `min(1 − IoU, distance / gate)` plus [`TrackerConfig::class_change_cost`] when the
//!    classes differ within the kind (solid ↔ hollow, static ↔ dynamic) plus
//!    [`TrackerConfig::unknown_color_cost`] when a colour is unknown.
//! 2. **Relabelled pairs.** An *incompatible* pair (another kind or another colour) is matched
//!    only when nothing else explains either side: both the track and the detection were left
//!    unmatched by step 1, and the masks overlap with IoU ≥ [`TrackerConfig::relabel_min_iou`].
//!    This absorbs a detector that misreads a colour or a class for a frame (a load half hidden
//!    by a rope) without letting two different objects that cross share an id; the final votes
//!    then outvote the misreading.
//!
//! The optimum first maximises the number of gated pairs, then minimises the summed cost.
//! Detections left over start new tracks. A track not matched stays alive while at most
//! [`TrackerConfig::max_gap`] video frames in a row have passed without it, so an object hidden
//! for a few frames comes back under its id. At the end tracks with fewer than
//! [`TrackerConfig::min_observations`] observations are dropped (a spurious one-frame detection
//! neither survives nor uses up an id), and ids `0..` are given in order of first appearance,
//! ties by the first centroid's x then y.

use std::collections::BTreeMap;

use serde::Serialize;

use super::assignment::assign;
use super::classes::Class;
use super::detection::{Detection, InstanceMask};

/// Tuning of the tracker. Distances are in frame pixels, times in video frames.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackerConfig {
    /// Most video frames in a row a track may go unseen and still be matched again. Default 10:
    /// a load hidden behind a rope or pulley for up to ~10 frames keeps its id; at every-5th-frame
    /// sampling this tolerates one missed sample.
    pub max_gap: usize,
    /// Mask IoU with the track's last mask that puts a compatible pair in the gate on its own.
    /// Default 0.1: slow objects (a few pixels a frame) overlap their last mask heavily, and a
    /// rope keeps overlapping itself while its centroid wanders.
    pub min_iou: f64,
    /// The centroid gate in object radii. Default 1.0: the detection's centroid must be within
    /// one radius of where the track was predicted (or last seen).
    pub distance_gate: f64,
    /// Extra gate radius per video frame since the track was last seen, pixels. Default 1.0:
    /// loads move a few pixels a frame and accelerate, so the prediction drifts over a gap.
    pub speed_slack_px: f64,
    /// Smallest object radius used by the gate, pixels. Default 4.0: a fixed point is a few
    /// pixels across and its centroid jitters by about a pixel.
    pub min_radius_px: f64,
    /// Added cost when the classes differ within one kind. Default 0.2: the detector sometimes
    /// hesitates between solid and hollow, or static and dynamic, pulleys; a same-class
    /// candidate at similar distance is preferred.
    pub class_change_cost: f64,
    /// Added cost when the track's or the detection's colour is unknown. Default 0.2: a known,
    /// equal colour is the stronger evidence.
    pub unknown_color_cost: f64,
    /// Mask IoU that lets an incompatible pair (other kind or colour) match when nothing else
    /// explains either side. Default 0.5: the same pixels, so almost surely the same object
    /// with a misread label.
    pub relabel_min_iou: f64,
    /// Tracks with fewer observations are dropped. Default 2: a one-frame detection is treated
    /// as spurious. Use 1 to keep every detection (e.g. with very sparse sampling).
    pub min_observations: usize,
}

impl Default for TrackerConfig {
    fn default() -> Self {
        TrackerConfig {
            max_gap: 10,
            min_iou: 0.1,
            distance_gate: 1.0,
            speed_slack_px: 1.0,
            min_radius_px: 4.0,
            class_change_cost: 0.2,
            unknown_color_cost: 0.2,
            relabel_min_iou: 0.5,
            min_observations: 2,
        }
    }
}

/// Why tracking could not run.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum TrackingError {
    /// The frames were not in strictly increasing order.
    #[error("frame `{frame}` comes after frame `{previous}`: frames must be strictly increasing")]
    FrameOrder {
        /// The frame before.
        previous: usize,
        /// The frame out of order.
        frame: usize,
    },
    /// A configuration value is out of range.
    #[error("tracker setting `{field}` is {value}, expected {expected}")]
    Config {
        /// The [`TrackerConfig`] field.
        field: &'static str,
        /// Its value.
        value: f64,
        /// What it should be.
        expected: &'static str,
    },
}

/// One object followed through the video.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct Track {
    /// `0..` in order of first appearance (ties by x, then y, of the first centroid).
    pub id: u32,
    /// Class by vote over the observations, each weighted by its detection score.
    pub class: Class,
    /// Colour by majority over the observations with a known colour; `None` if none had one.
    pub color: Option<u8>,
    /// The detections it was built from, in frame order.
    pub observations: Vec<TrackPoint>,
}

impl Track {
    /// The first frame the object was seen in.
    pub fn first_frame(&self) -> Option<usize> {
        self.observations.first().map(|o| o.frame)
    }

    /// The last frame the object was seen in.
    pub fn last_frame(&self) -> Option<usize> {
        self.observations.last().map(|o| o.frame)
    }

    /// The observation in `frame`, if the object was seen there.
    pub fn at_frame(&self, frame: usize) -> Option<&TrackPoint> {
        self.observations
            .binary_search_by_key(&frame, |o| o.frame)
            .ok()
            .and_then(|i| self.observations.get(i))
    }
}

/// One observation of a tracked object.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct TrackPoint {
    /// 0-based video frame.
    pub frame: usize,
    /// Index of the detection in that frame's list (as given to [`track`]).
    pub detection: usize,
    /// Mask centroid `[x, y]`, pixels (the box centre when the mask is empty).
    pub centroid: [f64; 2],
    /// The detection's box `[x0, y0, x1, y1]`, pixels.
    pub bbox: [f32; 4],
}

/// What the tracker needs of one detection, computed once.
struct Prepared<'a> {
    /// Index in the frame's list.
    index: usize,
    detection: &'a Detection,
    centroid: [f64; 2],
    /// Half the box diagonal, pixels.
    radius: f64,
    area: u64,
}

impl<'a> Prepared<'a> {
    /// `None` when the detection has neither pixels nor a finite box: nothing to place.
    fn new(index: usize, detection: &'a Detection) -> Option<Self> {
        let box_from_mask = detection
            .mask
            .bounds()
            .map(|b| b.map(f64::from))
            .filter(|b| b[2] > b[0]);
        let box_given = Some(detection.bbox.map(f64::from))
            .filter(|b| b.iter().all(|v| v.is_finite()) && b[2] >= b[0] && b[3] >= b[1]);
        let rectangle = box_from_mask.or(box_given)?;
        let centroid = detection.mask.centroid().unwrap_or([
            f64::midpoint(rectangle[0], rectangle[2]),
            f64::midpoint(rectangle[1], rectangle[3]),
        ]);
        let radius = 0.5 * (rectangle[2] - rectangle[0]).hypot(rectangle[3] - rectangle[1]);
        Some(Prepared {
            index,
            detection,
            centroid,
            radius,
            area: detection.mask.area(),
        })
    }

    /// The canonical order inside a frame: position, then labels, then score, then input index.
    fn canonical_cmp(&self, other: &Self) -> std::cmp::Ordering {
        let (a, b) = (self.detection, other.detection);
        self.centroid[0]
            .total_cmp(&other.centroid[0])
            .then(self.centroid[1].total_cmp(&other.centroid[1]))
            .then(a.class.cmp(&b.class))
            .then(a.color.cmp(&b.color))
            .then(b.score.total_cmp(&a.score))
            .then(self.area.cmp(&other.area))
            .then(self.index.cmp(&other.index))
    }
}

/// A track being built.
struct LiveTrack<'a> {
    /// Observations so far, in frame order.
    points: Vec<TrackPoint>,
    last_mask: &'a InstanceMask,
    last_area: u64,
    last_radius: f64,
    /// Summed score weight and count per class.
    class_votes: BTreeMap<Class, (f64, usize)>,
    /// Count per known colour.
    color_votes: BTreeMap<u8, usize>,
}

impl<'a> LiveTrack<'a> {
    fn new(frame: usize, prepared: &Prepared<'a>) -> Self {
        let mut track = LiveTrack {
            points: Vec::new(),
            last_mask: &prepared.detection.mask,
            last_area: 0,
            last_radius: 0.0,
            class_votes: BTreeMap::new(),
            color_votes: BTreeMap::new(),
        };
        track.push(frame, prepared);
        track
    }

    fn push(&mut self, frame: usize, prepared: &Prepared<'a>) {
        let detection = prepared.detection;
        self.points.push(TrackPoint {
            frame,
            detection: prepared.index,
            centroid: prepared.centroid,
            bbox: detection.bbox,
        });
        self.last_mask = &detection.mask;
        self.last_area = prepared.area;
        self.last_radius = prepared.radius;
        let weight = f64::from(detection.score);
        let weight = if weight.is_finite() && weight > 0.0 {
            weight
        } else {
            0.0
        };
        let vote = self.class_votes.entry(detection.class).or_insert((0.0, 0));
        vote.0 += weight;
        vote.1 += 1;
        if let Some(color) = detection.color {
            *self.color_votes.entry(color).or_insert(0) += 1;
        }
    }

    fn last_point(&self) -> &TrackPoint {
        self.points
            .last()
            .expect("a live track is created with one observation")
    }

    /// The class with the largest summed score, ties by more observations, then label order.
    fn class(&self) -> Class {
        let mut best: Option<(Class, f64, usize)> = None;
        for (&class, &(weight, count)) in &self.class_votes {
            let better = best.is_none_or(|(_, w, c)| {
                weight.total_cmp(&w).then(count.cmp(&c)) == std::cmp::Ordering::Greater
            });
            if better {
                best = Some((class, weight, count));
            }
        }
        best.map(|(class, _, _)| class)
            .expect("a live track has at least one class vote")
    }

    /// The most frequent known colour, ties by the smaller palette id.
    fn color(&self) -> Option<u8> {
        let mut best: Option<(u8, usize)> = None;
        for (&color, &count) in &self.color_votes {
            if best.is_none_or(|(_, c)| count > c) {
                best = Some((color, count));
            }
        }
        best.map(|(color, _)| color)
    }

    /// Where the constant-velocity model puts the centroid in `frame`.
    fn predicted(&self, frame: usize) -> [f64; 2] {
        let last = self.last_point();
        let n = self.points.len();
        let Some(previous) = n.checked_sub(2).and_then(|i| self.points.get(i)) else {
            return last.centroid;
        };
        let span = (last.frame - previous.frame) as f64;
        let ahead = frame.saturating_sub(last.frame) as f64;
        let step =
            |k: usize| last.centroid[k] + (last.centroid[k] - previous.centroid[k]) * ahead / span;
        [step(0), step(1)]
    }
}

/// Mask IoU from two masks and their known areas.
fn iou(a: &InstanceMask, area_a: u64, b: &InstanceMask, area_b: u64) -> f64 {
    let intersection = a.intersection(b);
    let union = area_a + area_b - intersection;
    if union == 0 {
        0.0
    } else {
        intersection as f64 / union as f64
    }
}

fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
    (a[0] - b[0]).hypot(a[1] - b[1])
}

fn check_config(config: &TrackerConfig) -> Result<(), TrackingError> {
    let non_negative = [
        ("min_iou", config.min_iou),
        ("speed_slack_px", config.speed_slack_px),
        ("min_radius_px", config.min_radius_px),
        ("class_change_cost", config.class_change_cost),
        ("unknown_color_cost", config.unknown_color_cost),
    ];
    for (field, value) in non_negative {
        if !(value.is_finite() && value >= 0.0) {
            return Err(TrackingError::Config {
                field,
                value,
                expected: "a finite number ≥ 0",
            });
        }
    }
    if !(config.distance_gate.is_finite() && config.distance_gate > 0.0) {
        return Err(TrackingError::Config {
            field: "distance_gate",
            value: config.distance_gate,
            expected: "a finite number > 0",
        });
    }
    if !(config.relabel_min_iou > 0.0 && config.relabel_min_iou <= 1.0) {
        return Err(TrackingError::Config {
            field: "relabel_min_iou",
            value: config.relabel_min_iou,
            expected: "a number in (0, 1]",
        });
    }
    Ok(())
}

/// Link detections across frames into tracks (see the module docs for the method).
///
/// `frames` holds each frame's detections, frames strictly increasing. Returns the tracks
/// sorted by id. Detections with neither mask pixels nor a finite box are skipped.
pub fn track(
    frames: &[(usize, Vec<Detection>)],
    config: &TrackerConfig,
) -> Result<Vec<Track>, TrackingError> {
    check_config(config)?;
    let mut live: Vec<LiveTrack<'_>> = Vec::new();
    // Tracks past `max_gap`, in creation order with the live ones (index = creation rank).
    let mut retired: Vec<(usize, LiveTrack<'_>)> = Vec::new();
    let mut live_rank: Vec<usize> = Vec::new();
    let mut created = 0_usize;
    let mut previous_frame: Option<usize> = None;

    for (frame, detections) in frames {
        let frame = *frame;
        if let Some(previous) = previous_frame
            && frame <= previous
        {
            return Err(TrackingError::FrameOrder { previous, frame });
        }
        previous_frame = Some(frame);

        // Retire tracks unseen for more than `max_gap` frames before this one.
        let mut index = 0;
        while index < live.len() {
            let last = live[index].last_point().frame;
            if frame.saturating_sub(last).saturating_sub(1) > config.max_gap {
                retired.push((live_rank.remove(index), live.remove(index)));
            } else {
                index += 1;
            }
        }

        let mut prepared: Vec<Prepared<'_>> = detections
            .iter()
            .enumerate()
            .filter_map(|(i, d)| Prepared::new(i, d))
            .collect();
        prepared.sort_by(Prepared::canonical_cmp);

        let mut track_of_detection: Vec<Option<usize>> = vec![None; prepared.len()];

        // Step 1: compatible pairs in the gate.
        let first = assign(live.len(), prepared.len(), |t, d| {
            compatible_cost(&live[t], &prepared[d], frame, config)
        });
        for (t, d) in first.iter().enumerate() {
            if let Some(d) = d {
                track_of_detection[*d] = Some(t);
            }
        }

        // Step 2: what nothing else explains, by strong overlap alone.
        let open_tracks: Vec<usize> = (0..live.len()).filter(|t| first[*t].is_none()).collect();
        let open_detections: Vec<usize> = (0..prepared.len())
            .filter(|d| track_of_detection[*d].is_none())
            .collect();
        let second = assign(open_tracks.len(), open_detections.len(), |t, d| {
            relabel_cost(
                &live[open_tracks[t]],
                &prepared[open_detections[d]],
                frame,
                config,
            )
        });
        for (t, d) in second.iter().enumerate() {
            if let Some(d) = d {
                track_of_detection[open_detections[*d]] = Some(open_tracks[t]);
            }
        }

        // Extend matched tracks, start new ones in canonical order.
        for (d, detection) in prepared.iter().enumerate() {
            if let Some(t) = track_of_detection[d] {
                live[t].push(frame, detection);
            } else {
                live.push(LiveTrack::new(frame, detection));
                live_rank.push(created);
                created += 1;
            }
        }
    }

    let mut all: Vec<(usize, LiveTrack<'_>)> = retired;
    all.extend(live_rank.into_iter().zip(live));
    all.retain(|(_, t)| t.points.len() >= config.min_observations.max(1));
    // Creation order is first-frame order, and within a frame the canonical (x, y) order.
    all.sort_by_key(|(rank, _)| *rank);
    let mut tracks = Vec::with_capacity(all.len());
    for (id, (_, live_track)) in (0_u32..).zip(all) {
        tracks.push(Track {
            id,
            class: live_track.class(),
            color: live_track.color(),
            observations: live_track.points,
        });
    }
    Ok(tracks)
}

/// Step 1's cost of giving `detection` (in `frame`) to `track`; `None` when incompatible or out
/// of the gate.
fn compatible_cost(
    track: &LiveTrack<'_>,
    detection: &Prepared<'_>,
    frame: usize,
    config: &TrackerConfig,
) -> Option<f64> {
    let class = track.class();
    if !class.same_kind(detection.detection.class) {
        return None;
    }
    let track_color = track.color();
    let mut appearance = 0.0;
    match (track_color, detection.detection.color) {
        (Some(a), Some(b)) if a != b => return None,
        (Some(_), Some(_)) => {}
        _ => appearance += config.unknown_color_cost,
    }
    if class != detection.detection.class {
        appearance += config.class_change_cost;
    }

    let (overlap, away, gate) = nearness(track, detection, frame, config);
    let in_gate = (overlap >= config.min_iou && overlap > 0.0) || away <= gate;
    in_gate.then(|| appearance + (1.0 - overlap).min(away / gate))
}

/// Step 2's cost of giving `detection` to `track`, both left over by step 1 (their colours or
/// kinds disagree): the same pixels (IoU at least [`TrackerConfig::relabel_min_iou`]), or an
/// object of the same kind inside step 1's distance gate, whose colour was misread for this
/// frame. The second kind costs more, so overlap wins where both are possible. A moving pulley
/// read in another colour for one sparse frame overlaps its last mask too little for the first
/// test, and would otherwise start a second track of the same object.
fn relabel_cost(
    track: &LiveTrack<'_>,
    detection: &Prepared<'_>,
    frame: usize,
    config: &TrackerConfig,
) -> Option<f64> {
    let (overlap, away, gate) = nearness(track, detection, frame, config);
    if overlap >= config.relabel_min_iou {
        Some(1.0 - overlap)
    } else {
        (track.class().same_kind(detection.detection.class) && away <= gate)
            .then(|| 1.0 + away / gate)
    }
}

/// How near `detection` (in `frame`) is to `track`: the masks' IoU, the centroid's distance
/// from the track's predicted or last position (pixels), and the distance gate (pixels).
fn nearness(
    track: &LiveTrack<'_>,
    detection: &Prepared<'_>,
    frame: usize,
    config: &TrackerConfig,
) -> (f64, f64, f64) {
    let last = track.last_point();
    let gap = frame.saturating_sub(last.frame) as f64;
    let radius = track
        .last_radius
        .max(detection.radius)
        .max(config.min_radius_px);
    let gate = config.distance_gate * radius + config.speed_slack_px * gap;
    let away = distance(track.predicted(frame), detection.centroid)
        .min(distance(last.centroid, detection.centroid));
    let overlap = iou(
        track.last_mask,
        track.last_area,
        &detection.detection.mask,
        detection.area,
    );
    (overlap, away, gate)
}

#[cfg(test)]
#[expect(
    clippy::float_cmp,
    reason = "centroids of whole-pixel squares are exact half-pixel values"
)]
mod tests {
    use super::*;
    use crate::perception::rope::test_class as class;

    const RED: u8 = 0;
    const BLUE: u8 = 5;
    const GREEN: u8 = 7;

    /// A `2·half × 2·half` square detection centred on `(cx, cy)` (whole pixels) in a 200×200
    /// frame.
    fn square(class: Class, color: Option<u8>, cx: i64, cy: i64, half: i64) -> Detection {
        let mask = InstanceMask::from_predicate(200, 200, |x, y| {
            let (x, y) = (i64::from(x), i64::from(y));
            (cx - half..cx + half).contains(&x) && (cy - half..cy + half).contains(&y)
        });
        Detection {
            frame: 0,
            class,
            score: 0.9,
            bbox: [
                (cx - half) as f32,
                (cy - half) as f32,
                (cx + half) as f32,
                (cy + half) as f32,
            ],
            mask,
            color,
        }
    }

    fn cube(color: u8, cx: i64, cy: i64) -> Detection {
        square(class("cube"), Some(color), cx, cy, 6)
    }

    fn run(frames: &[(usize, Vec<Detection>)]) -> Vec<Track> {
        track(frames, &TrackerConfig::default()).unwrap()
    }

    /// A frame number as a pixel offset.
    fn px(frame: usize) -> i64 {
        i64::try_from(frame).unwrap()
    }

    /// Each track's frames and centroid x (as bits), for compact assertions.
    fn paths(tracks: &[Track]) -> Vec<Vec<(usize, u64)>> {
        tracks
            .iter()
            .map(|t| {
                t.observations
                    .iter()
                    .map(|o| (o.frame, o.centroid[0].to_bits()))
                    .collect()
            })
            .collect()
    }

    #[test]
    fn straight_motion_is_one_track_dense_and_sparse() {
        // 3 px a frame to the right, every frame.
        let dense: Vec<_> = (0..12)
            .map(|f| (f, vec![cube(RED, 20 + 3 * px(f), 50)]))
            .collect();
        let tracks = run(&dense);
        assert_eq!(tracks.len(), 1);
        assert_eq!(tracks[0].id, 0);
        assert_eq!(tracks[0].class, class("cube"));
        assert_eq!(tracks[0].color, Some(RED));
        assert_eq!(tracks[0].observations.len(), 12);
        assert_eq!(tracks[0].observations[4].centroid, [32.0, 50.0]);
        assert_eq!(tracks[0].observations[4].bbox, [26.0, 44.0, 38.0, 56.0]);
        // Every 5th frame, 2 px a frame down: 10 px between samples, a 12 px cube.
        let sparse: Vec<_> = (0..8)
            .map(|k| (5 * k, vec![cube(RED, 60, 20 + 10 * px(k))]))
            .collect();
        let tracks = run(&sparse);
        assert_eq!(tracks.len(), 1);
        assert_eq!(tracks[0].observations.len(), 8);
        assert_eq!(tracks[0].first_frame(), Some(0));
        assert_eq!(tracks[0].last_frame(), Some(35));
        assert_eq!(
            tracks[0].at_frame(15).map(|o| o.centroid),
            Some([60.0, 50.0])
        );
        assert_eq!(tracks[0].at_frame(16), None);
    }

    #[test]
    fn crossing_objects_of_different_colours_keep_their_ids() {
        // Red goes right, blue goes left, on the same row: they overlap fully at frame 10.
        let frames: Vec<_> = (0..21)
            .map(|f| {
                let k = px(f);
                (
                    f,
                    vec![cube(BLUE, 80 - 3 * k, 50), cube(RED, 20 + 3 * k, 50)],
                )
            })
            .collect();
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 2);
        // Red starts on the left, so it gets id 0.
        assert_eq!((tracks[0].id, tracks[0].color), (0, Some(RED)));
        assert_eq!((tracks[1].id, tracks[1].color), (1, Some(BLUE)));
        for track in &tracks {
            assert_eq!(track.observations.len(), 21);
            let color = track.color;
            for o in &track.observations {
                assert_eq!(frames[o.frame].1[o.detection].color, color, "{o:?}");
            }
        }
        // Same again with the blue one hidden while they overlap (frames 9..=11).
        let hidden: Vec<_> = frames
            .iter()
            .map(|(f, d)| {
                let keep = if (9..=11).contains(f) { 1 } else { 2 };
                (*f, d[2 - keep..].to_vec())
            })
            .collect();
        let tracks = run(&hidden);
        assert_eq!(tracks.len(), 2);
        assert_eq!(tracks[0].color, Some(RED));
        assert_eq!(tracks[0].observations.len(), 21);
        assert_eq!(tracks[1].color, Some(BLUE));
        assert_eq!(tracks[1].observations.len(), 18);
        assert_eq!(tracks[1].at_frame(12).map(|o| o.centroid[0]), Some(44.0));
    }

    #[test]
    fn same_colour_crossing_is_held_apart_by_motion() {
        // Two red cubes on crossing diagonals; constant velocity carries each through the
        // crossing at frame 10.
        let frames: Vec<_> = (0..21)
            .map(|f| {
                let k = px(f);
                (
                    f,
                    vec![
                        cube(RED, 20 + 3 * k, 20 + 3 * k),
                        cube(RED, 20 + 3 * k, 80 - 3 * k),
                    ],
                )
            })
            .collect();
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 2);
        for track in &tracks {
            let ys: Vec<f64> = track.observations.iter().map(|o| o.centroid[1]).collect();
            let rising = ys.windows(2).all(|w| w[1] > w[0]);
            let falling = ys.windows(2).all(|w| w[1] < w[0]);
            assert!(rising || falling, "{ys:?}");
        }
        // At frame 0 both are at x = 20; the tie goes to the smaller y.
        assert_eq!(tracks[0].observations[0].centroid, [20.0, 20.0]);
    }

    #[test]
    fn an_object_hidden_for_five_frames_comes_back_with_its_id() {
        // A sphere falls 2 px a frame; it is missing in frames 8..=12. A static pulley stays.
        let frames: Vec<_> = (0..20)
            .map(|f| {
                let mut d = vec![square(
                    class("solid static pulley"),
                    Some(GREEN),
                    150,
                    30,
                    10,
                )];
                if !(8..=12).contains(&f) {
                    d.push(square(class("sphere"), Some(BLUE), 40, 30 + 2 * px(f), 5));
                }
                (f, d)
            })
            .collect();
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 2);
        assert_eq!(
            (tracks[0].class, tracks[0].observations.len()),
            (class("sphere"), 15)
        );
        assert_eq!(
            (tracks[1].class, tracks[1].observations.len()),
            (class("solid static pulley"), 20)
        );
        assert_eq!(tracks[0].at_frame(13).map(|o| o.centroid[1]), Some(56.0));

        // Hidden for longer than `max_gap`: it comes back as a new track.
        let config = TrackerConfig {
            max_gap: 4,
            ..TrackerConfig::default()
        };
        let tracks = track(&frames, &config).unwrap();
        assert_eq!(tracks.len(), 3);
        assert_eq!(tracks[0].last_frame(), Some(7));
        assert_eq!(tracks[2].first_frame(), Some(13));
        assert_eq!(tracks[2].class, class("sphere"));
    }

    #[test]
    fn a_new_object_gets_a_new_id_and_a_spurious_one_none() {
        let frames: Vec<_> = (0..16)
            .map(|f| {
                let k = px(f);
                let mut d = vec![cube(RED, 100, 40 + k)];
                if f == 4 {
                    // A weak duplicate 3 px off the cube: same class, same colour.
                    let mut ghost = cube(RED, 103, 44);
                    ghost.score = 0.3;
                    d.insert(0, ghost);
                }
                if f == 6 {
                    // A lone false positive far away.
                    d.push(square(class("rope"), Some(GREEN), 20, 150, 3));
                }
                if f >= 10 {
                    d.push(square(class("sphere"), Some(BLUE), 30, 30, 5));
                }
                (f, d)
            })
            .collect();
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 2);
        assert_eq!((tracks[0].id, tracks[0].class), (0, class("cube")));
        assert_eq!(tracks[0].observations.len(), 16);
        // In frame 4 the cube's track took the real cube (index 1), not the ghost.
        assert_eq!(tracks[0].at_frame(4).map(|o| o.detection), Some(1));
        assert_eq!(
            tracks[0].at_frame(4).map(|o| o.centroid),
            Some([100.0, 44.0])
        );
        assert_eq!((tracks[1].id, tracks[1].class), (1, class("sphere")));
        assert_eq!(tracks[1].first_frame(), Some(10));
        // Keeping single observations, the ghost and the false positive become tracks 1 and 2.
        let config = TrackerConfig {
            min_observations: 1,
            ..TrackerConfig::default()
        };
        let tracks = track(&frames, &config).unwrap();
        let firsts: Vec<_> = tracks
            .iter()
            .map(|t| (t.id, t.first_frame(), t.class))
            .collect();
        assert_eq!(
            firsts,
            vec![
                (0, Some(0), class("cube")),
                (1, Some(4), class("cube")),
                (2, Some(6), class("rope")),
                (3, Some(10), class("sphere")),
            ]
        );
    }

    #[test]
    fn a_misread_colour_or_class_stays_on_the_track_and_is_outvoted() {
        let frames: Vec<_> = (0..6)
            .map(|f| {
                let mut d = cube(RED, 50, 50 + px(f));
                if f == 2 {
                    d.color = Some(BLUE);
                }
                if f == 3 {
                    d.class = class("sphere");
                    d.score = 0.95;
                }
                (f, vec![d])
            })
            .collect();
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 1);
        assert_eq!(tracks[0].observations.len(), 6);
        assert_eq!(tracks[0].color, Some(RED));
        assert_eq!(tracks[0].class, class("cube"));
    }

    /// Seed 9473's video 0: a movable pulley sinking, seen every 10th frame, read in another
    /// colour in one of them. It moved too far between samples for its masks to overlap by half,
    /// so only the distance gate can keep it on its track; without it the misread frame started
    /// a second pulley, and the rope was read round both.
    #[test]
    fn a_moving_object_misread_in_one_sparse_frame_stays_one_track() {
        let frames: Vec<_> = (0..7)
            .map(|sample| {
                let frame = sample * 10;
                let color = if sample == 5 { BLUE } else { RED };
                (
                    frame,
                    vec![square(
                        class("cube"),
                        Some(color),
                        100,
                        40 + 2 * px(frame),
                        25,
                    )],
                )
            })
            .collect();
        let (first, second) = (&frames[4].1[0], &frames[5].1[0]);
        assert!(
            iou(
                &first.mask,
                first.mask.area(),
                &second.mask,
                second.mask.area()
            ) < 0.5,
            "the misread frame overlaps the last one by less than half"
        );
        let tracks = run(&frames);
        assert_eq!(tracks.len(), 1, "{:?}", paths(&tracks));
        assert_eq!(tracks[0].observations.len(), 7);
        assert_eq!(tracks[0].color, Some(RED));
    }

    /// A vertical rope `x0..x0 + 3` from `top` to `bottom`, over a 200×200 frame.
    fn rope(color: u8, x0: u32, top: u32, bottom: u32) -> Detection {
        let mask = InstanceMask::from_predicate(200, 200, |x, y| {
            (x0..x0 + 3).contains(&x) && (top..bottom).contains(&y)
        });
        Detection {
            frame: 0,
            class: class("rope"),
            score: 0.8,
            bbox: [x0 as f32, top as f32, (x0 + 3) as f32, bottom as f32],
            mask,
            color: Some(color),
        }
    }

    #[test]
    fn ropes_over_a_pulley_keep_their_ids_and_a_misread_rope_colour_is_absorbed() {
        // A static pulley at (100, 40); a rope on each side of it, the left one paying out
        // (its bottom and its load go down 1 px a frame), the right one reeling in. Both ropes
        // run over the pulley (rows 30..50). In frame 5 the left rope is read as green, the
        // pulley's colour.
        let frames: Vec<_> = (0..12_u32)
            .map(|f| {
                let mut left = rope(RED, 88, 30, 120 + f);
                if f == 5 {
                    left.color = Some(GREEN);
                }
                let d = vec![
                    square(class("solid static pulley"), Some(GREEN), 100, 40, 12),
                    left,
                    rope(BLUE, 110, 30, 120 - f),
                    cube(BLUE, 89, 126 + i64::from(f)),
                ];
                (f as usize, d)
            })
            .collect();
        let tracks = run(&frames);
        let summary: Vec<_> = tracks
            .iter()
            .map(|t| (t.id, t.class, t.color, t.observations.len()))
            .collect();
        assert_eq!(
            summary,
            vec![
                // The cube's centroid (x = 89.0) is left of the left rope's (89.5).
                (0, class("cube"), Some(BLUE), 12),
                (1, class("rope"), Some(RED), 12),
                (2, class("solid static pulley"), Some(GREEN), 12),
                (3, class("rope"), Some(BLUE), 12),
            ]
        );
        for t in &tracks {
            for o in &t.observations {
                assert_eq!(frames[o.frame].1[o.detection].class, t.class);
            }
        }
    }

    #[test]
    fn output_is_deterministic_and_independent_of_detection_order() {
        let frames: Vec<_> = (0..15)
            .map(|f| {
                let k = px(f);
                let mut d = vec![
                    cube(RED, 20 + 3 * k, 50),
                    cube(BLUE, 80 - 3 * k, 50),
                    square(class("rope"), Some(GREEN), 60, 100, 20),
                    square(class("hollow dynamic pulley"), Some(RED), 60, 120 - k, 8),
                ];
                if f % 3 == 1 {
                    d.remove(1);
                }
                (f, d)
            })
            .collect();
        let first = run(&frames);
        assert_eq!(first, run(&frames));
        assert_eq!(first.len(), 4);
        // Reverse and rotate every frame's list: same tracks, same ids, same detections.
        let permuted: Vec<_> = frames
            .iter()
            .map(|(f, d)| {
                let mut d = d.clone();
                d.reverse();
                let n = d.len();
                d.rotate_left(f % n);
                (*f, d)
            })
            .collect();
        let second = run(&permuted);
        assert_eq!(paths(&first), paths(&second));
        for (a, b) in first.iter().zip(&second) {
            assert_eq!((a.id, a.class, a.color), (b.id, b.class, b.color));
            for (oa, ob) in a.observations.iter().zip(&b.observations) {
                assert_eq!(
                    frames[oa.frame].1[oa.detection],
                    permuted[ob.frame].1[ob.detection]
                );
            }
        }
    }

    #[test]
    fn bad_input_is_an_error_and_empty_input_no_tracks() {
        let frames = vec![(3, vec![cube(RED, 50, 50)]), (3, vec![cube(RED, 50, 50)])];
        assert_eq!(
            track(&frames, &TrackerConfig::default()),
            Err(TrackingError::FrameOrder {
                previous: 3,
                frame: 3
            })
        );
        let config = TrackerConfig {
            distance_gate: 0.0,
            ..TrackerConfig::default()
        };
        assert!(matches!(
            track(&[], &config),
            Err(TrackingError::Config {
                field: "distance_gate",
                ..
            })
        ));
        assert_eq!(track(&[], &TrackerConfig::default()), Ok(vec![]));
        // A detection with no pixels and no finite box is skipped.
        let mut nothing = cube(RED, 50, 50);
        nothing.mask = InstanceMask::empty();
        nothing.bbox = [f32::NAN; 4];
        let frames = vec![(0, vec![nothing.clone()]), (1, vec![nothing])];
        assert_eq!(run(&frames), vec![]);
    }
}

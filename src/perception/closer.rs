//! A closer look: the class of a track decided again with the detector run on windows of the
//! frame at twice its usual scale.
//!
//! The detector sees a 1080p frame shrunk four times (480 × 270), where a pulley is about 30
//! pixels wide and the three holes of a hollow one a few pixels each: solid and hollow pulleys,
//! and cubes and spheres, are confused there now and then, while the same model (trained on
//! such windows as well as on whole frames) tells them apart on a window of the frame shrunk
//! only twice. Each track whose class has rivals (the same kind, or kinds one word names, such
//! as rope's loads) is looked at again on a few frames: windows of the model's input size at
//! twice the scale are laid over those tracks, the detector runs on each, and the track's class
//! becomes the one with the largest summed score over its own detections in those frames and
//! the window detections that overlap them. Measured on generated rope videos (frames 0, 30,
//! 60): pulley classes 252 of 265 right from the whole frames, 262 from the windows, 263 from
//! both; loads 198, 203 and 203 of 203.
//!
//! Input: the tracks of a pass, its detections and frames, a detector, which classes are
//! rivals. Output: the tracks' classes (changed only where the closer look disagrees) and the
//! number of windows the detector ran on. Frames smaller than twice the model's input get no
//! closer look (the window would have to be enlarged, which the model never saw).

use std::collections::BTreeMap;

use super::classes::Class;
use super::detection::{Detection, box_iou};
use super::detector::{Detector, DetectorError};
use super::frames::RgbFrame;
use super::tracking::Track;

/// How much larger objects are in a window than in the whole frame as the detector sees it.
pub const ZOOM: u32 = 2;

/// Least box overlap (IoU) of a window detection with a track's box for it to vote.
pub const MIN_VOTE_IOU: f64 = 0.5;

/// Share of a window's width and height kept clear at its inner edges: a target box must lie
/// inside the window shrunk by this on every side (where the window does not meet the frame's
/// edge) for the window to count as showing it whole.
const WINDOW_MARGIN: f64 = 0.05;

/// A window of a frame, `[x0, y0, width, height]` in frame pixels.
pub type Window = [u32; 4];

/// Windows of `window_width × window_height` over a `frame_width × frame_height` frame that show
/// every box of `targets` (`[x0, y0, x1, y1]`, pixels) whole: the first target no window shows
/// yet gets a window centred on it (moved inside the frame), which then also shows whichever
/// later targets fit in it. Empty when the window does not fit in the frame.
pub fn windows_over(
    frame_width: u32,
    frame_height: u32,
    window_width: u32,
    window_height: u32,
    targets: &[[f32; 4]],
) -> Vec<Window> {
    if window_width == 0
        || window_height == 0
        || window_width > frame_width
        || window_height > frame_height
    {
        return Vec::new();
    }
    let mut windows: Vec<Window> = Vec::new();
    for target in targets {
        if target.iter().any(|v| !v.is_finite()) {
            continue;
        }
        if windows
            .iter()
            .any(|w| shows_whole(*w, *target, frame_width, frame_height))
        {
            continue;
        }
        let start = |low: f32, high: f32, size: u32, limit: u32| -> u32 {
            let centre = f64::midpoint(f64::from(low), f64::from(high));
            clamped_pixel(centre - f64::from(size) / 2.0, limit - size)
        };
        let x0 = start(target[0], target[2], window_width, frame_width);
        let y0 = start(target[1], target[3], window_height, frame_height);
        windows.push([x0, y0, window_width, window_height]);
    }
    windows
}

/// `value` rounded to a whole pixel within `0..=limit` (0 for NaN).
#[allow(clippy::cast_possible_truncation, clippy::cast_sign_loss)] // clamped into u32's range
fn clamped_pixel(value: f64, limit: u32) -> u32 {
    value.round().clamp(0.0, f64::from(limit)) as u32
}

/// Whether `target` lies inside `window`, clear of its inner edges by [`WINDOW_MARGIN`].
fn shows_whole(window: Window, target: [f32; 4], frame_width: u32, frame_height: u32) -> bool {
    let [x0, y0, w, h] = window.map(f64::from);
    let margin_x = w * WINDOW_MARGIN;
    let margin_y = h * WINDOW_MARGIN;
    let left = if x0 <= 0.0 { 0.0 } else { x0 + margin_x };
    let top = if y0 <= 0.0 { 0.0 } else { y0 + margin_y };
    let right = if x0 + w >= f64::from(frame_width) {
        x0 + w
    } else {
        x0 + w - margin_x
    };
    let bottom = if y0 + h >= f64::from(frame_height) {
        y0 + h
    } else {
        y0 + h - margin_y
    };
    let t = target.map(f64::from);
    t[0] >= left && t[1] >= top && t[2] <= right && t[3] <= bottom
}

/// The pixels of `window` of `frame`, as a frame of its own (same index); `None` when the
/// window is not inside the frame.
pub fn crop(frame: &RgbFrame, window: Window) -> Option<RgbFrame> {
    let [x0, y0, w, h] = window;
    if x0.checked_add(w)? > frame.width || y0.checked_add(h)? > frame.height {
        return None;
    }
    let row_bytes = w as usize * 3;
    let mut rgb = Vec::with_capacity(row_bytes * h as usize);
    for y in y0..y0 + h {
        let start = (y as usize * frame.width as usize + x0 as usize) * 3;
        rgb.extend_from_slice(frame.rgb.get(start..start + row_bytes)?);
    }
    Some(RgbFrame {
        index: frame.index,
        width: w,
        height: h,
        rgb,
    })
}

/// One vote: a class and the detector's score for it.
pub type Vote = (Class, f32);

/// The class with the largest summed score among `votes` (ties: the lower label); `None`
/// without votes.
pub fn winning_class(votes: &[Vote]) -> Option<Class> {
    let mut sums: BTreeMap<Class, f64> = BTreeMap::new();
    for (class, score) in votes {
        if score.is_finite() {
            *sums.entry(*class).or_insert(0.0) += f64::from(*score);
        }
    }
    let mut best: Option<(Class, f64)> = None;
    for (class, sum) in sums {
        if best.is_none_or(|(_, top)| sum > top) {
            best = Some((class, sum));
        }
    }
    best.map(|(class, _)| class)
}

/// Decides the class of every track with rivals again (see the module doc) on the frames of
/// `pixels` whose index is in `frames`. `detections` are the pass's detections by frame (the
/// tracks' observations index into them); `rivals(a, b)` says whether classes `a` and `b` are
/// alternatives for one object. Returns the number of windows the detector ran on.
pub fn look_closer(
    tracks: &mut [Track],
    detections: &[(usize, Vec<Detection>)],
    pixels: &[RgbFrame],
    frames: &[usize],
    detector: &mut Detector,
    rivals: &dyn Fn(Class, Class) -> bool,
) -> Result<u64, DetectorError> {
    let config = detector.config();
    let (input_width, input_height) = (config.input_width, config.input_height);
    let has_rivals: Vec<bool> = tracks
        .iter()
        .map(|track| {
            detector
                .classes()
                .all()
                .any(|other| other != track.class && rivals(track.class, other))
        })
        .collect();
    if !has_rivals.contains(&true) {
        return Ok(0);
    }
    let mut votes: Vec<Vec<Vote>> = vec![Vec::new(); tracks.len()];
    let mut windows_run = 0;
    for image in pixels.iter().filter(|p| frames.contains(&p.index)) {
        // The window: the model's input at ZOOM times the scale the whole frame is seen at
        // (the frame's width over ZOOM, the model's aspect).
        let window_width = image.width / ZOOM;
        let window_height = u32::try_from(
            u64::from(input_height) * u64::from(window_width) / u64::from(input_width.max(1)),
        )
        .unwrap_or(u32::MAX);
        if window_width < input_width || window_height < input_height {
            continue;
        }
        let found = detections
            .iter()
            .find(|(frame, _)| *frame == image.index)
            .map(|(_, found)| found.as_slice())
            .unwrap_or_default();
        // The tracks to look at in this frame, with their detection there.
        let targets: Vec<(usize, &Detection)> = tracks
            .iter()
            .enumerate()
            .filter(|(t, _)| has_rivals[*t])
            .filter_map(|(t, track)| {
                let point = track.at_frame(image.index)?;
                Some((t, found.get(point.detection)?))
            })
            .collect();
        let boxes: Vec<[f32; 4]> = targets.iter().map(|(_, d)| d.bbox).collect();
        let mut seen: Vec<(Class, f32, [f32; 4])> = Vec::new();
        for window in windows_over(
            image.width,
            image.height,
            window_width,
            window_height,
            &boxes,
        ) {
            let Some(part) = crop(image, window) else {
                continue;
            };
            windows_run += 1;
            for detection in detector.detect(&part)? {
                let b = detection.bbox;
                let (dx, dy) = (window[0] as f32, window[1] as f32);
                let bbox = [b[0] + dx, b[1] + dy, b[2] + dx, b[3] + dy];
                if shows_whole(window, bbox, image.width, image.height) {
                    seen.push((detection.class, detection.score, bbox));
                }
            }
        }
        for (t, detection) in targets {
            votes[t].push((detection.class, detection.score));
            // The window detection of a rival class overlapping this one most.
            let closest = seen
                .iter()
                .filter(|(class, _, _)| {
                    *class == tracks[t].class || rivals(tracks[t].class, *class)
                })
                .map(|(class, score, bbox)| {
                    (
                        class,
                        score,
                        box_iou(bbox.map(f64::from), detection.bbox.map(f64::from)),
                    )
                })
                .filter(|(_, _, overlap)| *overlap >= MIN_VOTE_IOU)
                .max_by(|a, b| a.2.total_cmp(&b.2));
            if let Some((class, score, _)) = closest {
                votes[t].push((*class, *score));
            }
        }
    }
    for (track, track_votes) in tracks.iter_mut().zip(&votes) {
        if let Some(class) = winning_class(track_votes) {
            track.class = class;
        }
    }
    Ok(windows_run)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::rope::test_class as class;

    #[test]
    fn windows_show_every_target_whole_and_stay_in_the_frame() {
        // Three pulleys near the top left (one window shows them all) and one at the bottom
        // right corner.
        let targets = [
            [300.0, 200.0, 410.0, 310.0],
            [420.0, 210.0, 530.0, 320.0],
            [100.0, 400.0, 210.0, 510.0],
            [1850.0, 1000.0, 1915.0, 1075.0],
        ];
        let windows = windows_over(1920, 1080, 960, 540, &targets);
        assert_eq!(windows, vec![[0, 0, 960, 540], [960, 540, 960, 540]]);
        for target in targets {
            assert!(windows.iter().any(|w| shows_whole(*w, target, 1920, 1080)));
        }
        // A target at a window's inner edge is not shown whole there: it gets its own window.
        let edge = [[300.0, 200.0, 410.0, 310.0], [900.0, 200.0, 1000.0, 300.0]];
        assert_eq!(windows_over(1920, 1080, 960, 540, &edge).len(), 2);
        // A window larger than the frame: no closer look.
        assert!(windows_over(900, 500, 960, 540, &targets).is_empty());
    }

    #[test]
    fn a_crop_is_the_window_pixels() {
        let frame = RgbFrame {
            index: 7,
            width: 4,
            height: 3,
            rgb: (0..36).collect(),
        };
        let part = crop(&frame, [1, 1, 2, 2]).expect("inside");
        assert_eq!(part.index, 7);
        assert_eq!(
            part.rgb,
            vec![15, 16, 17, 18, 19, 20, 27, 28, 29, 30, 31, 32]
        );
        assert!(crop(&frame, [3, 0, 2, 1]).is_none());
    }

    #[test]
    fn the_class_with_the_largest_summed_score_wins() {
        let (solid, hollow) = (class("solid static pulley"), class("hollow static pulley"));
        // Three whole-frame votes for hollow at 0.9 (2.7) against three window votes for solid
        // at 0.95 and one hollow vote at 0.3 (the closer look decides).
        let votes = [
            (hollow, 0.9),
            (hollow, 0.9),
            (hollow, 0.9),
            (solid, 0.95),
            (solid, 0.95),
            (solid, 0.95),
            (hollow, 0.3),
        ];
        assert_eq!(winning_class(&votes), Some(hollow));
        assert_eq!(winning_class(&votes[..6]), Some(solid));
        assert_eq!(winning_class(&[(solid, f32::NAN)]), None);
        assert_eq!(winning_class(&[]), None);
    }
}

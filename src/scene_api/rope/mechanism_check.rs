//! How well the rope mechanism read from pixels (`perceived`) matches the annotated one, for
//! `bench perception`: elements found where they are, and ropes read with the right elements in
//! the right order and the right turns.
//!
//! Input: a video folder with its annotations (`outputs.json`, `outputs4D.json`) and the
//! perception models. Output: a [`MechanismCheck`] of counts. Annotated elements are placed at
//! their first 4-D centroid when the video has one (moving bodies), else at their layout
//! position; a perceived element stands for the annotated one of the same class nearest to it,
//! within [`MATCH_RADIUS`] units, one to one.

use std::path::Path;

use serde::Serialize;
use serde_json::json;

use super::perceived::perceive_mechanism;
use super::simulation::{RopeLayoutPath, RopeSimulationError, rope_paths};
use crate::dataset::rope::{RopeAnnotation, VOCABULARY};
use crate::dataset::{FourDData, VideoFolder};
use crate::perception::assignment::assign;
use crate::perception::classes::{Class, ClassTable};
use crate::perception::rope::PERCEPTION;
use crate::physics::rope::Turn;
use crate::scene_api::perceiver::Perceiver;
use crate::scene_api::{ApiError, PerceptionModels};

/// Farthest a perceived element may be from the annotated one it stands for, units (a pulley's
/// radius).
pub const MATCH_RADIUS: f64 = 1.5;

/// The perceived mechanism of one video against its annotation.
#[derive(Debug, Clone, Default, PartialEq, Serialize)]
pub struct MechanismCheck {
    /// Annotated pulleys, loads and fixed points on ropes.
    pub elements: usize,
    /// Of those, found by perception (same class, within [`MATCH_RADIUS`]).
    pub elements_found: usize,
    /// Mean distance of the found ones from their annotated position, units.
    pub mean_position_error: f64,
    /// Annotated ropes.
    pub ropes: usize,
    /// Of those, read with the same elements in the same order (either direction).
    pub ropes_read: usize,
    /// Of those, also with the same turn at every pulley.
    pub ropes_read_with_turns: usize,
    /// Perceived ropes that match no annotated one.
    pub extra_ropes: usize,
    /// What was not read right, for diagnosis: annotated elements not found (`name (class)`)
    /// and each rope not read with its turns, beside the perceived path closest to it (empty in
    /// the summed total).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub missed_elements: Vec<String>,
    /// Ropes not read right: the annotated path and the closest perceived one.
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub missed_ropes: Vec<MissedRope>,
}

/// An annotated rope not read right and the perceived rope most like it.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub struct MissedRope {
    /// The annotated path: element names in order, each with its turn (`cw`, `ccw` or `-`).
    pub annotated: Vec<String>,
    /// The perceived path sharing most elements with it, in the annotated names where an
    /// element was matched (`?name` where not), with turns; empty when no rope shares any.
    pub closest_read: Vec<String>,
}

/// The mechanism read from pixels against the annotated one, per video and summed, as
/// `bench perception` reports it (`mechanism`); the first-pass frames are detected again for it.
/// The scenario table lists it as rope's scene reading check.
pub fn mechanism_report(
    videos: &[VideoFolder],
    models: &PerceptionModels,
) -> Result<serde_json::Value, ApiError> {
    let mut total = MechanismCheck::default();
    let mut per_video = Vec::new();
    let mut error_sum = 0.0;
    let mut all_right = 0;
    for video in videos {
        let check = check_rope_mechanism(&video.dir, models)
            .map_err(|error| ApiError::Data(format!("video {}: {error}", video.dir.display())))?;
        total.elements += check.elements;
        total.elements_found += check.elements_found;
        total.ropes += check.ropes;
        total.ropes_read += check.ropes_read;
        total.ropes_read_with_turns += check.ropes_read_with_turns;
        total.extra_ropes += check.extra_ropes;
        error_sum += check.mean_position_error * check.elements_found as f64;
        if check.ropes_read_with_turns == check.ropes && check.extra_ropes == 0 {
            all_right += 1;
        }
        per_video.push(json!({"video": video.id.0, "check": check}));
    }
    total.mean_position_error = error_sum / total.elements_found.max(1) as f64;
    Ok(json!({
        "match_radius_units": MATCH_RADIUS,
        "total": total,
        "videos_read_entirely": all_right,
        "per_video": per_video,
    }))
}

/// Reads the mechanism of the video in `video_dir` from its pixels and compares it with the
/// annotated one.
pub fn check_rope_mechanism(
    video_dir: &Path,
    models: &PerceptionModels,
) -> Result<MechanismCheck, ApiError> {
    let annotation = RopeAnnotation::load(&video_dir.join("outputs.json"))?;
    let four_d_path = video_dir.join("outputs4D.json");
    let four_d = if four_d_path.is_file() {
        Some(FourDData::load(&four_d_path)?)
    } else {
        None
    };
    let camera = annotation.camera.clone().ok_or_else(|| {
        ApiError::Unavailable(format!(
            "{}: no camera calibration (outputCamera)",
            video_dir.display()
        ))
    })?;
    let mut perceiver = Perceiver::open(video_dir, models, PERCEPTION.classes, &VOCABULARY)?;
    let perceived = perceive_mechanism(&mut perceiver, &camera)?;
    let classes = ClassTable::of_scenario(PERCEPTION.classes);
    let unavailable = |error: RopeSimulationError| {
        ApiError::Unavailable(format!("{}: {error}", video_dir.display()))
    };
    let truth_paths = rope_paths(&annotation, four_d.as_ref()).map_err(unavailable)?;
    let seen_paths =
        rope_paths(&perceived.annotation, Some(&perceived.four_d)).map_err(unavailable)?;

    // Elements on ropes, with class and position.
    let place = |annotation: &RopeAnnotation, four_d: Option<&FourDData>, name: &str| {
        four_d
            .and_then(|data| data.rigid_bodies.get(name))
            .and_then(|track| track.poses.first())
            .map(|(at, _)| [at[0], at[1]])
            .or_else(|| annotation.element_positions.get(name).copied())
    };
    let elements =
        |paths: &[RopeLayoutPath], annotation: &RopeAnnotation, four_d: Option<&FourDData>| {
            let mut list: Vec<(String, Class, [f64; 2])> = Vec::new();
            for (_, names, _) in paths {
                for name in names {
                    if list.iter().any(|(n, _, _)| n == name) {
                        continue;
                    }
                    if let (Some(class), Some(at)) =
                        (classes.of_object(name), place(annotation, four_d, name))
                    {
                        list.push((name.clone(), class, at));
                    }
                }
            }
            list
        };
    let truth_elements = elements(&truth_paths, &annotation, four_d.as_ref());
    let seen_elements = elements(&seen_paths, &perceived.annotation, Some(&perceived.four_d));
    let matched = assign(truth_elements.len(), seen_elements.len(), |t, s| {
        let (_, class_t, at_t) = &truth_elements[t];
        let (_, class_s, at_s) = &seen_elements[s];
        let distance = (at_t[0] - at_s[0]).hypot(at_t[1] - at_s[1]);
        (class_t == class_s && distance <= MATCH_RADIUS).then_some(distance)
    });
    let mut check = MechanismCheck {
        elements: truth_elements.len(),
        ropes: truth_paths.len(),
        ..MechanismCheck::default()
    };
    let mut error_sum = 0.0;
    for (t, s) in matched.iter().enumerate() {
        if let Some(s) = s {
            check.elements_found += 1;
            let (a, b) = (truth_elements[t].2, seen_elements[*s].2);
            error_sum += (a[0] - b[0]).hypot(a[1] - b[1]);
        }
    }
    check.mean_position_error = if check.elements_found > 0 {
        error_sum / check.elements_found as f64
    } else {
        0.0
    };
    // A perceived name → the annotated name it stands for.
    let truth_name = |seen: &str| {
        let s = seen_elements.iter().position(|(n, _, _)| n == seen)?;
        let t = matched.iter().position(|m| *m == Some(s))?;
        Some(truth_elements[t].0.clone())
    };
    let mut used = vec![false; seen_paths.len()];
    let mut read_right = vec![false; truth_paths.len()];
    for (truth_index, (_, names, turns)) in truth_paths.iter().enumerate() {
        for (index, (_, seen_names, seen_turns)) in seen_paths.iter().enumerate() {
            if used[index] {
                continue;
            }
            let mapped: Vec<Option<String>> = seen_names.iter().map(|n| truth_name(n)).collect();
            let forward = mapped
                .iter()
                .map(Option::as_deref)
                .eq(names.iter().map(|n| Some(n.as_str())));
            let backward = mapped
                .iter()
                .rev()
                .map(Option::as_deref)
                .eq(names.iter().map(|n| Some(n.as_str())));
            if !(forward || backward) {
                continue;
            }
            used[index] = true;
            check.ropes_read += 1;
            // Turns flip with the direction of travel.
            let same_turns = if forward {
                seen_turns == turns
            } else {
                seen_turns
                    .iter()
                    .rev()
                    .map(|t| t.map(Turn::reversed))
                    .eq(turns.iter().copied())
            };
            if same_turns {
                check.ropes_read_with_turns += 1;
                read_right[truth_index] = true;
            }
            break;
        }
    }
    check.extra_ropes = used.iter().filter(|u| !**u).count();
    check.missed_elements = truth_elements
        .iter()
        .zip(&matched)
        .filter(|(_, m)| m.is_none())
        .map(|((name, class, _), _)| format!("{name} ({})", classes.name(*class)))
        .collect();
    check.missed_ropes = missed_ropes(&truth_paths, &read_right, &seen_paths, &truth_name);
    Ok(check)
}

/// A path as `name turn` words (`cw`, `ccw`, `-` at ends).
fn with_turns(names: &[String], turns: &[Option<Turn>]) -> Vec<String> {
    names
        .iter()
        .enumerate()
        .map(|(index, name)| {
            let turn = match turns.get(index).copied().flatten() {
                Some(Turn::CounterClockwise) => "ccw",
                Some(Turn::Clockwise) => "cw",
                None => "-",
            };
            format!("{name} {turn}")
        })
        .collect()
}

/// Each annotated rope not read right, beside the perceived path sharing most elements with it
/// (its names mapped to the annotated ones through `truth_name`).
fn missed_ropes(
    truth_paths: &[RopeLayoutPath],
    read_right: &[bool],
    seen_paths: &[RopeLayoutPath],
    truth_name: &dyn Fn(&str) -> Option<String>,
) -> Vec<MissedRope> {
    let mut missed = Vec::new();
    for (truth_index, (_, names, turns)) in truth_paths.iter().enumerate() {
        if read_right.get(truth_index).copied().unwrap_or(false) {
            continue;
        }
        let closest = seen_paths
            .iter()
            .map(|(_, seen_names, seen_turns)| {
                let mapped: Vec<String> = seen_names
                    .iter()
                    .map(|n| truth_name(n).unwrap_or_else(|| format!("?{n}")))
                    .collect();
                let shared = mapped.iter().filter(|n| names.contains(n)).count();
                (shared, mapped, seen_turns)
            })
            .filter(|(shared, _, _)| *shared > 0)
            .max_by_key(|(shared, _, _)| *shared);
        missed.push(MissedRope {
            annotated: with_turns(names, turns),
            closest_read: closest
                .map(|(_, mapped, seen_turns)| with_turns(&mapped, seen_turns))
                .unwrap_or_default(),
        });
    }
    missed
}

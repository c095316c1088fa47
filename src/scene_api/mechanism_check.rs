//! How well the rope mechanism read from pixels (`perceived_rope`) matches the annotated one, for
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

use super::error::ApiError;
use super::perceived::Perceiver;
use super::rope_sim::{RopeLayoutPath, rope_paths};
use super::scene::PerceptionModels;
use crate::dataset::FourDData;
use crate::dataset::rope::RopeAnnotation;
use crate::perception::assignment::assign;
use crate::perception::detection::ObjectClass;

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
    let mut perceiver = Perceiver::open(video_dir, models)?;
    let perceived = perceiver.mechanism(&camera)?;
    let unavailable = |error: super::rope_sim::RopeSimulationError| {
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
            let mut list: Vec<(String, ObjectClass, [f64; 2])> = Vec::new();
            for (_, names, _) in paths {
                for name in names {
                    if list.iter().any(|(n, _, _)| n == name) {
                        continue;
                    }
                    if let (Some(class), Some(at)) = (
                        ObjectClass::from_object_name(name),
                        place(annotation, four_d, name),
                    ) {
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
    for (_, names, turns) in &truth_paths {
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
                    .map(|t| t.map(crate::physics::rope::Turn::reversed))
                    .eq(turns.iter().copied())
            };
            if same_turns {
                check.ropes_read_with_turns += 1;
            }
            break;
        }
    }
    check.extra_ropes = used.iter().filter(|u| !**u).count();
    Ok(check)
}

//! Rope masses and tensions as the video shows them (`--dynamics simulate`): the masses
//! inferred from the tracked motion (`physics::rope::identify`, through
//! `simulation::infer_rope_masses`), with the detector's tracks in place of the annotated ones
//! under `--perception maskrcnn`, and the property queries answered from them ("cannot tell"
//! unless the motion decides).

use std::sync::{Mutex, PoisonError};

use indexmap::IndexMap;

use super::perceived::perceived_positions;
use super::simulation::{RopeMassInference, infer_rope_masses};
use super::{GRAVITY_M_PER_S2, RopeBackend};
use crate::dataset::FourDData;
use crate::dataset::rope::{RopeObjectKind, parse_rope_object_name};
use crate::physics::rope::identify::{BodyVerdict, PairVerdict};
use crate::scene_api::perceiver::Perceiver;
use crate::scene_api::{ApiError, Property, SceneObjectInfo};

/// Fewest frames a perceived track needs to stand for a body in mass inference.
const MIN_PERCEIVED_FRAMES: usize = 30;

/// A per-frame track with gaps filled: linearly between seen frames, the first seen position
/// before it; it ends at the last seen frame.
fn filled(track: &[Option<[f64; 3]>]) -> Vec<[f64; 3]> {
    let seen: Vec<(usize, [f64; 3])> = track
        .iter()
        .enumerate()
        .filter_map(|(i, p)| p.map(|p| (i, p)))
        .collect();
    let (Some(first), Some(last)) = (seen.first(), seen.last()) else {
        return Vec::new();
    };
    let mut out = Vec::with_capacity(last.0 + 1);
    for frame in 0..=last.0 {
        let after = seen.partition_point(|(i, _)| *i < frame);
        let point = match (
            after.checked_sub(1).and_then(|b| seen.get(b)),
            seen.get(after),
        ) {
            (_, Some((i, p))) if *i == frame => *p,
            (Some((i0, p0)), Some((i1, p1))) => {
                let t = (frame - i0) as f64 / (i1 - i0) as f64;
                [0, 1, 2].map(|c| p0[c] + t * (p1[c] - p0[c]))
            }
            _ => first.1,
        };
        out.push(point);
    }
    out
}

impl RopeBackend {
    /// Every load's mass as inferred from the motion, for the factual run of a perceived
    /// mechanism; unavailable unless the motion determines each one.
    pub(super) fn inferred_masses(&self) -> Result<IndexMap<String, f64>, ApiError> {
        let inference = self.mass_inference()?;
        self.annotation
            .output_mass_kg
            .keys()
            .map(|load| match inference.load(load) {
                Some(BodyVerdict::Determined { mass }) => Ok((load.clone(), *mass)),
                _ => Err(ApiError::Unavailable(format!(
                    "the factual run needs every load's mass, and the motion does not determine the {load}'s"
                ))),
            })
            .collect()
    }

    /// The load masses inferred from the tracked motion, once per scene.
    fn mass_inference(&self) -> Result<&RopeMassInference, ApiError> {
        let inferred = self.inference.get_or_init(|| {
            let four_d = self.four_d.as_ref().ok_or_else(|| {
                ApiError::Unavailable(
                    "masses are inferred from the tracked motion, and this video has no outputs4D.json"
                        .to_string(),
                )
            })?;
            let perceived;
            let four_d = match &self.perceiver {
                Some(perceiver) => {
                    perceived = self.perceived_tracks(perceiver, four_d)?;
                    &perceived
                }
                None => four_d,
            };
            infer_rope_masses(&self.annotation, four_d).map_err(|error| {
                ApiError::Unavailable(format!(
                    "cannot infer masses from this video's motion: {error}"
                ))
            })
        });
        inferred.as_ref().map_err(Clone::clone)
    }

    /// `four_d` with the moving bodies' tracks (loads, movable pulleys) replaced by the
    /// detector's, lifted onto the scene plane; a body the detector did not follow through at
    /// least [`MIN_PERCEIVED_FRAMES`] frames has no track. Gaps are filled linearly.
    fn perceived_tracks(
        &self,
        perceiver: &Mutex<Perceiver>,
        four_d: &FourDData,
    ) -> Result<FourDData, ApiError> {
        let camera = self.annotation.camera.as_ref().ok_or_else(|| {
            ApiError::Unavailable(
                "perceived tracks need the camera record (outputCamera), which this video lacks"
                    .to_string(),
            )
        })?;
        let perceived = perceived_positions(
            &mut perceiver.lock().unwrap_or_else(PoisonError::into_inner),
            camera,
        )?;
        let mut tracked = four_d.clone();
        for (name, body) in &mut tracked.rigid_bodies {
            let moving = parse_rope_object_name(name).is_some_and(|p| {
                matches!(p.kind, RopeObjectKind::Cube | RopeObjectKind::Sphere)
                    || (p.kind == RopeObjectKind::Pulley && p.dynamics == "dynamic")
            });
            if body.is_static || !moving {
                continue;
            }
            let positions = perceived
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, p)| filled(p))
                .unwrap_or_default();
            body.poses = if positions.len() >= MIN_PERCEIVED_FRAMES {
                positions.into_iter().map(|p| (p, [0.0; 3])).collect()
            } else {
                Vec::new()
            };
        }
        Ok(tracked)
    }

    /// The loads a rope carries (`object_rope_map`), by annotation name.
    fn loads_on(&self, rope: usize) -> Vec<&str> {
        self.structure
            .loads()
            .filter(|load| self.structure.rope_of(*load) == Some(rope))
            .filter_map(|load| self.objects.get(load).map(|o| o.name.as_str()))
            .collect()
    }

    /// `query` under `Simulate`: masses and tensions from the tracked motion. The objects are
    /// already checked to have the property.
    pub(super) fn query_observed(
        &self,
        property: Property,
        infos: &[&SceneObjectInfo],
    ) -> Result<Vec<Option<f64>>, ApiError> {
        let inference = self.mass_inference()?;
        let unknown = || vec![None; infos.len()];
        if let [first, second] = infos
            && !self.comparable(first, second)
        {
            return Ok(unknown());
        }
        match property {
            Property::Mass => {
                let mut loads: Vec<&str> = infos.iter().map(|o| o.name.as_str()).collect();
                loads.dedup();
                let Some(masses) = observed_masses(inference, &loads) else {
                    return Ok(unknown());
                };
                Ok(infos
                    .iter()
                    .map(|o| {
                        loads
                            .iter()
                            .position(|l| *l == o.name)
                            .and_then(|at| masses.get(at).copied())
                    })
                    .collect())
            }
            Property::Tension => {
                // Tension is the weight of the load a rope carries; it is known when the loads
                // involved compare decidedly and each rope's loads weigh the same.
                let per_rope: Vec<Vec<&str>> = infos
                    .iter()
                    .map(|o| self.loads_on(o.id.0 as usize))
                    .collect();
                let mut loads: Vec<&str> = per_rope.iter().flatten().copied().collect();
                loads.sort_unstable();
                loads.dedup();
                let Some(masses) = observed_masses(inference, &loads) else {
                    return Ok(unknown());
                };
                let mass_of = |load: &str| {
                    loads
                        .iter()
                        .position(|l| *l == load)
                        .and_then(|at| masses.get(at).copied())
                };
                let values: Vec<Option<f64>> = per_rope
                    .iter()
                    .map(|carried| {
                        let first = mass_of(carried.first()?)?;
                        carried
                            .iter()
                            .all(|load| mass_of(load).is_some_and(|m| (m - first).abs() < 1e-9))
                            .then_some(first * GRAVITY_M_PER_S2)
                    })
                    .collect();
                if values.iter().any(Option::is_none) {
                    return Ok(unknown());
                }
                Ok(values)
            }
            _ => Ok(unknown()),
        }
    }
}

/// Nominal masses (kg) of `loads` from the motion: when one load's mass is determined, or
/// every pair of them is decided; `None` when the motion cannot tell.
fn observed_masses(inference: &RopeMassInference, loads: &[&str]) -> Option<Vec<f64>> {
    match loads {
        [] => None,
        [load] => match inference.load(load)? {
            BodyVerdict::Determined { mass } => Some(vec![nominal_kg(*mass)]),
            BodyVerdict::Undetermined(_) => None,
        },
        _ => {
            let mut masses = vec![None; loads.len()];
            for (i, first) in loads.iter().enumerate() {
                for (j, second) in loads.iter().enumerate().skip(i + 1) {
                    if first == second {
                        continue;
                    }
                    let PairVerdict::Decided { masses: pair, .. } =
                        inference.pair(first, second)?
                    else {
                        return None;
                    };
                    masses[i] = Some(nominal_kg(pair[0]));
                    masses[j] = Some(nominal_kg(pair[1]));
                }
            }
            masses.into_iter().collect()
        }
    }
}

/// The benchmark's nominal mass of a simulated one, kg: `ceil(m·100)/100` (`docs/data/rope.md`,
/// scene reading), so a load of 1.975 × 0.2 kg reads 0.4.
fn nominal_kg(mass: f64) -> f64 {
    (mass * 100.0).ceil() / 100.0
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn perceived_tracks_are_filled_linearly_and_end_at_the_last_sighting() {
        let p = |y: f64| Some([0.0, y, 0.0]);
        let track = vec![None, p(1.0), None, None, p(4.0), p(5.0), None];
        let heights: Vec<f64> = filled(&track).iter().map(|q| q[1]).collect();
        assert_eq!(heights, vec![1.0, 1.0, 2.0, 3.0, 4.0, 5.0]);
        assert!(filled(&[None, None]).is_empty());
    }
}

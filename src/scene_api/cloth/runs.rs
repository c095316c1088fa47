//! The cloth scene's runs under `--dynamics simulate`: what the video shows (the cloths' tracked
//! particles, read once, on the first question that needs them) and each half's simulated run
//! (made on the first question about that half's boxes, so a video whose questions ask about
//! the cloths' properties, or about one half, simulates nothing, or one half).
//!
//! Input: the video folder (`outputs4D.json`) and its annotation (the boxes' sizes, shapes and
//! start poses: what the first frames show). Output: the [`ClothVerdict`] and each half's
//! [`HalfRun`]. Errors are kept and replayed to every later question that needs the same part.

use std::path::{Path, PathBuf};
use std::sync::OnceLock;

use super::infer::{ClothReading, ClothVerdict, goes_through, read_cloths};
use super::simulate::{ClothModel, HalfRun, SeenBox, SeenCloth, SeenHalf, simulate_half};
use crate::dataset::FourDData;
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::{ClothAnnotation, Friction, VALUES};
use crate::scene_api::ApiError;

/// What the video shows of the two cloths.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Observed {
    /// Left, right.
    pub readings: [ClothReading; 2],
    /// The properties' verdicts.
    pub verdict: ClothVerdict,
}

/// The lazily made parts of one video's simulation.
pub(crate) struct ClothRuns {
    folder: PathBuf,
    model: ClothModel,
    observed: OnceLock<Result<Observed, ApiError>>,
    halves: [OnceLock<Result<HalfRun, ApiError>>; 2],
}

impl ClothRuns {
    /// The runs of the video in `folder`, simulated under `model`.
    pub(crate) fn new(folder: PathBuf, model: ClothModel) -> ClothRuns {
        ClothRuns {
            folder,
            model,
            observed: OnceLock::new(),
            halves: [OnceLock::new(), OnceLock::new()],
        }
    }

    /// Runs simulated and solver updates taken so far.
    pub(crate) fn work(&self) -> (u64, u64) {
        self.halves
            .iter()
            .filter_map(|slot| slot.get().and_then(|run| run.as_ref().ok()))
            .fold((0, 0), |(runs, steps), run| {
                (
                    runs + 1,
                    steps + u64::try_from(run.updates).unwrap_or(u64::MAX),
                )
            })
    }

    /// What the video shows of the cloths (read on first use).
    pub(crate) fn observed(&self) -> Result<&Observed, ApiError> {
        self.observed
            .get_or_init(|| observe(&self.folder))
            .as_ref()
            .map_err(Clone::clone)
    }

    /// The simulated run of `side`'s half (made on first use).
    pub(crate) fn half(
        &self,
        annotation: &ClothAnnotation,
        side: Side,
    ) -> Result<&HalfRun, ApiError> {
        let slot = match side {
            Side::Left => &self.halves[0],
            Side::Right => &self.halves[1],
        };
        slot.get_or_init(|| {
            let observed = self.observed()?;
            let half = seen_half(annotation, side, observed);
            simulate_half(&half, &self.model).map_err(|error| {
                ApiError::Unavailable(format!(
                    "the simulation of the {} half failed: {error}",
                    side.word()
                ))
            })
        })
        .as_ref()
        .map_err(Clone::clone)
    }
}

/// Reads the cloths from the tracked particles of the video in `folder`.
pub(crate) fn observe(folder: &Path) -> Result<Observed, ApiError> {
    let path = folder.join("outputs4D.json");
    let four_d = FourDData::load(&path).map_err(|error| {
        ApiError::Unavailable(format!(
            "--dynamics simulate reads the cloths' tracked particles: {error}"
        ))
    })?;
    let readings = read_cloths(&four_d)?;
    let verdict = ClothVerdict::of(&readings);
    Ok(Observed { readings, verdict })
}

/// `side`'s half as the video shows it: the annotation's boxes where they start (what the
/// first frames show), each marked where the cloth never goes through its place, and the cloth read from its particles, with the properties of the
/// verdict (where a property is not told, the mean of the release's two values).
pub(crate) fn seen_half(annotation: &ClothAnnotation, side: Side, observed: &Observed) -> SeenHalf {
    let reading = match side {
        Side::Left => &observed.readings[0],
        Side::Right => &observed.readings[1],
    };
    let boxes = annotation
        .objects(side)
        .boxes()
        .map(|record| {
            let mut seen = SeenBox::from_record(record, None);
            seen.undisturbed =
                !goes_through(&reading.track, seen.position, seen.orientation, seen.size);
            seen
        })
        .collect();
    let pick = |told: Option<Side>, [more, less]: [f64; 2]| match told {
        Some(winner) if winner == side => more,
        Some(_) => less,
        None => f64::midpoint(more, less),
    };
    SeenHalf {
        boxes,
        cloth: SeenCloth {
            spawn: reading.spawn.clone(),
            stretch_compliance: pick(observed.verdict.stretches, VALUES.stretch_compliance),
            max_bending: pick(observed.verdict.bends, VALUES.max_bending),
            friction: observed.verdict.friction_guess.map(|high| {
                if high == side {
                    Friction::High
                } else {
                    Friction::Low
                }
            }),
            pull_distance: reading.pull_distance,
        },
    }
}

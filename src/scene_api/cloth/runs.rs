//! The cloth scene's runs under `--dynamics simulate`: what the video shows (the cloths' tracked
//! particles, read once, on the first question that needs them) and each half's simulated run
//! (made on the first question about that half's boxes, so a video whose questions ask about
//! the cloths' properties, or about one half, simulates nothing, or one half).
//!
//! Input: the video folder (`outputs4D.json`) and its annotation (the boxes' sizes, shapes and
//! start poses: what the first frames show), or under `--perception maskrcnn` the video's
//! frames, its camera and the perceived boxes (the cloths' masks, read by `pixels`). Output: the
//! [`ClothVerdict`] and each half's [`HalfRun`]. Errors are kept and replayed to every later
//! question that needs the same part.

use std::path::{Path, PathBuf};
use std::sync::{Mutex, OnceLock, PoisonError};

use super::infer::{ClothVerdict, goes_through, read_cloths};
use super::motion::start_regions;
use super::pixels;
use super::simulate::{ClothModel, HalfRun, SeenBox, SeenCloth, SeenHalf, simulate_half};
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::{ClothAnnotation, Friction, VALUES};
use crate::dataset::{Camera, FourDData};
use crate::physics::vector3::Vector;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::{Perceiver, camera_model, kept_work};

/// What the video shows of one cloth that a simulation replays.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ObservedCloth {
    /// Its particles at the spawn (a flat square grid), units.
    pub spawn: Vec<Vector>,
    /// How far the handle drags it, units.
    pub pull_distance: f64,
    /// Its tracked particles per frame, units (`None` read from pixels).
    pub track: Option<Vec<Vec<Vector>>>,
}

/// What the video shows of the two cloths.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct Observed {
    /// Left, right.
    pub cloths: [ObservedCloth; 2],
    /// The properties' verdicts.
    pub verdict: ClothVerdict,
    /// The boxes the masks show standing still where they started (`motion`; none read from
    /// tracked particles, whose path tells the same per half).
    pub still: Vec<String>,
}

/// Where the cloths are read from.
enum Source {
    /// The tracked particles of the video in this folder (`--perception annotation`).
    Tracked(PathBuf),
    /// The video's frames through the detector, seen through the camera (`--perception
    /// maskrcnn`).
    Perceived {
        perceiver: Box<Mutex<Perceiver>>,
        camera: Camera,
        /// The boxes perception read.
        boxes: Box<ClothAnnotation>,
    },
}

/// The lazily made parts of one video's simulation.
pub(crate) struct ClothRuns {
    source: Source,
    model: ClothModel,
    observed: OnceLock<Result<Observed, ApiError>>,
    halves: [OnceLock<Result<HalfRun, ApiError>>; 2],
}

impl ClothRuns {
    /// The runs of the video in `folder`, simulated under `model`, its cloths read from their
    /// tracked particles.
    pub(crate) fn new(folder: PathBuf, model: ClothModel) -> ClothRuns {
        ClothRuns::of(Source::Tracked(folder), model)
    }

    /// The runs of the video `perceiver` opened, its cloths read from their masks seen through
    /// `camera`, its boxes (`boxes`, as perception read them) watched for motion.
    pub(crate) fn perceived(
        perceiver: Perceiver,
        camera: Camera,
        boxes: ClothAnnotation,
        model: ClothModel,
    ) -> ClothRuns {
        let source = Source::Perceived {
            perceiver: Box::new(Mutex::new(perceiver)),
            camera,
            boxes: Box::new(boxes),
        };
        ClothRuns::of(source, model)
    }

    fn of(source: Source, model: ClothModel) -> ClothRuns {
        ClothRuns {
            source,
            model,
            observed: OnceLock::new(),
            halves: [OnceLock::new(), OnceLock::new()],
        }
    }

    /// What the cloths were read from, for messages.
    pub(crate) fn evidence(&self) -> &'static str {
        match self.source {
            Source::Tracked(_) => "tracked particles",
            Source::Perceived { .. } => "masks",
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

    /// Frames decoded and run through the detector so far (none from tracked particles).
    pub(crate) fn perception_work(&self) -> (u64, u64) {
        match &self.source {
            Source::Tracked(_) => (0, 0),
            Source::Perceived { perceiver, .. } => kept_work(Some(perceiver)),
        }
    }

    /// What the video shows of the cloths (read on first use).
    pub(crate) fn observed(&self) -> Result<&Observed, ApiError> {
        self.observed
            .get_or_init(|| match &self.source {
                Source::Tracked(folder) => observe(folder),
                Source::Perceived {
                    perceiver,
                    camera,
                    boxes,
                } => {
                    let mut perceiver = perceiver.lock().unwrap_or_else(PoisonError::into_inner);
                    observe_pixels(&mut perceiver, camera, boxes)
                }
            })
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
    Ok(Observed {
        cloths: readings.map(|reading| ObservedCloth {
            spawn: reading.spawn,
            pull_distance: reading.pull_distance,
            track: Some(reading.track),
        }),
        verdict,
        still: Vec::new(),
    })
}

/// Reads the cloths from their masks in the video `perceiver` opened, seen through `camera`,
/// and which of `boxes` stood still.
fn observe_pixels(
    perceiver: &mut Perceiver,
    camera: &Camera,
    boxes: &ClothAnnotation,
) -> Result<Observed, ApiError> {
    let (width, height, _) = perceiver.frames();
    let model = camera_model(camera, (width, height));
    // One detector pass for the cloths and the boxes' motion, though only the simulation needs
    // the motion: a scene asked about properties alone reads 31 frames more (2 of the 100 videos
    // of seed 7070), where splitting the pass would run the detector twice on every other.
    let frames = pixels::pass_frames();
    let regions = start_regions(perceiver, boxes, &model);
    let masks = pixels::seen_masks(perceiver, &model, &frames, &regions)?;
    let still = regions
        .iter()
        .zip(&masks.motions)
        .filter(|(region, motion)| motion.still(region))
        .map(|(region, _)| region.name.clone())
        .collect();
    if masks.cloths.iter().all(Vec::is_empty) {
        return Err(ApiError::Unavailable(
            "--perception maskrcnn reads the cloths from their masks, and the detector found no cloth in the video".to_string(),
        ));
    }
    let seen = pixels::read_cloths(&masks, &model);
    let [left, right] = seen.spawns;
    Ok(Observed {
        cloths: [
            ObservedCloth {
                spawn: left,
                pull_distance: pixels::MEAN_PULL,
                track: None,
            },
            ObservedCloth {
                spawn: right,
                pull_distance: pixels::MEAN_PULL,
                track: None,
            },
        ],
        verdict: seen.verdict,
        still,
    })
}

/// `side`'s half as the video shows it: the annotation's boxes where they start (what the
/// first frames show), each marked undisturbed where the tracked cloth never goes through its
/// place (read from pixels: where its own masks show it standing still), and the cloth as read, with the properties of the verdict (where a property is not told, the mean of
/// the release's two values).
pub(crate) fn seen_half(annotation: &ClothAnnotation, side: Side, observed: &Observed) -> SeenHalf {
    let reading = match side {
        Side::Left => &observed.cloths[0],
        Side::Right => &observed.cloths[1],
    };
    let boxes = annotation
        .objects(side)
        .boxes()
        .map(|record| {
            let mut seen = SeenBox::from_record(record, None);
            // From the tracked cloth: undisturbed where its path never goes through the box's
            // place. Masks show no such path, but a box's own masks show it standing still
            // (`motion`). (Marking the boxes the cloth's mask lies on after the handle lets go
            // as immovable scored P-Opt. 54.6 / P-Ques. 31.2 on the 16 tuning videos of seed
            // 3410, against 75.3 / 62.5 with every box movable.)
            seen.undisturbed = reading.track.as_ref().map_or_else(
                || observed.still.contains(&seen.name),
                |track| !goes_through(track, seen.position, seen.orientation, seen.size),
            );
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

#[cfg(test)]
mod tests {
    use super::*;

    /// Read from pixels (no tracked path), the boxes the masks show standing still are the
    /// undisturbed ones (their pool's immovable mass), and only those.
    #[test]
    fn from_pixels_the_boxes_seen_still_are_undisturbed() {
        let path = Path::new(env!("CARGO_MANIFEST_DIR")).join("tests/data/cloth_collision/0");
        let annotation = ClothAnnotation::load(&path.join("outputs.json")).unwrap();
        let cloth = ObservedCloth {
            spawn: pixels::spawn_grid(Side::Left, 2.55),
            pull_distance: pixels::MEAN_PULL,
            track: None,
        };
        let observed = Observed {
            cloths: [cloth.clone(), cloth],
            verdict: ClothVerdict {
                stretches: None,
                bends: None,
                friction: None,
                friction_guess: None,
            },
            still: vec!["Gray Pillar".to_string()],
        };
        let half = seen_half(&annotation, Side::Left, &observed);
        let undisturbed: Vec<(&str, bool)> = half
            .boxes
            .iter()
            .map(|seen| (seen.name.as_str(), seen.undisturbed))
            .collect();
        assert_eq!(
            undisturbed,
            [
                ("Green Plate", false),
                ("Gray Pillar", true),
                ("Blue Plate", false)
            ]
        );
    }
}

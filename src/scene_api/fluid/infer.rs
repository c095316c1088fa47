//! Fluid properties inferred from what a video shows, for `--dynamics simulate`: which fluid is
//! denser than which (from how fluids layer in the containers), whether each fluid is sticky
//! (from how fast it flows along the sticks), and a density per fluid for a simulator (a total
//! order consistent with the inferred one, mapped onto the release's density pool).
//!
//! Inputs: the scene as perception sees it ([`PerceivedFluidScene`]: tank sticks, containers,
//! fluid names and emitter positions, built from the layout without its densities or
//! viscosities) and the tracked particles of `outputs4D.json` ([`FourDData`]) over the video's
//! frames only (frames `0..250`, updates up to 500). Nothing that is an answer is read: no
//! `trackingData`, no counterfactual run, no density or viscosity of the layout.
//!
//! Outputs: [`FluidInference`], every verdict with its evidence (particle counts, heights,
//! speeds) so it can be explained, and "cannot decide" where the video does not show enough.
//! `bench inference` scores it against the annotations ([`inference_report`]).
//!
//! Why these signals. The truth relations come from fluids found together in a container at the
//! end of the run, and the solver lets the denser fluid sink through the lighter one, so fluids
//! sharing a container at the end of the video lie in layers, the denser below. Sticky fluids
//! (Obi viscosity 10) are damped towards rest near a collider, so they creep along a stick
//! while non-sticky ones (0.02) slide off at a few units a second.

mod bench;
pub(crate) mod masks;
#[cfg(test)]
mod tests;

pub(crate) use bench::{InferenceScore, inference_report};

use indexmap::IndexMap;
use serde::Serialize;

use crate::dataset::FourDData;
use crate::dataset::fluid::outcome::{DensityOrder, DensityOrdering, Rect};
use crate::dataset::fluid::world::{
    CAPTURE_UPDATES, DENSITIES_3_FLUIDS, DENSITIES_4_FLUIDS, UPDATE_SECONDS, UPDATES_PER_FRAME,
};
use crate::dataset::fluid::{FluidLayout, Viscosity, base_fluid_name};
use crate::scene_api::ApiError;
use crate::scene_api::fluid::seen::SeenFlow;

/// Frames of the video (updates 2 to 500, every second one): the 4-D data's frames past these,
/// if any, are not read.
const VIDEO_FRAMES: usize = (CAPTURE_UPDATES / UPDATES_PER_FRAME) as usize;
/// Seconds between two frames.
const FRAME_SECONDS: f64 = UPDATES_PER_FRAME as f64 * UPDATE_SECONDS;

/// A fluid takes part in a piece of layering evidence with more than this many tracked
/// particles in the region at the last frame.
const LAYER_MIN_PARTICLES: usize = 2;
/// A piece of layering evidence decides a pair when it exceeds this, units (a height gap, or a
/// sinking extrapolated to the truth's count); a particle spacing is 0.025.
const LAYER_MARGIN: f64 = 0.02;
/// A container's column reaches this far above its funnel's box, units: fluid resting on the
/// guided sticks' upper ends lies in layers too.
const COLUMN_TOP: f64 = 0.5;
/// Sinking is measured over the video's last this many frames.
const SINK_WINDOW: usize = 40;
/// A particle counts as settled in a region after more than this many frames inside it.
const SETTLED_FRAMES: usize = 10;
/// Frames from the video's end (update 500) to the truth's count (update 700): the sinking over
/// the window is extrapolated over them.
const TRUTH_HORIZON_FRAMES: f64 = 100.0;

/// A particle counts as on a stick within this distance of the stick's surface (units): resting
/// particles sit about half a spacing off it, flowing ones a few spacings.
const STICK_NEAR: f64 = 0.08;
/// A fluid whose particles move slower than this near the sticks (median, units/s) is sticky:
/// on the tuning videos sticky fluids had medians 0.10–0.47, non-sticky ones 0.89–3.2.
const STICKY_SPEED: f64 = 0.65;
/// The viscosity is decided from at least this many particle-frames on sticks.
const VISCOSITY_MIN_SAMPLES: usize = 20;
/// ... of at least this many distinct tracked particles.
const VISCOSITY_MIN_PARTICLES: usize = 3;

/// Why the inference cannot run on a video's data.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub(crate) enum InferError {
    /// A fluid of the scene has no tracked particles in the 4-D data.
    #[error("video `{video}`: fluid `{fluid}` has no tracked particles in outputs4D.json")]
    Untracked {
        /// The video.
        video: String,
        /// The fluid key.
        fluid: String,
    },
    /// The 4-D data tracks a fluid the scene does not have.
    #[error("video `{video}`: outputs4D.json tracks `{key}`, which is not a fluid of the scene")]
    UnknownFluid {
        /// The video.
        video: String,
        /// The soft-body key.
        key: String,
    },
    /// A tracked position is not a finite number.
    #[error("video `{video}`: fluid `{key}` particle {particle} at frame {frame} is not finite")]
    NotFinite {
        /// The video.
        video: String,
        /// The soft-body key.
        key: String,
        /// The frame.
        frame: usize,
        /// The particle's index in the frame.
        particle: usize,
    },
    /// The scene has no fluid to give a density.
    #[error("video `{video}`: no fluid was seen (the release has 3 or 4)")]
    NoFluids {
        /// The video.
        video: String,
    },
}

impl From<InferError> for ApiError {
    fn from(error: InferError) -> Self {
        ApiError::Data(error.to_string())
    }
}

/// A stick as a segment in world coordinates.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct StickSegment {
    /// `<C> Stick`.
    pub(crate) name: String,
    /// One end, world units.
    pub(crate) start: [f64; 2],
    /// The other end.
    pub(crate) end: [f64; 2],
    /// Half its thickness, units.
    pub(crate) half_thickness: f64,
}

impl StickSegment {
    /// The distance from `point` to the stick's surface (0 inside).
    fn distance(&self, point: [f64; 2]) -> f64 {
        let (dx, dy) = (self.end[0] - self.start[0], self.end[1] - self.start[1]);
        let length2 = dx * dx + dy * dy;
        let t = if length2 > 0.0 {
            (((point[0] - self.start[0]) * dx + (point[1] - self.start[1]) * dy) / length2)
                .clamp(0.0, 1.0)
        } else {
            0.0
        };
        let gap = (point[0] - self.start[0] - t * dx).hypot(point[1] - self.start[1] - t * dy);
        (gap - self.half_thickness).max(0.0)
    }
}

/// A container as the layering sees it: its cup and its funnel (the guided sticks' box).
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct ContainerRegion {
    /// `<C> Container`.
    pub(crate) name: String,
    /// The cup, world units.
    #[serde(skip)]
    pub(crate) cup: Rect,
    /// The bounding box of the funnel's guided sticks, world units.
    #[serde(skip)]
    pub(crate) funnel: Rect,
}

impl ContainerRegion {
    /// The container's column: the funnel's x-range, from the cup's floor to [`COLUMN_TOP`]
    /// above the funnel's box.
    fn column(&self) -> Rect {
        Rect {
            min: [self.funnel.min[0], self.cup.min[1]],
            max: [self.funnel.max[0], self.funnel.max[1] + COLUMN_TOP],
        }
    }
}

/// What perception sees of a fluid scene: geometry and fluid names, no properties.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct PerceivedFluidScene {
    /// The regular sticks.
    pub(crate) sticks: Vec<StickSegment>,
    /// The containers, left to right.
    pub(crate) containers: Vec<ContainerRegion>,
    /// The base fluids (`Blue Fluid`), in layout order, with their emitter's world position.
    pub(crate) fluids: Vec<(String, [f64; 2])>,
}

impl PerceivedFluidScene {
    /// The scene of `layout`: only its geometry and names (never `density` or `viscosity`).
    pub(crate) fn from_layout(layout: &FluidLayout) -> PerceivedFluidScene {
        let origin = layout.tank.origin;
        let world = |point: [f64; 2]| [point[0] + origin[0], point[1] + origin[1]];
        PerceivedFluidScene {
            sticks: layout
                .sticks
                .iter()
                .map(|stick| StickSegment {
                    name: stick.name.clone(),
                    start: world(stick.start),
                    end: world(stick.end),
                    half_thickness: stick.scale[1] / 2.0,
                })
                .collect(),
            containers: layout
                .reservoirs
                .iter()
                .map(|reservoir| ContainerRegion {
                    name: reservoir.name.clone(),
                    cup: reservoir.cup_box(origin),
                    funnel: reservoir.funnel_box(origin),
                })
                .collect(),
            fluids: layout
                .fluids
                .iter()
                .map(|fluid| {
                    let [x, y, _] = fluid.emitter_position;
                    (fluid.name.clone(), world([x, y]))
                })
                .collect(),
        }
    }
}

/// One tracked particle: its emitter key and its position in each video frame (`None` before it
/// is emitted).
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ParticleTrack {
    /// The emitter key (`Blue Fluid`, `Later Emitted Blue Fluid`).
    pub(crate) key: String,
    /// World `[x, y]` per frame.
    pub(crate) positions: Vec<Option<[f64; 2]>>,
}

/// Every tracked particle of each base fluid, in the scene's fluid order.
pub(crate) type FluidTracks = IndexMap<String, Vec<ParticleTrack>>;

/// The tracks of `four_d` by base fluid of `scene`, frames `0..250` only. A later emitter's
/// particles join its base fluid's.
pub(crate) fn fluid_tracks(
    video: &str,
    scene: &PerceivedFluidScene,
    four_d: &FourDData,
) -> Result<FluidTracks, InferError> {
    let mut tracks: FluidTracks = scene
        .fluids
        .iter()
        .map(|(name, _)| (name.clone(), Vec::new()))
        .collect();
    for (key, body) in &four_d.soft_bodies {
        let Some(fluid) = tracks.get_mut(base_fluid_name(key)) else {
            return Err(InferError::UnknownFluid {
                video: video.to_string(),
                key: key.clone(),
            });
        };
        let frames = &body.particles[..body.particles.len().min(VIDEO_FRAMES)];
        let count = frames.iter().map(Vec::len).max().unwrap_or(0);
        let first = fluid.len();
        fluid.extend((0..count).map(|_| ParticleTrack {
            key: key.clone(),
            positions: vec![None; frames.len()],
        }));
        for (frame, particles) in frames.iter().enumerate() {
            for (particle, point) in particles.iter().enumerate() {
                if !(point[0].is_finite() && point[1].is_finite()) {
                    return Err(InferError::NotFinite {
                        video: video.to_string(),
                        key: key.clone(),
                        frame,
                        particle,
                    });
                }
                if let Some(slot) = fluid
                    .get_mut(first + particle)
                    .and_then(|track| track.positions.get_mut(frame))
                {
                    *slot = Some([point[0], point[1]]);
                }
            }
        }
    }
    if let Some((fluid, _)) = tracks.iter().find(|(_, particles)| particles.is_empty()) {
        return Err(InferError::Untracked {
            video: video.to_string(),
            fluid: fluid.clone(),
        });
    }
    Ok(tracks)
}

/// One fluid's particles in one region of a container at the last frame.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct Layer {
    /// The base fluid.
    pub(crate) fluid: String,
    /// Its tracked particles (or pixels) inside the region.
    pub(crate) particles: usize,
    /// Their median height, units.
    pub(crate) median_y: f64,
}

/// What a layering comparison measures.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub(crate) enum LayerEvidence {
    /// Median heights in the container's column at the last frame (tracked particles).
    ColumnHeights,
    /// How fast each fluid's settled particles sink in the cup over the last frames.
    CupSinking,
    /// The same in the funnel.
    FunnelSinking,
    /// Mean heights over the columns of a cup or the pool both fluids fill (masks).
    MaskHeights,
}

/// How two fluids lie in one container, and what that says.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct LayerComparison {
    /// The container.
    pub(crate) container: String,
    /// What was measured.
    pub(crate) evidence: LayerEvidence,
    /// The first fluid's layer.
    pub(crate) first: Layer,
    /// The second fluid's layer.
    pub(crate) second: Layer,
    /// Heights: the first's median height minus the second's. Sinking: how much further the
    /// first's settled particles moved up than the second's over the window, extrapolated to
    /// the truth's count. Units; negative: the first lies lower, or sinks through the second.
    pub(crate) gap: f64,
    /// The denser fluid by this container, when both layers have enough particles and their
    /// heights differ by more than the margin.
    pub(crate) heavier: Option<String>,
}

/// The inferred density order and its evidence.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct DensityInference {
    /// Every pair of fluids found together (at least one particle each) in a container's cup at
    /// the last frame, per container.
    pub(crate) comparisons: Vec<LayerComparison>,
    /// `(heavier, lighter)` pairs decided by the containers, before closure. Each deciding
    /// container votes for its lower fluid with the smaller of the two particle counts; the
    /// pair goes the way of the total, and is left out on a tie.
    pub(crate) relations: Vec<(String, String)>,
    /// Pairs (scene order) whose deciding containers disagree: a dense fluid that arrives late
    /// and sticky may not have sunk by the end of the video.
    pub(crate) conflicts: Vec<(String, String)>,
    /// The relations closed transitively.
    #[serde(skip)]
    pub(crate) ordering: DensityOrdering,
}

impl DensityInference {
    /// How `first`'s density compares with `second`'s: `Unknown` when the video does not order
    /// them ("can not answer"), `Contradictory` when its layering orders them both ways.
    pub(crate) fn order(&self, first: &str, second: &str) -> DensityOrder {
        self.ordering
            .order(base_fluid_name(first), base_fluid_name(second))
    }
}

/// The median of `values` (`NaN`-free), `None` when empty.
fn median(values: &mut [f64]) -> Option<f64> {
    values.sort_by(f64::total_cmp);
    let middle = values.len() / 2;
    match values.len() {
        0 => None,
        n if n % 2 == 1 => values.get(middle).copied(),
        _ => Some(f64::midpoint(
            *values.get(middle - 1)?,
            *values.get(middle)?,
        )),
    }
}

/// One fluid's tracked particles in one region: its layer there at the last frame, and per
/// frame of the sinking window the sum of the settled particles' height changes and their
/// count.
struct RegionTrace {
    layer: Layer,
    /// `(sum of Δy, settled particles)` per window frame.
    settling: Vec<(f64, usize)>,
}

/// Where `fluid`'s `particles` are in `region` (see [`RegionTrace`]); `None` when none is there
/// at `last`, the video's last frame.
fn region_trace(
    fluid: &str,
    particles: &[ParticleTrack],
    region: &Rect,
    last: usize,
) -> Option<RegionTrace> {
    let window_start = (last + 1).saturating_sub(SINK_WINDOW).max(1);
    let mut settling = vec![(0.0, 0); last + 1 - window_start.min(last + 1)];
    let mut last_heights = Vec::new();
    for particle in particles {
        // Frames inside the region in a row, up to the previous frame.
        let mut inside_for = 0usize;
        let mut previous: Option<[f64; 2]> = None;
        for frame in 0..=last {
            let point = particle.positions.get(frame).copied().flatten();
            let inside = point.filter(|p| region.contains(*p));
            if frame >= window_start
                && let (Some(now), Some(before)) = (inside, previous)
                && inside_for > SETTLED_FRAMES
                && let Some(slot) = settling.get_mut(frame - window_start)
            {
                slot.0 += now[1] - before[1];
                slot.1 += 1;
            }
            inside_for = if inside.is_some() { inside_for + 1 } else { 0 };
            previous = inside;
            if frame == last
                && let Some(now) = inside
            {
                last_heights.push(now[1]);
            }
        }
    }
    let particles = last_heights.len();
    Some(RegionTrace {
        layer: Layer {
            fluid: fluid.to_string(),
            particles,
            median_y: median(&mut last_heights)?,
        },
        settling,
    })
}

/// The denser of two fluids by a layering `gap` (negative: `first` lies lower or sinks), when
/// both take part (`enough`) and it exceeds [`LAYER_MARGIN`].
fn heavier_by_gap(first: &str, second: &str, gap: f64, enough: bool) -> Option<String> {
    if !enough || gap.abs() <= LAYER_MARGIN {
        None
    } else if gap < 0.0 {
        Some(first.to_string())
    } else {
        Some(second.to_string())
    }
}

/// How much further `first`'s settled particles rose than `second`'s, summed over the window
/// frames where both have some (mean height change each); `None` when there is no such frame.
fn relative_rise(first: &RegionTrace, second: &RegionTrace) -> Option<f64> {
    let mut total = None;
    for (&(sum_a, count_a), &(sum_b, count_b)) in first.settling.iter().zip(&second.settling) {
        if count_a > 0 && count_b > 0 {
            #[expect(clippy::cast_precision_loss, reason = "particle counts up to 3,000")]
            let step = sum_a / count_a as f64 - sum_b / count_b as f64;
            *total.get_or_insert(0.0) += step;
        }
    }
    total
}

/// The density order the tracked particles show. Per container, three pieces of evidence
/// compare each two fluids both present there at the last frame: their median heights in the
/// container's column (lower is denser), and how fast their settled particles sink in the cup
/// and in the funnel over the last [`SINK_WINDOW`] frames, extrapolated over the
/// [`TRUTH_HORIZON_FRAMES`] to the truth's count (a denser fluid lying on top sinks through the
/// lighter one). Each decides when both fluids have more than [`LAYER_MIN_PARTICLES`] there
/// and it exceeds [`LAYER_MARGIN`], and votes ([`density_from_comparisons`]).
pub(crate) fn infer_density(scene: &PerceivedFluidScene, tracks: &FluidTracks) -> DensityInference {
    let frames = tracks
        .values()
        .flatten()
        .map(|track| track.positions.len())
        .max()
        .unwrap_or(0);
    let Some(last) = frames.checked_sub(1) else {
        return density_from_comparisons(Vec::new());
    };
    let mut comparisons = Vec::new();
    for container in &scene.containers {
        for (evidence, region) in [
            (LayerEvidence::ColumnHeights, container.column()),
            (LayerEvidence::CupSinking, container.cup),
            (LayerEvidence::FunnelSinking, container.funnel),
        ] {
            let traces: Vec<RegionTrace> = tracks
                .iter()
                .filter_map(|(fluid, particles)| region_trace(fluid, particles, &region, last))
                .collect();
            for (index, a) in traces.iter().enumerate() {
                for b in traces.iter().skip(index + 1) {
                    let gap = match evidence {
                        LayerEvidence::ColumnHeights => a.layer.median_y - b.layer.median_y,
                        _ => match relative_rise(a, b) {
                            #[expect(clippy::cast_precision_loss, reason = "40 frames")]
                            Some(rise) => rise * TRUTH_HORIZON_FRAMES / SINK_WINDOW as f64,
                            None => continue,
                        },
                    };
                    let (first, second) = (a.layer.clone(), b.layer.clone());
                    let enough = first.particles > LAYER_MIN_PARTICLES
                        && second.particles > LAYER_MIN_PARTICLES;
                    let heavier = heavier_by_gap(&first.fluid, &second.fluid, gap, enough);
                    comparisons.push(LayerComparison {
                        container: container.name.clone(),
                        evidence,
                        first,
                        second,
                        gap,
                        heavier,
                    });
                }
            }
        }
    }
    density_from_comparisons(comparisons)
}

/// The density order the regions' decided comparisons vote for: each votes for its lower
/// fluid with the smaller of the two layers' sizes; a pair goes the way of the total, and is
/// left out on a tie.
pub(crate) fn density_from_comparisons(comparisons: Vec<LayerComparison>) -> DensityInference {
    // Votes per pair, keyed (first, second) in comparison order: positive for the first
    // lying lower.
    let mut votes: IndexMap<(String, String), (i64, bool, bool)> = IndexMap::new();
    for comparison in &comparisons {
        let Some(heavier) = &comparison.heavier else {
            continue;
        };
        let weight = i64::try_from(comparison.first.particles.min(comparison.second.particles))
            .unwrap_or(i64::MAX);
        let first_lower = *heavier == comparison.first.fluid;
        let entry = votes
            .entry((
                comparison.first.fluid.clone(),
                comparison.second.fluid.clone(),
            ))
            .or_insert((0, false, false));
        if first_lower {
            entry.0 = entry.0.saturating_add(weight);
            entry.1 = true;
        } else {
            entry.0 = entry.0.saturating_sub(weight);
            entry.2 = true;
        }
    }
    let mut relations = Vec::new();
    let mut conflicts = Vec::new();
    for ((first, second), (total, first_below, second_below)) in votes {
        if first_below && second_below {
            conflicts.push((first.clone(), second.clone()));
        }
        match total.cmp(&0) {
            std::cmp::Ordering::Greater => relations.push((first, second)),
            std::cmp::Ordering::Less => relations.push((second, first)),
            std::cmp::Ordering::Equal => {}
        }
    }
    DensityInference {
        ordering: DensityOrdering::new(&relations),
        comparisons,
        relations,
        conflicts,
    }
}

/// One fluid's flow on the sticks and the class it gives.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct ViscosityEvidence {
    /// The base fluid.
    pub(crate) fluid: String,
    /// Particle-frames within [`STICK_NEAR`] of a regular stick (speeds measured).
    pub(crate) samples: usize,
    /// Distinct tracked particles among them.
    pub(crate) particles: usize,
    /// Their median speed, units/s (the score: sticky below [`STICKY_SPEED`]).
    pub(crate) median_speed: Option<f64>,
    /// The class, `None` when the fluid was seen too little on sticks.
    pub(crate) class: Option<Viscosity>,
}

/// Each fluid's viscosity class from its speed along the sticks.
pub(crate) fn infer_viscosity(
    scene: &PerceivedFluidScene,
    tracks: &FluidTracks,
) -> Vec<ViscosityEvidence> {
    tracks
        .iter()
        .map(|(fluid, particles)| {
            let mut speeds = Vec::new();
            let mut seen = 0;
            for track in particles {
                let before = speeds.len();
                for pair in track.positions.windows(2) {
                    let [Some(from), Some(to)] = pair else {
                        continue;
                    };
                    if scene.sticks.iter().any(|s| s.distance(*to) < STICK_NEAR) {
                        speeds.push((to[0] - from[0]).hypot(to[1] - from[1]) / FRAME_SECONDS);
                    }
                }
                if speeds.len() > before {
                    seen += 1;
                }
            }
            let samples = speeds.len();
            let median_speed = median(&mut speeds);
            let enough = samples >= VISCOSITY_MIN_SAMPLES && seen >= VISCOSITY_MIN_PARTICLES;
            let class = median_speed.filter(|_| enough).map(|speed| {
                if speed < STICKY_SPEED {
                    Viscosity::Sticky
                } else {
                    Viscosity::NonSticky
                }
            });
            ViscosityEvidence {
                fluid: fluid.clone(),
                samples,
                particles: seen,
                median_speed,
                class,
            }
        })
        .collect()
}

/// A fluid's place in the total density order a simulator uses.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct DensityRank {
    /// The base fluid.
    pub(crate) fluid: String,
    /// 0 for the lightest.
    pub(crate) rank: usize,
    /// The release's pool value at that rank, kg/m³.
    pub(crate) density: f64,
    /// Whether its place among some neighbour was set by the tie-break rather than by the
    /// inferred order.
    pub(crate) tie_broken: bool,
}

/// How strongly the layering, thin or level layers included, puts `fluid` below `other`: over
/// every container comparison of the two, the other's median height minus its own, weighted by
/// the smaller particle count. Positive: `fluid` tends to lie below, so it is likely denser.
fn leaning_below(density: &DensityInference, fluid: &str, other: &str) -> f64 {
    density
        .comparisons
        .iter()
        .map(|comparison| {
            #[expect(clippy::cast_precision_loss, reason = "particle counts up to 200")]
            let weight = comparison.first.particles.min(comparison.second.particles) as f64;
            if comparison.first.fluid == fluid && comparison.second.fluid == other {
                -weight * comparison.gap
            } else if comparison.first.fluid == other && comparison.second.fluid == fluid {
                weight * comparison.gap
            } else {
                0.0
            }
        })
        .sum()
}

/// A total order of the fluids, lightest first, consistent with the inferred relations, each
/// mapped to the release's pool value at its rank.
///
/// Tie-break, deterministic: repeatedly take, among the remaining fluids that are not known to
/// be heavier than another remaining one (all remaining, should contradictory relations leave
/// none), the one the weak layering evidence puts least below the other candidates (the sum
/// of [`leaning_below`] over them), then the first in scene order.
pub(crate) fn density_ranks(
    video: &str,
    scene: &PerceivedFluidScene,
    density: &DensityInference,
) -> Result<Vec<DensityRank>, InferError> {
    // Fewer fluids than the release ever has (1 or 2) are fluids perception missed: the
    // 3-fluid pool's ends (or middle) keep the ones read apart, so the scene still runs and only
    // the questions about the missing fluid fail.
    // More than the release ever has are a fluid read twice or a spurious one: the 4-fluid
    // pool's range evenly spaced, so the scene still runs and only questions about the
    // misread fluids go wrong.
    let pool: Vec<f64> = match scene.fluids.len() {
        1 => vec![DENSITIES_3_FLUIDS[1]],
        2 => vec![DENSITIES_3_FLUIDS[0], DENSITIES_3_FLUIDS[2]],
        3 => DENSITIES_3_FLUIDS.to_vec(),
        4 => DENSITIES_4_FLUIDS.to_vec(),
        0 => {
            return Err(InferError::NoFluids {
                video: video.to_string(),
            });
        }
        count => {
            let (lightest, heaviest) = (DENSITIES_4_FLUIDS[0], DENSITIES_4_FLUIDS[3]);
            #[expect(clippy::cast_precision_loss, reason = "a handful of fluids")]
            let step = (heaviest - lightest) / (count - 1) as f64;
            #[expect(clippy::cast_precision_loss, reason = "a handful of fluids")]
            (0..count)
                .map(|rank| lightest + step * rank as f64)
                .collect()
        }
    };
    let mut remaining: Vec<String> = scene.fluids.iter().map(|(name, _)| name.clone()).collect();
    let mut ranks = Vec::new();
    while !remaining.is_empty() {
        let heavier_than_one = |fluid: &String| {
            remaining
                .iter()
                .any(|other| density.order(fluid, other) == DensityOrder::Heavier)
        };
        let mut candidates: Vec<usize> = (0..remaining.len())
            .filter(|&i| remaining.get(i).is_some_and(|f| !heavier_than_one(f)))
            .collect();
        if candidates.is_empty() {
            candidates = (0..remaining.len()).collect();
        }
        let below = |index: usize| -> f64 {
            let Some(fluid) = remaining.get(index) else {
                return 0.0;
            };
            candidates
                .iter()
                .filter_map(|&other| remaining.get(other))
                .filter(|other| *other != fluid)
                .map(|other| leaning_below(density, fluid, other))
                .sum()
        };
        let Some(&chosen) = candidates
            .iter()
            .min_by(|&&a, &&b| below(a).total_cmp(&below(b)).then(a.cmp(&b)))
        else {
            break;
        };
        let tie_broken = candidates.len() > 1;
        let fluid = remaining.remove(chosen);
        let rank = ranks.len();
        ranks.push(DensityRank {
            density: pool.get(rank).copied().unwrap_or(f64::NAN),
            fluid,
            rank,
            tie_broken,
        });
    }
    Ok(ranks)
}

/// Everything inferred of one video's fluids.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct FluidInference {
    /// The density order and its evidence.
    pub(crate) density: DensityInference,
    /// Each fluid's viscosity class and evidence, in scene order.
    pub(crate) viscosity: Vec<ViscosityEvidence>,
    /// What the masks said of each fluid's viscosity (inference from masks only).
    #[serde(skip_serializing_if = "Vec::is_empty")]
    pub(crate) mask_viscosity: Vec<masks::MaskViscosity>,
    /// The total order for a simulator, lightest first.
    pub(crate) ranks: Vec<DensityRank>,
}

/// Infers the fluid properties of `video` from its perceived scene and tracked particles.
pub(crate) fn infer_fluid_properties(
    video: &str,
    scene: &PerceivedFluidScene,
    four_d: &FourDData,
) -> Result<FluidInference, InferError> {
    let tracks = fluid_tracks(video, scene, four_d)?;
    let density = infer_density(scene, &tracks);
    let viscosity = infer_viscosity(scene, &tracks);
    let ranks = density_ranks(video, scene, &density)?;
    Ok(FluidInference {
        density,
        viscosity,
        mask_viscosity: Vec::new(),
        ranks,
    })
}

/// Infers the fluid properties of `video` from its perceived scene and what the detector saw
/// of its fluids (`--perception maskrcnn`, [`masks`]).
pub(crate) fn infer_from_masks(
    video: &str,
    scene: &PerceivedFluidScene,
    flow: &SeenFlow,
) -> Result<FluidInference, InferError> {
    let density = masks::infer_density_from_masks(scene, flow);
    let (viscosity, mask_viscosity) = masks::infer_viscosity_from_masks(scene, flow);
    let ranks = density_ranks(video, scene, &density)?;
    Ok(FluidInference {
        density,
        viscosity,
        mask_viscosity,
        ranks,
    })
}

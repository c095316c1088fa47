//! Fluid properties from what the detector sees (`--perception maskrcnn`): each fluid's pixels
//! per frame, lifted onto the scene's plane ([`SeenFlow`]), with no particle identities.
//!
//! * **Density order: layering by columns.** The regions where fluids come to rest are each
//!   container's cup and the pool (the tank's bottom outside the cups, below y = −2.3). Over
//!   the last 20 frames, each fluid's pixels are counted in 0.1-unit cells and their heights
//!   summed; in a region, per 0.1-wide column, a fluid's mean height. Two fluids compare over
//!   the columns both fill (each at least [`MIN_COLUMN_PIXELS`]): the mean of their height
//!   differences weighted by the smaller amount. A region decides a pair when both fluids
//!   have more than [`MIN_REGION_PIXELS`] there and the gap exceeds 0.02 units, and votes for its
//!   lower fluid with the smaller amount; a pair goes the way of the total
//!   ([`super::density_from_comparisons`], as for tracked particles). Columns compare fluids
//!   that lie over one another, where a median over a whole cup mixes a fluid lying beside
//!   another with one lying under it; the pool holds most of the fluid that missed the cups.
//! * **Viscosity: the stream's necking.** Each first emitter releases its fluid with some
//!   random sideways velocity; a sticky fluid (Obi viscosity 10) damps it and its stream
//!   narrows below the emitter, a non-sticky one (0.02) spreads. Per slice 0.05 deep below the
//!   emitter, over frames 25–77 (the steady stream), the median of the standard deviation of
//!   the stream's x; the necking rate is the slope, through the origin, of
//!   `1 − sd(depth) / sd(top 0.1)` against depth over the slices deeper than 0.15 and clear of
//!   the sticks by 0.2 units. Sticky above [`NECK_RATE`]. Where a stick is within 0.2 units
//!   under the emitter the stream cannot be seen to neck, and the fluid's residence on the
//!   sticks decides instead: its pixels on the sticks in frames 200–228, after the first
//!   emitters have drained, over their peak; sticky above [`RESIDENCE_STICKY`]. The release
//!   never gives every fluid one class, so when every decided fluid came out one class, the
//!   one whose necking was most towards the other class is flipped.
//!
//! Rules and thresholds were chosen on the exact segmentation of 24 generated videos
//! (`generate --scenario fluid --seed 3201 --appearance randomized`) perturbed as a detector
//! perturbs masks (`scripts/perception/README.md`, fluid section), never on the videos the
//! headline figures are measured on.

use indexmap::IndexMap;
use serde::Serialize;

use super::{
    ContainerRegion, DensityInference, LayerComparison, LayerEvidence, PerceivedFluidScene,
    StickSegment, ViscosityEvidence, density_from_comparisons, heavier_by_gap, median,
};
use crate::dataset::fluid::Viscosity;
use crate::dataset::fluid::outcome::Rect;
use crate::scene_api::fluid::seen::SeenFlow;

/// Frames whose fluid lies where it comes to rest: the last 20 of the video.
pub(crate) const DENSITY_FRAMES: std::ops::RangeInclusive<usize> = 230..=249;
/// Frames of the first emitters' steady streams (they pour through frame 81).
pub(crate) const NECK_FRAMES: std::ops::RangeInclusive<usize> = 25..=77;
/// Frames after the first emitters' fluid has drained, before the later ones open.
pub(crate) const RESIDENCE_FRAMES: std::ops::RangeInclusive<usize> = 200..=228;
/// Every how many frames the residence's peak is looked for.
pub(crate) const PEAK_FRAME_STEP: usize = 5;

/// Cell side of the layering grid, units.
const CELL: f64 = 0.1;
/// The pool: below this (world y), outside the cups.
const POOL_TOP: f64 = -2.3;
/// A fluid fills a column with at least this many pixels there (of a 480×270 frame, as every
/// pixel count here: [`SeenFlow::pixel_weight`]).
pub(crate) const MIN_COLUMN_PIXELS: f64 = 2.0;
/// A region decides a pair when both fluids have more than this many pixels in the columns
/// they share.
pub(crate) const MIN_REGION_PIXELS: f64 = 10.0;

/// The bottom of the emitters' boxes, world y (centres at 2.85, boxes 0.25 tall).
const EMITTER_BOTTOM: f64 = 2.725;
/// Depth slices of the stream, units below the emitter.
const SLICE: f64 = 0.05;
const SLICES: usize = 26;
/// The stream is looked for within this of its emitter's centre, units.
const STREAM_HALF_WIDTH: f64 = 0.6;
/// A slice's spread needs this many pixels of the stream in it in a frame.
const MIN_SLICE_PIXELS: f64 = 3.0;
/// A slice's median spread needs this many frames with enough stream.
const MIN_SLICE_FRAMES: usize = 10;
/// Slices used for the rate start this deep, units (the first two are the reference).
const NECK_MIN_DEPTH: f64 = 0.15;
/// The stream counts as clear of a stick this far from it, units.
const NECK_MARGIN: f64 = 0.2;
/// Sticky when the necking rate (per unit of depth) is above this.
pub(crate) const NECK_RATE: f64 = 0.33;
/// Points within this of a stick's centre line lie on it, units.
const STICK_BAND: f64 = 0.35;
/// The residence decides only when the fluid's peak on the sticks is at least this many
/// pixels.
const RESIDENCE_MIN_PEAK: f64 = 50.0;
/// Sticky when the late share on the sticks is above this.
pub(crate) const RESIDENCE_STICKY: f64 = 0.13;

/// The frames the inference reads, in order.
pub(crate) fn frames_needed(frame_count: usize) -> Vec<usize> {
    let mut frames: Vec<usize> = NECK_FRAMES
        .chain(RESIDENCE_FRAMES)
        .chain(DENSITY_FRAMES)
        .chain((0..frame_count).step_by(PEAK_FRAME_STEP))
        .filter(|f| *f < frame_count)
        .collect();
    frames.sort_unstable();
    frames.dedup();
    frames
}

/// The density order the layering of `flow`'s last frames shows.
pub(crate) fn infer_density_from_masks(
    scene: &PerceivedFluidScene,
    flow: &SeenFlow,
) -> DensityInference {
    let fluids: Vec<&str> = scene.fluids.iter().map(|(name, _)| name.as_str()).collect();
    let frames: Vec<usize> = flow
        .frames
        .iter()
        .enumerate()
        .filter(|(_, (frame, _))| DENSITY_FRAMES.contains(frame))
        .map(|(index, _)| index)
        .collect();
    let per_frame = 1.0 / frames.len().max(1) as f64;
    // Per region, per fluid, per column: (pixels, sum of pixels × height), averaged over
    // frames.
    let regions: Vec<(String, Region<'_>)> = scene
        .containers
        .iter()
        .map(|c| (c.name.clone(), Region::Cup(&c.cup)))
        .chain(std::iter::once((
            "pool".to_string(),
            Region::Pool(&scene.containers),
        )))
        .collect();
    let mut comparisons = Vec::new();
    for (name, region) in &regions {
        let mut columns: Vec<IndexMap<i64, (f64, f64)>> = vec![IndexMap::new(); fluids.len()];
        for &index in &frames {
            for (fluid, cells) in fluids.iter().zip(columns.iter_mut()) {
                for point in flow.at(index, fluid) {
                    if !region.holds(*point) {
                        continue;
                    }
                    #[expect(
                        clippy::cast_possible_truncation,
                        reason = "a column index within the tank"
                    )]
                    let column = (point[0] / CELL).floor() as i64;
                    let entry = cells.entry(column).or_insert((0.0, 0.0));
                    let area = flow.pixel_weight * per_frame;
                    entry.0 += area;
                    entry.1 += area * point[1];
                }
            }
        }
        for (i, first) in fluids.iter().enumerate() {
            for (j, second) in fluids.iter().enumerate().skip(i + 1) {
                if let Some(comparison) =
                    compare_columns(name, (first, &columns[i]), (second, &columns[j]))
                {
                    comparisons.push(comparison);
                }
            }
        }
    }
    density_from_comparisons(comparisons)
}

/// Where fluid comes to rest.
enum Region<'a> {
    /// A container's cup.
    Cup(&'a Rect),
    /// The tank's bottom outside the cups.
    Pool(&'a [ContainerRegion]),
}

impl Region<'_> {
    fn holds(&self, point: [f64; 2]) -> bool {
        match self {
            Region::Cup(cup) => cup.contains(point),
            Region::Pool(containers) => {
                point[1] < POOL_TOP && !containers.iter().any(|c| c.cup.contains(point))
            }
        }
    }
}

/// Two fluids' layering over the columns of a region both fill.
fn compare_columns(
    region: &str,
    (first, a): (&str, &IndexMap<i64, (f64, f64)>),
    (second, b): (&str, &IndexMap<i64, (f64, f64)>),
) -> Option<LayerComparison> {
    let (mut weight, mut weighted_gap, mut area_a, mut area_b) = (0.0, 0.0, 0.0, 0.0);
    let (mut height_a, mut height_b) = (0.0, 0.0);
    for (column, (area, height_sum)) in a {
        let Some((other_area, other_sum)) = b.get(column) else {
            continue;
        };
        if *area < MIN_COLUMN_PIXELS || *other_area < MIN_COLUMN_PIXELS {
            continue;
        }
        let (mean_a, mean_b) = (height_sum / area, other_sum / other_area);
        let w = area.min(*other_area);
        weight += w;
        weighted_gap += w * (mean_a - mean_b);
        area_a += area;
        area_b += other_area;
        height_a += w * mean_a;
        height_b += w * mean_b;
    }
    if weight <= 0.0 {
        return None;
    }
    let gap = weighted_gap / weight;
    let enough = area_a > MIN_REGION_PIXELS && area_b > MIN_REGION_PIXELS;
    let heavier = heavier_by_gap(first, second, gap, enough);
    Some(LayerComparison {
        container: region.to_string(),
        evidence: LayerEvidence::MaskHeights,
        first: super::Layer {
            fluid: first.to_string(),
            particles: whole_pixels(area_a),
            median_y: height_a / weight,
        },
        second: super::Layer {
            fluid: second.to_string(),
            particles: whole_pixels(area_b),
            median_y: height_b / weight,
        },
        gap,
        heavier,
    })
}

/// A pixel count rounded to a whole number (a layer's size in the report; the votes weigh the
/// smaller of two).
fn whole_pixels(pixels: f64) -> usize {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "a small non-negative count"
    )]
    let whole = pixels.round().max(0.0) as usize;
    whole
}

/// What the masks say of one fluid's viscosity.
#[derive(Debug, Clone, PartialEq, Serialize)]
pub(crate) struct MaskViscosity {
    /// The base fluid.
    pub(crate) fluid: String,
    /// The stream's necking rate, per unit of depth, when its stream was seen clear of the
    /// sticks.
    pub(crate) necking_rate: Option<f64>,
    /// The share of its peak on the sticks still there in frames 200–228.
    pub(crate) residence: Option<f64>,
    /// Which decided: `necking`, `residence`, `flipped` (the release never gives every fluid
    /// one class) or `none`.
    pub(crate) rule: &'static str,
}

/// Each fluid's viscosity class from its stream's necking (or its residence on the sticks).
pub(crate) fn infer_viscosity_from_masks(
    scene: &PerceivedFluidScene,
    flow: &SeenFlow,
) -> (Vec<ViscosityEvidence>, Vec<MaskViscosity>) {
    let mut seen: Vec<MaskViscosity> = scene
        .fluids
        .iter()
        .map(|(fluid, emitter)| MaskViscosity {
            fluid: fluid.clone(),
            necking_rate: necking_rate(scene, flow, fluid, *emitter),
            residence: residence(scene, flow, fluid),
            rule: "none",
        })
        .collect();
    let mut classes: Vec<Option<Viscosity>> = seen
        .iter_mut()
        .map(|fluid| {
            let sticky = match (fluid.necking_rate, fluid.residence) {
                (Some(rate), _) => {
                    fluid.rule = "necking";
                    rate > NECK_RATE
                }
                (None, Some(share)) => {
                    fluid.rule = "residence";
                    share > RESIDENCE_STICKY
                }
                (None, None) => return None,
            };
            Some(if sticky {
                Viscosity::Sticky
            } else {
                Viscosity::NonSticky
            })
        })
        .collect();
    let decided: Vec<Viscosity> = classes.iter().flatten().copied().collect();
    if let Some(&only) = decided.first()
        && decided.iter().all(|class| *class == only)
    {
        // Flip the fluid whose necking leans most towards the other class.
        let towards_other = |rate: f64| match only {
            Viscosity::Sticky => -rate,
            Viscosity::NonSticky => rate,
        };
        let pick = seen
            .iter()
            .enumerate()
            .filter_map(|(index, fluid)| Some((index, towards_other(fluid.necking_rate?))))
            .max_by(|a, b| a.1.total_cmp(&b.1).then(b.0.cmp(&a.0)));
        if let Some((index, _)) = pick {
            classes[index] = Some(match only {
                Viscosity::Sticky => Viscosity::NonSticky,
                Viscosity::NonSticky => Viscosity::Sticky,
            });
            seen[index].rule = "flipped";
        }
    }
    let evidence = seen
        .iter()
        .zip(&classes)
        .map(|(fluid, class)| ViscosityEvidence {
            fluid: fluid.fluid.clone(),
            samples: 0,
            particles: 0,
            median_speed: None,
            class: *class,
        })
        .collect();
    (evidence, seen)
}

/// How far below the emitter at x `centre` its stream is clear of every stick (by
/// [`NECK_MARGIN`]), units.
fn free_depth(sticks: &[StickSegment], centre: f64) -> f64 {
    let depths = (0..=130).map(|step| f64::from(step) * 0.01);
    for depth in depths {
        let clear = (0..15).all(|i| {
            let x = centre - 0.35 + 0.05 * f64::from(i);
            sticks
                .iter()
                .all(|s| s.distance([x, EMITTER_BOTTOM - depth]) >= NECK_MARGIN)
        });
        if !clear {
            return depth;
        }
    }
    1.31
}

/// The stream's necking rate below the emitter at `emitter` (world), when seen clear of the
/// sticks.
fn necking_rate(
    scene: &PerceivedFluidScene,
    flow: &SeenFlow,
    fluid: &str,
    emitter: [f64; 2],
) -> Option<f64> {
    let free = free_depth(&scene.sticks, emitter[0]);
    if free < 0.2 {
        return None;
    }
    // Per slice, the spread of each frame.
    let mut spreads: Vec<Vec<f64>> = vec![Vec::new(); SLICES];
    for (index, (frame, _)) in flow.frames.iter().enumerate() {
        if !NECK_FRAMES.contains(frame) {
            continue;
        }
        let mut slices: Vec<Vec<f64>> = vec![Vec::new(); SLICES];
        for point in flow.at(index, fluid) {
            let depth = EMITTER_BOTTOM - point[1];
            if depth <= 0.0 || (point[0] - emitter[0]).abs() >= STREAM_HALF_WIDTH {
                continue;
            }
            #[expect(
                clippy::cast_possible_truncation,
                clippy::cast_sign_loss,
                reason = "a positive depth over a slice's"
            )]
            let slice = (depth / SLICE) as usize;
            if let Some(list) = slices.get_mut(slice) {
                list.push(point[0]);
            }
        }
        for (slice, xs) in slices.iter().enumerate() {
            if (xs.len() as f64) * flow.pixel_weight < MIN_SLICE_PIXELS {
                continue;
            }
            let n = xs.len() as f64;
            let mean = xs.iter().sum::<f64>() / n;
            let spread = (xs.iter().map(|x| (x - mean).powi(2)).sum::<f64>() / n).sqrt();
            spreads[slice].push(spread);
        }
    }
    let profile: Vec<Option<f64>> = spreads
        .iter_mut()
        .map(|values| {
            if values.len() >= MIN_SLICE_FRAMES {
                median(values)
            } else {
                None
            }
        })
        .collect();
    let (Some(Some(first)), Some(Some(second))) = (profile.first(), profile.get(1)) else {
        return None;
    };
    let reference = 0.5 * (first + second);
    if reference <= 0.0 {
        return None;
    }
    let (mut xy, mut xx) = (0.0, 0.0);
    for (slice, spread) in profile.iter().enumerate() {
        let Some(spread) = spread else { continue };
        let (top, bottom) = (slice as f64 * SLICE, (slice + 1) as f64 * SLICE);
        if top < NECK_MIN_DEPTH - 1e-9 || bottom > free + 1e-9 {
            continue;
        }
        let x = 0.5 * (top + bottom) - 0.05;
        xy += x * (1.0 - spread / reference);
        xx += x * x;
    }
    (xx > 0.0).then(|| xy / xx)
}

/// The share of the fluid's peak on the sticks (over the frames read) still on them after the
/// first emitters have drained; `None` when it was never much on them.
fn residence(scene: &PerceivedFluidScene, flow: &SeenFlow, fluid: &str) -> Option<f64> {
    let on_sticks = |index: usize| -> f64 {
        let count = flow
            .at(index, fluid)
            .iter()
            .filter(|p| scene.sticks.iter().any(|s| on_stick(s, **p)))
            .count();
        count as f64 * flow.pixel_weight
    };
    let (mut peak, mut late, mut late_frames) = (0.0_f64, 0.0, 0usize);
    for (index, (frame, _)) in flow.frames.iter().enumerate() {
        let area = on_sticks(index);
        peak = peak.max(area);
        if RESIDENCE_FRAMES.contains(frame) {
            late += area;
            late_frames += 1;
        }
    }
    (peak >= RESIDENCE_MIN_PEAK && late_frames > 0).then(|| late / late_frames as f64 / peak)
}

/// Whether `point` lies in the band round a stick's centre line (within [`STICK_BAND`] of it,
/// and along it to 0.1 past its ends).
fn on_stick(stick: &StickSegment, point: [f64; 2]) -> bool {
    let (dx, dy) = (stick.end[0] - stick.start[0], stick.end[1] - stick.start[1]);
    let length = dx.hypot(dy);
    if length <= 0.0 {
        return false;
    }
    let (ux, uy) = (dx / length, dy / length);
    let (rx, ry) = (point[0] - stick.start[0], point[1] - stick.start[1]);
    let along = rx * ux + ry * uy;
    let across = (rx * uy - ry * ux).abs();
    along > -0.1 && along < length + 0.1 && across < STICK_BAND
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A scene of three fluids with emitters at x = −1.5, 0 and 1.5, one cup `[-2, -1] ×
    /// [-4, -3.125]`, and one stick far below the emitters (from (−2, −1) to (2, −1.5)).
    fn scene() -> PerceivedFluidScene {
        PerceivedFluidScene {
            sticks: vec![StickSegment {
                name: "Red Stick".to_string(),
                start: [-2.0, -1.0],
                end: [2.0, -1.5],
                half_thickness: 0.075,
            }],
            containers: vec![ContainerRegion {
                name: "Red Container".to_string(),
                cup: Rect {
                    min: [-2.0, -4.0],
                    max: [-1.0, -3.125],
                },
                funnel: Rect {
                    min: [-2.2, -3.125],
                    max: [-0.8, -2.75],
                },
            }],
            fluids: vec![
                ("Blue Fluid".to_string(), [-1.5, 2.85]),
                ("Pink Fluid".to_string(), [0.0, 2.85]),
                ("Green Fluid".to_string(), [1.5, 2.85]),
            ],
        }
    }

    /// Frames `frames`, each with `points(frame, fluid index)` of the three fluids; pixels of a
    /// 480 × 270 frame.
    fn flow(
        frames: impl Iterator<Item = usize>,
        points: impl Fn(usize, usize) -> Vec<[f64; 2]>,
    ) -> SeenFlow {
        let names = ["Blue Fluid", "Pink Fluid", "Green Fluid"];
        SeenFlow {
            frames: frames
                .map(|frame| {
                    let fluids = names
                        .iter()
                        .enumerate()
                        .map(|(index, name)| ((*name).to_string(), points(frame, index)))
                        .collect();
                    (frame, fluids)
                })
                .collect(),
            unnamed_pixels: 0,
            pixel_weight: 1.0,
        }
    }

    /// A block of points `[x0, x1] × [y0, y1]` at 0.02-unit spacing.
    fn block(x0: f64, x1: f64, y0: f64, y1: f64) -> Vec<[f64; 2]> {
        let mut points = Vec::new();
        let (mut y, step) = (y0, 0.02);
        while y < y1 {
            let mut x = x0;
            while x < x1 {
                points.push([x, y]);
                x += step;
            }
            y += step;
        }
        points
    }

    #[test]
    fn the_fluid_under_another_in_the_same_columns_is_denser_and_side_by_side_decides_nothing() {
        // Pink lies under blue across the cup; green lies beside them in the pool.
        let layered = flow(DENSITY_FRAMES, |_, fluid| match fluid {
            0 => block(-1.9, -1.1, -3.8, -3.6),
            1 => block(-1.9, -1.1, -4.0, -3.8),
            _ => block(0.0, 0.5, -4.0, -3.8),
        });
        let density = infer_density_from_masks(&scene(), &layered);
        assert_eq!(
            density.relations,
            vec![("Pink Fluid".to_string(), "Blue Fluid".to_string())]
        );
        let cup = &density.comparisons[0];
        assert_eq!(cup.container, "Red Container");
        assert!(
            (cup.gap - 0.2).abs() < 0.02,
            "blue 0.2 above pink: {}",
            cup.gap
        );
        // Frames outside the last 20 are not read.
        let early = flow(0..10, |_, fluid| match fluid {
            0 => block(-1.9, -1.1, -3.8, -3.6),
            1 => block(-1.9, -1.1, -4.0, -3.8),
            _ => Vec::new(),
        });
        assert!(
            infer_density_from_masks(&scene(), &early)
                .relations
                .is_empty()
        );
        // A few pixels are not a layer.
        let thin = flow(DENSITY_FRAMES, |_, fluid| match fluid {
            0 => block(-1.9, -1.86, -3.8, -3.78),
            1 => block(-1.9, -1.1, -4.0, -3.8),
            _ => Vec::new(),
        });
        assert!(
            infer_density_from_masks(&scene(), &thin)
                .relations
                .is_empty()
        );
    }

    /// A stream below the emitter at `centre` whose spread is `spread(depth)`: in every frame,
    /// 30 points a slice spread evenly across ±√3 · spread (a standard deviation of `spread`).
    fn stream(centre: f64, spread: impl Fn(f64) -> f64) -> Vec<[f64; 2]> {
        let mut points = Vec::new();
        for slice in 0..SLICES {
            let depth = (slice as f64 + 0.5) * SLICE;
            let half = 3.0_f64.sqrt() * spread(depth);
            for k in 0..30 {
                let x = centre - half + 2.0 * half * f64::from(k) / 29.0;
                points.push([x, EMITTER_BOTTOM - depth]);
            }
        }
        points
    }

    #[test]
    fn a_stream_that_narrows_is_sticky_one_that_spreads_is_not() {
        // Blue narrows by half over a unit of depth, pink and green widen.
        let streams = flow(NECK_FRAMES, |_, fluid| match fluid {
            0 => stream(-1.5, |d| 0.1 * (1.0 - 0.5 * d)),
            1 => stream(0.0, |d| 0.1 * (1.0 + 0.3 * d)),
            _ => stream(1.5, |d| 0.1 * (1.0 + 0.1 * d)),
        });
        let (evidence, seen) = infer_viscosity_from_masks(&scene(), &streams);
        let classes: Vec<Option<Viscosity>> = evidence.iter().map(|e| e.class).collect();
        assert_eq!(
            classes,
            [
                Some(Viscosity::Sticky),
                Some(Viscosity::NonSticky),
                Some(Viscosity::NonSticky)
            ]
        );
        // The spread is √(mean square) of evenly spaced points, a little under the target;
        // the rate is the narrowing per unit of depth.
        let rate = seen[0].necking_rate.unwrap();
        assert!((rate - 0.5).abs() < 0.08, "{rate}");
        assert!(seen[1].necking_rate.unwrap() < 0.0);
        assert!(seen.iter().all(|fluid| fluid.rule == "necking"));
    }

    #[test]
    fn when_every_fluid_reads_one_class_the_least_sure_is_flipped() {
        // All three widen; green widens least, so it is the one taken for sticky.
        let streams = flow(NECK_FRAMES, |_, fluid| match fluid {
            0 => stream(-1.5, |d| 0.1 * (1.0 + 0.5 * d)),
            1 => stream(0.0, |d| 0.1 * (1.0 + 0.3 * d)),
            _ => stream(1.5, |d| 0.1 * (1.0 + 0.05 * d)),
        });
        let (evidence, seen) = infer_viscosity_from_masks(&scene(), &streams);
        assert_eq!(evidence[2].class, Some(Viscosity::Sticky));
        assert_eq!(seen[2].rule, "flipped");
        assert_eq!(evidence[0].class, Some(Viscosity::NonSticky));
    }

    #[test]
    fn a_stream_hidden_by_a_stick_falls_back_on_residence() {
        // A stick 0.1 under the blue emitter: no necking is read, and blue stays on the
        // stick after the others drained.
        let mut blocked = scene();
        blocked.sticks.push(StickSegment {
            name: "Gray Stick".to_string(),
            start: [-2.0, EMITTER_BOTTOM - 0.15],
            end: [-1.0, EMITTER_BOTTOM - 0.15],
            half_thickness: 0.075,
        });
        let frames = (0..250).step_by(PEAK_FRAME_STEP).chain(RESIDENCE_FRAMES);
        let on_stick = block(-1.9, -1.1, EMITTER_BOTTOM - 0.1, EMITTER_BOTTOM - 0.05);
        let late = flow(frames, |frame, fluid| match fluid {
            0 => on_stick.clone(),
            1 if frame < 100 => block(-1.9, -1.1, -1.3, -1.2),
            _ => Vec::new(),
        });
        let (evidence, seen) = infer_viscosity_from_masks(&blocked, &late);
        assert_eq!(seen[0].necking_rate, None);
        assert_eq!(seen[0].rule, "residence");
        assert!((seen[0].residence.unwrap() - 1.0).abs() < 1e-9);
        assert_eq!(evidence[0].class, Some(Viscosity::Sticky));
        assert_eq!(seen[1].residence, Some(0.0));
        assert_eq!(evidence[1].class, Some(Viscosity::NonSticky));
        assert_eq!(evidence[2].class, None, "never seen");
    }

    #[test]
    fn the_frames_read_cover_every_rule_once() {
        let frames = frames_needed(250);
        assert!(frames.windows(2).all(|pair| pair[0] < pair[1]));
        for frame in NECK_FRAMES.chain(RESIDENCE_FRAMES).chain(DENSITY_FRAMES) {
            assert!(frames.contains(&frame), "{frame}");
        }
        assert!(frames.contains(&0) && frames.contains(&195));
        // Every fifth frame shares 11 with the streams', 6 with the residence's and 4 with
        // the layering's.
        assert_eq!(frames.len(), 53 + 29 + 20 + 50 - 11 - 6 - 4);
        assert_eq!(frames_needed(40).last(), Some(&39));
    }
}

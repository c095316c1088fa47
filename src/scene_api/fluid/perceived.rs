//! A fluid scene read from pixels (`--perception maskrcnn`): the sticks, containers and emitters
//! the detector finds in the first two seconds, placed in the world through the camera
//! calibration, and written in the release's format so the simulate backend runs on it as on an
//! annotation.
//!
//! Input: the first pass of a [`Perceiver`] (tracks of the fluid classes over frames 0–60 with
//! their colours) and the video's camera record. Output: [`PerceivedFluid`], a release-format
//! [`FluidAnnotation`] (layout, `allObjectTransforms`, camera; no tracking data) and what the
//! video could not tell, object by object.
//!
//! How each object is placed (world units, on the scene's plane; the release lays out every
//! fluid scene on `z = 0`, its boxes 0.2 deep, so a box's visible front face is at `z = −0.1`):
//! * a **stick**: its earliest full-size mask's pixels (before fluid runs along it) that are unlike
//!   the wall, lifted onto the front face's plane, their principal axis the
//!   stick's, their extent along it its length; its thickness is the release's (0.15), which a
//!   4-pixel-wide mask cannot measure better;
//! * a **container**: its mask's lifted extent, fitted to the release's container layout (2–4
//!   evenly spaced slots across the tank, each a cup 0.6 of the slot wide and 0.875 tall on the
//!   floor under two funnel sticks from the slot's edges at the sticks' band): the slot nearest
//!   the seen centre, the slot count from the seen width;
//! * an **emitter**: its box's lifted centre across; its height and width are the release's
//!   (under the ceiling at y = 2.85, which hides the top of the box; 0.5 wide). A fluid's first
//!   emitter is the one of its colour with fluid of that colour falling below it during the
//!   pass (first emitters open with the video; later ones some 20 frames before its end).
//!
//! A fluid is the colour of a first emitter. An object whose colour is not read, or that
//! repeats a colour its class never repeats, is left out and said so.

use std::collections::BTreeMap;

use indexmap::IndexMap;

use crate::dataset::Camera;
use crate::dataset::fluid::world::{NORMAL_TEMPERATURE, PARTICLES_PER_EMITTER, TANK_SIZE};
use crate::dataset::fluid::{
    ContainerPart, FluidAnnotation, FluidLayout, FluidRecord, FluidTracking, ObjectTransform,
    ReservoirRecord, StickRecord, TankLayout, Viscosity, container_name, container_part_name,
    emitter_name, fluid_name, later_fluid_name, palette_name, stick_name,
};
use crate::perception::camera::{CameraModel, principal_segment};
use crate::perception::classes::ClassTable;
use crate::perception::color::{unlike_wall, wall_color};
use crate::perception::detection::{Detection, InstanceMask};
use crate::perception::frames::RgbFrame;
use crate::perception::tracking::Track;
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::Perceiver;

use super::stick_masks::{earliest_full_mask, largest_mask, second_color_frames, second_colors};

/// The plane of the boxes' visible front faces, world z.
const FRONT_FACE_Z: f64 = -0.1;
/// The plane the fluids flow in, world z.
pub(crate) const FLUID_PLANE_Z: f64 = 0.0;
/// The release's stick thickness and depth, units.
const STICK_SCALE: [f64; 2] = [0.15, 0.2];
/// The release's emitter width between its side walls, and its box height, units.
const EMITTER_WIDTH: f64 = 0.5;
const EMITTER_HEIGHT: f64 = 0.25;
/// Half the thickness of cup walls and floors and of emitter walls, units.
const THIN_HALF_THICKNESS: f64 = 0.025;
/// The tank origin `(O_x, O_y)` every layout position is relative to, units.
const ORIGIN: [f64; 2] = [-TANK_SIZE[0] / 2.0, -TANK_SIZE[1] / 2.0];
/// Containers share the tank's width plus its side clearances in equal slots, units.
const SLOTS_WIDTH: f64 = TANK_SIZE[0] + 2.0 * 0.2;
/// A slot's left edge is at this world x for slot 0.
const SLOTS_LEFT: f64 = ORIGIN[0] - 0.2;
/// The funnels' top (the sticks' band's bottom) and the floor's top, world y.
const FUNNEL_TOP_Y: f64 = ORIGIN[1] - 1.5;
const FLOOR_TOP_Y: f64 = -4.0;
/// A cup's width as a share of its slot, its height, and how far in from the cup's edge the
/// funnel sticks end, as a share of the cup's width (`receptor_w_relative`, …).
const CUP_WIDTH_SHARE: f64 = 0.6;
const CUP_HEIGHT: f64 = 0.875;
const FUNNEL_REACH_IN: f64 = 0.15;
/// Every emitter's centre height, world y: the release hangs them under the ceiling, whose
/// front hides the top of their boxes, so their pixels say less about it than the layout does.
const EMITTER_Y: f64 = 2.85;
/// Fluid of an emitter's colour within this many units of its centre line, below it, during the
/// first pass says the emitter is pouring.
const POUR_HALF_WIDTH: f64 = 0.4;

/// A fluid scene as the video shows it.
#[derive(Debug, Clone)]
pub(crate) struct PerceivedFluid {
    /// The perceived scene in the release's format (no tracking data).
    pub annotation: FluidAnnotation,
    /// Per first-pass track, the object it was read as (`None`: none).
    pub names: Vec<Option<String>>,
    /// What the video could not tell, one line per object.
    pub unknown: Vec<String>,
    /// Object name → its second-choice colour words, likeliest first (sticks only).
    pub other_colors: BTreeMap<String, Vec<String>>,
}

/// A track of a static class placed in the world.
#[derive(Debug, Clone)]
struct Placed {
    track: usize,
    color: u8,
    /// The lifted pixels of its placing mask (a stick: its earliest full mask; else its largest).
    points: Vec<[f64; 2]>,
}

pub(crate) use crate::scene_api::perceiver::camera_model;

/// The world points of a mask's pixel centres on the plane `z`.
pub(crate) fn lift_mask(model: &CameraModel, mask: &InstanceMask, z: f64) -> Vec<[f64; 2]> {
    mask.pixels()
        .filter_map(|(x, y)| model.lift_to_plane(f64::from(x) + 0.5, f64::from(y) + 0.5, z))
        .collect()
}

/// What the first pass saw: its tracks, its detections by frame and the model's classes.
#[derive(Clone, Copy)]
pub(crate) struct FirstPass<'a> {
    /// The tracks over frames 0–60.
    pub tracks: &'a [Track],
    /// Their detections, by frame.
    pub detections: &'a BTreeMap<usize, Vec<Detection>>,
    /// The model's classes.
    pub classes: &'a ClassTable,
    /// Frames whose pixels refine the masks by colour (none: masks as they are).
    pub frames: &'a BTreeMap<usize, RgbFrame>,
}

/// Reads the scene of the video `perceiver` opened, seen through `camera`.
pub(crate) fn perceive_scene(
    perceiver: &mut Perceiver,
    camera: &Camera,
) -> Result<PerceivedFluid, ApiError> {
    perceiver.first_pass()?;
    let (width, height, frame_count) = perceiver.frames();
    let model = camera_model(camera, (width, height));
    if perceiver.classes().is_none() {
        // No frame was read: an empty scene.
        return Ok(PerceivedFluid {
            annotation: annotation(Vec::new(), Vec::new(), &[], camera),
            names: vec![None; perceiver.first_tracks().len()],
            unknown: vec!["the video has no frames".to_string()],
            other_colors: BTreeMap::new(),
        });
    }
    // The frames of the sticks' placing masks, whose pixels are read by colour, and those of the
    // containers' masks their second-choice colours are read from.
    let color_frames = second_color_frames(perceiver);
    let frames: BTreeMap<usize, RgbFrame> = perceiver
        .read_frames(&color_frames)?
        .into_iter()
        .map(|frame| (frame.index, frame))
        .collect();
    let Some(classes) = perceiver.classes() else {
        return Err(ApiError::Unavailable(
            "the detector's classes are unknown".into(),
        ));
    };
    let pass = FirstPass {
        tracks: perceiver.first_tracks(),
        detections: perceiver.first_detections(),
        classes,
        frames: &frames,
    };
    let mut perceived = read_scene(pass, &model, camera);
    perceived.annotation.frame_count = frame_count;
    perceived.other_colors = second_colors(perceiver, &perceived.names, &frames)?;
    Ok(perceived)
}

/// The scene `pass` shows through `model` (the projection of `camera`).
pub(crate) fn read_scene(
    pass: FirstPass<'_>,
    model: &CameraModel,
    camera: &Camera,
) -> PerceivedFluid {
    let FirstPass {
        tracks,
        detections,
        classes,
        frames,
    } = pass;
    let mut names: Vec<Option<String>> = vec![None; tracks.len()];
    let mut unknown = Vec::new();
    let by_kind = |kind: &str| -> Vec<Placed> {
        tracks
            .iter()
            .enumerate()
            .filter(|(_, track)| classes.kind(track.class) == kind)
            .filter_map(|(index, track)| {
                let (frame, mask) = if kind == "stick" {
                    earliest_full_mask(track, detections)?
                } else {
                    largest_mask(track, detections)?
                };
                let points = match frames.get(&frame) {
                    Some(rgb) if kind == "stick" => {
                        let masks: Vec<&InstanceMask> = detections
                            .get(&frame)
                            .map(|found| found.iter().map(|d| &d.mask).collect())
                            .unwrap_or_default();
                        lift_object_pixels(model, mask, rgb, &masks)
                    }
                    _ => lift_mask(model, mask, FRONT_FACE_Z),
                };
                Some(Placed {
                    track: index,
                    color: track.color?,
                    points,
                })
            })
            .collect()
    };
    for track in tracks {
        let kind = classes.kind(track.class);
        if track.color.is_none() && kind != "fluid" {
            let at = track.observations.first().map_or([0.0; 2], |p| p.centroid);
            unknown.push(format!(
                "a {kind} at pixel ({:.0}, {:.0}) whose colour was not read",
                at[0], at[1]
            ));
        }
    }
    let sticks = place_sticks(by_kind("stick"), &mut names, &mut unknown);
    let containers = place_containers(by_kind("container"), &mut names, &mut unknown);
    let pours = pouring(detections, classes, model);
    let emitters = place_emitters(by_kind("emitter"), &pours, &mut names);
    PerceivedFluid {
        annotation: annotation(sticks, containers, &emitters, camera),
        names,
        unknown,
        other_colors: BTreeMap::new(),
    }
}

/// A mask pixel belongs to its object when its colour is at least this unlike the wall's
/// ([`unlike_wall`]; 0.02 is a 15% difference in one channel).
const OBJECT_UNLIKE_WALL: f64 = 0.02;

/// The lifted pixels of `mask` whose colour in `frame` is unlike the wall's (the wall read
/// round `masks`, the frame's detections): the detector's masks run some pixels past a stick's
/// ends onto the wall, which would lengthen it. A stick nearly the wall's colour (white, grey)
/// keeps its whole mask when fewer than half of its pixels pass.
fn lift_object_pixels(
    model: &CameraModel,
    mask: &InstanceMask,
    frame: &RgbFrame,
    masks: &[&InstanceMask],
) -> Vec<[f64; 2]> {
    let Some(wall) = wall_color(frame, masks) else {
        return lift_mask(model, mask, FRONT_FACE_Z);
    };
    let object: Vec<(u32, u32)> = mask
        .pixels()
        .filter(|(x, y)| unlike_wall(frame, *x, *y, wall).is_some_and(|u| u >= OBJECT_UNLIKE_WALL))
        .collect();
    if (object.len() as u64) * 2 < mask.area() {
        return lift_mask(model, mask, FRONT_FACE_Z);
    }
    object
        .into_iter()
        .filter_map(|(x, y)| {
            model.lift_to_plane(f64::from(x) + 0.5, f64::from(y) + 0.5, FRONT_FACE_Z)
        })
        .collect()
}

/// The colour name of a palette id (`Light Blue`).
fn color_name(color: u8) -> Option<&'static str> {
    palette_name(i64::from(color))
}

/// Keeps the first object of each colour, saying what it drops.
fn distinct_colors(placed: Vec<Placed>, kind: &str, unknown: &mut Vec<String>) -> Vec<Placed> {
    let mut kept: Vec<Placed> = Vec::new();
    for object in placed {
        if kept.iter().any(|other| other.color == object.color) {
            unknown.push(format!(
                "two {kind}s read as {}: the second is left out",
                color_name(object.color).unwrap_or("?").to_lowercase()
            ));
            continue;
        }
        kept.push(object);
    }
    kept
}

/// A stick: `(name, colour, start, end)` in world units.
type SeenStick = (String, u8, [f64; 2], [f64; 2]);

/// The sticks: each mask's principal axis and extent, bottom to top (the release's order).
fn place_sticks(
    placed: Vec<Placed>,
    names: &mut [Option<String>],
    unknown: &mut Vec<String>,
) -> Vec<SeenStick> {
    let mut sticks = Vec::new();
    for object in distinct_colors(placed, "stick", unknown) {
        let Some(color) = color_name(object.color) else {
            continue;
        };
        let Some((start, end)) = principal_segment(&object.points) else {
            unknown.push(format!(
                "the {} stick is too small to place",
                color.to_lowercase()
            ));
            continue;
        };
        let name = stick_name(color);
        if let Some(slot) = names.get_mut(object.track) {
            *slot = Some(name.clone());
        }
        sticks.push((name, object.color, start, end));
    }
    sticks.sort_by(|a, b| {
        let centre = |s: &SeenStick| s.2[1] + s.3[1];
        centre(a).total_cmp(&centre(b))
    });
    sticks
}

/// The least and greatest x of `points` (infinities, low above high, when there are none).
fn x_extent(points: &[[f64; 2]]) -> (f64, f64) {
    points
        .iter()
        .fold((f64::INFINITY, f64::NEG_INFINITY), |(low, high), p| {
            (low.min(p[0]), high.max(p[0]))
        })
}

/// A container: `(name, colour, slot, slot count)`.
type SeenContainer = (String, u8, usize, usize);

/// The containers, left to right: each fitted to the release's layout of 2–4 equal slots.
fn place_containers(
    placed: Vec<Placed>,
    names: &mut [Option<String>],
    unknown: &mut Vec<String>,
) -> Vec<SeenContainer> {
    let placed = distinct_colors(placed, "container", unknown);
    // The slot count: from the widths seen (a container spans its slot), else the count seen.
    let widths: Vec<f64> = placed
        .iter()
        .filter_map(|object| {
            let (low, high) = x_extent(&object.points);
            (high > low).then_some(high - low)
        })
        .collect();
    let count = if widths.is_empty() {
        placed.len()
    } else {
        let mean = widths.iter().sum::<f64>() / widths.len() as f64;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a positive ratio clamped to 2..4"
        )]
        let by_width = (SLOTS_WIDTH / mean).round().clamp(2.0, 4.0) as usize;
        by_width.max(placed.len().min(4))
    };
    let unit = SLOTS_WIDTH / count.max(1) as f64;
    let mut containers: Vec<SeenContainer> = Vec::new();
    for object in placed {
        let Some(color) = color_name(object.color) else {
            continue;
        };
        let n = object.points.len().max(1) as f64;
        let centre = object.points.iter().map(|p| p[0]).sum::<f64>() / n;
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "clamped to the slots"
        )]
        let slot = ((centre - SLOTS_LEFT) / unit - 0.5)
            .round()
            .clamp(0.0, (count - 1) as f64) as usize;
        if containers.iter().any(|c| c.2 == slot) {
            unknown.push(format!(
                "the {} container stands where another was seen: left out",
                color.to_lowercase()
            ));
            continue;
        }
        let name = container_name(color);
        if let Some(entry) = names.get_mut(object.track) {
            *entry = Some(name.clone());
        }
        containers.push((name, object.color, slot, count));
    }
    containers.sort_by_key(|c| c.2);
    containers
}

/// Per colour, the fluid pixels seen below each point of the first pass, lifted: `(colour,
/// points)` of every fluid detection (the pieces of the first two seconds).
fn pouring(
    detections: &BTreeMap<usize, Vec<Detection>>,
    classes: &ClassTable,
    model: &CameraModel,
) -> Vec<(u8, Vec<[f64; 2]>)> {
    detections
        .values()
        .flatten()
        .filter(|d| classes.kind(d.class) == "fluid")
        .filter_map(|d| Some((d.color?, lift_mask(model, &d.mask, FLUID_PLANE_Z))))
        .collect()
}

/// An emitter: `(fluid key, colour, centre, later)`.
type SeenEmitter = (String, u8, [f64; 2], bool);

/// The emitters: of each colour, the one with most fluid of its colour falling below it is
/// the fluid's first emitter and the next its later one (the release has at most two); first
/// emitters then later ones, each left to right.
fn place_emitters(
    placed: Vec<Placed>,
    pours: &[(u8, Vec<[f64; 2]>)],
    names: &mut [Option<String>],
) -> Vec<SeenEmitter> {
    // (track, colour, centre, fluid points below it)
    let mut seen: Vec<(usize, u8, [f64; 2], usize)> = placed
        .into_iter()
        .filter_map(|object| {
            // The middle of the box's extent across: its pixel mean leans to whichever end
            // shows more.
            let (low, high) = x_extent(&object.points);
            if high < low {
                return None;
            }
            let centre = [0.5 * (low + high), EMITTER_Y];
            let below = pours
                .iter()
                .filter(|(color, _)| *color == object.color)
                .flat_map(|(_, points)| points)
                .filter(|p| (p[0] - centre[0]).abs() < POUR_HALF_WIDTH && p[1] < centre[1])
                .count();
            Some((object.track, object.color, centre, below))
        })
        .collect();
    // Most poured first within a colour; ties by x.
    seen.sort_by(|a, b| {
        a.1.cmp(&b.1)
            .then(b.3.cmp(&a.3))
            .then(a.2[0].total_cmp(&b.2[0]))
    });
    let mut emitters: Vec<SeenEmitter> = Vec::new();
    for (track, color, centre, _) in seen {
        let Some(color_word) = color_name(color) else {
            continue;
        };
        let later = match emitters.iter().filter(|e| e.1 == color).count() {
            0 => false,
            1 => true,
            _ => continue,
        };
        let key = if later {
            later_fluid_name(color_word)
        } else {
            fluid_name(color_word)
        };
        if let Some(entry) = names.get_mut(track) {
            *entry = Some(emitter_name(&key));
        }
        emitters.push((key, color, centre, later));
    }
    emitters.sort_by(|a, b| a.3.cmp(&b.3).then(a.2[0].total_cmp(&b.2[0])));
    emitters
}

/// A world point relative to the tank origin.
fn local(point: [f64; 2]) -> [f64; 3] {
    [point[0] - ORIGIN[0], point[1] - ORIGIN[1], 0.0]
}

/// The release record of a stick from `start` to `end` (world).
fn stick_record(name: String, color: u8, start: [f64; 2], end: [f64; 2]) -> StickRecord {
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    let angle = dy.atan2(dx);
    let centre = [0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1])];
    let length = dx.hypot(dy);
    let start_local = local(start);
    let end_local = local(end);
    StickRecord {
        name,
        color,
        temperature: NORMAL_TEMPERATURE.to_string(),
        is_rotatable: false,
        position: local(centre),
        rotation_deg: [0.0, 0.0, angle.to_degrees()],
        scale: [length, STICK_SCALE[0], STICK_SCALE[1]],
        start: [start_local[0], start_local[1]],
        end: [end_local[0], end_local[1]],
        length,
        angle_rad: angle,
    }
}

/// The pose of a box of `thickness` along the segment `start`–`end` (world).
fn transform(start: [f64; 2], end: [f64; 2], thickness: f64) -> ObjectTransform {
    let (dx, dy) = (end[0] - start[0], end[1] - start[1]);
    ObjectTransform {
        position: [0.5 * (start[0] + end[0]), 0.5 * (start[1] + end[1]), 0.0],
        rotation_deg: [0.0, 0.0, dy.atan2(dx).to_degrees()],
        scale: [dx.hypot(dy), thickness, STICK_SCALE[1]],
    }
}

/// A collider part: its name, the ends of its centre line (world) and its thickness.
type PartSegment = (String, [f64; 2], [f64; 2], f64);

/// A fluid: its name, colour, first emitter's centre and later emitter's, if any.
type SeenFluid = (String, u8, [f64; 2], Option<[f64; 2]>);

/// The container in `slot` of `count`: its record and its parts' segments (funnel sticks,
/// floor, walls) with their thickness, world units.
fn container_parts(
    name: &str,
    color: u8,
    slot: usize,
    count: usize,
) -> (ReservoirRecord, Vec<PartSegment>) {
    let unit = SLOTS_WIDTH / count.max(1) as f64;
    let left_edge = SLOTS_LEFT + slot as f64 * unit;
    let cup_width = CUP_WIDTH_SHARE * unit;
    let cup_x = left_edge + unit / 2.0;
    let (cup_left, cup_right) = (cup_x - cup_width / 2.0, cup_x + cup_width / 2.0);
    let rim = FLOOR_TOP_Y + CUP_HEIGHT;
    // Each funnel stick runs from the slot's edge at the funnels' top towards the cup's rim and
    // ends above the cup, a share of its width in.
    let slope = (rim - FUNNEL_TOP_Y) / (cup_left - left_edge);
    let reach_left = cup_left + FUNNEL_REACH_IN * cup_width;
    let reach_y = FUNNEL_TOP_Y + slope * (reach_left - left_edge);
    let reach_right = cup_right - FUNNEL_REACH_IN * cup_width;
    let right_edge = left_edge + unit;
    let part = |p: ContainerPart| container_part_name(name, p);
    let left_stick = stick_record(
        part(ContainerPart::LeftGuidedStick),
        color,
        [left_edge, FUNNEL_TOP_Y],
        [reach_left, reach_y],
    );
    let right_stick = stick_record(
        part(ContainerPart::RightGuidedStick),
        color,
        [right_edge, FUNNEL_TOP_Y],
        [reach_right, reach_y],
    );
    let inset = THIN_HALF_THICKNESS;
    let thin = 2.0 * inset;
    let segments = vec![
        (
            left_stick.name.clone(),
            [left_edge, FUNNEL_TOP_Y],
            [reach_left, reach_y],
            STICK_SCALE[0],
        ),
        (
            right_stick.name.clone(),
            [right_edge, FUNNEL_TOP_Y],
            [reach_right, reach_y],
            STICK_SCALE[0],
        ),
        (
            part(ContainerPart::BottomFloor),
            [cup_left, FLOOR_TOP_Y + inset],
            [cup_right, FLOOR_TOP_Y + inset],
            thin,
        ),
        (
            part(ContainerPart::LeftVerticalWall),
            [cup_left + inset, FLOOR_TOP_Y],
            [cup_left + inset, rim],
            thin,
        ),
        (
            part(ContainerPart::RightVerticalWall),
            [cup_right - inset, FLOOR_TOP_Y],
            [cup_right - inset, rim],
            thin,
        ),
    ];
    let centre = local([cup_x, FLOOR_TOP_Y + CUP_HEIGHT / 2.0]);
    let record = ReservoirRecord {
        name: name.to_string(),
        color,
        cup_position: centre,
        cup_scale: [cup_width, CUP_HEIGHT, STICK_SCALE[1]],
        stick_left: left_stick,
        stick_right: right_stick,
    };
    (record, segments)
}

/// The release-format annotation of a perceived scene.
fn annotation(
    sticks: Vec<SeenStick>,
    containers: Vec<SeenContainer>,
    emitters: &[SeenEmitter],
    camera: &Camera,
) -> FluidAnnotation {
    // A fluid per first emitter, with the later emitter of its colour if one was seen.
    let fluids: Vec<SeenFluid> = emitters
        .iter()
        .filter(|e| !e.3)
        .map(|(key, color, centre, _)| {
            let later = emitters.iter().find(|e| e.3 && e.1 == *color).map(|e| e.2);
            (key.clone(), *color, *centre, later)
        })
        .collect();
    let mut transforms: IndexMap<String, ObjectTransform> = IndexMap::new();
    let mut stick_records = Vec::new();
    for (name, color, start, end) in sticks {
        transforms.insert(name.clone(), transform(start, end, STICK_SCALE[0]));
        stick_records.push(stick_record(name, color, start, end));
    }
    let mut reservoirs = Vec::new();
    for (name, color, slot, count) in containers {
        let (record, segments) = container_parts(&name, color, slot, count);
        for (part, start, end, thickness) in segments {
            transforms.insert(part, transform(start, end, thickness));
        }
        reservoirs.push(record);
    }
    for (key, _, centre, _) in emitters {
        let half = EMITTER_WIDTH / 2.0 + THIN_HALF_THICKNESS;
        for (side, sign) in [("Left", -1.0), ("Right", 1.0)] {
            let x = centre[0] + sign * half;
            transforms.insert(
                format!("{} {side} Wall", emitter_name(key)),
                transform(
                    [x, centre[1] - EMITTER_HEIGHT / 2.0],
                    [x, centre[1] + EMITTER_HEIGHT / 2.0],
                    2.0 * THIN_HALF_THICKNESS,
                ),
            );
        }
    }
    let fluid_records = fluids
        .into_iter()
        .map(|(name, color, centre, later)| FluidRecord {
            name,
            color,
            // Not read under `--dynamics simulate`: densities and viscosities are inferred.
            density: 0.0,
            viscosity: Viscosity::NonSticky,
            viscosity_value: 0.0,
            surface_tension: 0.0,
            amount: PARTICLES_PER_EMITTER,
            emitter_position: local(centre),
            has_predictive_emitter: later.is_some(),
            predictive_emitter_position: later.map_or([0.0; 3], local),
            predictive_emitter_color: later.map(|_| color),
        })
        .collect();
    FluidAnnotation {
        tracking: FluidTracking::default(),
        layout: FluidLayout {
            tank: TankLayout {
                size: TANK_SIZE,
                centre: [0.0; 3],
                origin: ORIGIN,
                numbers: IndexMap::new(),
            },
            sticks: stick_records,
            reservoirs,
            fluids: fluid_records,
        },
        object_transforms: transforms,
        camera: Some(camera.clone()),
        light_rotation_deg: IndexMap::new(),
        counterfactuals: Vec::new(),
        id_to_object_name: Vec::new(),
        frame_count: 0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::fluid::PERCEPTION;
    use crate::perception::tracking::{TrackerConfig, track};
    use crate::scene_api::perceiver::truth_detections;
    use std::path::Path;

    /// The first pass a perfect detector makes on a video: its segmentation truth on frames
    /// 0, 10, …, 60 as detections (containers whole, fluids in pieces), tracked.
    fn truth_pass(video: &Path) -> (Vec<Track>, BTreeMap<usize, Vec<Detection>>, ClassTable) {
        let wanted: Vec<usize> = (0..=60).step_by(10).collect();
        let (per_frame, classes) = truth_detections(video, PERCEPTION.classes, &wanted);
        let tracks = track(&per_frame, &TrackerConfig::default()).unwrap();
        (tracks, per_frame.into_iter().collect(), classes)
    }

    fn distance(a: [f64; 2], b: [f64; 2]) -> f64 {
        (a[0] - b[0]).hypot(a[1] - b[1])
    }

    /// Read from the segmentation truth of both demo videos (320 × 180 mp4s), the scene is the
    /// annotated one: every stick within 0.1 units at both ends, every container in its slot
    /// (cup and funnel as recorded, which rounds to 0.01),
    /// every emitter within 0.1 units and first or later as annotated, the same fluids.
    #[test]
    fn a_perfect_detector_reads_the_annotated_scene() {
        for id in ["0", "1"] {
            let video = Path::new(env!("CARGO_MANIFEST_DIR"))
                .join("eval/demo/fluid_slides")
                .join(id);
            let truth = FluidAnnotation::load(&video.join("outputs.json")).unwrap();
            let camera = truth.camera.clone().unwrap();
            let (tracks, detections, classes) = truth_pass(&video);
            let pass = FirstPass {
                tracks: &tracks,
                detections: &detections,
                classes: &classes,
                frames: &BTreeMap::new(),
            };
            let model = camera_model(&camera, (320, 180));
            let read = read_scene(pass, &model, &camera);
            assert!(read.unknown.is_empty(), "video {id}: {:?}", read.unknown);
            let seen = &read.annotation.layout;
            let check = super::super::reading_check::compare(&truth.layout, seen);
            assert!(check.entire(), "video {id}: {check:?}");
            let origin = truth.layout.tank.origin;
            let world = |p: [f64; 2]| [p[0] + origin[0], p[1] + origin[1]];
            let names = |sticks: &[StickRecord]| {
                let mut names: Vec<String> = sticks.iter().map(|s| s.name.clone()).collect();
                names.sort();
                names
            };
            assert_eq!(
                names(&seen.sticks),
                names(&truth.layout.sticks),
                "video {id}"
            );
            for stick in &truth.layout.sticks {
                let found = seen.sticks.iter().find(|s| s.name == stick.name).unwrap();
                let (a, b) = (world(stick.start), world(stick.end));
                let (c, d) = (world(found.start), world(found.end));
                let error =
                    (distance(a, c).max(distance(b, d))).min(distance(a, d).max(distance(b, c)));
                assert!(
                    error < 0.1,
                    "video {id} {}: ends {error} units off: {:?} {:?} vs {:?} {:?}",
                    stick.name,
                    stick.start,
                    stick.end,
                    found.start,
                    found.end
                );
            }
            assert_eq!(
                seen.reservoirs.len(),
                truth.layout.reservoirs.len(),
                "video {id}"
            );
            for (found, container) in seen.reservoirs.iter().zip(&truth.layout.reservoirs) {
                assert_eq!(found.name, container.name, "video {id}");
                let (a, b) = (found.cup_box(origin), container.cup_box(origin));
                for (x, y) in a.min.iter().chain(&a.max).zip(b.min.iter().chain(&b.max)) {
                    assert!(
                        (x - y).abs() < 0.011,
                        "video {id} {}: cup {a:?} vs {b:?}",
                        container.name
                    );
                }
                let (a, b) = (found.funnel_box(origin), container.funnel_box(origin));
                for (x, y) in a.min.iter().chain(&a.max).zip(b.min.iter().chain(&b.max)) {
                    assert!(
                        (x - y).abs() < 0.011,
                        "video {id} {}: funnel {a:?} vs {b:?}",
                        container.name
                    );
                }
            }
            let fluid_names = |layout: &FluidLayout| {
                let mut names: Vec<(String, bool)> = layout
                    .fluids
                    .iter()
                    .map(|f| (f.name.clone(), f.has_predictive_emitter))
                    .collect();
                names.sort();
                names
            };
            assert_eq!(fluid_names(seen), fluid_names(&truth.layout), "video {id}");
            for fluid in &truth.layout.fluids {
                let found = seen.fluids.iter().find(|f| f.name == fluid.name).unwrap();
                let (a, b) = (fluid.emitter_position, found.emitter_position);
                assert!(
                    distance([a[0], a[1]], [b[0], b[1]]) < 0.1,
                    "video {id} {}: {a:?} vs {b:?}",
                    fluid.name
                );
                if fluid.has_predictive_emitter {
                    let (a, b) = (
                        fluid.predictive_emitter_position,
                        found.predictive_emitter_position,
                    );
                    assert!(
                        distance([a[0], a[1]], [b[0], b[1]]) < 0.1,
                        "video {id} later {}: {a:?} vs {b:?}",
                        fluid.name
                    );
                }
            }
        }
    }
}

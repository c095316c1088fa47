//! The rope mechanism as perception reads it, written in the release's own format: a
//! [`RopeAnnotation`] (objects, rope paths and groups, layout positions, camera) and a
//! [`FourDData`] (first-frame poses of the moving bodies, each rope's shape as tracked
//! particles), so `--perception maskrcnn --dynamics simulate` runs the same scene code and
//! simulator as the oracle, on what the detector saw instead of what the generator recorded.
//!
//! Input: the first-pass tracks of the video (class, colour, detections with masks), its frames,
//! the frames' size and the camera calibration. Each non-rope track becomes a node at its mask
//! centroid lifted onto the scene plane `z = 0`; each rope's path is read from its pixels in every
//! first-pass frame and voted on (`evidence`, `topology`), and a rope end with no object under it
//! becomes a fixed point. Output: a [`PerceivedRope`]. Nothing recorded by the generator is read
//! except the camera calibration (position, angles, field of view), which is an input of
//! perception as it would be for a calibrated real rig; `mirrored` is derived from it (the
//! camera sits at `z < 0`).
//!
//! Objects get release-style names from what was seen (`Red Hollow Static Pulley (0 3)`); the
//! grid id is the track's index, since the layout grid cannot be seen. Loads start at the
//! counterfactual baseline mass (0.2 kg, ×1.975 under a movable pulley) in `outputMass`: only the
//! equal-mass counterfactual runs read it, and masses asked about are inferred from the motion.

use indexmap::IndexMap;

use super::evidence::{FrameReader, loose_ends};
use super::hanging::missed_connections;
use super::topology::{Node, NodeKind, RopePath, distance};
use crate::dataset::rope::{RopeAnnotation, world};
use crate::dataset::{Camera, FourDData, RigidBodyTrack, SoftBodyTrack};
use crate::perception::camera::CameraModel;
use crate::perception::classes::ClassTable;
use crate::perception::detection::Detection;
use crate::perception::frames::RgbFrame;
use crate::perception::palette::palette_color;
use crate::perception::rope::PERCEPTION;
use crate::perception::tracking::{Track, TrackPoint};
use crate::scene_api::ApiError;
use crate::scene_api::perceiver::Perceiver;

/// The release's tracked-particle spacing along a rope, units.
const PARTICLE_SPACING: f64 = 0.5;
/// How far from a sample point a rope's mask pixel may be and still cover it, units.
const COVER_RADIUS: f64 = 0.35;

/// Centres closer than this are one object seen twice, units (objects of the release are at
/// least a load's width apart).
pub(super) const SAME_OBJECT_DISTANCE: f64 = 0.9;

/// Share of a detection's mask that two or more surer objects of its kind must cover for it to
/// be those objects seen as one ([`spans_two`]).
const SPANNED_SHARE: f64 = 0.8;

/// The mechanism read from pixels.
#[derive(Debug, Clone)]
pub(crate) struct PerceivedRope {
    /// The release-format annotation of the perceived scene.
    pub annotation: RopeAnnotation,
    /// First-frame poses of loads and movable pulleys, and each rope's particles.
    pub four_d: FourDData,
    /// Per first-pass track, the name it was given (`None`: not an object of the scene).
    pub names: Vec<Option<String>>,
    /// Objects seen but on no rope that was read (findable, not simulated), by name.
    pub unattached: Vec<String>,
}

/// A world point on the `z = 0` plane seen at pixel `(x, y)`, if the viewing ray meets it in
/// front of the camera.
pub(crate) fn lift(model: &CameraModel, camera: &Camera, x: f64, y: f64) -> Option<[f64; 2]> {
    let direction = model.ray(x, y);
    if direction[2].abs() < 1e-9 {
        return None;
    }
    let distance = -camera.position[2] / direction[2];
    let world = [
        camera.position[0] + distance * direction[0],
        camera.position[1] + distance * direction[1],
    ];
    (distance > 0.0 && world.iter().all(|v| v.is_finite())).then_some(world)
}

/// What a track of a rope class is in the mechanism: a node of this kind, or (`None`) a rope.
fn node_kind(class_name: &str) -> Option<NodeKind> {
    match class_name {
        "cube" | "sphere" => Some(NodeKind::Load),
        "fixed point" => Some(NodeKind::Anchor),
        "solid static pulley" => Some(NodeKind::StaticPulley { solid: true }),
        "hollow static pulley" => Some(NodeKind::StaticPulley { solid: false }),
        "solid dynamic pulley" => Some(NodeKind::MovablePulley { solid: true }),
        "hollow dynamic pulley" => Some(NodeKind::MovablePulley { solid: false }),
        _ => None,
    }
}

/// The release-style name of a track: colour words, then the class's words.
fn base_name(track: &Track, classes: &ClassTable) -> String {
    let color = track
        .color
        .and_then(palette_color)
        .map_or("Unknown", |c| c.name);
    // The class's words (`hollow static pulley`), capitalised as the release writes them.
    let words: Vec<String> = classes
        .name(track.class)
        .split(' ')
        .map(|word| {
            let mut letters = word.chars();
            letters.next().map_or_else(String::new, |first| {
                first.to_uppercase().chain(letters).collect()
            })
        })
        .collect();
    format!("{color} {}", words.join(" "))
}

/// Unique, release-style names of the tracks (`Red Hollow Static Pulley (0 3)`): pulleys carry
/// their track index as a grid id, since the layout grid cannot be seen.
fn track_names(tracks: &[Track], classes: &ClassTable) -> Vec<Option<String>> {
    let mut names: Vec<Option<String>> = Vec::with_capacity(tracks.len());
    for (index, track) in tracks.iter().enumerate() {
        let base = base_name(track, classes);
        let pulley = classes.kind(track.class) == "pulley";
        let taken = |name: &str| names.iter().flatten().any(|n| n == name);
        let name = if pulley {
            format!("{base} (0 {index})")
        } else if taken(&base) {
            format!("{base} (1 {index})")
        } else {
            base
        };
        names.push(Some(name));
    }
    names
}

/// A track's first observation and its detection.
fn detection_of<'a>(
    track: &'a Track,
    detections: &'a std::collections::BTreeMap<usize, Vec<Detection>>,
) -> Option<(&'a TrackPoint, &'a Detection)> {
    let first = track.observations.first()?;
    let detection = detections.get(&first.frame)?.get(first.detection)?;
    Some((first, detection))
}

/// What the first pass over a video saw, as [`perceive_rope`] reads it.
#[derive(Debug, Clone, Copy)]
pub(crate) struct FirstPass<'a> {
    /// The model's classes.
    pub(crate) classes: &'a ClassTable,
    /// The first pass's tracks.
    pub(crate) tracks: &'a [Track],
    /// Its detections by frame (the tracks' observations index into them).
    pub(crate) detections: &'a std::collections::BTreeMap<usize, Vec<Detection>>,
    /// The frames' width and height.
    pub(crate) size: (u32, u32),
    /// The video's frame count.
    pub(crate) frame_count: usize,
}

/// The mechanism as seen (`--dynamics simulate`): objects named from their tracks, rope paths
/// read from the rope masks in every first-pass frame and voted on, positions lifted through the
/// camera. The first-pass tracks take the names of the objects they stand for.
pub(crate) fn perceive_mechanism(
    perceiver: &mut Perceiver,
    camera: &Camera,
) -> Result<PerceivedRope, ApiError> {
    // The ropes' pixels are read from the first pass's frames; they are decoded again only if
    // the pass ran earlier for another purpose (the scene keeps no frames).
    let mut frames = perceiver.first_pass()?;
    if frames.is_empty() {
        let wanted = perceiver.first_frames();
        frames = perceiver.read_frames(&wanted)?;
    }
    // A video without frames ran no detector: no classes were read, and there are no tracks.
    let classes = perceiver
        .classes()
        .cloned()
        .unwrap_or_else(|| ClassTable::of_scenario(PERCEPTION.classes));
    let (width, height, frame_count) = perceiver.frames();
    let perceived = perceive_rope(
        &FirstPass {
            classes: &classes,
            tracks: perceiver.first_tracks(),
            detections: perceiver.first_detections(),
            size: (width, height),
            frame_count,
        },
        &frames,
        camera,
    );
    perceiver.set_names(perceived.names.clone());
    Ok(perceived)
}

/// Per named object, its world position (units, on the `z = 0` plane) in each frame (`None`:
/// not seen in that frame).
pub(crate) type PerceivedPositions = Vec<(String, Vec<Option<[f64; 3]>>)>;

pub(crate) use crate::scene_api::perceiver::camera_model;

pub(crate) fn perceived_positions(
    perceiver: &mut Perceiver,
    camera: &Camera,
) -> Result<PerceivedPositions, ApiError> {
    let named = perceiver.full_pass()?;
    let (width, height, _) = perceiver.frames();
    let model = camera_model(camera, (width, height));
    let mut positions = Vec::new();
    for (name, track) in named {
        let last = track.last_frame().unwrap_or(0);
        let mut per_frame = vec![None; last + 1];
        for point in &track.observations {
            if let Some(world) = lift(&model, camera, point.centroid[0], point.centroid[1])
                && let Some(slot) = per_frame.get_mut(point.frame)
            {
                *slot = Some([world[0], world[1], 0.0]);
            }
        }
        positions.push((name, per_frame));
    }
    Ok(positions)
}

/// The tracks of a first pass placed in the scene: nodes at their lifted centroids (with the
/// track each stands for), and ropes with their detections.
struct Placed<'a> {
    nodes: Vec<Node>,
    node_track: Vec<usize>,
    ropes: Vec<(usize, &'a Detection)>,
}

/// Places every track: a node track at its first centroid lifted onto the scene plane, a rope
/// track as a rope. Most confident first, so that of two tracks on one object (the detector's
/// NMS is per class: one pulley can come out as a solid and as a hollow one) the surer one is
/// kept; the name of a track that stands for no object is cleared.
fn place_tracks<'a>(
    pass: &FirstPass<'a>,
    model: &CameraModel,
    camera: &Camera,
    names: &mut [Option<String>],
) -> Placed<'a> {
    let (tracks, detections, classes) = (pass.tracks, pass.detections, pass.classes);
    let mut placed = Placed {
        nodes: Vec::new(),
        node_track: Vec::new(),
        ropes: Vec::new(),
    };
    let mut order: Vec<usize> = (0..tracks.len()).collect();
    let confidence = |index: usize| {
        detection_of(&tracks[index], detections).map_or(0.0, |(_, detection)| detection.score)
    };
    order.sort_by(|&a, &b| confidence(b).total_cmp(&confidence(a)).then(a.cmp(&b)));
    for index in order {
        let track = &tracks[index];
        let Some((point, detection)) = detection_of(track, detections) else {
            continue;
        };
        match node_kind(classes.name(track.class)) {
            Some(kind) => {
                if let Some(centre) = lift(model, camera, point.centroid[0], point.centroid[1])
                    && !placed
                        .nodes
                        .iter()
                        .any(|node| distance(node.centre, centre) < SAME_OBJECT_DISTANCE)
                    && !spans_two(detection, point.frame, &placed, pass)
                {
                    placed.nodes.push(Node { kind, centre });
                    placed.node_track.push(index);
                } else {
                    // A second track on an object already placed (or one that cannot be
                    // placed) is not an object of the scene.
                    names[index] = None;
                }
            }
            None => placed.ropes.push((index, detection)),
        }
    }
    placed
}

/// Whether `detection` (of frame `frame`) is two surer objects of its kind seen as one: its
/// mask overlaps the masks of at least two placed nodes of its kind in that frame, which
/// together cover [`SPANNED_SHARE`] of it (the detector sometimes adds a pulley box round two
/// pulleys that touch, centred between them, where no pulley is).
fn spans_two(
    detection: &Detection,
    frame: usize,
    placed: &Placed<'_>,
    pass: &FirstPass<'_>,
) -> bool {
    let masks: Vec<&Detection> = placed
        .node_track
        .iter()
        .filter_map(|&track| {
            let point = pass.tracks[track].at_frame(frame)?;
            pass.detections.get(&frame)?.get(point.detection)
        })
        .filter(|other| {
            other.class.same_kind(detection.class)
                && detection
                    .mask
                    .pixels()
                    .any(|(x, y)| other.mask.contains(x, y))
        })
        .collect();
    if masks.len() < 2 {
        return false;
    }
    let area = detection.mask.area();
    let covered = detection
        .mask
        .pixels()
        .filter(|&(x, y)| masks.iter().any(|other| other.mask.contains(x, y)))
        .count();
    area > 0 && covered as f64 >= SPANNED_SHARE * area as f64
}

/// Pixels per [`COVER_RADIUS`] round the middle of the scene (at least 1.5), for how far a
/// rope's pixels may be from a sample point and still cover it.
fn reach_pixels(nodes: &[Node], model: &CameraModel) -> f64 {
    let middle = nodes.iter().fold([0.0, 0.0], |sum, n| {
        [sum[0] + n.centre[0], sum[1] + n.centre[1]]
    });
    let count = nodes.len().max(1) as f64;
    let middle = [middle[0] / count, middle[1] / count];
    let here = model.project([middle[0], middle[1], 0.0]);
    let beside = model.project([middle[0] + COVER_RADIUS, middle[1], 0.0]);
    match (here, beside) {
        (Some(a), Some(b)) => (a.x - b.x).hypot(a.y - b.y).max(1.5),
        _ => 1.5,
    }
}

/// Reads the mechanism of one video from its first pass. Each rope is read in every frame of
/// `frames` (the pass's frames, with pixels) where it was detected, from that frame's masks,
/// pixels and node positions, and the path read most often wins (ties: the earliest frame's), so
/// one frame with a broken mask or a hidden stretch does not decide the mechanism. Without
/// frames, each rope is read once from its first detection's mask alone.
pub(crate) fn perceive_rope(
    pass: &FirstPass<'_>,
    frames: &[RgbFrame],
    camera: &Camera,
) -> PerceivedRope {
    let FirstPass {
        classes,
        tracks,
        detections,
        size,
        frame_count,
    } = *pass;
    let model = camera_model(camera, size);
    // Names: unique, release-style.
    let mut names = track_names(tracks, classes);
    let Placed {
        mut nodes,
        node_track,
        ropes,
    } = place_tracks(pass, &model, camera, &mut names);
    // Where a rope's pixels end with no object to end at (a fixed point too small to be
    // detected), the rope may end there: a candidate fixed point, kept if a read rope ends on it.
    let tracked_nodes = nodes.len();
    nodes.extend(loose_ends(pass, (&ropes, frames), &nodes, &model, camera));
    let reader = FrameReader {
        pass,
        model: &model,
        reach_px: reach_pixels(&nodes, &model),
    };
    // Per rope, the distinct paths read and how many frames read each, in first-read order.
    let mut votes: Vec<Vec<(RopePath, usize)>> = vec![Vec::new(); ropes.len()];
    let mut tally = |paths: Vec<Option<RopePath>>| {
        for (rope_votes, path) in votes.iter_mut().zip(paths) {
            let Some(path) = path else { continue };
            match rope_votes
                .iter_mut()
                .find(|(seen, _)| seen.nodes == path.nodes && seen.turns == path.turns)
            {
                Some((_, count)) => *count += 1,
                None => rope_votes.push((path, 1)),
            }
        }
    };
    if frames.is_empty() {
        let first: Vec<Option<&Detection>> = ropes.iter().map(|(_, d)| Some(*d)).collect();
        tally(reader.read(&nodes, &first, None));
    }
    for frame in frames {
        // Where each node and rope is in this frame (a node not seen here keeps its first place).
        let here: Vec<Node> = nodes
            .iter()
            .enumerate()
            .map(|(index, node)| {
                node_track
                    .get(index)
                    .and_then(|&track| tracks[track].at_frame(frame.index))
                    .and_then(|p| lift(&model, camera, p.centroid[0], p.centroid[1]))
                    .map_or(*node, |centre| Node { centre, ..*node })
            })
            .collect();
        let seen: Vec<Option<&Detection>> = ropes
            .iter()
            .map(|(track, _)| {
                let point = tracks[*track].at_frame(frame.index)?;
                detections.get(&frame.index)?.get(point.detection)
            })
            .collect();
        tally(reader.read(&here, &seen, Some(frame)));
    }
    let mut paths: Vec<Option<RopePath>> = votes
        .into_iter()
        .map(|rope_votes| {
            let mut best: Option<(RopePath, usize)> = None;
            for (path, count) in rope_votes {
                if best.as_ref().is_none_or(|(_, most)| count > *most) {
                    best = Some((path, count));
                }
            }
            best.map(|(path, _)| path)
        })
        .collect();
    // The detector can split one rope into several detections: a rope read along the same
    // elements as a surer one, or not read but of a read rope's colour, is part of that one.
    for later in 0..paths.len() {
        let same_path = paths[..later].iter().flatten().any(|earlier| {
            paths[later].as_ref().is_some_and(|path| {
                path.nodes == earlier.nodes || path.nodes.iter().rev().eq(earlier.nodes.iter())
            })
        });
        let colour = tracks[ropes[later].0].color;
        let fragment = paths[later].is_none()
            && colour.is_some()
            && (0..paths.len()).any(|other| {
                other != later && paths[other].is_some() && tracks[ropes[other].0].color == colour
            });
        if same_path || fragment {
            paths[later] = None;
            names[ropes[later].0] = None;
        }
    }
    // The candidate ends some read rope ends on become fixed points of the scene.
    let loose: Vec<(usize, String)> = (tracked_nodes..nodes.len())
        .filter(|node| paths.iter().flatten().any(|path| path.nodes.contains(node)))
        .enumerate()
        .map(|(k, node)| (node, format!("Unknown Fixed Point (2 {k})")))
        .collect();
    // A movable pulley no read rope ends at, with a load on no rope straight under it: the
    // short connection rope between them is there even if the detector missed it.
    let read_paths: Vec<&RopePath> = paths.iter().flatten().collect();
    let connections: Vec<(String, RopePath)> = missed_connections(&nodes, &read_paths)
        .into_iter()
        .enumerate()
        .map(|(k, path)| (format!("Unknown Rope (2 {k})"), path))
        .collect();
    assemble(
        names,
        &nodes,
        (&node_track, &loose),
        (&ropes, &paths, &connections),
        camera,
        frame_count,
    )
}

/// The representative of `i`'s set in a union-find forest.
fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

/// The ropes of a scene as [`assemble`] takes them: the rope tracks with their first detection,
/// the path read for each (`None`: not read), and the connection ropes added (name, path).
type ReadRopes<'a, 'd> = (
    &'a [(usize, &'d Detection)],
    &'a [Option<RopePath>],
    &'a [(String, RopePath)],
);

/// Writes the read paths (and the connection ropes added under movable pulleys) as
/// release-format annotation and 4-D data.
fn assemble(
    names: Vec<Option<String>>,
    nodes: &[Node],
    (node_track, loose): (&[usize], &[(usize, String)]),
    (ropes, paths, connections): ReadRopes<'_, '_>,
    camera: &Camera,
    frame_count: usize,
) -> PerceivedRope {
    let name_of = |track: usize| names.get(track).cloned().flatten().unwrap_or_default();
    let node_name = |node: usize| {
        node_track.get(node).map_or_else(
            || {
                loose
                    .iter()
                    .find(|(index, _)| *index == node)
                    .map(|(_, name)| name.clone())
                    .unwrap_or_default()
            },
            |&t| name_of(t),
        )
    };
    // Ropes that were read, as (rope name, node path).
    let read: Vec<(String, &RopePath)> = ropes
        .iter()
        .zip(paths)
        .filter_map(|((track, _), path)| Some((name_of(*track), path.as_ref()?)))
        .chain(connections.iter().map(|(name, path)| (name.clone(), path)))
        .collect();
    let (related_groups, related_groups_in_rope) =
        group_listings(&read, &rope_groups(&read), &node_name);
    let mut annotation = RopeAnnotation {
        mode: "PERCEIVED".to_string(),
        related_groups,
        related_groups_in_rope,
        result_rotation: IndexMap::new(),
        result_motion: IndexMap::new(),
        result_tension: IndexMap::new(),
        predictive_event_type: IndexMap::new(),
        predictive_event_body: IndexMap::new(),
        output_mass_kg: IndexMap::new(),
        camera: Some(Camera {
            mirrored: camera.position[2] < 0.0,
            ..camera.clone()
        }),
        counterfactuals: Vec::new(),
        id_to_object_name: Vec::new(),
        frame_count,
        element_positions: IndexMap::new(),
    };
    // Loads: every load seen, at the counterfactual baseline mass.
    for (node, &track) in node_track.iter().enumerate() {
        let name = name_of(track);
        if nodes[node].kind == NodeKind::Load {
            let multiplier = super::simulation::load_multiplier(&annotation, &name);
            annotation
                .output_mass_kg
                .insert(name.clone(), world::BASELINE_MASS_KG * multiplier);
        }
        annotation
            .element_positions
            .insert(name, nodes[node].centre);
    }
    // Fixed points read from where a rope's pixels end: placed, static, never detected.
    for (node, name) in loose {
        annotation
            .element_positions
            .insert(name.clone(), nodes[*node].centre);
    }
    annotation.id_to_object_name = names
        .iter()
        .enumerate()
        .filter_map(|(i, n)| Some((u32::try_from(i).ok()?, n.clone()?)))
        .collect();
    // 4-D: moving bodies at their first position; ropes as particles along their paths.
    let mut four_d = FourDData::default();
    for (node, &track) in node_track.iter().enumerate() {
        let moving = matches!(
            nodes[node].kind,
            NodeKind::Load | NodeKind::MovablePulley { .. }
        );
        let centre = nodes[node].centre;
        let pose = ([centre[0], centre[1], 0.0], [0.0; 3]);
        four_d.rigid_bodies.insert(
            name_of(track),
            RigidBodyTrack {
                is_static: !moving,
                poses: if moving { vec![pose] } else { Vec::new() },
                voxels: Vec::new(),
                first_pose: Some(pose),
            },
        );
    }
    for (node, name) in loose {
        let centre = nodes[*node].centre;
        four_d.rigid_bodies.insert(
            name.clone(),
            RigidBodyTrack {
                is_static: true,
                poses: Vec::new(),
                voxels: Vec::new(),
                first_pose: Some(([centre[0], centre[1], 0.0], [0.0; 3])),
            },
        );
    }
    for (rope, path) in &read {
        let particles = path
            .polyline(nodes, PARTICLE_SPACING)
            .into_iter()
            .map(|p| [p[0], p[1], 0.0])
            .collect();
        four_d.soft_bodies.insert(
            rope.clone(),
            SoftBodyTrack {
                particles: vec![particles],
            },
        );
    }
    // Objects on no read rope stay findable.
    let on_rope = |name: &str| {
        annotation.related_groups_in_rope.iter().any(|g| {
            g.iter()
                .any(|(rope, elements)| rope == name || elements.iter().any(|e| e == name))
        })
    };
    let unattached = names
        .iter()
        .flatten()
        .filter(|name| !on_rope(name) && !annotation.output_mass_kg.contains_key(*name))
        .cloned()
        .collect();
    PerceivedRope {
        annotation,
        four_d,
        names,
        unattached,
    }
}

/// The read ropes in groups of ropes sharing a node (union-find over rope indices), each group in
/// rope order, the groups in order of their first rope.
fn rope_groups(read: &[(String, &RopePath)]) -> Vec<Vec<usize>> {
    let mut parent: Vec<usize> = (0..read.len()).collect();
    for a in 0..read.len() {
        for b in a + 1..read.len() {
            if read[a].1.nodes.iter().any(|n| read[b].1.nodes.contains(n)) {
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[ra.max(rb)] = ra.min(rb);
            }
        }
    }
    let roots: Vec<usize> = (0..read.len()).map(|i| root(&mut parent, i)).collect();
    let mut groups: Vec<Vec<usize>> = Vec::new();
    for rope in 0..read.len() {
        match groups.iter_mut().find(|g| roots[g[0]] == roots[rope]) {
            Some(group) => group.push(rope),
            None => groups.push(vec![rope]),
        }
    }
    groups
}

/// One group's `relatedGroupsInRope` entry: per rope, its elements with itself between them.
type RopeElements = IndexMap<String, Vec<String>>;

/// The release's `relatedGroups` (each group's elements and ropes as one chain) and
/// `relatedGroupsInRope` (per rope, its elements and itself between them) of `groups`.
fn group_listings(
    read: &[(String, &RopePath)],
    groups: &[Vec<usize>],
    node_name: &dyn Fn(usize) -> String,
) -> (Vec<Vec<String>>, Vec<RopeElements>) {
    let mut related_groups = Vec::new();
    let mut related_groups_in_rope = Vec::new();
    for group in groups {
        // The main rope is the longest; side ropes are listed after the node they hang from.
        let mut order = group.clone();
        order.sort_by_key(|&r| (std::cmp::Reverse(read[r].1.nodes.len()), r));
        let mut in_rope = IndexMap::new();
        for &r in &order {
            let (rope, path) = &read[r];
            let mut elements = Vec::new();
            for (i, &node) in path.nodes.iter().enumerate() {
                if i > 0 {
                    elements.push(rope.clone());
                }
                elements.push(node_name(node));
            }
            in_rope.insert(rope.clone(), elements);
        }
        let mut listed = Vec::new();
        let mut placed = vec![false; read.len()];
        write_chain(read, order[0], None, node_name, &mut listed, &mut placed);
        for &r in &order {
            if !placed[r] {
                write_chain(read, r, None, node_name, &mut listed, &mut placed);
            }
        }
        related_groups.push(listed);
        related_groups_in_rope.push(in_rope);
    }
    (related_groups, related_groups_in_rope)
}

/// Appends rope `rope`'s chain to `listed` in `relatedGroups` order (`node, rope, node, …`),
/// starting from `from` when given, and after each node the side ropes that end there.
fn write_chain(
    read: &[(String, &RopePath)],
    rope: usize,
    from: Option<usize>,
    node_name: &dyn Fn(usize) -> String,
    listed: &mut Vec<String>,
    placed: &mut [bool],
) {
    placed[rope] = true;
    let (name, path) = &read[rope];
    let mut nodes = path.nodes.clone();
    if from.is_some_and(|f| nodes.last() == Some(&f)) {
        nodes.reverse();
    }
    for (i, &node) in nodes.iter().enumerate() {
        // A side rope's first node is the shared one, already listed.
        if !(i == 0 && from == Some(node)) {
            if i > 0 || from.is_some() {
                listed.push(name.clone());
            }
            listed.push(node_name(node));
        }
        for (other, (_, other_path)) in read.iter().enumerate() {
            let ends_here =
                other_path.nodes.first() == Some(&node) || other_path.nodes.last() == Some(&node);
            if !placed[other] && ends_here {
                // The rope this chain is on resumes after the side chain.
                write_chain(read, other, Some(node), node_name, listed, placed);
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::engine::rope::RopeScene;
    use crate::perception::detection::InstanceMask;
    use crate::physics::rope::Turn;
    use crate::scene_api::rope::simulation::tests::sample;
    use crate::scene_api::rope::simulation::{Run, rope_paths, simulate_rope};

    fn kind_of(name: &str) -> NodeKind {
        let table = ClassTable::of_scenario(PERCEPTION.classes);
        table
            .of_object(name)
            .and_then(|class| node_kind(table.name(class)))
            .unwrap()
    }

    /// A detection of `class` whose mask is the rectangle `[x0, x1) × [0, 10)` of frame 0.
    fn block(class: &str, x0: u32, x1: u32) -> Detection {
        let mask = InstanceMask::new(x0, 0, x1 - x0, 10, vec![true; (x1 - x0) as usize * 10])
            .expect("a mask");
        Detection {
            frame: 0,
            class: crate::perception::rope::test_class(class),
            score: 1.0,
            bbox: [x0 as f32, 0.0, x1 as f32, 10.0],
            mask,
            color: None,
        }
    }

    #[test]
    fn a_pulley_box_round_two_placed_pulleys_is_not_a_third_pulley() {
        let pulley = "solid static pulley";
        let found = vec![
            block(pulley, 0, 10),
            block(pulley, 10, 20),
            block("hollow static pulley", 2, 18),
            block("cube", 2, 18),
            block(pulley, 5, 30),
        ];
        let tracks: Vec<Track> = found
            .iter()
            .enumerate()
            .map(|(index, detection)| Track {
                id: u32::try_from(index).unwrap(),
                class: detection.class,
                color: None,
                observations: vec![TrackPoint {
                    frame: 0,
                    detection: index,
                    centroid: [0.0; 2],
                    bbox: detection.bbox,
                }],
            })
            .collect();
        let classes = ClassTable::of_scenario(PERCEPTION.classes);
        let detections = std::collections::BTreeMap::from([(0, found.clone())]);
        let pass = FirstPass {
            classes: &classes,
            tracks: &tracks,
            detections: &detections,
            size: (40, 10),
            frame_count: 1,
        };
        let node = Node {
            kind: NodeKind::StaticPulley { solid: true },
            centre: [0.0; 2],
        };
        let placed = Placed {
            nodes: vec![node, node],
            node_track: vec![0, 1],
            ropes: Vec::new(),
        };
        // Covered by the two placed pulleys: the two seen as one.
        assert!(spans_two(&found[2], 0, &placed, &pass));
        // Not a pulley: a cube there is its own object.
        assert!(!spans_two(&found[3], 0, &placed, &pass));
        // Overlapping both, but a third of it outside them: an object of its own.
        assert!(!spans_two(&found[4], 0, &placed, &pass));
        // With one pulley placed, nothing spans two.
        let one = Placed {
            nodes: vec![node],
            node_track: vec![0],
            ropes: Vec::new(),
        };
        assert!(!spans_two(&found[2], 0, &one, &pass));
    }

    fn rope_detection() -> Detection {
        Detection {
            frame: 0,
            class: crate::perception::rope::test_class("rope"),
            score: 1.0,
            bbox: [0.0; 4],
            mask: InstanceMask::empty(),
            color: None,
        }
    }

    /// The annotated mechanism of the real video, fed through the perceived route (nodes at its
    /// elements' start positions, its paths and turns), comes out as an annotation that
    /// simulates exactly as the original: same groups, same outcome of every mass
    /// counterfactual.
    #[test]
    fn the_annotated_mechanism_written_as_perceived_simulates_the_same() {
        let (annotation, four_d) = sample();
        let paths = rope_paths(&annotation, Some(&four_d)).unwrap();
        let mut names: Vec<Option<String>> = Vec::new();
        let mut nodes = Vec::new();
        let mut node_track = Vec::new();
        for (_, elements, _) in &paths {
            for name in elements {
                if names.iter().flatten().any(|n| n == name) {
                    continue;
                }
                let at = four_d
                    .rigid_bodies
                    .get(name)
                    .and_then(|t| t.poses.first())
                    .map(|(p, _)| [p[0], p[1]])
                    .or_else(|| annotation.element_positions.get(name).copied())
                    .unwrap();
                node_track.push(names.len());
                nodes.push(Node {
                    kind: kind_of(name),
                    centre: at,
                });
                names.push(Some(name.clone()));
            }
        }
        let detection = rope_detection();
        let mut ropes = Vec::new();
        let mut read = Vec::new();
        for (rope, elements, turns) in &paths {
            ropes.push((names.len(), &detection));
            names.push(Some(rope.clone()));
            let indices = elements
                .iter()
                .map(|e| {
                    let track = names.iter().position(|n| n.as_deref() == Some(e)).unwrap();
                    node_track.iter().position(|t| *t == track).unwrap()
                })
                .collect();
            read.push(Some(RopePath::unscored(indices, turns.clone())));
        }
        let camera = annotation.camera.clone().unwrap();
        let perceived = assemble(
            names,
            &nodes,
            (&node_track, &[]),
            (&ropes, &read, &[]),
            &camera,
            150,
        );
        assert_eq!(
            perceived.annotation.related_groups_in_rope,
            annotation.related_groups_in_rope
        );
        assert!(perceived.unattached.is_empty());
        assert_eq!(
            perceived.annotation.camera.as_ref().map(|c| c.mirrored),
            Some(true),
            "mirrored is read from the camera's side (z < 0)"
        );
        // The turns survive the round trip through particles.
        let again = rope_paths(&perceived.annotation, Some(&perceived.four_d)).unwrap();
        assert_eq!(again, paths);
        assert!(
            again
                .iter()
                .flat_map(|(_, _, t)| t)
                .any(|t| *t == Some(Turn::Clockwise)),
            "{again:?}"
        );
        // Both engines see the same objects and relations.
        let scene = RopeScene::from_annotation("0", &perceived.annotation).unwrap();
        let original = RopeScene::from_annotation("0", &annotation).unwrap();
        assert_eq!(scene.objects().len(), original.objects().len());
        for load in ["Purple Cube", "Green Cube", "Pink Sphere"] {
            let mut masses = perceived.annotation.output_mass_kg.clone();
            assert_eq!(masses.len(), 3);
            *masses.get_mut(load).unwrap() -= 0.1;
            let seen = simulate_rope(
                &perceived.annotation,
                Some(&perceived.four_d),
                &masses,
                None,
                Run::Counterfactual,
            )
            .unwrap();
            let truth = simulate_rope(
                &annotation,
                Some(&four_d),
                &masses,
                None,
                Run::Counterfactual,
            )
            .unwrap();
            assert_eq!(seen.motion, truth.motion, "{load} lighter");
            assert_eq!(seen.rotation, truth.rotation, "{load} lighter");
        }
    }

    /// A movable pulley's own rope is listed after it, then the main rope resumes, as the
    /// release writes `relatedGroups`; the load under it is marked as such (×1.975).
    #[test]
    fn side_ropes_are_listed_after_their_pulley() {
        let r = world::wrap_radius(false);
        let names = [
            "Red Fixed Point",
            "Blue Hollow Dynamic Pulley (0 1)",
            "Green Hollow Static Pulley (0 2)",
            "Gray Cube",
            "Pink Sphere",
            "White Rope",
            "Black Rope",
        ];
        let nodes = vec![
            Node {
                kind: NodeKind::Anchor,
                centre: [-r, 10.0],
            },
            Node {
                kind: NodeKind::MovablePulley { solid: false },
                centre: [0.0, 2.0],
            },
            Node {
                kind: NodeKind::StaticPulley { solid: false },
                centre: [2.0 * r, 10.0],
            },
            Node {
                kind: NodeKind::Load,
                centre: [3.0 * r, 4.0],
            },
            Node {
                kind: NodeKind::Load,
                centre: [0.0, -2.0],
            },
        ];
        let detection = rope_detection();
        let ropes = [(5, &detection), (6, &detection)];
        let main = RopePath::unscored(
            vec![0, 1, 2, 3],
            vec![
                None,
                Some(Turn::CounterClockwise),
                Some(Turn::Clockwise),
                None,
            ],
        );
        let side = RopePath::unscored(vec![4, 1], vec![None, None]);
        let camera = sample().0.camera.unwrap();
        let perceived = assemble(
            names.iter().map(|n| Some((*n).to_string())).collect(),
            &nodes,
            (&[0, 1, 2, 3, 4], &[]),
            (&ropes, &[Some(main), Some(side)], &[]),
            &camera,
            150,
        );
        assert_eq!(
            perceived.annotation.related_groups,
            vec![vec![
                "Red Fixed Point",
                "White Rope",
                "Blue Hollow Dynamic Pulley (0 1)",
                "Black Rope",
                "Pink Sphere",
                "White Rope",
                "Green Hollow Static Pulley (0 2)",
                "White Rope",
                "Gray Cube",
            ]]
        );
        let masses = &perceived.annotation.output_mass_kg;
        assert!((masses["Pink Sphere"] - 0.2 * 1.975).abs() < 1e-12);
        assert!((masses["Gray Cube"] - 0.2).abs() < 1e-12);
    }
}

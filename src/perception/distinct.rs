//! Distinct colours within a class: where a scenario paints the objects of one class from their
//! own colour pool (rope: each of cubes, spheres, fixed points, ropes and the four kinds of
//! pulley has its own shuffled pool, so no two share a colour), two tracks of one class read in
//! one colour are a misreading, and the one whose pixels say that colour less firmly takes the
//! next colour its pixels name that no other object of its class has.
//!
//! Input: the tracks of a pass, the detections and frames they were built from, the colour
//! model and the class table. Output: the tracks' colours, changed only where two of a class
//! collided.

use std::collections::BTreeMap;

use super::classes::{Class, ClassTable};
use super::color::{ColorModel, features, wall_color};
use super::detection::{Detection, InstanceMask};
use super::frames::RgbFrame;
use super::tracking::Track;

/// Gives the tracks of each class distinct colours when `table` says the class's objects never
/// share one. Tracks sharing a colour are ranked by how many colour-model votes
/// that colour got over their observations; the first keeps it, each other one takes the
/// colour with most votes among those its class can have that no other track of its class
/// holds (it keeps the shared colour when its pixels name no such colour). Frames missing from
/// `pixels` give no votes.
pub fn separate_class_colors(
    tracks: &mut [Track],
    detections: &[(usize, Vec<Detection>)],
    pixels: &[RgbFrame],
    model: &ColorModel,
    table: &ClassTable,
) {
    let collisions: Vec<(Class, u8, Vec<usize>)> = colliding_groups(tracks)
        .into_iter()
        .filter(|(class, _, _)| table.distinct_colors(*class))
        .collect();
    if collisions.is_empty() {
        return;
    }
    let walls: BTreeMap<usize, [f64; 3]> = detections
        .iter()
        .filter_map(|(frame, found)| {
            let image = pixels.iter().find(|p| p.index == *frame)?;
            let masks: Vec<&InstanceMask> = found.iter().map(|d| &d.mask).collect();
            Some((*frame, wall_color(image, &masks)?))
        })
        .collect();
    // The votes of the colours `allowed` over a track's observations.
    let votes = |track: &Track, allowed: &[u8]| -> BTreeMap<u8, usize> {
        let mut tally = BTreeMap::new();
        for point in &track.observations {
            let found = detections
                .iter()
                .find(|(frame, _)| *frame == point.frame)
                .and_then(|(_, found)| found.get(point.detection));
            let image = pixels.iter().find(|p| p.index == point.frame);
            let (Some(detection), Some(image), Some(wall)) =
                (found, image, walls.get(&point.frame))
            else {
                continue;
            };
            if let Some(seen) = features(image, &detection.mask, *wall) {
                for (color, count) in model.votes(&seen, allowed) {
                    *tally.entry(color).or_insert(0) += count;
                }
            }
        }
        tally
    };
    for (class, color, members) in collisions {
        let class_colors = table.colors(class);
        let mut ranked: Vec<(usize, usize)> = members
            .iter()
            .map(|&at| {
                let said = votes(&tracks[at], class_colors)
                    .get(&color)
                    .copied()
                    .unwrap_or(0);
                (at, said)
            })
            .collect();
        // Most votes for the shared colour first; ties by the earlier track.
        ranked.sort_by(|a, b| b.1.cmp(&a.1).then(a.0.cmp(&b.0)));
        for &(at, _) in ranked.iter().skip(1) {
            let held: Vec<u8> = tracks
                .iter()
                .enumerate()
                .filter(|(other, t)| *other != at && t.class == class)
                .filter_map(|(_, t)| t.color)
                .collect();
            let free: Vec<u8> = if class_colors.is_empty() {
                super::palette::PALETTE.iter().map(|c| c.id).collect()
            } else {
                class_colors.to_vec()
            }
            .into_iter()
            .filter(|c| !held.contains(c))
            .collect();
            if free.is_empty() {
                continue;
            }
            let best = votes(&tracks[at], &free)
                .into_iter()
                .max_by(|a, b| a.1.cmp(&b.1).then(b.0.cmp(&a.0)));
            if let Some((next, _)) = best {
                tracks[at].color = Some(next);
            }
        }
    }
}

/// The groups of two or more tracks of one class with one colour: (class, colour, track
/// indices), in class then colour order.
fn colliding_groups(tracks: &[Track]) -> Vec<(Class, u8, Vec<usize>)> {
    let mut groups: BTreeMap<(Class, u8), Vec<usize>> = BTreeMap::new();
    for (at, track) in tracks.iter().enumerate() {
        if let Some(color) = track.color {
            groups.entry((track.class, color)).or_default().push(at);
        }
    }
    groups
        .into_iter()
        .filter(|(_, members)| members.len() > 1)
        .map(|((class, color), members)| (class, color, members))
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::perception::classes::{ClassTable, ClassWords};
    use crate::perception::color::ColorModel;
    use crate::perception::rope::{PERCEPTION, test_class};
    use crate::perception::tracking::{TrackerConfig, track};

    /// Rope's cube as a class whose objects may share a colour.
    static SHARED: [ClassWords; 1] = [ClassWords {
        name: "cube",
        kind: "cube",
        attributes: &[],
        colors: &[],
        pieces: false,
        distinct_colors: false,
    }];

    const RED: u8 = 0;
    const PINK: u8 = 7;
    const WALL: [u8; 3] = [200, 200, 200];

    /// A 100×60 frame of wall with two 12×12 cubes painted `left` and `right`.
    fn frame(index: usize, left: [u8; 3], right: [u8; 3]) -> (RgbFrame, Vec<Detection>) {
        let square =
            |x0: u32| move |x: u32, y: u32| (x0..x0 + 12).contains(&x) && (20..32).contains(&y);
        let mut rgb = Vec::new();
        for y in 0..60 {
            for x in 0..100 {
                rgb.extend_from_slice(&if square(10)(x, y) {
                    left
                } else if square(70)(x, y) {
                    right
                } else {
                    WALL
                });
            }
        }
        let cube = |x0: u32| Detection {
            frame: index,
            class: test_class("cube"),
            score: 0.9,
            bbox: [x0 as f32, 20.0, (x0 + 12) as f32, 32.0],
            mask: InstanceMask::from_predicate(100, 60, square(x0)),
            // Both read red, as a per-frame majority can.
            color: Some(RED),
        };
        let image = RgbFrame {
            index,
            width: 100,
            height: 60,
            rgb,
        };
        (image, vec![cube(10), cube(70)])
    }

    fn model() -> ColorModel {
        // Red and pink samples as the features of painted squares on the wall.
        let (image, found) = frame(0, [200, 0, 20], [240, 120, 140]);
        let masks: Vec<&InstanceMask> = found.iter().map(|d| &d.mask).collect();
        let wall = wall_color(&image, &masks).unwrap();
        let red = features(&image, &found[0].mask, wall).unwrap();
        let pink = features(&image, &found[1].mask, wall).unwrap();
        let mut samples = Vec::new();
        for i in 0..8 {
            let jitter = f64::from(i) * 1e-3;
            samples.push((RED, [red[0] + jitter, red[1], red[2]]));
            samples.push((PINK, [pink[0] + jitter, pink[1], pink[2]]));
        }
        ColorModel::fit(&samples, "test").unwrap()
    }

    #[test]
    fn two_cubes_read_in_one_colour_are_told_apart_by_their_pixels() {
        // The left cube is red; the right one, a reddish pink, was read red too. Rope cubes
        // never share a colour, so the one whose pixels say red less firmly becomes pink.
        let mut images = Vec::new();
        let mut detections = Vec::new();
        for index in 0..3 {
            let (image, found) = frame(index, [200, 0, 20], [225, 70, 90]);
            images.push(image);
            detections.push((index, found));
        }
        let mut tracks = track(&detections, &TrackerConfig::default()).unwrap();
        assert_eq!(tracks.len(), 2);
        assert!(tracks.iter().all(|t| t.color == Some(RED)));
        let table = ClassTable::of_scenario(PERCEPTION.classes);
        let model = model();
        separate_class_colors(&mut tracks, &detections, &images, &model, &table);
        let left = tracks
            .iter()
            .find(|t| t.observations[0].centroid[0] < 50.0)
            .unwrap();
        let right = tracks
            .iter()
            .find(|t| t.observations[0].centroid[0] > 50.0)
            .unwrap();
        assert_eq!((left.color, right.color), (Some(RED), Some(PINK)));

        // A class whose objects may share colours keeps both red.
        let mut shared = track(&detections, &TrackerConfig::default()).unwrap();
        let mut scenario = PERCEPTION.classes;
        scenario.classes = &SHARED;
        let table = ClassTable::of_scenario(scenario);
        separate_class_colors(&mut shared, &detections, &images, &model, &table);
        assert!(shared.iter().all(|t| t.color == Some(RED)));
    }
}

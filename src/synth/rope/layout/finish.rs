//! What follows an accepted layout: groups moved apart (`RearrangeObjects`), the factual masses
//! drawn, and `metaSamplingData` written in the release's form.

use rand::Rng;
use rand::seq::SliceRandom;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::{
    ElementKind, LOAD_MASSES_KG, Layout, LoadShape, MIN_DISTANCE_BETWEEN_GROUPS, RANDOM_LAYOUT_P,
    REARRANGED_GROUP_GAP,
};

/// Moves whole groups apart (`RearrangeObjects`): always when two groups come closer than 4
/// units, otherwise with probability ½; groups are shuffled left to right with 7-unit gaps and
/// placed at random heights in the scene's height band, keeping the overall centre.
pub(super) fn rearrange(layout: &mut Layout, rng: &mut ChaCha8Rng) {
    let groups = layout_groups(layout);
    if groups.len() < 2 {
        return;
    }
    let close = groups_too_close(layout, &groups);
    let random_layout = if rng.random::<f64>() < RANDOM_LAYOUT_P {
        true
    } else {
        close
    };
    if !random_layout {
        return;
    }
    let boxes: Vec<([f64; 2], [f64; 2])> =
        groups.iter().map(|names| bounds(layout, names)).collect();
    let targets = group_targets(&boxes, rng);
    let shifts = group_shifts(&boxes, &targets);
    move_groups(layout, &groups, &shifts);
}

/// Where `name` is in the layout (the origin when it has no position).
fn position(layout: &Layout, name: &str) -> [f64; 2] {
    layout.positions.get(name).copied().unwrap_or([0.0, 0.0])
}

/// Layout groups: non-rope names per related group, merged when they share a name.
fn layout_groups(layout: &Layout) -> Vec<Vec<String>> {
    let mut groups: Vec<Vec<String>> = Vec::new();
    for group in &layout.related_groups {
        let names: Vec<String> = group
            .iter()
            .filter(|n| !n.ends_with(" Rope") && layout.positions.contains_key(*n))
            .cloned()
            .collect();
        if names.is_empty() {
            continue;
        }
        match groups
            .iter()
            .position(|g| g.iter().any(|n| names.contains(n)))
        {
            Some(g) => {
                for name in names {
                    if !groups[g].contains(&name) {
                        groups[g].push(name);
                    }
                }
            }
            None => groups.push(names),
        }
    }
    groups
}

/// Whether an object of one group is closer than 4 units to an object of another.
fn groups_too_close(layout: &Layout, groups: &[Vec<String>]) -> bool {
    let mut close = false;
    for (a, first) in groups.iter().enumerate() {
        for second in &groups[a + 1..] {
            for p in first {
                for q in second {
                    let (pa, pb) = (position(layout, p), position(layout, q));
                    if (pa[0] - pb[0]).hypot(pa[1] - pb[1]) < MIN_DISTANCE_BETWEEN_GROUPS {
                        close = true;
                    }
                }
            }
        }
    }
    close
}

/// The bounding box `(low, high)` of the named objects.
fn bounds(layout: &Layout, names: &[String]) -> ([f64; 2], [f64; 2]) {
    let mut low = [f64::INFINITY; 2];
    let mut high = [f64::NEG_INFINITY; 2];
    for name in names {
        let p = position(layout, name);
        for axis in 0..2 {
            low[axis] = low[axis].min(p[axis]);
            high[axis] = high[axis].max(p[axis]);
        }
    }
    (low, high)
}

/// The groups' new centres: shuffled left to right with 7-unit gaps, each at a random height
/// in the band the groups span together.
fn group_targets(boxes: &[([f64; 2], [f64; 2])], rng: &mut ChaCha8Rng) -> Vec<[f64; 2]> {
    let mut order: Vec<usize> = (0..boxes.len()).collect();
    order.shuffle(rng);
    let mut targets = vec![[0.0; 2]; boxes.len()];
    let mut base = 0.0;
    for &g in &order {
        let width = boxes[g].1[0] - boxes[g].0[0];
        targets[g][0] = base + width / 2.0;
        base += width + REARRANGED_GROUP_GAP;
    }
    let top = boxes
        .iter()
        .map(|b| b.1[1])
        .fold(f64::NEG_INFINITY, f64::max);
    let bottom = boxes.iter().map(|b| b.0[1]).fold(f64::INFINITY, f64::min);
    let band = top - bottom;
    for (g, target) in targets.iter_mut().enumerate() {
        let height = boxes[g].1[1] - boxes[g].0[1];
        let low = -band + height / 2.0;
        let high = -height / 2.0;
        target[1] = if high > low {
            rng.random_range(low..high)
        } else {
            low
        };
    }
    targets
}

/// The centre of the box holding all `boxes`.
fn union_centre(boxes: &[([f64; 2], [f64; 2])]) -> [f64; 2] {
    let low = [
        boxes.iter().map(|b| b.0[0]).fold(f64::INFINITY, f64::min),
        boxes.iter().map(|b| b.0[1]).fold(f64::INFINITY, f64::min),
    ];
    let high = [
        boxes
            .iter()
            .map(|b| b.1[0])
            .fold(f64::NEG_INFINITY, f64::max),
        boxes
            .iter()
            .map(|b| b.1[1])
            .fold(f64::NEG_INFINITY, f64::max),
    ];
    [
        f64::midpoint(low[0], high[0]),
        f64::midpoint(low[1], high[1]),
    ]
}

/// Per group, how far it moves: to its target, plus the shift that keeps the overall centre
/// where it was.
fn group_shifts(boxes: &[([f64; 2], [f64; 2])], targets: &[[f64; 2]]) -> Vec<[f64; 2]> {
    let moved: Vec<([f64; 2], [f64; 2])> = boxes
        .iter()
        .zip(targets)
        .map(|(b, t)| {
            let half = [(b.1[0] - b.0[0]) / 2.0, (b.1[1] - b.0[1]) / 2.0];
            (
                [t[0] - half[0], t[1] - half[1]],
                [t[0] + half[0], t[1] + half[1]],
            )
        })
        .collect();
    let original_centre = union_centre(boxes);
    let moved_centre = union_centre(&moved);
    let delta = [
        original_centre[0] - moved_centre[0],
        original_centre[1] - moved_centre[1],
    ];
    (0..boxes.len())
        .map(|g| {
            let centre = [
                f64::midpoint(boxes[g].0[0], boxes[g].1[0]),
                f64::midpoint(boxes[g].0[1], boxes[g].1[1]),
            ];
            [
                targets[g][0] - centre[0] + delta[0],
                targets[g][1] - centre[1] + delta[1],
            ]
        })
        .collect()
}

/// Moves every object of each group (and the load hanging under it) by the group's shift.
fn move_groups(layout: &mut Layout, groups: &[Vec<String>], shifts: &[[f64; 2]]) {
    for (names, shift) in groups.iter().zip(shifts) {
        for name in names {
            if let Some(p) = layout.positions.get_mut(name) {
                p[0] += shift[0];
                p[1] += shift[1];
            }
            for rope in &mut layout.ropes {
                for element in &mut rope.path {
                    if element.name == *name {
                        element.position[0] += shift[0];
                        element.position[1] += shift[1];
                        if let Some((load, _)) = &element.hanging
                            && let Some(p) = layout.positions.get_mut(load)
                        {
                            p[0] += shift[0];
                            p[1] += shift[1];
                        }
                    }
                }
            }
        }
    }
}

/// The factual masses: each load draws from {0.15, 0.25, 0.20} kg; in 80% of scenes the draw is
/// repeated (up to 100 times) until min(n, 3) distinct values appear; then the multiplier.
pub(super) fn sample_masses(layout: &mut Layout, rng: &mut ChaCha8Rng) {
    let count = layout.loads.len();
    let draw = |rng: &mut ChaCha8Rng| -> Vec<f64> {
        (0..count)
            .map(|_| LOAD_MASSES_KG[rng.random_range(0..LOAD_MASSES_KG.len())])
            .collect()
    };
    let mut masses = draw(rng);
    if rng.random::<f64>() > 0.2 {
        let wanted = count.min(3);
        for _ in 0..100 {
            let mut distinct = masses.clone();
            distinct.sort_by(f64::total_cmp);
            distinct.dedup();
            if distinct.len() >= wanted {
                break;
            }
            masses = draw(rng);
        }
    }
    layout.masses_kg = masses
        .iter()
        .zip(&layout.loads)
        .map(|(m, (_, multiplier))| m * multiplier)
        .collect();
}

/// `metaSamplingData` in the release's form.
pub(super) fn build_meta(layout: &Layout, partial: &Value) -> Value {
    let rope_meta: Vec<Value> = layout
        .ropes
        .iter()
        .map(|rope| {
            Value::Array(
                rope.path
                    .iter()
                    .map(|e| {
                        let mut entry = serde_json::Map::new();
                        entry.insert("type".into(), json!(f64::from(e.code)));
                        entry.insert("x".into(), json!(e.position[0]));
                        entry.insert("y".into(), json!(e.position[1]));
                        entry.insert("z".into(), json!(0.0));
                        if let (Some((layer, column)), Some((col_state, layer_state))) =
                            (e.grid, e.in_states)
                        {
                            entry.insert("idx".into(), json!(f64::from(column)));
                            entry.insert("idy".into(), json!(f64::from(layer)));
                            entry.insert("idx_in_states".into(), json!(col_state as f64));
                            entry.insert("idy_in_states".into(), json!(layer_state as f64));
                            entry.insert("scale".into(), json!(if e.solid { 0.0 } else { 1.0 }));
                        }
                        entry.insert("position".into(), json!(f64::from(e.row)));
                        if let Some(shape) = e.load_shape {
                            entry.insert(
                                "loadShape".into(),
                                json!(if shape == LoadShape::Cube { 1.0 } else { 0.0 }),
                            );
                        }
                        if let Some(color) = e.load_color {
                            entry.insert("loadColor".into(), json!(f64::from(color)));
                        }
                        if e.kind != ElementKind::TiedToPulley {
                            entry.insert("color".into(), json!(f64::from(e.color)));
                        }
                        if let Some((x, y)) = e.target {
                            entry.insert("target_x".into(), json!(f64::from(x)));
                            entry.insert("target_y".into(), json!(f64::from(y)));
                        }
                        Value::Object(entry)
                    })
                    .collect(),
            )
        })
        .collect();
    json!({
        "metaSampling": rope_meta,
        "connection": partial.get("connection").cloned().unwrap_or(json!([])),
        "name2idsInPose": layout.ids_in_pose,
        "name2position": layout.positions,
        "dynamicObjectIndex": layout.ropes.iter().map(|r| r.dynamic_indices.clone()).collect::<Vec<_>>(),
    })
}

//! Names and relations: every object's name, the ropes' and cables' names and colours, the
//! ends tied to pulleys, the release's per-rope lists, related groups and load list, and the
//! positions by name.

use indexmap::IndexMap;
use serde_json::json;

use super::colors::{Pools, color_name};
use super::kind::{DYNAMIC_WAIT, DYNAMIC_WITH_LOAD};
use super::scheme::Connect;
use super::{Cable, Element, ElementKind, Layout, LayoutRope, LoadShape, Rejection, Y_STEP, world};

/// Names every object, builds the cables and the related groups.
pub(super) fn name_and_group(
    mut paths: Vec<Vec<Element>>,
    dynamic_indices: Vec<Vec<usize>>,
    connects: &[Connect],
    pools: &mut Pools,
) -> Result<Layout, Rejection> {
    name_objects(&mut paths);
    let ropes = main_cables(paths, dynamic_indices, pools);
    let tied = tied_ends(&ropes)?;
    let cables = pulley_cables(connects, &ropes, pools)?;
    check_unique_names(&ropes, &cables)?;
    let lists = relation_lists(&ropes, &tied);
    let mut grouping = group_ropes(&ropes, &cables, &tied, &lists)?;
    let (related_groups, related_groups_in_rope) =
        related_groups(&ropes, &cables, &lists, &mut grouping);
    if related_groups
        .iter()
        .zip(&related_groups_in_rope)
        .any(|(g, r)| g.is_empty() && r.is_empty())
    {
        return Err(Rejection::Malformed);
    }
    let loads = output_loads(&ropes);
    let (positions, ids_in_pose) = pose_maps(&ropes);
    let meta = json!({
        "connection": connects.iter().map(|c| json!({
            "x1": c.upper.0, "y1": c.upper.1, "x2": c.lower.0, "y2": c.lower.1,
        })).collect::<Vec<_>>(),
    });
    Ok(Layout {
        ropes,
        cables,
        related_groups,
        related_groups_in_rope,
        masses_kg: vec![0.0; loads.len()],
        loads,
        positions,
        ids_in_pose,
        meta,
    })
}

/// Object names: pulleys by colour, kind and grid slot, fixed points and loads by colour (and
/// shape); a tied end has none.
fn name_objects(paths: &mut [Vec<Element>]) {
    for path in paths {
        for element in path.iter_mut() {
            element.name = match element.kind {
                ElementKind::StaticPulley | ElementKind::MovablePulley => {
                    let (layer, column) = element.grid.unwrap_or((0, 0));
                    format!(
                        "{} {} {} Pulley ({layer} {column})",
                        color_name(element.color),
                        if element.solid { "Solid" } else { "Hollow" },
                        if element.kind == ElementKind::StaticPulley {
                            "Static"
                        } else {
                            "Dynamic"
                        }
                    )
                }
                ElementKind::FixedPoint(_) => format!("{} Fixed Point", color_name(element.color)),
                ElementKind::Load => format!(
                    "{} {}",
                    color_name(element.color),
                    element.load_shape.unwrap_or(LoadShape::Cube).word()
                ),
                ElementKind::TiedToPulley => String::new(),
            };
        }
    }
}

/// Ropes: each main cable, then its load connections in element order, each taking the next
/// rope colour.
fn main_cables(
    paths: Vec<Vec<Element>>,
    dynamic_indices: Vec<Vec<usize>>,
    pools: &mut Pools,
) -> Vec<LayoutRope> {
    let mut ropes = Vec::new();
    for (path, dynamic) in paths.into_iter().zip(dynamic_indices) {
        let color = pools.rope.take();
        let name = format!("{} Rope", color_name(color));
        let mut path = path;
        for element in &mut path {
            let carries = element.kind == ElementKind::MovablePulley
                && matches!(element.code, DYNAMIC_WAIT | DYNAMIC_WITH_LOAD);
            if carries {
                let shape = element.load_shape.unwrap_or(LoadShape::Cube);
                let load = format!(
                    "{} {}",
                    color_name(element.load_color.unwrap_or(0)),
                    shape.word()
                );
                let connection = format!("{} Rope", color_name(pools.rope.take()));
                element.hanging = Some((load, connection));
            }
        }
        ropes.push(LayoutRope {
            name,
            color,
            path,
            dynamic_indices: dynamic,
        });
    }
    ropes
}

/// The name of the pulley at grid slot `target` (`(column, layer)`), if any.
fn pulley_at_grid(ropes: &[LayoutRope], target: (i32, i32)) -> Option<String> {
    ropes
        .iter()
        .flat_map(|r| r.path.iter())
        .find(|e| e.is_pulley() && e.grid == Some((target.1, target.0)))
        .map(|e| e.name.clone())
}

/// Tied ends find their pulley by grid slot: per tied end, its rope, whether it is the rope's
/// start, and the pulley's name.
fn tied_ends(ropes: &[LayoutRope]) -> Result<Vec<(usize, bool, String)>, Rejection> {
    let mut tied: Vec<(usize, bool, String)> = Vec::new();
    for (index, rope) in ropes.iter().enumerate() {
        for (at_start, element) in [(true, rope.path.first()), (false, rope.path.last())] {
            if let Some(element) = element
                && element.kind == ElementKind::TiedToPulley
            {
                let target = element.target.ok_or(Rejection::Malformed)?;
                tied.push((
                    index,
                    at_start,
                    pulley_at_grid(ropes, target).ok_or(Rejection::Malformed)?,
                ));
            }
        }
    }
    Ok(tied)
}

/// The pulley–pulley cables, each taking the next rope colour.
fn pulley_cables(
    connects: &[Connect],
    ropes: &[LayoutRope],
    pools: &mut Pools,
) -> Result<Vec<Cable>, Rejection> {
    let mut cables = Vec::new();
    for connect in connects {
        let upper = pulley_at_grid(ropes, connect.upper).ok_or(Rejection::Malformed)?;
        let lower = pulley_at_grid(ropes, connect.lower).ok_or(Rejection::Malformed)?;
        let color = pools.rope.take();
        cables.push(Cable {
            name: format!("{} Rope", color_name(color)),
            upper,
            lower,
        });
    }
    Ok(cables)
}

/// Duplicate names lose the scene in the release (a dictionary throws).
fn check_unique_names(ropes: &[LayoutRope], cables: &[Cable]) -> Result<(), Rejection> {
    let mut seen: Vec<String> = Vec::new();
    let mut check = |name: &str| -> Result<(), Rejection> {
        if name.is_empty() {
            return Ok(());
        }
        if seen.iter().any(|s| s == name) {
            return Err(Rejection::DuplicateName(name.to_string()));
        }
        seen.push(name.to_string());
        Ok(())
    };
    for rope in ropes {
        check(&rope.name)?;
        for element in &rope.path {
            check(&element.name)?;
            if let Some((load, connection)) = &element.hanging {
                check(load)?;
                check(connection)?;
            }
        }
    }
    for cable in cables {
        check(&cable.name)?;
    }
    Ok(())
}

/// Per-rope lists (`AnswerRelations`): the rope's elements interleaved with its name, hanging
/// loads after their connections, the ends (and the pulleys tied ends hold) at either side.
fn relation_lists(ropes: &[LayoutRope], tied: &[(usize, bool, String)]) -> Vec<Vec<String>> {
    let mut lists: Vec<Vec<String>> = Vec::new();
    for rope in ropes {
        let mut list = Vec::new();
        let last = rope.path.len() - 1;
        for element in &rope.path[1..last] {
            list.push(rope.name.clone());
            list.push(element.name.clone());
            if let Some((load, connection)) = &element.hanging {
                list.push(connection.clone());
                list.push(load.clone());
            }
        }
        list.push(rope.name.clone());
        if !rope.path[0].name.is_empty() {
            list.insert(0, rope.path[0].name.clone());
        }
        if !rope.path[last].name.is_empty() {
            list.push(rope.path[last].name.clone());
        }
        lists.push(list);
    }
    for (rope, at_start, target) in tied {
        if *at_start {
            lists[*rope].insert(0, target.clone());
        } else {
            lists[*rope].push(target.clone());
        }
    }
    lists
}

/// Ropes joined into related groups, and the group each cable belongs to.
struct Grouping {
    /// Union–find labels, one per rope.
    label: Vec<usize>,
    /// Each group's ropes: joined ropes in joining order first, then the others.
    groups: Vec<Vec<usize>>,
    /// Each group's root label.
    group_roots: Vec<usize>,
    /// Per cable, a rope of its group; `None` for a cable between static pulleys.
    cable_group: Vec<Option<usize>>,
}

/// The root of rope `i`'s label, pointing `i` straight at it.
fn find(label: &mut [usize], i: usize) -> usize {
    let mut root = i;
    while label[root] != root {
        root = label[root];
    }
    label[i] = root;
    root
}

/// Joins the groups of ropes `a` and `b`, noting both in joining `order`.
fn union(label: &mut [usize], a: usize, b: usize, order: &mut Vec<usize>) {
    for r in [a, b] {
        if !order.contains(&r) {
            order.push(r);
        }
    }
    let (ra, rb) = (find(label, a), find(label, b));
    if ra != rb {
        label[rb] = ra;
    }
}

/// Groups: ropes joined by a cable between movable pulleys, or by an end tied to a movable
/// pulley, are one group.
fn group_ropes(
    ropes: &[LayoutRope],
    cables: &[Cable],
    tied: &[(usize, bool, String)],
    lists: &[Vec<String>],
) -> Result<Grouping, Rejection> {
    let rope_of = |name: &str| lists.iter().position(|l| l.iter().any(|n| n == name));
    let dynamic = |name: &str| name.contains("Dynamic");
    let mut label: Vec<usize> = (0..ropes.len()).collect();
    let mut joined_order: Vec<usize> = Vec::new();
    let mut cable_group: Vec<Option<usize>> = Vec::new();
    for cable in cables {
        let a = rope_of(&cable.upper).ok_or(Rejection::Malformed)?;
        let b = rope_of(&cable.lower).ok_or(Rejection::Malformed)?;
        match (dynamic(&cable.upper), dynamic(&cable.lower)) {
            (true, true) => {
                union(&mut label, a, b, &mut joined_order);
                cable_group.push(Some(a));
            }
            (true, false) => cable_group.push(Some(a)),
            (false, true) => cable_group.push(Some(b)),
            (false, false) => cable_group.push(None),
        }
    }
    for (rope, _, target) in tied {
        if dynamic(target) {
            let other = rope_of_excluding(lists, target, *rope).ok_or(Rejection::Malformed)?;
            union(&mut label, *rope, other, &mut joined_order);
        }
    }
    let mut order = joined_order;
    for rope in 0..ropes.len() {
        if !order.contains(&rope) {
            order.push(rope);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_roots: Vec<usize> = Vec::new();
    for rope in order {
        let root = find(&mut label, rope);
        if let Some(g) = group_roots.iter().position(|&r| r == root) {
            groups[g].push(rope);
        } else {
            group_roots.push(root);
            groups.push(vec![rope]);
        }
    }
    Ok(Grouping {
        label,
        groups,
        group_roots,
        cable_group,
    })
}

/// One `relatedGroupsInRope` entry: rope or cable name → the names it relates.
type ByRope = IndexMap<String, Vec<String>>;

/// `relatedGroups` and `relatedGroupsInRope`: per group its ropes' lists, and per rope of it the
/// main cable, each load connection and each cable it holds; then a group of its own for each
/// cable between static pulleys.
fn related_groups(
    ropes: &[LayoutRope],
    cables: &[Cable],
    lists: &[Vec<String>],
    grouping: &mut Grouping,
) -> (Vec<Vec<String>>, Vec<ByRope>) {
    let mut related_groups = Vec::new();
    let mut related_groups_in_rope = Vec::new();
    for (g, members) in grouping.groups.iter().enumerate() {
        let mut flat = Vec::new();
        let mut by_rope: IndexMap<String, Vec<String>> = IndexMap::new();
        for &rope in members {
            flat.extend(lists[rope].iter().cloned());
            let mut main = lists[rope].clone();
            for element in &ropes[rope].path {
                if let Some((load, connection)) = &element.hanging {
                    by_rope.insert(
                        connection.clone(),
                        vec![element.name.clone(), connection.clone(), load.clone()],
                    );
                    if let Some(at) = main.iter().position(|n| n == connection) {
                        main.remove(at);
                    }
                    if let Some(at) = main.iter().position(|n| n == load) {
                        main.remove(at);
                    }
                }
            }
            by_rope.insert(ropes[rope].name.clone(), main);
        }
        for (cable, group) in cables.iter().zip(&grouping.cable_group) {
            if group.is_some_and(|r| find(&mut grouping.label, r) == grouping.group_roots[g]) {
                by_rope.insert(
                    cable.name.clone(),
                    vec![cable.upper.clone(), cable.name.clone(), cable.lower.clone()],
                );
            }
        }
        related_groups.push(flat);
        related_groups_in_rope.push(by_rope);
    }
    for (cable, group) in cables.iter().zip(&grouping.cable_group) {
        if group.is_none() {
            related_groups.push(Vec::new());
            let mut by_rope = IndexMap::new();
            by_rope.insert(
                cable.name.clone(),
                vec![cable.upper.clone(), cable.name.clone(), cable.lower.clone()],
            );
            related_groups_in_rope.push(by_rope);
        }
    }
    (related_groups, related_groups_in_rope)
}

/// Loads in `outputMass` order: hanging loads (rope by rope), then end loads, each with its
/// mass multiplier.
fn output_loads(ropes: &[LayoutRope]) -> Vec<(String, f64)> {
    let mut loads: Vec<(String, f64)> = Vec::new();
    for rope in ropes {
        for element in &rope.path {
            if let Some((load, _)) = &element.hanging {
                loads.push((load.clone(), world::MOVABLE_PULLEY_LOAD_MULTIPLIER));
            }
        }
    }
    for rope in ropes {
        for element in [rope.path.first(), rope.path.last()].into_iter().flatten() {
            if element.kind == ElementKind::Load {
                loads.push((element.name.clone(), 1.0));
            }
        }
    }
    loads
}

/// `name2position` and `name2idsInPose`: every named element's position and `(rope, index)`,
/// a hanging load half a row under its pulley at its pulley's index.
fn pose_maps(ropes: &[LayoutRope]) -> (IndexMap<String, [f64; 2]>, IndexMap<String, [usize; 2]>) {
    let mut positions: IndexMap<String, [f64; 2]> = IndexMap::new();
    let mut ids_in_pose: IndexMap<String, [usize; 2]> = IndexMap::new();
    for (r, rope) in ropes.iter().enumerate() {
        for (e, element) in rope.path.iter().enumerate() {
            if element.name.is_empty() {
                continue;
            }
            positions
                .entry(element.name.clone())
                .or_insert(element.position);
            ids_in_pose.entry(element.name.clone()).or_insert([r, e]);
            if let Some((load, _)) = &element.hanging {
                positions
                    .entry(load.clone())
                    .or_insert([element.position[0], element.position[1] - 0.5 * Y_STEP]);
                ids_in_pose.entry(load.clone()).or_insert([r, e]);
            }
        }
    }
    (positions, ids_in_pose)
}

/// The rope other than `excluded` whose list holds `name`.
fn rope_of_excluding(lists: &[Vec<String>], name: &str, excluded: usize) -> Option<usize> {
    lists
        .iter()
        .enumerate()
        .find(|(i, l)| *i != excluded && l.iter().any(|n| n == name))
        .map(|(i, _)| i)
}

//! The walk's slots turned into rope paths: each rope's pulleys in walk order with their
//! positions and colours, its two ends, and the limit of two dynamic nodes per cable.

use rand::Rng;
use rand_chacha::ChaCha8Rng;

use super::colors::{Pools, random_shape};
use super::kind::{
    DYNAMIC_WAIT, DYNAMIC_WITH_LOAD, END_DYNAMIC_LOAD, END_DYNAMIC_PULY, END_DYNAMIC_WAIT,
    END_STATIC_CEIL, END_STATIC_FLOO, STATICS,
};
use super::scheme::{Scheme, Slot};
use super::{
    BASE_X, BASE_Y, CEIL_FLOOR_SCALE, Element, ElementKind, LAYER_STEP,
    MAX_DYNAMIC_NODES_PER_CABLE, OBJ_POS_SCALE, RADIUS_SCALE, Rejection, X_STEP, Y_STEP,
};

/// Poses: each rope collects the pulley slots of the walk, in list order, up to its end; the
/// pulleys get their positions, colours and (movable pulleys waiting for a load) load shapes.
pub(super) fn rope_poses(
    scheme: &Scheme,
    rng: &mut ChaCha8Rng,
    pools: &mut Pools,
) -> Result<Vec<Vec<Element>>, Rejection> {
    let mut ropes: Vec<Vec<Element>> = Vec::new();
    let flat: Vec<(usize, usize, &Slot)> = scheme
        .states
        .iter()
        .enumerate()
        .flat_map(|(layer, slots)| {
            slots
                .iter()
                .enumerate()
                .map(move |(column, slot)| (column, layer, slot))
        })
        .collect();
    let mut cursor = 0;
    for pair in scheme.divisions.chunks(2) {
        let end = &pair[1];
        let mut path = Vec::new();
        loop {
            let Some(&(column, layer, slot)) = flat.get(cursor) else {
                return Err(Rejection::Malformed);
            };
            cursor += 1;
            if slot.state <= STATICS {
                path.push(pulley_element((column, layer, slot), rng, pools));
            }
            if slot.x == end.x && slot.depth == end.depth {
                break;
            }
        }
        if path.is_empty() {
            return Err(Rejection::Malformed);
        }
        ropes.push(path);
    }
    Ok(ropes)
}

/// The pulley of `slot`, at `(column, layer)` of the walk's slot lists: its position, its
/// colour, and the shape and colour of the load a movable pulley waiting for one carries.
fn pulley_element(
    (column, layer, slot): (usize, usize, &Slot),
    rng: &mut ChaCha8Rng,
    pools: &mut Pools,
) -> Element {
    let row = slot.position;
    let y =
        BASE_Y - if row % 2 == 0 { 0.0 } else { Y_STEP } - 2.0 * f64::from(slot.depth) * LAYER_STEP;
    let x = BASE_X + f64::from(slot.x) * X_STEP;
    let dynamic = slot.state != STATICS;
    let (load_shape, load_color) = if slot.state == DYNAMIC_WITH_LOAD || slot.state == DYNAMIC_WAIT
    {
        let shape = random_shape(rng);
        (Some(shape), Some(pools.load(shape)))
    } else {
        (None, None)
    };
    let color = if dynamic {
        if slot.big {
            pools.movable_hollow.take()
        } else {
            pools.movable_solid.take()
        }
    } else {
        pools.static_pulley(!slot.big)
    };
    Element {
        kind: if dynamic {
            ElementKind::MovablePulley
        } else {
            ElementKind::StaticPulley
        },
        code: slot.state,
        name: String::new(),
        position: [x, y],
        grid: Some((slot.depth, slot.x)),
        in_states: Some((column, layer)),
        solid: !slot.big,
        row,
        color,
        load_shape,
        load_color,
        hanging: None,
        target: None,
    }
}

/// Terminals: each division becomes the end element before or after its rope's first or last
/// pulley (a ceiling or floor point, a load, or an end tied to a pulley's axle).
pub(super) fn add_terminals(
    scheme: &Scheme,
    ropes: &mut [Vec<Element>],
    rng: &mut ChaCha8Rng,
    pools: &mut Pools,
) -> Result<(), Rejection> {
    for (index, division) in scheme.divisions.iter().enumerate() {
        let rope = index / 2;
        let at_start = index % 2 == 0;
        let code = if division.kind == END_DYNAMIC_WAIT {
            END_DYNAMIC_LOAD
        } else {
            division.kind
        };
        let adjacent = if at_start {
            ropes[rope].first()
        } else {
            ropes[rope].last()
        }
        .cloned()
        .ok_or(Rejection::Malformed)?;
        let direction = f64::from(if division.depth % 2 == 0 { -1 } else { 1 })
            * if at_start { 1.0 } else { -1.0 };
        let x = adjacent.position[0] + 0.5 * X_STEP * direction * RADIUS_SCALE;
        let mut y =
            adjacent.position[1] + if adjacent.row % 2 == 0 { -1.0 } else { 1.0 } * 0.5 * Y_STEP;
        let (kind, color, load_shape) = match code {
            END_STATIC_CEIL => {
                y += Y_STEP * CEIL_FLOOR_SCALE;
                (
                    ElementKind::FixedPoint(true),
                    pools.fixed_point.take(),
                    None,
                )
            }
            END_STATIC_FLOO => {
                y -= Y_STEP * CEIL_FLOOR_SCALE;
                (
                    ElementKind::FixedPoint(false),
                    pools.fixed_point.take(),
                    None,
                )
            }
            END_DYNAMIC_LOAD => {
                y = adjacent.position[1] - OBJ_POS_SCALE * Y_STEP;
                let shape = random_shape(rng);
                (ElementKind::Load, pools.load(shape), Some(shape))
            }
            END_DYNAMIC_PULY => {
                y = adjacent.position[1] - OBJ_POS_SCALE * Y_STEP;
                (ElementKind::TiedToPulley, 0, None)
            }
            _ => return Err(Rejection::Malformed),
        };
        let element = Element {
            kind,
            code,
            name: String::new(),
            position: [x, y],
            grid: None,
            in_states: None,
            solid: false,
            row: adjacent.row,
            color,
            load_shape,
            load_color: None,
            hanging: None,
            target: division.target,
        };
        if at_start {
            ropes[rope].insert(0, element);
        } else {
            ropes[rope].push(element);
        }
    }
    Ok(())
}

/// At most two dynamic nodes per cable: surplus ones become static pulleys or fixed points.
/// Returns, per rope, the path indices that stay dynamic.
pub(super) fn limit_dynamic_nodes(
    ropes: &mut [Vec<Element>],
    rng: &mut ChaCha8Rng,
    pools: &mut Pools,
) -> Vec<Vec<usize>> {
    let mut dynamic_indices: Vec<Vec<usize>> = Vec::new();
    for path in ropes {
        let last = path.len() - 1;
        let mut nodes: Vec<usize> = (1..last).filter(|&i| path[i].code < STATICS).collect();
        for end in [0, last] {
            if matches!(path[end].code, END_DYNAMIC_LOAD | END_DYNAMIC_PULY) {
                nodes.push(end);
            }
        }
        let mut attempts = 0;
        while nodes.len() > MAX_DYNAMIC_NODES_PER_CABLE && attempts < 50 {
            attempts += 1;
            let pick = rng.random_range(0..nodes.len());
            let index = nodes[pick];
            if path[index].code == END_DYNAMIC_PULY {
                continue;
            }
            let element = &mut path[index];
            if index == 0 || index == last {
                let floor = element.row / 2 == 0;
                element.code = if floor {
                    END_STATIC_FLOO
                } else {
                    END_STATIC_CEIL
                };
                element.kind = ElementKind::FixedPoint(!floor);
                element.position[1] += OBJ_POS_SCALE * Y_STEP
                    + if element.row % 2 == 0 { -1.0 } else { 1.0 } * 0.5 * Y_STEP
                    + if floor { -1.0 } else { 1.0 } * CEIL_FLOOR_SCALE * Y_STEP;
                element.color = pools.fixed_point.take();
                element.load_shape = None;
            } else {
                element.code = STATICS;
                element.kind = ElementKind::StaticPulley;
                element.color = pools.static_pulley(element.solid);
                // The release keeps the stale load keys in metaSampling; the load is gone.
            }
            nodes.remove(pick);
        }
        dynamic_indices.push(nodes);
    }
    dynamic_indices
}

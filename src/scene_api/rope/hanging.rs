//! Connection ropes the detector missed: the short rope a load hangs on under a movable pulley.
//!
//! In the release a movable pulley that holds no other rope's end and hangs from no cable
//! carries a load on a connection rope from its axle, the load's centre
//! [`CONNECTION_DROP`] units straight below the axle. Between the pulley's rim and the load's
//! top less than two units of that rope show, a few pixels in the frame the detector sees, and it
//! is the rope the detector misses most. Where the pixels show a movable pulley that no read
//! rope ends at, and a load on no read rope hanging under it, that rope is there: it is added
//! from the pulley to the load. Anything else (a load off to the side, two loads under one
//! pulley, a pulley that some read rope ends at) is left as read.
//!
//! Input: the scene's nodes and the paths read from the pixels. Output: the connection ropes to
//! add, as paths.

use super::topology::{Node, NodeKind, RopePath};
use crate::dataset::rope::world::CONNECTION_DROP;

/// How far the load's centre may be from [`CONNECTION_DROP`] below the axle, across and along
/// the rope, units: the centres are mask centroids lifted onto the scene plane (a few tenths of
/// a unit off), and the pulley may have moved a little before the first frame.
const DROP_TOLERANCE: [f64; 2] = [0.8, 1.5];

/// The connection ropes to add: per movable pulley that no path of `paths` ends at, the one
/// load on no path whose centre lies within [`DROP_TOLERANCE`] of [`CONNECTION_DROP`] below
/// it (none when two loads do), as a path from the pulley to the load.
pub(super) fn missed_connections(nodes: &[Node], paths: &[&RopePath]) -> Vec<RopePath> {
    let ends_at = |node: usize| {
        paths
            .iter()
            .any(|path| path.nodes.first() == Some(&node) || path.nodes.last() == Some(&node))
    };
    let on_a_path = |node: usize| paths.iter().any(|path| path.nodes.contains(&node));
    let mut added: Vec<RopePath> = Vec::new();
    for (pulley, node) in nodes.iter().enumerate() {
        if !matches!(node.kind, NodeKind::MovablePulley { .. }) || ends_at(pulley) {
            continue;
        }
        let hanging: Vec<usize> = nodes
            .iter()
            .enumerate()
            .filter(|(load, candidate)| {
                candidate.kind == NodeKind::Load
                    && !on_a_path(*load)
                    && !added.iter().any(|path| path.nodes.contains(load))
                    && (candidate.centre[0] - node.centre[0]).abs() <= DROP_TOLERANCE[0]
                    && (node.centre[1] - CONNECTION_DROP - candidate.centre[1]).abs()
                        <= DROP_TOLERANCE[1]
            })
            .map(|(load, _)| load)
            .collect();
        if let [load] = hanging[..] {
            added.push(RopePath {
                nodes: vec![pulley, load],
                turns: vec![None, None],
                covered: 0,
                missed: 0,
                on_mask: 0,
            });
        }
    }
    added
}

#[cfg(test)]
mod tests {
    use super::*;

    fn node(kind: NodeKind, x: f64, y: f64) -> Node {
        Node {
            kind,
            centre: [x, y],
        }
    }

    fn path(nodes: Vec<usize>) -> RopePath {
        let turns = vec![None; nodes.len()];
        RopePath {
            nodes,
            turns,
            covered: 1,
            missed: 0,
            on_mask: 1,
        }
    }

    #[test]
    fn a_load_under_a_movable_pulley_no_rope_ends_at_hangs_from_it() {
        let movable = NodeKind::MovablePulley { solid: false };
        let nodes = [
            node(NodeKind::StaticPulley { solid: true }, 0.0, 10.0),
            node(movable, 4.0, 5.0),
            node(NodeKind::Load, 4.2, 1.1),
            node(NodeKind::Anchor, 8.0, 12.0),
            node(NodeKind::Load, -3.0, 2.0),
        ];
        // The main rope: load 4 over the static pulley, under the movable one, to the anchor.
        let main = path(vec![4, 0, 1, 3]);
        let added = missed_connections(&nodes, &[&main]);
        assert_eq!(added.len(), 1);
        assert_eq!(added[0].nodes, vec![1, 2]);
        assert_eq!(added[0].turns, vec![None, None]);
        // Read already: nothing to add.
        let connection = path(vec![1, 2]);
        assert!(missed_connections(&nodes, &[&main, &connection]).is_empty());
        // A rope ends at the pulley (it holds another rope's end): nothing to add.
        let held = path(vec![1, 4]);
        assert!(missed_connections(&nodes, &[&path(vec![0, 3]), &held]).is_empty());
    }

    #[test]
    fn a_load_off_to_the_side_or_two_candidates_add_nothing() {
        let movable = NodeKind::MovablePulley { solid: true };
        let main = path(vec![0, 1, 3]);
        let aside = [
            node(NodeKind::StaticPulley { solid: true }, 0.0, 10.0),
            node(movable, 4.0, 5.0),
            node(NodeKind::Load, 5.5, 1.0),
            node(NodeKind::Anchor, 8.0, 12.0),
        ];
        assert!(missed_connections(&aside, &[&main]).is_empty());
        let too_low = [
            aside[0],
            aside[1],
            node(NodeKind::Load, 4.0, -1.0),
            aside[3],
        ];
        assert!(missed_connections(&too_low, &[&main]).is_empty());
        let two = [
            aside[0],
            aside[1],
            node(NodeKind::Load, 4.0, 1.0),
            aside[3],
            node(NodeKind::Load, 4.3, 0.5),
        ];
        assert!(missed_connections(&two, &[&main]).is_empty());
    }
}

//! The groups of bodies the ropes couple (a union–find over the ropes' bodies).

use super::super::{Mount, Network, Point};

/// The groups of bodies coupled by ropes (a rope couples the bodies tied to it and the bodies
/// carrying the pulleys it passes), each sorted, in order of their first body; and per body the
/// ropes it is on.
pub(super) fn coupled_groups(network: &Network) -> (Vec<Vec<usize>>, Vec<Vec<usize>>) {
    let count = network.bodies.len();
    let mut parent: Vec<usize> = (0..count).collect();
    let mut ropes_of = vec![Vec::new(); count];
    for (rope_index, rope) in network.ropes.iter().enumerate() {
        let bodies: Vec<usize> = rope
            .path
            .iter()
            .filter_map(|point| match *point {
                Point::Body(body) => Some(body),
                Point::Pulley(pulley) => match network.pulleys.get(pulley)?.mount {
                    Mount::Body(body) => Some(body),
                    Mount::Fixed(_) => None,
                },
                Point::Fixed(_) => None,
            })
            .filter(|&body| body < count)
            .collect();
        for &body in &bodies {
            if !ropes_of[body].contains(&rope_index) {
                ropes_of[body].push(rope_index);
            }
        }
        for pair in bodies.windows(2) {
            let (a, b) = (root(&mut parent, pair[0]), root(&mut parent, pair[1]));
            parent[a.max(b)] = a.min(b);
        }
    }
    let mut groups: Vec<Vec<usize>> = Vec::new();
    let mut group_of_root: Vec<Option<usize>> = vec![None; count];
    for body in 0..count {
        let r = root(&mut parent, body);
        if let Some(index) = group_of_root[r] {
            groups[index].push(body);
        } else {
            group_of_root[r] = Some(groups.len());
            groups.push(vec![body]);
        }
    }
    (groups, ropes_of)
}

/// The representative of `at`'s set in a union–find forest (halving the path on the way).
fn root(parent: &mut [usize], mut at: usize) -> usize {
    while parent[at] != at {
        parent[at] = parent[parent[at]];
        at = parent[at];
    }
    at
}

//! The release's labelling of a fluid run (`trackingData`, `docs/data/fluid.md`), as pure
//! functions: which colliders each fluid's particles touched ([`emitter_stick_stat`]), which
//! fluids end in which container ([`receptor_fluid_stat`]), the density order the containers
//! reveal ([`density_relations`]), the sticks a factual run re-simulates without
//! ([`counterfactual_sticks`]), and the regular sticks fluids pass
//! ([`temperature_askable_sticks`]).
//!
//! One labelling for every user: the generator labels its truth with it (`synth`), and a
//! simulating backend can label its predictions with it, so the two can only differ in the motion
//! they label. The rules follow the release's generator (`HeatTransport.Summary`); where this
//! module chooses an order the release left to its containers, the doc says so.
//!
//! Inputs are plain: collider names per particle, particle positions as `[x, y]` world points,
//! axis-aligned boxes ([`Rect`]). Outputs are the maps `outputs.json` stores, in file order.

use std::collections::BTreeSet;

use indexmap::IndexMap;
use rand::Rng;

use super::names::{base_fluid_name, emitter_name};
use super::world::{
    CONTACT_MIN_PARTICLES, COUNTERFACTUAL_MAX_REMOVED_STICKS, COUNTERFACTUAL_MIN_PASS_PARTICLES,
    NORMAL_TEMPERATURE, RECEPTOR_MIN_PARTICLES,
};

/// Per fluid, per collider: particles (`perEmitterStickStat`); or per container, per fluid
/// (`perReceptorFluidStat`).
pub type ParticleCounts = IndexMap<String, IndexMap<String, u32>>;

/// An axis-aligned box in the world's x/y plane, units.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Rect {
    /// Lower-left corner `[x, y]`.
    pub min: [f64; 2],
    /// Upper-right corner `[x, y]`.
    pub max: [f64; 2],
}

impl Rect {
    /// The box of this centre and size (`[width, height]`).
    pub fn from_centre_size(centre: [f64; 2], size: [f64; 2]) -> Rect {
        Rect {
            min: [centre[0] - size[0] / 2.0, centre[1] - size[1] / 2.0],
            max: [centre[0] + size[0] / 2.0, centre[1] + size[1] / 2.0],
        }
    }

    /// The smallest box holding every point; `None` for no points.
    pub fn bounding(points: &[[f64; 2]]) -> Option<Rect> {
        let (first, rest) = points.split_first()?;
        let mut rect = Rect {
            min: *first,
            max: *first,
        };
        for point in rest {
            for (axis, &coordinate) in point.iter().enumerate() {
                rect.min[axis] = rect.min[axis].min(coordinate);
                rect.max[axis] = rect.max[axis].max(coordinate);
            }
        }
        Some(rect)
    }

    /// Whether `point` lies strictly inside (the release compares with `>` and `<`, so a particle
    /// on the boundary is outside).
    pub fn contains(&self, point: [f64; 2]) -> bool {
        point[0] > self.min[0]
            && point[0] < self.max[0]
            && point[1] > self.min[1]
            && point[1] < self.max[1]
    }
}

/// A container as the counting sees it: its cup and the bounding box of its funnel's two guided
/// sticks, in world coordinates.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Receptor<'a> {
    /// The container's name (`Red Container`).
    pub name: &'a str,
    /// The cup: centre `cupPosition + (O_x, O_y)`, size `cupScale` (x, y).
    pub cup: Rect,
    /// The funnel: the bounding box of both guided sticks' end points, shifted by `(O_x, O_y)`.
    pub funnel: Rect,
}

/// The release's test for a regular stick among collider names: the name contains `Stick` and
/// not `Guided` (so a container's funnel sticks are not regular).
pub fn is_regular_stick(collider: &str) -> bool {
    collider.contains("Stick") && !collider.contains("Guided")
}

/// `perEmitterStickStat[fluid]`: for each collider, how many of the fluid's particles touched
/// it (each particle counted once per collider), from each particle's collider path, already
/// cut at its first invalid step.
///
/// Kept: colliders touched by more than [`CONTACT_MIN_PARTICLES`] particles. Emitter parts (any
/// collider whose name contains `Emitter`) are folded into one entry `<fluid> Emitter` holding
/// the largest of their counts, kept whatever its size. As in the release, this folds another
/// fluid's emitter parts into the fluid's own entry too. Order: colliders in the order
/// particles first touched them (particles in the given order, each path in order), which is
/// the release's insertion order.
pub fn emitter_stick_stat<P, S>(fluid: &str, particle_paths: &[P]) -> IndexMap<String, u32>
where
    P: AsRef<[S]>,
    S: AsRef<str>,
{
    let own_emitter = emitter_name(fluid);
    let mut stat: IndexMap<String, u32> = IndexMap::new();
    for (collider, count) in contact_counts(particle_paths) {
        if collider.contains("Emitter") {
            let entry = stat.entry(own_emitter.clone()).or_insert(count);
            *entry = (*entry).max(count);
        } else if count > CONTACT_MIN_PARTICLES {
            stat.insert(collider, count);
        }
    }
    stat
}

/// Per collider, the particles whose path contains it, in first-touch order.
fn contact_counts<P, S>(particle_paths: &[P]) -> IndexMap<String, u32>
where
    P: AsRef<[S]>,
    S: AsRef<str>,
{
    let mut counts: IndexMap<String, u32> = IndexMap::new();
    for path in particle_paths {
        let mut seen: BTreeSet<&str> = BTreeSet::new();
        for collider in path.as_ref() {
            let collider = collider.as_ref();
            if seen.insert(collider) {
                let count = counts.entry(collider.to_string()).or_insert(0);
                *count = count.saturating_add(1);
            }
        }
    }
    counts
}

/// `temperatureAskableStick`: the regular sticks some fluid's entry of `stick_stat`
/// (`perEmitterStickStat`, already cut at [`CONTACT_MIN_PARTICLES`]) lists, each with its
/// temperature from `temperature_stick` (`temperatureStick`; [`NORMAL_TEMPERATURE`] when absent),
/// in first-listed order.
pub fn temperature_askable_sticks(
    stick_stat: &ParticleCounts,
    temperature_stick: &IndexMap<String, String>,
) -> IndexMap<String, String> {
    let mut askable = IndexMap::new();
    for collider in stick_stat.values().flat_map(IndexMap::keys) {
        if is_regular_stick(collider) && !askable.contains_key(collider) {
            let temperature = temperature_stick
                .get(collider)
                .cloned()
                .unwrap_or_else(|| NORMAL_TEMPERATURE.to_string());
            askable.insert(collider.clone(), temperature);
        }
    }
    askable
}

/// `perReceptorFluidStat`: for each container, how many particles of each fluid end strictly
/// inside its cup or its funnel box (a particle inside two containers' boxes counts in both, as
/// in the release), given each fluid's final particle positions.
///
/// Kept: fluids with more than [`RECEPTOR_MIN_PARTICLES`] particles; a container any particle
/// reached stays listed even when none of its fluids passes the cut (the release writes `{}`
/// then). Order: containers and fluids in the order their first particle was found, fluids and
/// particles taken in the given order (the release walks particles in solver order, which is
/// emitter order).
pub fn receptor_fluid_stat(
    receptors: &[Receptor<'_>],
    fluids: &[(&str, &[[f64; 2]])],
) -> ParticleCounts {
    let mut raw = ParticleCounts::new();
    for &(fluid, positions) in fluids {
        for &position in positions {
            for receptor in receptors {
                if receptor.cup.contains(position) || receptor.funnel.contains(position) {
                    let count = raw
                        .entry(receptor.name.to_string())
                        .or_default()
                        .entry(fluid.to_string())
                        .or_insert(0);
                    *count = count.saturating_add(1);
                }
            }
        }
    }
    raw.into_iter()
        .map(|(container, counts)| {
            let kept = counts
                .into_iter()
                .filter(|(_, count)| *count > RECEPTOR_MIN_PARTICLES)
                .collect();
            (container, kept)
        })
        .collect()
}

/// `allDensityRelations` as `(heavier, lighter)` pairs: every two fluids listed together in some
/// container of `receptor_stat` (`perReceptorFluidStat`), heavier first, then the transitive
/// closure ([`transitive_closure`]).
///
/// `densities` gives each fluid's density; a name not in it is looked up without the
/// `Later Emitted ` prefix, so passing the base fluids is enough. Pairs of equal density (a fluid
/// and its own predictive emitter) or of unknown density give no relation. (The release added
/// such a pair in both directions, which its closure then turned into self-relations such as
/// `(Blue Fluid, Blue Fluid)`; the annotation reader drops those.) Order: containers, then
/// ordered pairs of their fluids, in map order; closure additions after.
pub fn density_relations(
    receptor_stat: &ParticleCounts,
    densities: &[(&str, f64)],
) -> Vec<(String, String)> {
    let density = |fluid: &str| {
        let base = base_fluid_name(fluid);
        densities
            .iter()
            .find(|(name, _)| *name == fluid)
            .or_else(|| densities.iter().find(|(name, _)| *name == base))
            .map(|(_, density)| *density)
    };
    let mut direct = Vec::new();
    for fluids in receptor_stat.values() {
        for first in fluids.keys() {
            for second in fluids.keys() {
                let (Some(first_density), Some(second_density)) = (density(first), density(second))
                else {
                    continue;
                };
                if first_density > second_density {
                    direct.push((first.clone(), second.clone()));
                }
            }
        }
    }
    transitive_closure(&direct)
}

/// How two fluids' densities compare in a run's recorded relations.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DensityOrder {
    /// The first is denser.
    Heavier,
    /// The first is lighter.
    Lighter,
    /// No recorded relation (after closure) links them: the video cannot compare them.
    Unknown,
    /// Relations in both directions: only corrupt data gives these.
    Contradictory,
}

/// The recorded `(heavier, lighter)` relations closed transitively ([`transitive_closure`]), for
/// comparing fluids: what the question engine asks from and the scene backend answers from.
#[derive(Debug, Clone, Default, PartialEq, Eq)]
pub struct DensityOrdering {
    heavier_than: BTreeSet<(String, String)>,
}

impl DensityOrdering {
    /// The closure of `relations`.
    pub fn new(relations: &[(String, String)]) -> DensityOrdering {
        DensityOrdering {
            heavier_than: transitive_closure(relations).into_iter().collect(),
        }
    }

    /// How `first`'s density compares with `second`'s (the relations' names).
    pub fn order(&self, first: &str, second: &str) -> DensityOrder {
        let pair = |a: &str, b: &str| self.heavier_than.contains(&(a.to_string(), b.to_string()));
        match (pair(first, second), pair(second, first)) {
            (true, false) => DensityOrder::Heavier,
            (false, true) => DensityOrder::Lighter,
            (false, false) => DensityOrder::Unknown,
            (true, true) => DensityOrder::Contradictory,
        }
    }
}

/// The relations with duplicates removed (first occurrence kept), then closed transitively as
/// the release does: repeatedly, for every pair of relations `(a, b)`, `(b, c)` in list order
/// (the list growing as it goes), add `(a, c)` if absent, until a pass adds nothing.
pub fn transitive_closure(relations: &[(String, String)]) -> Vec<(String, String)> {
    let mut known: BTreeSet<(String, String)> = BTreeSet::new();
    let mut closed: Vec<(String, String)> = relations
        .iter()
        .filter(|relation| known.insert((*relation).clone()))
        .cloned()
        .collect();
    loop {
        let mut added = false;
        let mut first = 0;
        while first < closed.len() {
            let mut second = 0;
            while second < closed.len() {
                if closed[first].1 == closed[second].0 {
                    let implied = (closed[first].0.clone(), closed[second].1.clone());
                    if known.insert(implied.clone()) {
                        closed.push(implied);
                        added = true;
                    }
                }
                second += 1;
            }
            first += 1;
        }
        if !added {
            return closed;
        }
    }
}

/// The sticks a factual run gets counterfactual runs without (`removedStickName`s, in run
/// order).
///
/// For each fluid of `stick_stat` (`perEmitterStickStat`, raw or cut at
/// [`CONTACT_MIN_PARTICLES`]: the choice is the same), its two most touched regular sticks
/// ([`is_regular_stick`]; ties keep the first listed as the most touched), each kept when more
/// than [`COUNTERFACTUAL_MIN_PASS_PARTICLES`] particles touched it; the second is added before
/// the first, and a stick already chosen is not added again. When nothing is chosen, the first
/// of `scene_sticks` (the run's regular sticks in `metaSamplingData.sticks` order) is used, as
/// the release does. When more than [`COUNTERFACTUAL_MAX_REMOVED_STICKS`] are chosen, the list
/// is shuffled (a forward Fisher–Yates, `j` drawn from `i..n`) and cut to that many.
pub fn counterfactual_sticks<S: AsRef<str>>(
    stick_stat: &ParticleCounts,
    scene_sticks: &[S],
    rng: &mut impl Rng,
) -> Vec<String> {
    let mut chosen: Vec<String> = Vec::new();
    for colliders in stick_stat.values() {
        let mut most: Option<(&str, u32)> = None;
        let mut second: Option<(&str, u32)> = None;
        for (collider, &count) in colliders {
            if !is_regular_stick(collider) {
                continue;
            }
            if most.is_none_or(|(_, most_count)| count > most_count) {
                second = most;
                most = Some((collider, count));
            } else if second.is_none_or(|(_, second_count)| count > second_count) {
                second = Some((collider, count));
            }
        }
        for (stick, count) in [second, most].into_iter().flatten() {
            if count > COUNTERFACTUAL_MIN_PASS_PARTICLES && !chosen.iter().any(|c| c == stick) {
                chosen.push(stick.to_string());
            }
        }
    }
    if chosen.is_empty() {
        chosen.extend(scene_sticks.first().map(|stick| stick.as_ref().to_string()));
    }
    if chosen.len() > COUNTERFACTUAL_MAX_REMOVED_STICKS {
        for index in 0..chosen.len() {
            let other = rng.random_range(index..chosen.len());
            chosen.swap(index, other);
        }
        chosen.truncate(COUNTERFACTUAL_MAX_REMOVED_STICKS);
    }
    chosen
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::util::seeded_rng;

    fn counts(entries: &[(&str, &[(&str, u32)])]) -> ParticleCounts {
        entries
            .iter()
            .map(|(outer, inner)| {
                (
                    (*outer).to_string(),
                    inner.iter().map(|(k, v)| ((*k).to_string(), *v)).collect(),
                )
            })
            .collect()
    }

    fn repeat(path: &[&'static str], times: usize) -> Vec<Vec<&'static str>> {
        vec![path.to_vec(); times]
    }

    #[test]
    fn stick_stat_counts_particles_once_per_collider_and_cuts_at_twenty() {
        let mut paths = Vec::new();
        // 25 particles: emitter wall, the brown stick twice (counted once), then the floor.
        paths.extend(repeat(
            &[
                "Blue Fluid Emitter Left Wall",
                "Brown Stick",
                "Brown Stick",
                "Red Container Bottom Floor",
            ],
            25,
        ));
        // 21 particles: the other emitter wall, the cyan stick, the brown stick.
        paths.extend(repeat(
            &["Blue Fluid Emitter Right Wall", "Cyan Stick", "Brown Stick"],
            21,
        ));
        // 20 particles touch the gray stick: not more than 20, dropped.
        paths.extend(repeat(&["Gray Stick"], 20));
        // 3 particles touch another fluid's emitter: folded into the own emitter entry.
        paths.extend(repeat(&["Pink Fluid Emitter"], 3));
        let stat = emitter_stick_stat("Blue Fluid", &paths);
        let expected: Vec<(&str, u32)> = vec![
            ("Blue Fluid Emitter", 25),
            ("Brown Stick", 46),
            ("Red Container Bottom Floor", 25),
            ("Cyan Stick", 21),
        ];
        assert_eq!(
            stat.iter()
                .map(|(k, v)| (k.as_str(), *v))
                .collect::<Vec<_>>(),
            expected
        );
        // The emitter entry is kept below the cut.
        let few = emitter_stick_stat(
            "Later Emitted Blue Fluid",
            &repeat(&["Later Emitted Blue Fluid Emitter"], 4),
        );
        assert_eq!(few.get("Later Emitted Blue Fluid Emitter"), Some(&4));
        let none: &[Vec<String>] = &[];
        assert!(emitter_stick_stat("Blue Fluid", none).is_empty());
    }

    #[test]
    fn askable_sticks_are_the_regular_sticks_listed() {
        let stat = counts(&[
            (
                "Blue Fluid",
                &[
                    ("Blue Fluid Emitter", 1500),
                    ("Cyan Stick", 300),
                    ("Red Container Left Guided Stick", 90),
                    ("Floor", 40),
                ],
            ),
            ("Pink Fluid", &[("Brown Stick", 30), ("Cyan Stick", 25)]),
        ]);
        let temperatures: IndexMap<String, String> =
            [("Brown Stick".to_string(), "Boiling".to_string())].into();
        let askable = temperature_askable_sticks(&stat, &temperatures);
        assert_eq!(
            askable
                .iter()
                .map(|(k, v)| (k.as_str(), v.as_str()))
                .collect::<Vec<_>>(),
            vec![("Cyan Stick", "Normal"), ("Brown Stick", "Boiling")]
        );
    }

    #[test]
    fn receptor_stat_counts_final_positions_in_cup_or_funnel() {
        // Red: cup x 0..1, y 0..1; funnel x -0.5..1.7, y 1..2. Green: cup x 2..3, y 0..1;
        // funnel x 1.5..3.5, y 1..2.
        let red = Receptor {
            name: "Red Container",
            cup: Rect::from_centre_size([0.5, 0.5], [1.0, 1.0]),
            funnel: Rect::bounding(&[[-0.5, 2.0], [0.2, 1.0], [1.7, 2.0], [0.8, 1.0]]).unwrap(),
        };
        let green = Receptor {
            name: "Green Container",
            cup: Rect::from_centre_size([2.5, 0.5], [1.0, 1.0]),
            funnel: Rect::bounding(&[[1.5, 2.0], [3.5, 1.0]]).unwrap(),
        };
        let mut blue = vec![[0.5, 0.5]; 30]; // 30 in the red cup
        blue.extend(vec![[1.0, 1.5]; 10]); // 10 in the red funnel: 40 in red
        blue.extend(vec![[2.5, 0.5]; 21]); // 21 in the green cup
        blue.extend(vec![[1.0, 0.5]; 50]); // on the red cup's edge: outside
        blue.extend(vec![[9.0, 9.0]; 50]); // nowhere
        let pink = vec![[2.2, 0.9]; 20]; // 20 in the green cup: cut
        let yellow = vec![[1.6, 1.5]; 25]; // inside both funnels: counted in both
        let stat = receptor_fluid_stat(
            &[red, green],
            &[
                ("Blue Fluid", &blue),
                ("Pink Fluid", &pink),
                ("Yellow Fluid", &yellow),
            ],
        );
        assert_eq!(
            stat,
            counts(&[
                ("Red Container", &[("Blue Fluid", 40), ("Yellow Fluid", 25)]),
                (
                    "Green Container",
                    &[("Blue Fluid", 21), ("Yellow Fluid", 25)]
                ),
            ])
        );
        // A container only reached by too few particles stays listed, empty.
        let only_pink = receptor_fluid_stat(&[red, green], &[("Pink Fluid", &pink)]);
        assert_eq!(only_pink, counts(&[("Green Container", &[])]));
    }

    #[test]
    fn density_relations_pair_fluids_sharing_a_container_and_close_them() {
        let stat = counts(&[
            (
                "Red Container",
                &[("Pink Fluid", 900), ("Yellow Fluid", 800)],
            ),
            (
                "Green Container",
                &[
                    ("Light Blue Fluid", 1000),
                    ("Later Emitted Yellow Fluid", 200),
                    ("Yellow Fluid", 50),
                ],
            ),
            ("Gray Container", &[]),
        ]);
        let densities = [
            ("Pink Fluid", 4400.0),
            ("Light Blue Fluid", 1600.0),
            ("Yellow Fluid", 3000.0),
        ];
        let relations = density_relations(&stat, &densities);
        let pair = |a: &str, b: &str| (a.to_string(), b.to_string());
        assert_eq!(
            relations,
            vec![
                pair("Pink Fluid", "Yellow Fluid"),
                pair("Later Emitted Yellow Fluid", "Light Blue Fluid"),
                pair("Yellow Fluid", "Light Blue Fluid"),
                // Closure: pink > yellow > light blue.
                pair("Pink Fluid", "Light Blue Fluid"),
            ]
        );
    }

    #[test]
    fn closure_deduplicates_and_follows_chains() {
        let pair = |a: &str, b: &str| (a.to_string(), b.to_string());
        let relations = [
            pair("C", "D"),
            pair("A", "B"),
            pair("B", "C"),
            pair("A", "B"),
        ];
        assert_eq!(
            transitive_closure(&relations),
            vec![
                pair("C", "D"),
                pair("A", "B"),
                pair("B", "C"),
                pair("A", "C"),
                pair("B", "D"),
                pair("A", "D"),
            ]
        );
        assert!(transitive_closure(&[]).is_empty());
    }

    #[test]
    fn counterfactual_sticks_take_each_fluids_two_most_touched_regular_sticks() {
        let stat = counts(&[
            (
                "Pink Fluid",
                &[
                    ("Pink Fluid Emitter", 1500),
                    ("Brown Stick", 900),
                    ("Red Container Left Guided Stick", 1200),
                    ("Cyan Stick", 350),
                    ("Gray Stick", 200),
                ],
            ),
            // Gray over the cut, nothing second: only gray.
            ("Light Blue Fluid", &[("Gray Stick", 1100), ("Floor", 400)]),
            // A tie: the first listed is the most touched; both already chosen.
            ("Yellow Fluid", &[("Cyan Stick", 640), ("Brown Stick", 640)]),
            // Second at exactly 100: not more than 100.
            (
                "Later Emitted Yellow Fluid",
                &[("White Stick", 230), ("Black Stick", 100)],
            ),
        ]);
        let mut rng = seeded_rng(0);
        let chosen = counterfactual_sticks(&stat, &["Brown Stick"], &mut rng);
        assert_eq!(
            chosen,
            vec!["Cyan Stick", "Brown Stick", "Gray Stick", "White Stick"]
        );
    }

    #[test]
    fn counterfactual_sticks_fall_back_to_the_first_stick_and_cap_at_six() {
        let few = counts(&[("Pink Fluid", &[("Brown Stick", 100), ("Cyan Stick", 60)])]);
        let mut rng = seeded_rng(1);
        assert_eq!(
            counterfactual_sticks(&few, &["Gray Stick", "Brown Stick"], &mut rng),
            vec!["Gray Stick"]
        );
        let empty: [&str; 0] = [];
        assert!(counterfactual_sticks(&few, &empty, &mut rng).is_empty());

        let colours = [
            "Red", "Orange", "Yellow", "Green", "Cyan", "Blue", "Purple", "Pink",
        ];
        let sticks: Vec<String> = colours.iter().map(|c| format!("{c} Stick")).collect();
        let many: ParticleCounts = sticks
            .chunks(2)
            .enumerate()
            .map(|(fluid, pair)| {
                let inner = pair.iter().map(|s| (s.clone(), 500)).collect();
                (format!("Fluid {fluid}"), inner)
            })
            .collect();
        let mut seen_orders = BTreeSet::new();
        for seed in 0..40 {
            let chosen = counterfactual_sticks(&many, &sticks, &mut seeded_rng(seed));
            assert_eq!(chosen.len(), 6);
            let distinct: BTreeSet<&String> = chosen.iter().collect();
            assert_eq!(distinct.len(), 6);
            assert!(chosen.iter().all(|c| sticks.contains(c)));
            seen_orders.insert(chosen);
        }
        assert!(
            seen_orders.len() > 10,
            "the cut is random: {}",
            seen_orders.len()
        );
        // The same seed gives the same choice.
        assert_eq!(
            counterfactual_sticks(&many, &sticks, &mut seeded_rng(7)),
            counterfactual_sticks(&many, &sticks, &mut seeded_rng(7))
        );
    }

    #[test]
    fn regular_sticks_exclude_guided_sticks() {
        let cases = [
            ("Brown Stick", true),
            ("Red Container Left Guided Stick", false),
            ("Red Container Bottom Floor", false),
            ("Blue Fluid Emitter", false),
        ];
        for (name, expected) in cases {
            assert_eq!(is_regular_stick(name), expected, "{name}");
        }
    }
}

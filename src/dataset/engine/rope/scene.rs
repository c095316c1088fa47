//! The engine's view of one rope video: its object list and the relations between loads, ported
//! from the public engine's `read_file.read_annotation_pulley` (`docs/data/rope.md`, scene
//! reading).
//!
//! Input: a validated [`RopeAnnotation`]. Output: a [`RopeScene`] holding
//!
//! * the [`EngineObject`] list in the public engine's order: loads (`outputMass` order), then
//!   ropes (`relatedGroupsInRope` keys), then pulleys and fixed points (first appearance in the
//!   `relatedGroupsInRope` element lists);
//! * which loads are related (same `relatedGroups` group), which hang under a movable pulley,
//!   and which rope each load hangs on;
//! * the phrase each object is called by in question text (`docs/data/rope.md`, reference phrases).
//!
//! Decisions that differ from the public engine, each also marked where it is made:
//!
//! * **No de-duplication** (`docs/data/rope.md`, quirks of the public engine). The public
//!   `add_object` dropped an object whose colour, shape, dynamics, class, mass and tension equalled
//!   an existing one, so two same-colour same-size static pulleys counted once. Here every distinct
//!   annotation name is one object.
//! * **Unambiguous references only.** An object whose lower-case name without grid suffix is
//!   shared with another object cannot be told apart in question text; it is still counted, but
//!   no question or option refers to it (the public engine emitted duplicate or conflicting
//!   options for such objects).
//! * **Full colour words in references.** For the light palette colours the public engine
//!   called a `Light Blue Cube` "blue cube" (contradicting its own exact-colour count) and stopped
//!   on `Light Coral` (no palette word). References here use the object's whole colour.

use std::collections::BTreeSet;

use indexmap::IndexMap;

use super::RopeEngineError as EngineError;
use crate::dataset::rope::{
    RopeAnnotation, RopeObjectKind, RopeObjectName, parse_rope_object_name,
};

/// Tolerance of every mass comparison, kg (the public engine's `EPS`).
pub(super) const MASS_EPSILON: f64 = 1e-5;

/// One object of the engine's state, as the public engine's `ObjectPulley` holds it.
#[derive(Debug, Clone, PartialEq)]
pub struct EngineObject {
    /// The annotation name as written (`Blue Solid Static Pulley (0 1)`); identifies the object.
    pub annotation_name: String,
    /// The public engine's object key: the lower-case name without the grid suffix
    /// (`blue solid static pulley`).
    pub name_key: String,
    /// The colour words, lower case (`purple`, `light blue`).
    pub color: String,
    /// The shape word(s) used by the shape and existence families: `cube`, `sphere`,
    /// `solid pulley`, `hollow pulley`, `rope` or `fixed point`.
    pub shape: String,
    /// The object kind.
    pub kind: RopeObjectKind,
    /// `dynamic` (loads, ropes, movable pulleys) or `static` (static pulleys, fixed points).
    pub dynamics: String,
    /// Loads only: the nominal mass `ceil(m·100)/100` of `outputMass`, kg. Loads under a movable
    /// pulley carry the generator's ×1.975 factor, so they read 0.3, 0.4 or 0.5.
    pub nominal_mass_kg: Option<f64>,
    /// Ropes only: `|first ResultTension value|`, N. Measured under the equal-mass baseline and
    /// never used by any question (`docs/data/rope.md`, quirks of the release's data); kept to
    /// mirror the public engine's state.
    pub rope_tension_newtons: Option<f64>,
}

impl EngineObject {
    /// The public engine's `class_type`: `object` (a load), `rope`, `pulley` or `fixed point`.
    pub fn class_type(&self) -> &'static str {
        match self.kind {
            RopeObjectKind::Cube | RopeObjectKind::Sphere => "object",
            RopeObjectKind::Rope => "rope",
            RopeObjectKind::Pulley => "pulley",
            RopeObjectKind::FixedPoint => "fixed point",
        }
    }

    fn from_name(parsed: &RopeObjectName) -> EngineObject {
        let shape = match (&parsed.kind, &parsed.pulley_shape) {
            (RopeObjectKind::Pulley, Some(pulley_shape)) => format!("{pulley_shape} pulley"),
            (kind, _) => kind.word().to_string(),
        };
        EngineObject {
            annotation_name: parsed.full.clone(),
            name_key: parsed.base_name(),
            color: parsed.color.clone(),
            shape,
            kind: parsed.kind,
            dynamics: parsed.dynamics.clone(),
            nominal_mass_kg: None,
            rope_tension_newtons: None,
        }
    }
}

/// The engine's state for one video.
#[derive(Debug, Clone)]
pub struct RopeScene {
    objects: Vec<EngineObject>,
    index_by_name: IndexMap<String, usize>,
    related_loads: BTreeSet<(usize, usize)>,
    movable_pulley_loads: BTreeSet<usize>,
    load_ropes: IndexMap<usize, usize>,
    references: Vec<Option<String>>,
}

impl RopeScene {
    /// Reads the annotation into the engine's object list and relations.
    pub fn from_annotation(
        video_id: &str,
        annotation: &RopeAnnotation,
    ) -> Result<RopeScene, EngineError> {
        let mut objects = read_loads(video_id, annotation)?;
        objects.extend(read_ropes(video_id, annotation)?);
        let pulleys = read_pulleys_and_fixed_points(video_id, annotation)?;
        // Decision (a), `docs/data/rope.md`, quirks of the public engine: no attribute-based
        // de-duplication. Only a repeated annotation name (the same pulley listed under two ropes)
        // is the same object.
        for pulley in pulleys {
            if !objects
                .iter()
                .any(|o| o.annotation_name == pulley.annotation_name)
            {
                objects.push(pulley);
            }
        }
        let index_by_name: IndexMap<String, usize> = objects
            .iter()
            .enumerate()
            .map(|(index, object)| (object.annotation_name.clone(), index))
            .collect();
        let groups: Vec<Vec<GroupElement>> = annotation
            .related_groups
            .iter()
            .map(|group| {
                group
                    .iter()
                    .map(|name| GroupElement::new(name, &index_by_name))
                    .collect()
            })
            .collect();
        let related_loads = relate_loads_in_groups(&groups, &objects);
        let movable_pulley_loads = link_loads_to_movable_pulleys(&groups, &objects);
        let load_ropes = map_loads_to_ropes(&groups, &objects);
        let references = (0..objects.len())
            .map(|index| reference_name(&objects, index))
            .collect();
        Ok(RopeScene {
            objects,
            index_by_name,
            related_loads,
            movable_pulley_loads,
            load_ropes,
            references,
        })
    }

    /// The objects in the public engine's order.
    pub fn objects(&self) -> &[EngineObject] {
        &self.objects
    }

    /// The object with this annotation name.
    pub fn index_of(&self, annotation_name: &str) -> Option<usize> {
        self.index_by_name.get(annotation_name).copied()
    }

    /// Whether two loads are in the same related group (so their masses can be compared).
    pub fn are_related(&self, first: usize, second: usize) -> bool {
        self.related_loads
            .contains(&(first.min(second), first.max(second)))
    }

    /// Whether a load is marked as hanging under a movable pulley (`link_dy_pulley`).
    pub fn hangs_under_movable_pulley(&self, load: usize) -> bool {
        self.movable_pulley_loads.contains(&load)
    }

    /// The rope a load hangs on (`object_rope_map`), when it is known and is an engine object.
    pub fn rope_of(&self, load: usize) -> Option<usize> {
        self.load_ropes.get(&load).copied()
    }

    /// The phrase an object is called by in questions (`blue pulley`), or `None` when no phrase
    /// tells it apart from another object.
    pub fn reference(&self, index: usize) -> Option<&str> {
        self.references.get(index).and_then(Option::as_deref)
    }

    /// The reference of the object with this annotation name, if it is an engine object and can
    /// be referred to unambiguously.
    pub fn reference_by_name(&self, annotation_name: &str) -> Option<&str> {
        self.index_of(annotation_name)
            .and_then(|index| self.reference(index))
    }

    /// The object at `index`, if any.
    pub fn object(&self, index: usize) -> Option<&EngineObject> {
        self.objects.get(index)
    }

    /// Load indices in object order.
    pub fn loads(&self) -> impl Iterator<Item = usize> + '_ {
        self.objects
            .iter()
            .enumerate()
            .filter(|(_, o)| o.kind.is_load())
            .map(|(index, _)| index)
    }
}

/// Loads from `outputMass`, in file order, with their nominal masses.
fn read_loads(
    video_id: &str,
    annotation: &RopeAnnotation,
) -> Result<Vec<EngineObject>, EngineError> {
    let mut loads = Vec::with_capacity(annotation.output_mass_kg.len());
    for (name, &mass_kg) in &annotation.output_mass_kg {
        let parsed = parse_rope_object_name(name)
            .filter(|parsed| parsed.kind.is_load())
            .ok_or_else(|| EngineError::NotALoad {
                video_id: video_id.to_string(),
                name: name.clone(),
            })?;
        let mut load = EngineObject::from_name(&parsed);
        load.nominal_mass_kg = Some(nominal_mass(video_id, name, mass_kg)?);
        loads.push(load);
    }
    Ok(loads)
}

/// Decision (d): masses are nominal, `ceil(m·100)/100` as in the public engine, so a load under a
/// movable pulley (×1.975) reads 0.3/0.4/0.5. The public engine stopped in `breakpoint()` when
/// the second decimal was neither 0 nor 5; that is an error here.
fn nominal_mass(video_id: &str, load: &str, mass_kg: f64) -> Result<f64, EngineError> {
    let hundredths = (mass_kg * 100.0).ceil();
    let nominal_kg = hundredths / 100.0;
    // `hundredths` is a whole number, so the remainder is exact.
    if hundredths.rem_euclid(5.0) > 0.0 {
        return Err(EngineError::UnexpectedMass {
            video_id: video_id.to_string(),
            load: load.to_string(),
            mass_kg,
            nominal_kg,
        });
    }
    Ok(nominal_kg)
}

/// One rope object per key of each `relatedGroupsInRope` group.
fn read_ropes(
    video_id: &str,
    annotation: &RopeAnnotation,
) -> Result<Vec<EngineObject>, EngineError> {
    let mut ropes: Vec<EngineObject> = Vec::new();
    for rope_name in annotation
        .related_groups_in_rope
        .iter()
        .flat_map(IndexMap::keys)
    {
        let parsed = parse_rope_object_name(rope_name)
            .filter(|parsed| parsed.kind == RopeObjectKind::Rope)
            .ok_or_else(|| EngineError::UnparsableName {
                video_id: video_id.to_string(),
                field: "relatedGroupsInRope",
                name: rope_name.clone(),
            })?;
        if ropes.iter().any(|rope| rope.annotation_name == parsed.full) {
            continue;
        }
        let mut rope = EngineObject::from_name(&parsed);
        // The public engine indexed `ResultTension[rope]` unguarded; a missing entry only loses
        // this unused value here.
        rope.rope_tension_newtons = annotation
            .result_tension
            .get(rope_name)
            .and_then(|pairs| pairs.values().next())
            .map(|tension| tension.abs());
        ropes.push(rope);
    }
    Ok(ropes)
}

/// Pulleys and fixed points from the `relatedGroupsInRope` element lists, in first-appearance
/// order. Loads and ropes in those lists are skipped (the public engine re-added a stale object
/// there, which its de-duplication then dropped).
fn read_pulleys_and_fixed_points(
    video_id: &str,
    annotation: &RopeAnnotation,
) -> Result<Vec<EngineObject>, EngineError> {
    let mut found: Vec<EngineObject> = Vec::new();
    for name in annotation
        .related_groups_in_rope
        .iter()
        .flat_map(IndexMap::values)
        .flatten()
    {
        let looks_like_pulley_or_anchor = name.contains("Pulley") || name.contains("Fixed Point");
        let parsed = match parse_rope_object_name(name) {
            Some(parsed) => parsed,
            None if name.starts_with("Shaft of") || !looks_like_pulley_or_anchor => continue,
            None => {
                return Err(EngineError::UnparsableName {
                    video_id: video_id.to_string(),
                    field: "relatedGroupsInRope",
                    name: name.clone(),
                });
            }
        };
        let is_pulley_or_anchor = matches!(
            parsed.kind,
            RopeObjectKind::Pulley | RopeObjectKind::FixedPoint
        );
        if is_pulley_or_anchor && !found.iter().any(|o| o.annotation_name == parsed.full) {
            found.push(EngineObject::from_name(&parsed));
        }
    }
    Ok(found)
}

/// One entry of a `relatedGroups` list, parsed once.
struct GroupElement {
    kind: Option<RopeObjectKind>,
    is_movable_pulley: bool,
    object: Option<usize>,
}

impl GroupElement {
    fn new(name: &str, index_by_name: &IndexMap<String, usize>) -> GroupElement {
        let parsed = parse_rope_object_name(name);
        GroupElement {
            kind: parsed.as_ref().map(|p| p.kind),
            is_movable_pulley: parsed
                .as_ref()
                .is_some_and(|p| p.kind == RopeObjectKind::Pulley && p.dynamics == "dynamic"),
            object: index_by_name.get(name).copied(),
        }
    }

    fn is_load(&self) -> bool {
        self.kind.is_some_and(RopeObjectKind::is_load)
    }

    fn is_rope(&self) -> bool {
        self.kind == Some(RopeObjectKind::Rope)
    }
}

/// Relations hold between loads of the same `relatedGroups` group only: the public engine relates
/// every pair of names of a group that are already objects when it runs, and at that point only
/// loads are. (It also relates ropes of one `relatedGroupsInRope` group; no question uses that.)
fn relate_loads_in_groups(
    groups: &[Vec<GroupElement>],
    objects: &[EngineObject],
) -> BTreeSet<(usize, usize)> {
    let mut related = BTreeSet::new();
    for group in groups {
        let loads: BTreeSet<usize> = group
            .iter()
            .filter_map(|element| element.object)
            .filter(|&index| objects.get(index).is_some_and(|o| o.kind.is_load()))
            .collect();
        for &first in &loads {
            for &second in loads.range(first + 1..) {
                related.insert((first, second));
            }
        }
    }
    related
}

/// `link_dy_pulley`: for each movable pulley in a group, the load two places after it (in the
/// generator's order a movable pulley is followed by its connection rope, then its load), or
/// failing that the load two places before it.
///
/// Kept as in the public engine, with one known quirk: an end load two places from a movable
/// pulley without a load of its own is marked too. The mark only chooses the base factor of a
/// mass statement ("twice"/"half"); the yes/no answer is computed from the masses either way, so
/// the quirk changes wording, never truth.
fn link_loads_to_movable_pulleys(
    groups: &[Vec<GroupElement>],
    objects: &[EngineObject],
) -> BTreeSet<usize> {
    let is_load_object = |element: &GroupElement| {
        element.is_load() && element.object.is_some_and(|i| objects.get(i).is_some())
    };
    let mut linked = BTreeSet::new();
    for group in groups {
        for (position, element) in group.iter().enumerate() {
            if !element.is_movable_pulley {
                continue;
            }
            let after = group.get(position + 2).filter(|e| is_load_object(e));
            let before = position
                .checked_sub(2)
                .and_then(|p| group.get(p))
                .filter(|e| is_load_object(e));
            // A load listed in `relatedGroups` but missing from `outputMass` is no engine object;
            // the public engine crashed on it (`KeyError`), here it is skipped.
            if let Some(load) = after.or(before).and_then(|e| e.object) {
                linked.insert(load);
            }
        }
    }
    linked
}

/// `object_rope_map`: the rope each load hangs on.
///
/// * A first element takes the next element, a last element the previous one.
/// * A middle element takes the next element if the one after that is a movable pulley, the
///   previous element (its connection rope) if the one before that is a movable pulley, and
///   otherwise the neighbouring rope, previous first.
///
/// Fixes: the public engine indexed `group[i+2]` unguarded (an `IndexError` for a load second to
/// last) and `group[i-2]` with Python's wrap-around for `i = 1`; here both are bounds-checked.
/// It also mapped a load to whatever element the position rule picked; here the pick must be a
/// rope that is an engine object, or the load gets no rope (and no tension question).
fn map_loads_to_ropes(
    groups: &[Vec<GroupElement>],
    objects: &[EngineObject],
) -> IndexMap<usize, usize> {
    let mut load_ropes = IndexMap::new();
    for group in groups {
        let movable_at = |position: Option<usize>| {
            position
                .and_then(|p| group.get(p))
                .is_some_and(|e| e.is_movable_pulley)
        };
        let rope_at = |position: Option<usize>| {
            position
                .and_then(|p| group.get(p))
                .filter(|e| e.is_rope())
                .and_then(|e| e.object)
        };
        let last = group.len().saturating_sub(1);
        for (position, element) in group.iter().enumerate() {
            let Some(load) = element
                .object
                .filter(|&i| objects.get(i).is_some_and(|o| o.kind.is_load()))
            else {
                continue;
            };
            let previous = position.checked_sub(1);
            let next = Some(position + 1);
            let rope = if position == 0 {
                rope_at(next)
            } else if position == last {
                rope_at(previous)
            } else if movable_at(Some(position + 2)) {
                rope_at(next)
            } else if movable_at(position.checked_sub(2)) {
                rope_at(previous)
            } else {
                rope_at(previous).or_else(|| rope_at(next))
            };
            if let Some(rope) = rope {
                load_ropes.insert(load, rope);
            }
        }
    }
    load_ropes
}

/// The phrase for object `index` (the public engine's `abbr_object_name`, `docs/data/rope.md`,
/// reference phrases): `<colour> <type>` if that pair is unique, else `<colour> <solid|hollow>
/// <type>`, else `<colour> <static|dynamic> <type>`, else the full lower-case name. `None` when
/// even the full name is shared with another object: such an object cannot be referred to
/// unambiguously.
fn reference_name(objects: &[EngineObject], index: usize) -> Option<String> {
    // Only pulley names carry shape and dynamics words; the public engine parsed them from names.
    fn pulley_words(object: &EngineObject) -> Option<(&str, &str)> {
        (object.kind == RopeObjectKind::Pulley).then(|| {
            (
                object.shape.trim_end_matches(" pulley"),
                object.dynamics.as_str(),
            )
        })
    }
    let target = objects.get(index)?;
    let type_word = target.kind.word();
    let same_color_and_type: Vec<&EngineObject> = objects
        .iter()
        .filter(|o| o.color == target.color && o.kind == target.kind)
        .collect();
    if same_color_and_type.len() == 1 {
        return Some(format!("{} {type_word}", target.color));
    }
    if let Some((shape, dynamics)) = pulley_words(target) {
        let same_shape = same_color_and_type
            .iter()
            .filter(|o| pulley_words(o).is_some_and(|(s, _)| s == shape))
            .count();
        if same_shape == 1 {
            return Some(format!("{} {shape} {type_word}", target.color));
        }
        let same_dynamics = same_color_and_type
            .iter()
            .filter(|o| pulley_words(o).is_some_and(|(_, d)| d == dynamics))
            .count();
        if same_dynamics == 1 {
            return Some(format!("{} {dynamics} {type_word}", target.color));
        }
    }
    let shared_name = objects
        .iter()
        .filter(|o| o.name_key == target.name_key)
        .count()
        > 1;
    (!shared_name).then(|| target.name_key.clone())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn nominal_masses_round_up_and_reject_odd_hundredths() {
        let cases = [
            (0.2, Ok(0.2)),
            (0.25, Ok(0.25)),
            (0.15, Ok(0.15)),
            (0.15 * 1.975, Ok(0.3)),
            (0.2 * 1.975, Ok(0.4)),
            (0.25 * 1.975, Ok(0.5)),
            (0.213, Err(0.22)),
            (0.200_000_1, Err(0.21)),
        ];
        for (mass_kg, expected) in cases {
            let result = nominal_mass("7", "Red Cube", mass_kg);
            match expected {
                Ok(nominal) => assert_eq!(result, Ok(nominal), "{mass_kg}"),
                Err(nominal_kg) => assert_eq!(
                    result,
                    Err(EngineError::UnexpectedMass {
                        video_id: "7".into(),
                        load: "Red Cube".into(),
                        mass_kg,
                        nominal_kg
                    }),
                    "{mass_kg}"
                ),
            }
        }
    }

    fn object(name: &str) -> EngineObject {
        EngineObject::from_name(&parse_rope_object_name(name).unwrap())
    }

    #[test]
    fn references_use_the_shortest_unique_phrase() {
        let objects: Vec<EngineObject> = [
            "Blue Solid Static Pulley (0 1)",
            "Blue Hollow Static Pulley (0 2)",
            "Red Solid Static Pulley (0 3)",
            "Red Solid Dynamic Pulley (1 3)",
            "Red Hollow Static Pulley (1 4)",
            "Green Solid Static Pulley (0 5)",
            "Green Solid Static Pulley (1 5)",
            "Light Blue Cube",
            "Blue Cube",
            "Light Coral Sphere",
            "Black Rope",
            "Brown Fixed Point",
        ]
        .into_iter()
        .map(object)
        .collect();
        let expected = [
            Some("blue solid pulley"),
            Some("blue hollow pulley"),
            Some("red solid static pulley"),
            Some("red dynamic pulley"),
            Some("red hollow pulley"),
            None,
            None,
            Some("light blue cube"),
            Some("blue cube"),
            Some("light coral sphere"),
            Some("black rope"),
            Some("brown fixed point"),
        ];
        for (index, expected) in expected.iter().enumerate() {
            assert_eq!(
                reference_name(&objects, index).as_deref(),
                *expected,
                "{}",
                objects[index].annotation_name
            );
        }
    }
}

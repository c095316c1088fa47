//! The words `find` understands: the palette's colours, and the kinds, group words, attributes
//! and suffix of the scene's scenario vocabulary.
//!
//! `find("blue solid pulley")` parses into a [`NameQuery`]; every word must be understood, so a
//! typo raises an error listing the vocabulary instead of silently finding nothing. Words naming
//! another scenario's objects (`container` in a rope scene), and objects the scenario shows but
//! never asks about, are understood and find nothing.

use super::error::{ApiError, misuse};
use super::object::{ObjectId, SceneObjectInfo};
use crate::dataset::Vocabulary;
use crate::perception::palette::color_words;

/// Words that carry no meaning for matching.
const FILLER_WORDS: [&str; 8] = ["the", "a", "an", "any", "all", "object", "objects", "every"];

/// A parsed `find` argument. `None` fields match anything.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct NameQuery {
    /// Exact colour (`light blue` is not `blue`).
    pub color: Option<String>,
    /// A kind or a group word of the scene's vocabulary (`load` matches cubes and spheres).
    pub kind: Option<String>,
    /// Attribute values the object must have (`shape` = `solid`), in the order given.
    pub attributes: Vec<(&'static str, String)>,
    /// The name asks for objects `find` never returns here (a kind of another scenario, or an
    /// object the scenario shows but does not ask about): it matches nothing.
    pub foreign_kind: bool,
}

impl NameQuery {
    /// Whether `object` (of a scene with `vocabulary`) has every feature of the query: its
    /// colour, its kind (or one of the kinds of a group word) and its attribute values. Objects
    /// perception did not find, and every object for a query of foreign kinds, never match.
    pub fn matches(&self, object: &SceneObjectInfo, vocabulary: &Vocabulary) -> bool {
        if self.foreign_kind || !object.visible {
            return false;
        }
        let group = self.kind.as_deref().and_then(|kind| vocabulary.group(kind));
        let kind_matches = match (group, self.kind.as_deref()) {
            (Some(kinds), _) => kinds.contains(&object.kind),
            (None, Some(kind)) => object.kind == kind,
            (None, None) => true,
        };
        kind_matches
            && self
                .color
                .as_ref()
                .is_none_or(|color| *color == object.color)
            && self.attributes_match(object)
    }

    /// Whether `object` is, by its second-choice colours, what the query names: everything but
    /// the colour matches, and the query's colour is one of [`SceneObjectInfo::other_colors`].
    /// Returns the colour's rank there (0: the likeliest second choice).
    pub fn second_choice(
        &self,
        object: &SceneObjectInfo,
        vocabulary: &Vocabulary,
    ) -> Option<usize> {
        let color = self.color.as_ref()?;
        let rank = object
            .other_colors
            .iter()
            .position(|other| other == color)?;
        let recoloured = NameQuery {
            color: None,
            ..self.clone()
        };
        recoloured.matches(object, vocabulary).then_some(rank)
    }

    /// When no object matches the query in its colour: the one object of `objects` that has the
    /// query's colour as its likeliest second choice ([`NameQuery::second_choice`]; ties: the
    /// first in scene order), if any. Never two: a program asking for one red stick gets one.
    pub fn second_choice_object(
        &self,
        objects: &[SceneObjectInfo],
        vocabulary: &Vocabulary,
    ) -> Option<ObjectId> {
        objects
            .iter()
            .filter_map(|object| Some((self.second_choice(object, vocabulary)?, object.id)))
            .min_by_key(|(rank, id)| (*rank, id.0))
            .map(|(_, id)| id)
    }

    fn attributes_match(&self, object: &SceneObjectInfo) -> bool {
        self.attributes
            .iter()
            .all(|(attribute, value)| object.attribute(attribute) == Some(value.as_str()))
    }
}

/// The vocabularies a name is parsed with: the scene's, and every scenario's (for words that
/// name other scenarios' objects).
#[derive(Debug, Clone, Copy)]
pub struct Words<'a> {
    /// The scene's scenario name, for messages (`rope`).
    pub scenario: &'a str,
    /// The scene's vocabulary.
    pub own: &'a Vocabulary,
    /// Every scenario's vocabulary, the scene's included.
    pub all: &'a [&'a Vocabulary],
}

impl Words<'_> {
    /// Whether `word` names an object of any scenario (a kind, or an unfindable object).
    fn is_any_object(&self, word: &str) -> bool {
        self.all
            .iter()
            .any(|v| v.has_kind(word) || v.unfindable.contains(&word))
    }

    /// `word` without a plural `s`, when the singular names an object (or the last word of a
    /// two-word kind, as `points` in `fixed points`) of any scenario, or a group word.
    fn singular(&self, word: &str) -> String {
        if let Some(stem) = word.strip_suffix('s') {
            let known = self.all.iter().any(|v| {
                v.object_words()
                    .any(|object| object == stem || object.rsplit(' ').next() == Some(stem))
            });
            if known {
                return stem.to_string();
            }
        }
        word.to_string()
    }
}

/// A description an API call names objects by (`register_event`'s attribute, `happen`'s
/// target), read with `find`'s words in `scenario`'s vocabulary alone: the query and the objects
/// of `objects` it matches. A description it cannot read is misuse, named after `function`.
pub(crate) fn resolve_description(
    objects: &[SceneObjectInfo],
    scenario: &'static str,
    vocabulary: &'static Vocabulary,
    description: &str,
    function: &str,
) -> Result<(NameQuery, Vec<ObjectId>), ApiError> {
    let own = [vocabulary];
    let words = Words {
        scenario,
        own: vocabulary,
        all: &own,
    };
    let query = parse_object_query(description, words).map_err(|error| {
        let reason = error.to_string();
        misuse(format!(
            "{function}: cannot read `{description}`: {}",
            reason.strip_prefix("find: ").unwrap_or(&reason)
        ))
    })?;
    let found = objects
        .iter()
        .filter(|object| query.matches(object, vocabulary))
        .map(|object| object.id)
        .collect();
    Ok((query, found))
}

/// Parses an object name with the scene's `words`.
pub fn parse_object_query(name: &str, words: Words<'_>) -> Result<NameQuery, ApiError> {
    let lower = name.to_lowercase();
    let mut query = NameQuery::default();
    let text = split_suffix(&lower, words, &mut query)?;
    let tokens: Vec<String> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .map(|w| w.trim_matches(|c: char| !c.is_alphanumeric() && c != '-'))
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect();
    let colors = color_words();
    let mut index = 0;
    while index < tokens.len() {
        let word = tokens[index].as_str();
        let next = tokens.get(index + 1).map(String::as_str);
        let pair = next.map(|n| format!("{word} {n}"));
        let pair_singular = next.map(|n| format!("{word} {}", words.singular(n)));
        // Two-word names first, so "light blue" is not "blue" and "fixed point" is not "fixed".
        if let Some(two) = pair.as_deref().filter(|p| colors.contains(p)) {
            set_once(&mut query.color, two, name, "colours")?;
            index += 2;
            continue;
        }
        if let Some(two) = pair_singular.as_deref().filter(|p| words.is_any_object(p)) {
            set_kind(&mut query, two, words, name)?;
            index += 2;
            continue;
        }
        let single = words.singular(word);
        if FILLER_WORDS.contains(&word) {
        } else if word == "grey" || colors.contains(&word) {
            let color = if word == "grey" { "gray" } else { word };
            set_once(&mut query.color, color, name, "colours")?;
        } else if words.is_any_object(&single) || words.own.group(&single).is_some() {
            set_kind(&mut query, &single, words, name)?;
        } else if let Some((attribute, value)) = words.own.attribute_word(word) {
            set_attribute(&mut query, attribute.name, attribute.plural, value, name)?;
        } else {
            return Err(unknown_word(word, name, words));
        }
        index += 1;
    }
    if query.kind.is_none() {
        let implied = query.attributes.iter().find_map(|(attribute, _)| {
            words
                .own
                .attribute(attribute)
                .and_then(|attribute| attribute.implies_kind)
        });
        query.kind = implied.map(str::to_string);
    }
    Ok(query)
}

/// The error for a word no vocabulary has: it lists what the scene understands.
fn unknown_word(word: &str, name: &str, words: Words<'_>) -> ApiError {
    let mut parts = vec![
        format!("colours ({})", color_words().join(", ")),
        format!("kinds ({})", words.own.kinds.join(", ")),
    ];
    for attribute in words.own.attributes {
        let mut values: Vec<&str> = Vec::new();
        for (_, value) in attribute.words {
            if !values.contains(value) {
                values.push(value);
            }
        }
        parts.push(format!("{} ({})", attribute.plural, values.join(", ")));
    }
    if let Some(suffix) = &words.own.suffix {
        parts.push(format!(
            "{} ids like `{}`",
            suffix.attribute, suffix.example
        ));
    }
    let understood = match parts.split_last() {
        Some((last, rest)) if !rest.is_empty() => format!("{} and {last}", rest.join(", ")),
        _ => parts.join(", "),
    };
    misuse(format!(
        "find: unknown word `{word}` in `{name}`; a {} scene understands {understood}",
        words.scenario
    ))
}

/// Records the kind or group word `kind`; a word for objects `find` never returns here marks
/// the query as matching nothing.
fn set_kind(
    query: &mut NameQuery,
    kind: &str,
    words: Words<'_>,
    name: &str,
) -> Result<(), ApiError> {
    if !words.own.has_kind(kind) && words.own.group(kind).is_none() {
        query.foreign_kind = true;
    }
    set_once(&mut query.kind, kind, name, "kinds")
}

fn set_once(
    slot: &mut Option<String>,
    value: &str,
    name: &str,
    plural: &str,
) -> Result<(), ApiError> {
    match slot {
        Some(existing) if existing != value => Err(misuse(format!(
            "find: `{name}` names two different {plural} (`{existing}` and `{value}`); find one object description at a time"
        ))),
        _ => {
            *slot = Some(value.to_string());
            Ok(())
        }
    }
}

fn set_attribute(
    query: &mut NameQuery,
    attribute: &'static str,
    plural: &str,
    value: &str,
    name: &str,
) -> Result<(), ApiError> {
    let mut slot = query
        .attributes
        .iter()
        .find(|(known, _)| *known == attribute)
        .map(|(_, value)| value.clone());
    set_once(&mut slot, value, name, plural)?;
    if !query
        .attributes
        .iter()
        .any(|(known, _)| *known == attribute)
    {
        query.attributes.push((attribute, value.to_string()));
    }
    Ok(())
}

/// Splits a trailing `(…)` off the name into the vocabulary's suffix attribute; the text before
/// it is returned.
fn split_suffix(text: &str, words: Words<'_>, query: &mut NameQuery) -> Result<String, ApiError> {
    let Some((head, tail)) = text.split_once('(') else {
        return Ok(text.to_string());
    };
    let Some(suffix) = &words.own.suffix else {
        return Err(misuse(format!(
            "find: `{text}` ends in `(…)`, which names nothing in a {} scene",
            words.scenario
        )));
    };
    let value = tail
        .trim_end()
        .strip_suffix(')')
        .and_then(suffix.parse)
        .ok_or_else(|| {
            misuse(format!(
                "find: `{text}` has a {} id that is not `{}`, e.g. `{}`",
                suffix.attribute, suffix.form, suffix.example
            ))
        })?;
    query.attributes.push((suffix.attribute, value));
    Ok(head.to_string())
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dataset::{ball, fluid, rope};
    use crate::scene_api::test_support::ALL_VOCABULARIES as ALL;

    fn rope_words() -> Words<'static> {
        Words {
            scenario: "rope",
            own: &rope::VOCABULARY,
            all: &ALL,
        }
    }

    fn parse(name: &str) -> Result<NameQuery, ApiError> {
        parse_object_query(name, rope_words())
    }

    fn query(
        color: Option<&str>,
        kind: Option<&str>,
        attributes: &[(&'static str, &str)],
    ) -> NameQuery {
        NameQuery {
            color: color.map(str::to_string),
            kind: kind.map(str::to_string),
            attributes: attributes
                .iter()
                .map(|(name, value)| (*name, (*value).to_string()))
                .collect(),
            foreign_kind: false,
        }
    }

    #[test]
    fn a_colour_nobody_was_read_in_finds_the_object_whose_second_choice_it_is() {
        use super::super::object::ObjectId;
        let stick = |id: u32, color: &str, others: &[&str]| {
            let mut object = SceneObjectInfo::new(
                ObjectId(id),
                &format!("{color} Stick"),
                color,
                "stick",
                &[],
                &fluid::VOCABULARY,
            );
            object.other_colors = others.iter().map(|c| (*c).to_string()).collect();
            object
        };
        // A red stick read as brown (red its first second choice), a white one read as gray.
        let objects = [
            stick(0, "brown", &["orange", "red"]),
            stick(1, "gray", &["white"]),
            stick(2, "blue", &["red"]),
        ];
        let words = Words {
            scenario: "fluid",
            own: &fluid::VOCABULARY,
            all: &ALL,
        };
        let find = |name: &str| {
            parse_object_query(name, words)
                .unwrap()
                .second_choice_object(&objects, &fluid::VOCABULARY)
        };
        // Rank 0 wins over the brown stick's rank 1.
        assert_eq!(find("red stick"), Some(ObjectId(2)));
        assert_eq!(find("white stick"), Some(ObjectId(1)));
        assert_eq!(find("orange stick"), Some(ObjectId(0)));
        assert_eq!(find("green stick"), None);
        // The kind must still match, and a query without a colour has no second choice.
        assert_eq!(find("white container"), None);
        assert_eq!(find("stick"), None);
    }

    #[test]
    fn names_parse_into_features() {
        let cases = [
            ("blue pulley", query(Some("blue"), Some("pulley"), &[])),
            (
                "the Solid Pulley",
                query(None, Some("pulley"), &[("shape", "solid")]),
            ),
            ("purple", query(Some("purple"), None, &[])),
            ("cubes", query(None, Some("cube"), &[])),
            ("loads", query(None, Some("load"), &[])),
            ("fixed point", query(None, Some("fixed point"), &[])),
            (
                "brown fixed points",
                query(Some("brown"), Some("fixed point"), &[]),
            ),
            (
                "light blue sphere",
                query(Some("light blue"), Some("sphere"), &[]),
            ),
            (
                "purple solid static pulley",
                query(
                    Some("purple"),
                    Some("pulley"),
                    &[("shape", "solid"), ("dynamic", "static")],
                ),
            ),
            (
                "hollow",
                query(None, Some("pulley"), &[("shape", "hollow")]),
            ),
            ("little", query(None, Some("pulley"), &[("shape", "solid")])),
            ("movable", query(None, None, &[("dynamic", "dynamic")])),
            ("grey rope", query(Some("gray"), Some("rope"), &[])),
        ];
        for (name, expected) in cases {
            assert_eq!(parse(name).unwrap(), expected, "{name}");
        }
        let grid = parse("blue solid static pulley (0 1)").unwrap();
        assert_eq!(grid.attributes[0], ("grid", "0 1".to_string()));
        let grid = parse("pulley ( 1   -1 )").unwrap();
        assert_eq!(grid.attributes[0], ("grid", "1 -1".to_string()));
    }

    #[test]
    fn other_scenarios_objects_are_understood_and_find_nothing() {
        for name in ["red container", "green floating walls", "ramp", "cloths"] {
            assert!(parse(name).unwrap().foreign_kind, "{name}");
        }
        assert!(!parse("load").unwrap().foreign_kind);
        let ball = Words {
            scenario: "ball",
            own: &ball::VOCABULARY,
            all: &ALL,
        };
        // Ramps are a ball scene's own objects now (findable by side); plain walls are seen but
        // never asked about; `load` is rope's word only.
        assert!(!parse_object_query("left ramp", ball).unwrap().foreign_kind);
        assert!(parse_object_query("wall", ball).unwrap().foreign_kind);
        assert!(!parse_object_query("red ball", ball).unwrap().foreign_kind);
        assert!(parse_object_query("load", ball).is_err());
        let error = parse_object_query("ball (0 1)", ball)
            .unwrap_err()
            .to_string();
        assert!(error.contains("names nothing in a ball scene"), "{error}");
    }

    #[test]
    fn unknown_or_contradictory_words_are_explained() {
        let error = parse("banana cube").unwrap_err().to_string();
        assert_eq!(
            error,
            "find: unknown word `banana` in `banana cube`; a rope scene understands colours (red, orange, yellow, green, cyan, blue, purple, pink, brown, gray, black, white, light blue, light green, light yellow, light coral, light purple), kinds (cube, sphere, pulley, rope, fixed point), pulley shapes (solid, hollow), dynamics (static, dynamic) and grid ids like `(0 1)`"
        );
        let error = parse("red blue cube").unwrap_err().to_string();
        assert!(error.contains("two different colours"), "{error}");
        let error = parse("solid hollow pulley").unwrap_err().to_string();
        assert!(error.contains("two different pulley shapes"), "{error}");
        let error = parse("cube sphere").unwrap_err().to_string();
        assert!(error.contains("two different kinds"), "{error}");
        let error = parse("pulley (0 x)").unwrap_err().to_string();
        assert_eq!(
            error,
            "find: `pulley (0 x)` has a grid id that is not `(layer column)`, e.g. `(0 1)`"
        );
    }
}

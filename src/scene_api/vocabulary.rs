//! The words `find` understands: colours, object kinds, pulley shapes, dynamics and grid ids.
//!
//! `find("blue solid pulley")` parses into a [`NameQuery`]; every word must be understood, so a
//! typo raises an error listing the vocabulary instead of silently finding nothing. Words naming
//! another scenario's objects (`container` in a rope scene) are understood and find nothing.

use super::error::{ApiError, misuse};
use crate::dataset::Scenario;

/// The generator's colour palette (`PlacementConfig.SoftColor`), lower case.
pub const COLOR_NAMES: [&str; 17] = [
    "red",
    "orange",
    "yellow",
    "green",
    "cyan",
    "blue",
    "purple",
    "pink",
    "brown",
    "gray",
    "black",
    "white",
    "light blue",
    "light green",
    "light yellow",
    "light coral",
    "light purple",
];

/// Object kinds per scenario, as the paper's prompt lists them.
fn kinds(scenario: Scenario) -> &'static [&'static str] {
    match scenario {
        Scenario::Rope => &["cube", "sphere", "pulley", "rope", "fixed point"],
        Scenario::Fluid => &["fluid", "container", "stick", "emitter"],
        Scenario::Cloth => &["cloth", "pillar", "plate"],
        Scenario::Ball => &["ball", "stick", "pit", "floating wall"],
    }
}

/// Words that carry no meaning for matching.
const FILLER_WORDS: [&str; 8] = ["the", "a", "an", "any", "all", "object", "objects", "every"];

/// A parsed `find` argument. `None` fields match anything.
#[derive(Debug, Clone, PartialEq, Eq, Default)]
pub struct NameQuery {
    /// Exact colour (`light blue` is not `blue`).
    pub color: Option<String>,
    /// Object kind; `load` matches cubes and spheres.
    pub kind: Option<String>,
    /// Pulley shape: `solid` or `hollow`.
    pub shape: Option<String>,
    /// `static` or `dynamic`.
    pub dynamics: Option<String>,
    /// Grid id `(layer, column)`.
    pub grid: Option<(i32, i32)>,
    /// The name asks for a kind that exists only in other scenarios: it matches nothing here.
    pub foreign_kind: bool,
}

/// Parses an object name for `scenario`.
pub fn parse_object_query(name: &str, scenario: Scenario) -> Result<NameQuery, ApiError> {
    let lower = name.to_lowercase();
    let (text, grid) = split_grid(&lower)?;
    let words: Vec<String> = text
        .split(|c: char| c.is_whitespace() || c == ',')
        .map(|w| w.trim_matches(|c: char| !c.is_alphanumeric() && c != '-'))
        .filter(|w| !w.is_empty())
        .map(str::to_string)
        .collect();
    let mut query = NameQuery {
        grid,
        ..NameQuery::default()
    };
    let mut index = 0;
    while index < words.len() {
        let word = words[index].as_str();
        let next = words.get(index + 1).map(String::as_str);
        let pair = next.map(|n| format!("{word} {n}"));
        let pair_singular = next.map(|n| format!("{word} {}", singular(n)));
        // Two-word names first, so "light blue" is not "blue" and "fixed point" is not "fixed".
        if let Some(two) = pair.as_deref().filter(|p| COLOR_NAMES.contains(p)) {
            set_once(&mut query.color, two, name, "colour")?;
            index += 2;
            continue;
        }
        if let Some(two) = pair_singular.as_deref().filter(|p| is_any_kind(p)) {
            set_kind(&mut query, two, scenario, name)?;
            index += 2;
            continue;
        }
        let single = singular(word);
        if FILLER_WORDS.contains(&word) {
        } else if word == "grey" || COLOR_NAMES.contains(&word) {
            set_once(
                &mut query.color,
                if word == "grey" { "gray" } else { word },
                name,
                "colour",
            )?;
        } else if is_any_kind(&single) {
            set_kind(&mut query, &single, scenario, name)?;
        } else if single == "load" && scenario == Scenario::Rope {
            set_once(&mut query.kind, "load", name, "kind")?;
        } else if let Some(shape) = pulley_shape(word) {
            set_once(&mut query.shape, shape, name, "pulley shape")?;
        } else if let Some(dynamics) = dynamics_word(word) {
            set_once(&mut query.dynamics, dynamics, name, "dynamics")?;
        } else {
            return Err(misuse(format!(
                "find: unknown word `{word}` in `{name}`; a {scenario} scene understands colours ({}), \
                 kinds ({}), pulley shapes (solid, hollow), dynamics (static, dynamic) and grid ids like `(0 1)`",
                COLOR_NAMES.join(", "),
                kinds(scenario).join(", ")
            )));
        }
        index += 1;
    }
    if query.shape.is_some() && query.kind.is_none() && scenario == Scenario::Rope {
        query.kind = Some("pulley".to_string());
    }
    Ok(query)
}

fn set_kind(
    query: &mut NameQuery,
    kind: &str,
    scenario: Scenario,
    name: &str,
) -> Result<(), ApiError> {
    if !kinds(scenario).contains(&kind) {
        query.foreign_kind = true;
    }
    set_once(&mut query.kind, kind, name, "kind")
}

fn set_once(
    slot: &mut Option<String>,
    value: &str,
    name: &str,
    what: &str,
) -> Result<(), ApiError> {
    match slot {
        Some(existing) if existing != value => Err(misuse(format!(
            "find: `{name}` names two different {what}s (`{existing}` and `{value}`); find one object description at a time"
        ))),
        _ => {
            *slot = Some(value.to_string());
            Ok(())
        }
    }
}

fn is_any_kind(word: &str) -> bool {
    Scenario::ALL.into_iter().any(|s| kinds(s).contains(&word)) || word == "wall" || word == "ramp"
}

fn singular(word: &str) -> String {
    match word {
        "spheres" => "sphere".to_string(),
        "pulleys" | "ropes" | "cubes" | "points" | "loads" | "fluids" | "containers" | "sticks"
        | "emitters" | "cloths" | "pillars" | "plates" | "balls" | "pits" | "walls" | "ramps" => {
            word[..word.len() - 1].to_string()
        }
        _ => word.to_string(),
    }
}

fn pulley_shape(word: &str) -> Option<&'static str> {
    // The generator's solid pulleys are the little ones, hollow pulleys the big ones.
    match word {
        "solid" | "little" | "small" => Some("solid"),
        "hollow" | "big" | "large" => Some("hollow"),
        _ => None,
    }
}

fn dynamics_word(word: &str) -> Option<&'static str> {
    match word {
        "static" | "stationary" => Some("static"),
        "dynamic" | "movable" | "moveable" | "moving" => Some("dynamic"),
        _ => None,
    }
}

/// Splits a trailing grid id `(l c)` off the name.
fn split_grid(text: &str) -> Result<(String, Option<(i32, i32)>), ApiError> {
    let Some((head, tail)) = text.split_once('(') else {
        return Ok((text.to_string(), None));
    };
    let bad = || {
        misuse(format!(
            "find: `{text}` has a grid id that is not `(layer column)`, e.g. `(0 1)`"
        ))
    };
    let inner = tail.trim_end().strip_suffix(')').ok_or_else(bad)?;
    let numbers: Vec<i32> = inner
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .map_err(|_| bad())?;
    match numbers.as_slice() {
        [layer, column] => Ok((head.to_string(), Some((*layer, *column)))),
        _ => Err(bad()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn query(
        color: Option<&str>,
        kind: Option<&str>,
        shape: Option<&str>,
        dynamics: Option<&str>,
    ) -> NameQuery {
        NameQuery {
            color: color.map(str::to_string),
            kind: kind.map(str::to_string),
            shape: shape.map(str::to_string),
            dynamics: dynamics.map(str::to_string),
            grid: None,
            foreign_kind: false,
        }
    }

    #[test]
    fn names_parse_into_features() {
        let cases = [
            (
                "blue pulley",
                query(Some("blue"), Some("pulley"), None, None),
            ),
            (
                "the Solid Pulley",
                query(None, Some("pulley"), Some("solid"), None),
            ),
            ("purple", query(Some("purple"), None, None, None)),
            ("cubes", query(None, Some("cube"), None, None)),
            ("fixed point", query(None, Some("fixed point"), None, None)),
            (
                "brown fixed points",
                query(Some("brown"), Some("fixed point"), None, None),
            ),
            (
                "light blue sphere",
                query(Some("light blue"), Some("sphere"), None, None),
            ),
            (
                "purple solid static pulley",
                query(
                    Some("purple"),
                    Some("pulley"),
                    Some("solid"),
                    Some("static"),
                ),
            ),
            ("hollow", query(None, Some("pulley"), Some("hollow"), None)),
            ("grey rope", query(Some("gray"), Some("rope"), None, None)),
        ];
        for (name, expected) in cases {
            assert_eq!(
                parse_object_query(name, Scenario::Rope).unwrap(),
                expected,
                "{name}"
            );
        }
        let grid = parse_object_query("blue solid static pulley (0 1)", Scenario::Rope).unwrap();
        assert_eq!(grid.grid, Some((0, 1)));
        assert!(
            parse_object_query("red container", Scenario::Rope)
                .unwrap()
                .foreign_kind
        );
    }

    #[test]
    fn unknown_or_contradictory_words_are_explained() {
        let error = parse_object_query("banana cube", Scenario::Rope)
            .unwrap_err()
            .to_string();
        assert!(
            error.starts_with(
                "find: unknown word `banana` in `banana cube`; a rope scene understands"
            ),
            "{error}"
        );
        assert!(
            error.contains("kinds (cube, sphere, pulley, rope, fixed point)"),
            "{error}"
        );
        let error = parse_object_query("red blue cube", Scenario::Rope)
            .unwrap_err()
            .to_string();
        assert!(error.contains("two different colours"), "{error}");
        let error = parse_object_query("pulley (0 x)", Scenario::Rope)
            .unwrap_err()
            .to_string();
        assert!(error.contains("grid id"), "{error}");
    }
}

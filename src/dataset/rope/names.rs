//! The grammar of rope object names (`Blue Solid Static Pulley (0 1)`, `Light Blue Cube`, ...):
//! what kind of object a name denotes and its colour, pulley shape, dynamics and grid id.

use serde::Serialize;

/// The kind of a rope-scene object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum RopeObjectKind {
    /// A cube load.
    Cube,
    /// A sphere load.
    Sphere,
    /// A static or movable pulley.
    Pulley,
    /// A rope (main cable, load connection or pulley–pulley cable).
    Rope,
    /// A rope end anchored to the ceiling or floor.
    FixedPoint,
}

impl RopeObjectKind {
    /// The word used in questions (`fixed point`).
    pub fn word(self) -> &'static str {
        match self {
            RopeObjectKind::Cube => "cube",
            RopeObjectKind::Sphere => "sphere",
            RopeObjectKind::Pulley => "pulley",
            RopeObjectKind::Rope => "rope",
            RopeObjectKind::FixedPoint => "fixed point",
        }
    }

    /// Whether the object is a load (its mass can be queried and changed).
    pub fn is_load(self) -> bool {
        matches!(self, RopeObjectKind::Cube | RopeObjectKind::Sphere)
    }
}

/// A rope object name split into its parts. All text fields are lower case.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct RopeObjectName {
    /// The annotation name, as written (`Blue Solid Static Pulley (0 1)`).
    pub full: String,
    /// The colour words (`blue`, `light blue`).
    pub color: String,
    /// The object kind.
    pub kind: RopeObjectKind,
    /// `solid` (little) or `hollow` (big), for pulleys.
    pub pulley_shape: Option<String>,
    /// `static` or `dynamic` (movable). Loads and ropes are dynamic, fixed points static.
    pub dynamics: String,
    /// The grid id `(layer, column)` of pulleys (columns can be negative in the release).
    pub grid: Option<(i32, i32)>,
}

impl RopeObjectName {
    /// The name without the grid suffix, lower case (`blue solid static pulley`); the public
    /// engine's object key.
    pub fn base_name(&self) -> String {
        self.full
            .split('(')
            .next()
            .unwrap_or_default()
            .trim()
            .to_lowercase()
    }
}

/// Parses a rope object name; `None` for names that are not question objects (`Solver`,
/// `Shaft of …`) or that do not follow the generator's grammar.
pub fn parse_rope_object_name(name: &str) -> Option<RopeObjectName> {
    if name.starts_with("Shaft of") {
        return None;
    }
    let (words_part, grid) = match name.split_once('(') {
        Some((head, tail)) => {
            let inner = tail.strip_suffix(')')?;
            let mut numbers = inner.split_whitespace().map(str::parse::<i32>);
            let layer = numbers.next()?.ok()?;
            let column = numbers.next()?.ok()?;
            if numbers.next().is_some() {
                return None;
            }
            (head.trim(), Some((layer, column)))
        }
        None => (name.trim(), None),
    };
    let words: Vec<String> = words_part
        .split_whitespace()
        .map(str::to_lowercase)
        .collect();
    let joined = |slice: &[String]| slice.join(" ");
    let (kind, color_words, pulley_shape, dynamics) = match words.as_slice() {
        [color @ .., last] if last == "cube" => (RopeObjectKind::Cube, color, None, "dynamic"),
        [color @ .., last] if last == "sphere" => (RopeObjectKind::Sphere, color, None, "dynamic"),
        [color @ .., last] if last == "rope" => (RopeObjectKind::Rope, color, None, "dynamic"),
        [color @ .., fixed, point] if fixed == "fixed" && point == "point" => {
            (RopeObjectKind::FixedPoint, color, None, "static")
        }
        [color @ .., shape, dynamics, pulley]
            if pulley == "pulley"
                && (shape == "solid" || shape == "hollow")
                && (dynamics == "static" || dynamics == "dynamic") =>
        {
            (
                RopeObjectKind::Pulley,
                color,
                Some(shape.clone()),
                dynamics.as_str(),
            )
        }
        _ => return None,
    };
    if color_words.is_empty() {
        return None;
    }
    Some(RopeObjectName {
        full: name.to_string(),
        color: joined(color_words),
        kind,
        pulley_shape,
        dynamics: dynamics.to_string(),
        grid,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn object_names_follow_the_generator_grammar() {
        let pulley = parse_rope_object_name("Blue Solid Static Pulley (0 1)").unwrap();
        assert_eq!(pulley.color, "blue");
        assert_eq!(pulley.kind, RopeObjectKind::Pulley);
        assert_eq!(pulley.pulley_shape.as_deref(), Some("solid"));
        assert_eq!(pulley.dynamics, "static");
        assert_eq!(pulley.grid, Some((0, 1)));
        assert_eq!(pulley.base_name(), "blue solid static pulley");
        let cube = parse_rope_object_name("Light Blue Cube").unwrap();
        assert_eq!(
            (cube.color.as_str(), cube.kind),
            ("light blue", RopeObjectKind::Cube)
        );
        let fixed = parse_rope_object_name("Brown Fixed Point").unwrap();
        assert_eq!(
            (fixed.kind, fixed.dynamics.as_str()),
            (RopeObjectKind::FixedPoint, "static")
        );
        let movable = parse_rope_object_name("Red Hollow Dynamic Pulley (1 2)").unwrap();
        assert_eq!(movable.dynamics, "dynamic");
        // The release's walk can step left of column 0 in its second layer.
        let left = parse_rope_object_name("Gray Solid Static Pulley (1 -1)").unwrap();
        assert_eq!(left.grid, Some((1, -1)));
        for not_an_object in [
            "Solver",
            "Shaft of Blue Solid Static Pulley (0 1)",
            "Cube",
            "Pulley (0 1)",
            "Red Pulley (x y)",
        ] {
            assert!(
                parse_rope_object_name(not_an_object).is_none(),
                "{not_an_object}"
            );
        }
    }
}

//! The grammar of cloth-scene names, as the release's generator builds them
//! (`docs/data/cloth.md`): boxes are `<C> Pillar`, `<C> Plate` (and `<C> Cube`, a tower layer that
//! was not merged into a pillar, which the release practically never writes), `<C>` a palette
//! name; the cloths are `Cloth (Left)` and `Cloth (Right)`. The two halves of the table have
//! their own keys (`clothLeft`, `leftAll`). This module builds the names too, so the generator
//! and the readers spell them one way.

use serde::Serialize;

use crate::dataset::palette::PALETTE_NAMES;

/// A half of the table: each has its own cloth and its own boxes.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Side {
    /// The half at negative x (centred 2.4 to the left).
    Left,
    /// The half at positive x.
    Right,
}

impl Side {
    /// Both halves, left first (the release's file order).
    pub const BOTH: [Side; 2] = [Side::Left, Side::Right];

    /// `left` or `right`, as questions say it (`_POS_`).
    pub fn word(self) -> &'static str {
        match self {
            Side::Left => "left",
            Side::Right => "right",
        }
    }

    /// The other half.
    #[must_use]
    pub fn other(self) -> Side {
        match self {
            Side::Left => Side::Right,
            Side::Right => Side::Left,
        }
    }

    /// The cloth's object name: `Cloth (Left)`, `Cloth (Right)` (what `collisionEvents` and
    /// `touchers` name it).
    pub fn cloth_name(self) -> &'static str {
        match self {
            Side::Left => "Cloth (Left)",
            Side::Right => "Cloth (Right)",
        }
    }

    /// The key of the half's cloth record: `clothLeft`, `clothRight`.
    pub fn cloth_key(self) -> &'static str {
        match self {
            Side::Left => "clothLeft",
            Side::Right => "clothRight",
        }
    }

    /// The key of the half's objects in `objectFullAnnotation`: `leftAll`, `rightAll`.
    pub fn objects_key(self) -> &'static str {
        match self {
            Side::Left => "leftAll",
            Side::Right => "rightAll",
        }
    }

    /// The half a cloth name names, if it is one.
    pub fn of_cloth_name(name: &str) -> Option<Side> {
        Side::BOTH
            .into_iter()
            .find(|side| side.cloth_name() == name)
    }
}

/// A box's `shape`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Shape {
    /// A tall cuboid: cubes stacked to 2.2 units and merged.
    Pillar,
    /// A thin upright slab.
    Plate,
    /// A single cube (a tower layer not merged; the release practically never has one).
    Cube,
}

impl Shape {
    /// Every shape, in the order above.
    pub const ALL: [Shape; 3] = [Shape::Pillar, Shape::Plate, Shape::Cube];

    /// The release's word (`Pillar`), as names and `shape` spell it.
    pub fn as_str(self) -> &'static str {
        match self {
            Shape::Pillar => "Pillar",
            Shape::Plate => "Plate",
            Shape::Cube => "Cube",
        }
    }

    /// The shape the release's word names.
    pub fn parse(text: &str) -> Option<Shape> {
        Shape::ALL.into_iter().find(|shape| shape.as_str() == text)
    }

    /// The word questions use (`plate`).
    pub fn word(self) -> &'static str {
        match self {
            Shape::Pillar => "pillar",
            Shape::Plate => "plate",
            Shape::Cube => "cube",
        }
    }
}

/// A parsed box name.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct BoxName {
    /// The palette name of its colour (`Light Blue`).
    pub color: &'static str,
    /// Its shape.
    pub shape: Shape,
}

/// `<C> <Shape>`: `Green Plate`.
pub fn box_name(color: &str, shape: Shape) -> String {
    format!("{color} {}", shape.as_str())
}

/// Parses a box name; `None` unless it is a palette name, a space and a shape word.
pub fn parse_box_name(name: &str) -> Option<BoxName> {
    let (color, shape) = name.rsplit_once(' ')?;
    let shape = Shape::parse(shape)?;
    let color = PALETTE_NAMES.iter().find(|palette| **palette == color)?;
    Some(BoxName { color, shape })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn box_names_parse_as_the_release_spells_them() {
        assert_eq!(
            parse_box_name("Light Blue Pillar"),
            Some(BoxName {
                color: "Light Blue",
                shape: Shape::Pillar
            })
        );
        assert_eq!(
            parse_box_name(&box_name("Green", Shape::Plate)),
            Some(BoxName {
                color: "Green",
                shape: Shape::Plate
            })
        );
        for bad in [
            "Teal Plate",
            "Green plate",
            "Green Slab",
            "Plate",
            "Cloth (Left)",
        ] {
            assert_eq!(parse_box_name(bad), None, "{bad}");
        }
    }

    #[test]
    fn cloth_names_and_keys_follow_the_side() {
        assert_eq!(Side::of_cloth_name("Cloth (Right)"), Some(Side::Right));
        assert_eq!(Side::of_cloth_name("Cloth (Middle)"), None);
        assert_eq!(
            (Side::Left.cloth_key(), Side::Left.objects_key()),
            ("clothLeft", "leftAll")
        );
        assert_eq!(Side::Right.other(), Side::Left);
    }
}

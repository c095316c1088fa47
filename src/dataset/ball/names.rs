//! The grammar of ball-scene object names, as the release's generator builds them
//! (`docs/data/ball.md`): `<C> Ball`, `<C> Floating Wall`, `Left Ramp` / `Right Ramp` (their
//! colours are not in their names) and `Floor Piece 1st` / `2nd` / `3rd`. `<C>` is a palette
//! name. This module builds the names too, so the generator and the readers spell them one way.

use serde::Serialize;

use crate::dataset::palette::PALETTE_NAMES;

/// The floor pieces' names, left to right.
pub const FLOOR_PIECES: [&str; 3] = ["Floor Piece 1st", "Floor Piece 2nd", "Floor Piece 3rd"];
/// The ramps' names: the right one first, as the release samples them.
pub const RAMPS: [&str; 2] = ["Right Ramp", "Left Ramp"];

/// What a ball-scene object is.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum BallObjectKind {
    /// `<C> Ball`.
    Ball,
    /// `<C> Floating Wall`.
    FloatingWall,
    /// `Left Ramp` or `Right Ramp`.
    Ramp,
    /// `Floor Piece 1st` …
    FloorPiece,
}

/// A parsed ball-scene object name.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct BallObjectName {
    /// The kind.
    pub kind: BallObjectKind,
    /// The palette name, for balls and floating walls.
    pub color: Option<&'static str>,
}

/// `<C> Ball`.
pub fn ball_name(color: &str) -> String {
    format!("{color} Ball")
}

/// `<C> Floating Wall`.
pub fn floating_wall_name(color: &str) -> String {
    format!("{color} Floating Wall")
}

/// Parses a ball-scene object name; `None` when it follows none of the release's patterns.
pub fn parse_ball_object_name(name: &str) -> Option<BallObjectName> {
    if RAMPS.contains(&name) {
        return Some(BallObjectName {
            kind: BallObjectKind::Ramp,
            color: None,
        });
    }
    if FLOOR_PIECES.contains(&name) {
        return Some(BallObjectName {
            kind: BallObjectKind::FloorPiece,
            color: None,
        });
    }
    let (color, kind) = if let Some(color) = name.strip_suffix(" Floating Wall") {
        (color, BallObjectKind::FloatingWall)
    } else {
        (name.strip_suffix(" Ball")?, BallObjectKind::Ball)
    };
    let color = PALETTE_NAMES.iter().find(|palette| **palette == color)?;
    Some(BallObjectName {
        kind,
        color: Some(color),
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_parse_as_the_release_spells_them() {
        let ball = parse_ball_object_name("Light Blue Ball").unwrap();
        assert_eq!(
            (ball.kind, ball.color),
            (BallObjectKind::Ball, Some("Light Blue"))
        );
        let wall = parse_ball_object_name(&floating_wall_name("Red")).unwrap();
        assert_eq!(
            (wall.kind, wall.color),
            (BallObjectKind::FloatingWall, Some("Red"))
        );
        assert_eq!(
            parse_ball_object_name("Left Ramp").map(|n| n.kind),
            Some(BallObjectKind::Ramp)
        );
        assert_eq!(
            parse_ball_object_name("Floor Piece 2nd").map(|n| n.kind),
            Some(BallObjectKind::FloorPiece)
        );
        for bad in [
            "Teal Ball",
            "Red ball",
            "Red Wall",
            "Floor Piece 4th",
            "Ball",
        ] {
            assert_eq!(parse_ball_object_name(bad), None, "{bad}");
        }
    }
}

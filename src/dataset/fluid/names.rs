//! The grammar of fluid object names, as the release's generator builds them
//! (`docs/data/fluid.md`): `<C> Fluid` and its emitter `<C> Fluid Emitter`, a predictive emitter's
//! fluid `Later Emitted <C> Fluid`, `<C> Stick`, `<C> Container` with its parts
//! (`<C> Container Left Guided Stick`, `… Bottom Floor`, …), and the tank's walls. `<C>` is a
//! palette name (`docs/data/common.md`, colour palette), one or two words (`Light Blue`).
//!
//! Besides parsing ([`parse_fluid_object_name`]), this module builds the names, so the generator
//! and the readers spell them one way.

use serde::Serialize;

pub use crate::dataset::palette::{PALETTE_NAMES, palette_name};

/// The prefix that names a predictive emitter's fluid (`Later Emitted Blue Fluid`).
pub const LATER_EMITTED_PREFIX: &str = "Later Emitted ";

/// A part of a container (a receptor): its cup walls and the two guided sticks of its funnel.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum ContainerPart {
    /// `<C> Container Left Guided Stick`: the funnel's left side.
    LeftGuidedStick,
    /// `<C> Container Right Guided Stick`: the funnel's right side.
    RightGuidedStick,
    /// `<C> Container Bottom Floor`: the cup's floor.
    BottomFloor,
    /// `<C> Container Left Vertical Wall`: the cup's left wall.
    LeftVerticalWall,
    /// `<C> Container Right Vertical Wall`: the cup's right wall.
    RightVerticalWall,
}

impl ContainerPart {
    /// Every part, in the order the parser tries them.
    pub const ALL: [ContainerPart; 5] = [
        ContainerPart::LeftGuidedStick,
        ContainerPart::RightGuidedStick,
        ContainerPart::BottomFloor,
        ContainerPart::LeftVerticalWall,
        ContainerPart::RightVerticalWall,
    ];

    /// The words after `<C> Container ` (`Left Guided Stick`).
    pub fn suffix(self) -> &'static str {
        match self {
            ContainerPart::LeftGuidedStick => "Left Guided Stick",
            ContainerPart::RightGuidedStick => "Right Guided Stick",
            ContainerPart::BottomFloor => "Bottom Floor",
            ContainerPart::LeftVerticalWall => "Left Vertical Wall",
            ContainerPart::RightVerticalWall => "Right Vertical Wall",
        }
    }
}

/// A wall of the tank.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum TankWall {
    /// `Left Vertical Wall`.
    Left,
    /// `Right Vertical Wall`.
    Right,
    /// `Floor`.
    Floor,
    /// `Ceiling` (does not collide in the release).
    Ceiling,
}

impl TankWall {
    /// Every wall.
    pub const ALL: [TankWall; 4] = [
        TankWall::Left,
        TankWall::Right,
        TankWall::Floor,
        TankWall::Ceiling,
    ];

    /// The wall's object name.
    pub fn name(self) -> &'static str {
        match self {
            TankWall::Left => "Left Vertical Wall",
            TankWall::Right => "Right Vertical Wall",
            TankWall::Floor => "Floor",
            TankWall::Ceiling => "Ceiling",
        }
    }
}

/// The kind of a fluid-scene object.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case", tag = "kind", content = "part")]
pub enum FluidObjectKind {
    /// A fluid (`<C> Fluid`, or `Later Emitted <C> Fluid` for a predictive emitter's fluid).
    Fluid,
    /// An emitter (`<fluid> Emitter`).
    Emitter,
    /// A regular stick (a ramp): `<C> Stick`.
    Stick,
    /// A container (a receptor): `<C> Container`.
    Container,
    /// A part of a container.
    ContainerPart(ContainerPart),
    /// A wall of the tank (no colour).
    TankWall(TankWall),
}

/// A fluid-scene object name split into its parts.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct FluidObjectName {
    /// The name as written.
    pub full: String,
    /// The palette name (`Light Blue`); `None` for the tank's walls.
    pub color: Option<&'static str>,
    /// Whether the name has the [`LATER_EMITTED_PREFIX`] (fluids and emitters only).
    pub later: bool,
    /// The object's kind.
    pub kind: FluidObjectKind,
}

impl FluidObjectName {
    /// The colour as questions write it, lower case (`light blue`).
    pub fn color_word(&self) -> Option<String> {
        self.color.map(str::to_lowercase)
    }
}

/// Parses a fluid-scene object name; `None` for names outside the generator's grammar (emitter
/// parts such as `Blue Fluid Emitter Right Wall`, `Solver`, `Background`, an unknown colour).
pub fn parse_fluid_object_name(name: &str) -> Option<FluidObjectName> {
    if let Some(wall) = TankWall::ALL.into_iter().find(|wall| wall.name() == name) {
        return Some(FluidObjectName {
            full: name.to_string(),
            color: None,
            later: false,
            kind: FluidObjectKind::TankWall(wall),
        });
    }
    let (later, rest) = match name.strip_prefix(LATER_EMITTED_PREFIX) {
        Some(rest) => (true, rest),
        None => (false, name),
    };
    // Container parts first: `… Left Guided Stick` also ends in ` Stick`.
    let mut endings: Vec<(String, FluidObjectKind)> = ContainerPart::ALL
        .into_iter()
        .map(|part| {
            (
                format!(" Container {}", part.suffix()),
                FluidObjectKind::ContainerPart(part),
            )
        })
        .collect();
    endings.extend([
        (" Fluid Emitter".to_string(), FluidObjectKind::Emitter),
        (" Fluid".to_string(), FluidObjectKind::Fluid),
        (" Stick".to_string(), FluidObjectKind::Stick),
        (" Container".to_string(), FluidObjectKind::Container),
    ]);
    for (ending, kind) in endings {
        let Some(color_words) = rest.strip_suffix(ending.as_str()) else {
            continue;
        };
        let Some(color) = PALETTE_NAMES.iter().find(|p| **p == color_words).copied() else {
            continue;
        };
        let emitted = matches!(kind, FluidObjectKind::Fluid | FluidObjectKind::Emitter);
        if later && !emitted {
            return None;
        }
        return Some(FluidObjectName {
            full: name.to_string(),
            color: Some(color),
            later,
            kind,
        });
    }
    None
}

/// `name` without the [`LATER_EMITTED_PREFIX`]: the fluid a predictive emitter emits
/// (`Later Emitted Blue Fluid` → `Blue Fluid`).
pub fn base_fluid_name(name: &str) -> &str {
    name.strip_prefix(LATER_EMITTED_PREFIX).unwrap_or(name)
}

/// `<C> Fluid`.
pub fn fluid_name(color: &str) -> String {
    format!("{color} Fluid")
}

/// `Later Emitted <C> Fluid`: the fluid key of `<C> Fluid`'s predictive emitter.
pub fn later_fluid_name(color: &str) -> String {
    format!("{LATER_EMITTED_PREFIX}{color} Fluid")
}

/// `<fluid> Emitter`: the emitter of a fluid key (`Later Emitted Blue Fluid Emitter`).
pub fn emitter_name(fluid: &str) -> String {
    format!("{fluid} Emitter")
}

/// `<C> Stick`.
pub fn stick_name(color: &str) -> String {
    format!("{color} Stick")
}

/// `<C> Container`.
pub fn container_name(color: &str) -> String {
    format!("{color} Container")
}

/// `<container> <part>` (`Red Container Left Guided Stick`).
pub fn container_part_name(container: &str, part: ContainerPart) -> String {
    format!("{container} {}", part.suffix())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_follow_the_generator_grammar() {
        use ContainerPart::{BottomFloor, LeftGuidedStick, RightVerticalWall};
        use FluidObjectKind::{Container, Emitter, Fluid, Stick};
        // (name, colour, later, kind)
        let cases = [
            ("Pink Fluid", Some("Pink"), false, Fluid),
            ("Light Blue Fluid", Some("Light Blue"), false, Fluid),
            (
                "Later Emitted Light Blue Fluid",
                Some("Light Blue"),
                true,
                Fluid,
            ),
            ("Yellow Fluid Emitter", Some("Yellow"), false, Emitter),
            (
                "Later Emitted Yellow Fluid Emitter",
                Some("Yellow"),
                true,
                Emitter,
            ),
            ("Brown Stick", Some("Brown"), false, Stick),
            ("Gray Container", Some("Gray"), false, Container),
            (
                "Red Container Left Guided Stick",
                Some("Red"),
                false,
                FluidObjectKind::ContainerPart(LeftGuidedStick),
            ),
            (
                "Red Container Bottom Floor",
                Some("Red"),
                false,
                FluidObjectKind::ContainerPart(BottomFloor),
            ),
            (
                "Light Purple Container Right Vertical Wall",
                Some("Light Purple"),
                false,
                FluidObjectKind::ContainerPart(RightVerticalWall),
            ),
            (
                "Left Vertical Wall",
                None,
                false,
                FluidObjectKind::TankWall(TankWall::Left),
            ),
            (
                "Floor",
                None,
                false,
                FluidObjectKind::TankWall(TankWall::Floor),
            ),
        ];
        for (name, color, later, kind) in cases {
            let parsed = parse_fluid_object_name(name).unwrap_or_else(|| panic!("{name}"));
            assert_eq!(
                (parsed.color, parsed.later, parsed.kind),
                (color, later, kind),
                "{name}"
            );
            assert_eq!(parsed.full, name);
        }
        assert_eq!(
            parse_fluid_object_name("Light Blue Fluid")
                .unwrap()
                .color_word()
                .as_deref(),
            Some("light blue")
        );
        for not_an_object in [
            "Blue Fluid Emitter Right Wall",
            "Solver",
            "Background",
            "Fluid",
            "Teal Fluid",
            "blue fluid",
            "Later Emitted Blue Stick",
            "Later Emitted Floor",
            "Red Container Top Floor",
        ] {
            assert!(
                parse_fluid_object_name(not_an_object).is_none(),
                "{not_an_object}"
            );
        }
    }

    #[test]
    fn builders_spell_what_the_parser_reads() {
        assert_eq!(fluid_name("Blue"), "Blue Fluid");
        assert_eq!(later_fluid_name("Blue"), "Later Emitted Blue Fluid");
        assert_eq!(
            emitter_name(&later_fluid_name("Blue")),
            "Later Emitted Blue Fluid Emitter"
        );
        assert_eq!(stick_name("Gray"), "Gray Stick");
        assert_eq!(
            container_part_name(&container_name("Red"), ContainerPart::RightGuidedStick),
            "Red Container Right Guided Stick"
        );
        assert_eq!(base_fluid_name("Later Emitted Blue Fluid"), "Blue Fluid");
        assert_eq!(base_fluid_name("Blue Fluid"), "Blue Fluid");
        assert_eq!(palette_name(12), Some("Light Blue"));
        assert_eq!(palette_name(16), Some("Light Purple"));
        assert_eq!(palette_name(17), None);
        assert_eq!(palette_name(-1), None);
    }
}

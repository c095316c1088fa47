//! Scene objects as the API exposes them: colour, kind and the attributes of their scenario's
//! vocabulary (rope: pulley shape, dynamics, grid id).

use serde::Serialize;

use crate::dataset::Vocabulary;

/// An object's index in its scene's object list.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
pub struct ObjectId(pub u32);

/// What a program can read about an object. Text fields are lower case.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct SceneObjectInfo {
    /// Its index in the scene.
    pub id: ObjectId,
    /// The annotation name (`Blue Solid Static Pulley (0 1)`).
    pub name: String,
    /// Colour words (`blue`, `light blue`).
    pub color: String,
    /// The object's kind, one of its scenario vocabulary's kinds (`pulley`).
    pub kind: &'static str,
    /// Every attribute of the scenario's vocabulary (its suffix attribute last), with the
    /// object's value or `None` when it has none (a cube has no pulley shape).
    pub attributes: Vec<ObjectAttribute>,
    /// Whether perception found it (always with `--perception annotation`); `find` returns
    /// only objects that were found.
    #[serde(skip)]
    pub visible: bool,
    /// Colour words perception gives this object as second choices, likeliest first
    /// (`--perception maskrcnn`): `find` names the object by one of them when no object was read
    /// in that colour (a red stick read as brown is still the red stick a program asks for).
    #[serde(skip)]
    pub other_colors: Vec<String>,
}

/// One attribute of an object.
#[derive(Debug, Clone, PartialEq, Eq, Serialize)]
pub struct ObjectAttribute {
    /// The attribute (`shape`).
    pub name: &'static str,
    /// The object's value (`solid`); `None` when it has none.
    pub value: Option<String>,
    /// Whether the value is part of the object's short name (`blue solid pulley`).
    #[serde(skip)]
    pub in_name: bool,
    /// Whether programs read it as a `SceneObject` attribute (a suffix attribute, such as
    /// rope's grid id, is matched by `find`'s `(…)` only).
    #[serde(skip)]
    pub readable: bool,
}

impl SceneObjectInfo {
    /// An object of a scene with `vocabulary`: `attributes` gives the values it has (others are
    /// `None`). It is visible.
    pub fn new(
        id: ObjectId,
        name: &str,
        color: &str,
        kind: &'static str,
        attributes: &[(&str, String)],
        vocabulary: &Vocabulary,
    ) -> SceneObjectInfo {
        let value = |attribute: &str| {
            attributes
                .iter()
                .find(|(name, _)| *name == attribute)
                .map(|(_, value)| value.clone())
        };
        let mut all: Vec<ObjectAttribute> = vocabulary
            .attributes
            .iter()
            .map(|attribute| ObjectAttribute {
                name: attribute.name,
                value: value(attribute.name),
                in_name: attribute.in_name,
                readable: true,
            })
            .collect();
        if let Some(suffix) = &vocabulary.suffix {
            all.push(ObjectAttribute {
                name: suffix.attribute,
                value: value(suffix.attribute),
                in_name: false,
                readable: false,
            });
        }
        SceneObjectInfo {
            id,
            name: name.to_string(),
            color: color.to_string(),
            kind,
            attributes: all,
            visible: true,
            other_colors: Vec::new(),
        }
    }

    /// The value of attribute `name`; `None` when the object has none or the scenario has no
    /// such attribute.
    pub fn attribute(&self, name: &str) -> Option<&str> {
        self.attributes
            .iter()
            .find(|attribute| attribute.name == name)
            .and_then(|attribute| attribute.value.as_deref())
    }

    /// Whether programs can read attribute `name` of the scenario's objects (see
    /// [`ObjectAttribute::readable`]).
    pub fn has_readable_attribute(&self, name: &str) -> bool {
        self.attributes
            .iter()
            .any(|attribute| attribute.name == name && attribute.readable)
    }

    /// Sets attribute `name` (an attribute of the scenario; others are ignored).
    pub fn set_attribute(&mut self, name: &str, value: Option<String>) {
        if let Some(slot) = self
            .attributes
            .iter_mut()
            .find(|attribute| attribute.name == name)
        {
            slot.value = value;
        }
    }

    /// The short name used in questions: colour, the values shown in names, kind (`blue solid
    /// pulley`, `purple cube`).
    pub fn describe(&self) -> String {
        // Objects without a colour (a ball scene's pits) start with their attributes.
        let mut words: Vec<&str> = Some(self.color.as_str())
            .filter(|color| !color.is_empty())
            .into_iter()
            .collect();
        words.extend(
            self.attributes
                .iter()
                .filter(|attribute| attribute.in_name)
                .filter_map(|attribute| attribute.value.as_deref()),
        );
        words.push(self.kind);
        words.join(" ")
    }
}

//! Scene objects as the API exposes them.

use serde::Serialize;

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
    /// The object class (`cube`, `sphere`, `pulley`, `rope`, `fixed point`).
    pub kind: String,
    /// Pulley shape (`solid` or `hollow`); `None` for other kinds.
    pub shape: Option<String>,
    /// `static` or `dynamic`.
    pub dynamics: String,
    /// Grid id `(layer, column)` of pulleys.
    pub grid: Option<(i32, i32)>,
    /// Whether perception found it (always with `--perception annotation`); `find` returns
    /// only objects that were found.
    #[serde(skip)]
    pub visible: bool,
}

impl SceneObjectInfo {
    /// The short name used in questions (`blue solid pulley`, `purple cube`).
    pub fn describe(&self) -> String {
        match &self.shape {
            Some(shape) => format!("{} {shape} {}", self.color, self.kind),
            None => format!("{} {}", self.color, self.kind),
        }
    }
}

//! Detector classes: the labels a model's description file gives its classes, and what each class
//! means in a scenario (its kind and attribute words).
//!
//! A model ships with a description (`<model>.json` beside `<model>.onnx`) whose `classes` map
//! label ids to class names (`"5": "solid static pulley"`). A scenario lists its classes with
//! their words ([`ScenarioClasses`], `perception/<scenario>/`). [`ClassTable::bind`] joins the two:
//! the model's labels that the scenario knows become [`Class`]es, so one model across scenarios or
//! one model per scenario both load, and a detection of a class the scenario does not know is
//! dropped. Input: a description file and a scenario's classes. Output: the table detections,
//! tracks, evaluation and the scene API read class words from.

use std::path::{Path, PathBuf};

/// One class as a scenario reads it.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct ClassWords {
    /// The class name in model descriptions (`solid static pulley`).
    pub name: &'static str,
    /// The scene kind it is (`pulley`), a kind of the scenario's vocabulary.
    pub kind: &'static str,
    /// The attribute values it carries (`shape` = `solid`, `dynamic` = `static`), attributes of
    /// the scenario's vocabulary.
    pub attributes: &'static [(&'static str, &'static str)],
    /// The palette ids objects of the class can have (the release's colour pools); empty when
    /// any. Colour reading chooses among these only: the release never paints a pulley black,
    /// so a dark gray pulley in dim light is gray, not black.
    pub colors: &'static [u8],
    /// Whether an object of the class shows as separate pieces (a fluid spread over several
    /// ramps and cups): the detector finds each connected piece, so each piece of the object's
    /// ground-truth mask is one truth instance ([`super::truth::pieces`]).
    pub pieces: bool,
    /// Whether no two objects of the class share a colour (the release paints them from their
    /// own shuffled pool), so two tracks of it read in one colour are a misreading
    /// (`perception::distinct`).
    pub distinct_colors: bool,
}

/// The object a ground-truth segmentation instance belongs to.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct TruthObject {
    /// The object's name; instances naming one object make one truth mask (a container drawn as
    /// its floor, walls and funnel sticks).
    pub name: String,
    /// Its palette colour, from the instance name's colour words.
    pub color: Option<u8>,
}

/// Each instance its own object, coloured by its name's first words (`Light Blue Rope` → 12).
pub fn instance_is_object(name: &str) -> TruthObject {
    TruthObject {
        name: name.to_string(),
        color: super::color::palette_id_of_name(name),
    }
}

/// A scenario's detector classes.
#[derive(Debug, Clone, Copy)]
pub struct ScenarioClasses {
    /// Every class the scenario's objects fall into, in the order reports list them.
    pub classes: &'static [ClassWords],
    /// The class name of a release object name (`Pink Hollow Static Pulley (0 5)` → `hollow
    /// static pulley`), for ground truth; `None` for objects that are no class (`Solver`).
    pub class_of_object: fn(&str) -> Option<&'static str>,
    /// The object a release segmentation instance is part of, with its colour, for ground
    /// truth ([`instance_is_object`] when every instance is an object).
    pub truth_object: fn(&str) -> TruthObject,
}

impl ScenarioClasses {
    /// The words of class `name`.
    pub fn words(&self, name: &str) -> Option<&'static ClassWords> {
        let classes: &'static [ClassWords] = self.classes;
        classes.iter().find(|class| class.name == name)
    }
}

/// A class as detections carry it: the model's label, and which of the table's kinds it is (so
/// tracking can compare kinds without the table).
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub struct Class {
    label: u16,
    kind: u16,
}

/// A class serialises as its label.
impl serde::Serialize for Class {
    fn serialize<S: serde::Serializer>(&self, serializer: S) -> Result<S::Ok, S::Error> {
        serializer.serialize_u16(self.label)
    }
}

impl Class {
    /// The model's label id.
    pub fn label(self) -> u16 {
        self.label
    }

    /// Whether the two classes are of one kind (`solid static pulley` and `hollow dynamic
    /// pulley` are both pulleys).
    pub fn same_kind(self, other: Class) -> bool {
        self.kind == other.kind
    }
    /// A class of its own kind with `label`, for tests that need no model description.
    #[cfg(test)]
    pub(crate) fn for_tests(label: u16) -> Class {
        Class { label, kind: label }
    }
}

/// Why a model's classes could not be read.
#[derive(Debug, Clone, PartialEq, Eq, thiserror::Error)]
pub enum ClassError {
    /// The description file is missing or unreadable.
    #[error("cannot read the model description {path}: {message}")]
    Read {
        /// The description file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
    /// The description has no usable `classes` map.
    #[error("model description {path}: {problem}")]
    Format {
        /// The description file.
        path: PathBuf,
        /// What is wrong.
        problem: String,
    },
    /// No class of the model is a class of the scenario.
    #[error(
        "model description {path} names none of the classes this scenario's objects fall into ({known})"
    )]
    NoneKnown {
        /// The description file.
        path: PathBuf,
        /// The scenario's class names.
        known: String,
    },
}

/// The description file of a model: `<model>.json` beside `<model>.onnx`.
pub fn description_path(model: &Path) -> PathBuf {
    model.with_extension("json")
}

/// The `classes` of a description file: label → name, in label order.
pub fn read_classes(path: &Path) -> Result<Vec<(u16, String)>, ClassError> {
    let text = fs_err::read_to_string(path).map_err(|error| ClassError::Read {
        path: path.to_path_buf(),
        message: error.to_string(),
    })?;
    let format = |problem: String| ClassError::Format {
        path: path.to_path_buf(),
        problem,
    };
    let value: serde_json::Value =
        serde_json::from_str(&text).map_err(|error| format(format!("not JSON: {error}")))?;
    let classes = value
        .get("classes")
        .and_then(serde_json::Value::as_object)
        .ok_or_else(|| format("has no `classes` object of label → name".to_string()))?;
    let mut out = Vec::with_capacity(classes.len());
    for (label, name) in classes {
        let label = label
            .parse::<u16>()
            .ok()
            .filter(|label| *label > 0)
            .ok_or_else(|| {
                format(format!(
                    "class label `{label}` is not a positive whole number"
                ))
            })?;
        let name = name
            .as_str()
            .ok_or_else(|| format(format!("class {label} has no name")))?;
        out.push((label, name.to_string()));
    }
    out.sort_by_key(|(label, _)| *label);
    Ok(out)
}

/// A model's classes as one scenario reads them.
#[derive(Debug, Clone)]
pub struct ClassTable {
    /// Per known label: the class and its words, in label order.
    entries: Vec<(Class, &'static ClassWords)>,
    /// The distinct kinds, indexed by [`Class`]'s kind.
    kinds: Vec<&'static str>,
    scenario: ScenarioClasses,
}

impl ClassTable {
    /// The model's labels (`classes`, label → name) that `scenario` knows; the others are left
    /// out, so their detections are dropped.
    pub fn bind(
        classes: &[(u16, String)],
        scenario: ScenarioClasses,
        description: &Path,
    ) -> Result<ClassTable, ClassError> {
        let mut table = ClassTable {
            entries: Vec::new(),
            kinds: Vec::new(),
            scenario,
        };
        for (label, name) in classes {
            if let Some(words) = scenario.words(name) {
                let kind = table.kind_index(words.kind);
                table.entries.push((
                    Class {
                        label: *label,
                        kind,
                    },
                    words,
                ));
            }
        }
        if table.entries.is_empty() {
            return Err(ClassError::NoneKnown {
                path: description.to_path_buf(),
                known: scenario
                    .classes
                    .iter()
                    .map(|c| c.name)
                    .collect::<Vec<_>>()
                    .join(", "),
            });
        }
        Ok(table)
    }

    /// Reads the description of `model` and binds it to `scenario`.
    pub fn for_model(model: &Path, scenario: ScenarioClasses) -> Result<ClassTable, ClassError> {
        let description = description_path(model);
        ClassTable::bind(&read_classes(&description)?, scenario, &description)
    }

    /// The scenario's own classes, labelled 1, 2, … in their order (for ground truth without a
    /// model, and tests).
    pub fn of_scenario(scenario: ScenarioClasses) -> ClassTable {
        let classes: Vec<(u16, String)> = scenario
            .classes
            .iter()
            .zip(1_u16..)
            .map(|(class, label)| (label, class.name.to_string()))
            .collect();
        ClassTable::bind(&classes, scenario, Path::new("(the scenario's classes)"))
            .expect("a scenario knows its own classes")
    }

    fn kind_index(&mut self, kind: &'static str) -> u16 {
        if let Some(index) = self.kinds.iter().position(|k| *k == kind) {
            return u16::try_from(index).unwrap_or(u16::MAX);
        }
        self.kinds.push(kind);
        u16::try_from(self.kinds.len() - 1).unwrap_or(u16::MAX)
    }

    /// The class of a model label; `None` for labels the scenario does not know.
    pub fn class(&self, label: i64) -> Option<Class> {
        self.entries
            .iter()
            .find(|(class, _)| i64::from(class.label) == label)
            .map(|(class, _)| *class)
    }

    /// Every class, in label order.
    pub fn all(&self) -> impl Iterator<Item = Class> + '_ {
        self.entries.iter().map(|(class, _)| *class)
    }

    /// The words of `class`.
    pub fn words(&self, class: Class) -> Option<&'static ClassWords> {
        self.entries
            .iter()
            .find(|(known, _)| *known == class)
            .map(|(_, words)| *words)
    }

    /// The class name (`solid static pulley`); `?` for a class of another table.
    pub fn name(&self, class: Class) -> &'static str {
        self.words(class).map_or("?", |words| words.name)
    }

    /// The kind word (`pulley`).
    pub fn kind(&self, class: Class) -> &'static str {
        self.words(class).map_or("?", |words| words.kind)
    }

    /// The value of attribute `name` (`shape` → `solid`); `None` when the class has none.
    pub fn attribute(&self, class: Class, name: &str) -> Option<&'static str> {
        self.words(class)?
            .attributes
            .iter()
            .find(|(attribute, _)| *attribute == name)
            .map(|(_, value)| *value)
    }

    /// Whether no two objects of `class` share a colour ([`ClassWords::distinct_colors`]).
    pub fn distinct_colors(&self, class: Class) -> bool {
        self.words(class).is_some_and(|words| words.distinct_colors)
    }

    /// The palette ids objects of `class` can have; empty when any.
    pub fn colors(&self, class: Class) -> &'static [u8] {
        self.words(class).map_or(&[], |words| words.colors)
    }

    /// The attribute names any class of the table carries, in first-seen order.
    pub fn attribute_names(&self) -> Vec<&'static str> {
        let mut names: Vec<&'static str> = Vec::new();
        for (_, words) in &self.entries {
            for (name, _) in words.attributes {
                if !names.contains(name) {
                    names.push(name);
                }
            }
        }
        names
    }

    /// Whether objects of `class` are found piece by piece ([`ClassWords::pieces`]).
    pub fn pieces(&self, class: Class) -> bool {
        self.words(class).is_some_and(|words| words.pieces)
    }

    /// The object a release segmentation instance is part of, with its colour (ground truth).
    pub fn truth_object(&self, instance_name: &str) -> TruthObject {
        (self.scenario.truth_object)(instance_name)
    }

    /// The class of a release object name, when the model has it (ground truth).
    pub fn of_object(&self, object_name: &str) -> Option<Class> {
        let name = (self.scenario.class_of_object)(object_name)?;
        self.entries
            .iter()
            .find(|(_, words)| words.name == name)
            .map(|(class, _)| *class)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const WORDS: [ClassWords; 3] = [
        ClassWords {
            name: "cube",
            kind: "cube",
            attributes: &[],
            colors: &[],
            pieces: false,
            distinct_colors: false,
        },
        ClassWords {
            name: "solid pulley",
            kind: "pulley",
            attributes: &[("shape", "solid")],
            colors: &[],
            pieces: false,
            distinct_colors: false,
        },
        ClassWords {
            name: "hollow pulley",
            kind: "pulley",
            attributes: &[("shape", "hollow")],
            colors: &[],
            pieces: false,
            distinct_colors: false,
        },
    ];

    fn object_class(name: &str) -> Option<&'static str> {
        name.ends_with("Cube").then_some("cube")
    }

    const SCENARIO: ScenarioClasses = ScenarioClasses {
        classes: &WORDS,
        class_of_object: object_class,
        truth_object: instance_is_object,
    };

    #[test]
    fn a_model_binds_the_labels_the_scenario_knows() {
        let model = [
            (2, "hollow pulley".to_string()),
            (7, "container".to_string()),
            (1, "cube".to_string()),
            (3, "solid pulley".to_string()),
        ];
        let table = ClassTable::bind(&model, SCENARIO, Path::new("m.json")).unwrap();
        assert_eq!(table.class(7), None);
        let hollow = table.class(2).unwrap();
        let solid = table.class(3).unwrap();
        let cube = table.class(1).unwrap();
        assert!(hollow.same_kind(solid) && !cube.same_kind(solid));
        assert_eq!(
            (table.name(hollow), table.kind(hollow)),
            ("hollow pulley", "pulley")
        );
        assert_eq!(table.attribute(solid, "shape"), Some("solid"));
        assert_eq!(table.attribute(cube, "shape"), None);
        assert_eq!(table.attribute_names(), vec!["shape"]);
        assert_eq!(table.of_object("Red Cube"), Some(cube));
        assert_eq!(table.of_object("Solver"), None);
        let unknown = ClassTable::bind(&[(1, "fluid".into())], SCENARIO, Path::new("m.json"));
        assert!(
            unknown
                .unwrap_err()
                .to_string()
                .contains("names none of the classes"),
        );
    }

    #[test]
    fn descriptions_are_read_and_checked() {
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("m.json");
        fs_err::write(&path, r#"{"classes": {"2": "b", "1": "a"}}"#).unwrap();
        assert_eq!(
            read_classes(&path).unwrap(),
            vec![(1, "a".to_string()), (2, "b".to_string())]
        );
        for (text, problem) in [
            ("{}", "has no `classes`"),
            (r#"{"classes": {"0": "a"}}"#, "label `0`"),
            (r#"{"classes": {"1": 3}}"#, "class 1 has no name"),
            ("[", "not JSON"),
        ] {
            fs_err::write(&path, text).unwrap();
            let error = read_classes(&path).unwrap_err().to_string();
            assert!(error.contains(problem), "{text}: {error}");
        }
        assert!(matches!(
            read_classes(&dir.path().join("none.json")),
            Err(ClassError::Read { .. })
        ));
        assert_eq!(
            description_path(Path::new("models/x.onnx")),
            Path::new("models/x.json")
        );
    }
}

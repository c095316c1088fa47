//! Typed access to a parsed JSON document that remembers where it is, so every error names the
//! file and the dotted field path (`CounterFactualAnnotations.2.0.ResultMotion.Purple Cube`).

use std::path::Path;

use serde_json::Value;

use super::DatasetError;

/// Reads a whole file, naming the path on failure.
pub(crate) fn read_bytes(path: &Path) -> Result<Vec<u8>, DatasetError> {
    #[expect(
        clippy::disallowed_methods,
        reason = "the error below names the path itself"
    )]
    std::fs::read(path).map_err(|source| DatasetError::read(path, source))
}

/// Reads and parses a JSON file.
pub(crate) fn read_json(path: &Path) -> Result<Value, DatasetError> {
    let bytes = read_bytes(path)?;
    serde_json::from_slice(&bytes).map_err(|source| DatasetError::Json {
        path: path.to_path_buf(),
        source,
    })
}

/// A JSON value together with the file it came from and its field path.
#[derive(Clone, Copy)]
pub(crate) struct Node<'a> {
    file: &'a Path,
    path: Option<&'a FieldPath<'a>>,
    value: &'a Value,
}

/// A linked list of path segments (cheap to extend while walking down).
pub(crate) struct FieldPath<'a> {
    parent: Option<&'a FieldPath<'a>>,
    segment: String,
}

impl FieldPath<'_> {
    fn render(&self) -> String {
        match self.parent {
            Some(parent) => format!("{}.{}", parent.render(), self.segment),
            None => self.segment.clone(),
        }
    }
}

impl<'a> Node<'a> {
    /// The document root of `file`.
    pub(crate) fn root(file: &'a Path, value: &'a Value) -> Self {
        Self {
            file,
            path: None,
            value,
        }
    }

    /// The dotted path of this node (empty at the root).
    pub(crate) fn field_path(&self) -> String {
        self.path
            .map_or_else(|| "<root>".to_string(), FieldPath::render)
    }

    /// An error about this node.
    pub(crate) fn error(&self, problem: impl Into<String>) -> DatasetError {
        DatasetError::Field {
            path: self.file.to_path_buf(),
            field: self.field_path(),
            problem: problem.into(),
        }
    }

    /// An error about a missing child `key` of this node.
    fn missing(&self, key: &str) -> DatasetError {
        let field = match self.path {
            Some(path) => format!("{}.{key}", path.render()),
            None => key.to_string(),
        };
        DatasetError::Field {
            path: self.file.to_path_buf(),
            field,
            problem: "is missing".to_string(),
        }
    }

    /// Walks into child `key` (which must exist), calling `visit` with the child node.
    pub(crate) fn field<T>(
        &self,
        key: &str,
        visit: impl FnOnce(Node<'_>) -> Result<T, DatasetError>,
    ) -> Result<T, DatasetError> {
        let object = self.object_map()?;
        let child = object.get(key).ok_or_else(|| self.missing(key))?;
        let path = FieldPath {
            parent: self.path,
            segment: key.to_string(),
        };
        visit(Node {
            file: self.file,
            path: Some(&path),
            value: child,
        })
    }

    /// Like [`Node::field`] but `None` when the key is absent.
    pub(crate) fn optional_field<T>(
        &self,
        key: &str,
        visit: impl FnOnce(Node<'_>) -> Result<T, DatasetError>,
    ) -> Result<Option<T>, DatasetError> {
        let object = self.object_map()?;
        match object.get(key) {
            None => Ok(None),
            Some(child) => {
                let path = FieldPath {
                    parent: self.path,
                    segment: key.to_string(),
                };
                visit(Node {
                    file: self.file,
                    path: Some(&path),
                    value: child,
                })
                .map(Some)
            }
        }
    }

    fn object_map(&self) -> Result<&'a serde_json::Map<String, Value>, DatasetError> {
        self.value
            .as_object()
            .ok_or_else(|| self.error(format!("must be an object, found {}", kind(self.value))))
    }

    /// Visits every `(key, child)` of an object in file order.
    pub(crate) fn entries<T>(
        &self,
        mut visit: impl FnMut(&str, Node<'_>) -> Result<T, DatasetError>,
    ) -> Result<Vec<T>, DatasetError> {
        let object = self.object_map()?;
        let mut out = Vec::with_capacity(object.len());
        for (key, child) in object {
            let path = FieldPath {
                parent: self.path,
                segment: key.clone(),
            };
            out.push(visit(
                key,
                Node {
                    file: self.file,
                    path: Some(&path),
                    value: child,
                },
            )?);
        }
        Ok(out)
    }

    /// Visits every element of an array in order.
    pub(crate) fn items<T>(
        &self,
        mut visit: impl FnMut(Node<'_>) -> Result<T, DatasetError>,
    ) -> Result<Vec<T>, DatasetError> {
        let array = self
            .value
            .as_array()
            .ok_or_else(|| self.error(format!("must be an array, found {}", kind(self.value))))?;
        let mut out = Vec::with_capacity(array.len());
        for (index, child) in array.iter().enumerate() {
            let path = FieldPath {
                parent: self.path,
                segment: index.to_string(),
            };
            out.push(visit(Node {
                file: self.file,
                path: Some(&path),
                value: child,
            })?);
        }
        Ok(out)
    }

    /// The number of elements of an array or entries of an object.
    pub(crate) fn len(&self) -> Result<usize, DatasetError> {
        match self.value {
            Value::Array(items) => Ok(items.len()),
            Value::Object(map) => Ok(map.len()),
            other => Err(self.error(format!("must be an array or object, found {}", kind(other)))),
        }
    }

    pub(crate) fn string(&self) -> Result<String, DatasetError> {
        self.value
            .as_str()
            .map(str::to_string)
            .ok_or_else(|| self.error(format!("must be a string, found {}", kind(self.value))))
    }

    pub(crate) fn boolean(&self) -> Result<bool, DatasetError> {
        self.value
            .as_bool()
            .ok_or_else(|| self.error(format!("must be true or false, found {}", kind(self.value))))
    }

    /// A finite number (NaN and infinities cannot come out of JSON, but huge integers can).
    pub(crate) fn number(&self) -> Result<f64, DatasetError> {
        let number = self
            .value
            .as_f64()
            .ok_or_else(|| self.error(format!("must be a number, found {}", kind(self.value))))?;
        if number.is_finite() {
            Ok(number)
        } else {
            Err(self.error("must be a finite number"))
        }
    }

    /// An integer in `i64` range (Unity writes some integers as floats such as `7.0`).
    pub(crate) fn integer(&self) -> Result<i64, DatasetError> {
        if let Some(integer) = self.value.as_i64() {
            return Ok(integer);
        }
        let number = self.number()?;
        if number.fract() == 0.0 && number.abs() < 9.0e15 {
            #[expect(
                clippy::cast_possible_truncation,
                reason = "checked integral and in range"
            )]
            Ok(number as i64)
        } else {
            Err(self.error(format!("must be an integer, found {number}")))
        }
    }

    /// A result sign: -1, 0 or +1.
    pub(crate) fn sign(&self) -> Result<i8, DatasetError> {
        match self.integer()? {
            -1 => Ok(-1),
            0 => Ok(0),
            1 => Ok(1),
            other => Err(self.error(format!("must be -1, 0 or 1, found {other}"))),
        }
    }

    /// An array of numbers of the given length.
    pub(crate) fn numbers(&self, expected_len: Option<usize>) -> Result<Vec<f64>, DatasetError> {
        let values = self.items(|item| item.number())?;
        match expected_len {
            Some(len) if values.len() != len => {
                Err(self.error(format!("must have {len} numbers, found {}", values.len())))
            }
            _ => Ok(values),
        }
    }
    /// A Unity `Vector3.ToString()` string such as `"(1.23, 0.45, 0.00)"` (the release writes
    /// some vectors this way; `docs/data/common.md`).
    pub(crate) fn unity_vector3(&self) -> Result<[f64; 3], DatasetError> {
        let text = self.string()?;
        parse_unity_vector3(&text).ok_or_else(|| {
            self.error(format!(
                "must be a Unity vector string \"(x, y, z)\" of three finite numbers, found \"{text}\""
            ))
        })
    }

    /// A C# value tuple of two numbers, `{"Item1": a, "Item2": b}`.
    pub(crate) fn number_pair(&self) -> Result<[f64; 2], DatasetError> {
        Ok([
            self.field("Item1", |n| n.number())?,
            self.field("Item2", |n| n.number())?,
        ])
    }
}

/// Parses `"(x, y, z)"`: parentheses, three comma-separated finite numbers, spaces anywhere.
fn parse_unity_vector3(text: &str) -> Option<[f64; 3]> {
    let inner = text.trim().strip_prefix('(')?.strip_suffix(')')?;
    let mut parts = inner.split(',').map(|part| part.trim().parse::<f64>().ok());
    let vector = [parts.next()??, parts.next()??, parts.next()??];
    (parts.next().is_none() && vector.iter().all(|c| c.is_finite())).then_some(vector)
}

/// A short name for the JSON type of `value`, for error messages.
pub(crate) fn kind(value: &Value) -> &'static str {
    match value {
        Value::Null => "null",
        Value::Bool(_) => "a boolean",
        Value::Number(_) => "a number",
        Value::String(_) => "a string",
        Value::Array(_) => "an array",
        Value::Object(_) => "an object",
    }
}

/// Checks that a record's `mode` is `expected` (`FACTUAL_PREDICTIVE`, `COUNTERFACTUAL_`).
pub(crate) fn expect_mode(node: Node<'_>, expected: &str) -> Result<(), DatasetError> {
    let mode = node.string()?;
    if mode == expected {
        Ok(())
    } else {
        Err(node.error(format!("must be `{expected}`, found `{mode}`")))
    }
}

/// `outputLight`: each light's Euler angles in degrees, by light object name, in file order.
pub(crate) fn light_rotations(
    node: Node<'_>,
) -> Result<indexmap::IndexMap<String, [f64; 3]>, DatasetError> {
    Ok(node
        .entries(|name, light| {
            let rotation = light.field("rotation", |r| r.numbers(Some(3)))?;
            Ok((name.to_string(), [rotation[0], rotation[1], rotation[2]]))
        })?
        .into_iter()
        .collect())
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn errors_name_file_and_dotted_field() {
        let value = json!({"a": {"b": [1, "x"]}});
        let root = Node::root(Path::new("outputs.json"), &value);
        let error = root
            .field("a", |a| a.field("b", |b| b.items(|item| item.number())))
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "`outputs.json`: field `a.b.1` must be a number, found a string"
        );
        let missing = root
            .field("a", |a| a.field("c", |c| c.string()))
            .unwrap_err();
        assert_eq!(
            missing.to_string(),
            "`outputs.json`: field `a.c` is missing"
        );
    }

    #[test]
    fn unity_vectors_parse_and_bad_ones_name_the_field() {
        let cases = [
            ("(1.23, 0.45, 0.00)", Some([1.23, 0.45, 0.0])),
            ("(-2.5,3,1e-2)", Some([-2.5, 3.0, 0.01])),
            (" ( 0.00 , -0.10 , 7.00 ) ", Some([0.0, -0.1, 7.0])),
            ("(1.0, 2.0)", None),
            ("(1.0, 2.0, 3.0, 4.0)", None),
            ("1.0, 2.0, 3.0", None),
            ("(1.0, x, 3.0)", None),
            ("(NaN, 0, 0)", None),
            ("(inf, 0, 0)", None),
        ];
        for (text, expected) in cases {
            assert_eq!(parse_unity_vector3(text), expected, "{text}");
        }
        let value =
            json!({"stick": {"position": "(1.0, 2.0)", "startP": {"Item1": 0.5, "Item2": -1}}});
        let root = Node::root(Path::new("outputs.json"), &value);
        let error = root
            .field("stick", |n| n.field("position", |p| p.unity_vector3()))
            .unwrap_err();
        assert_eq!(
            error.to_string(),
            "`outputs.json`: field `stick.position` must be a Unity vector string \"(x, y, z)\" of three finite numbers, found \"(1.0, 2.0)\""
        );
        let pair = root
            .field("stick", |n| n.field("startP", |p| p.number_pair()))
            .unwrap();
        assert_eq!(pair.map(f64::to_bits), [0.5_f64, -1.0].map(f64::to_bits));
    }

    #[test]
    fn integers_accept_unity_floats_but_not_fractions() {
        let value = json!([7.0, 7.5, -1, 2]);
        let root = Node::root(Path::new("f.json"), &value);
        let results: Vec<_> = root.items(|item| Ok(item.integer().ok())).unwrap();
        assert_eq!(results, vec![Some(7), None, Some(-1), Some(2)]);
        assert!(root.items(|item| item.sign()).is_err());
    }
}

//! `SandboxValue`: a program's result, copied out of the interpreter into plain Rust data.
//!
//! Input is the Python object a program returned (or assigned to `answer`); output is a
//! serde-serialisable tree the `answer` module normalises. Conversion is bounded by
//! [`ValueLimits`] (depth, node count, text bytes, integer digits), so a huge or deeply nested
//! result fails as [`Error::ResultTooLarge`] instead of exhausting the worker or the JSON line.
//! Non-finite floats serialise as the strings `"nan"`, `"inf"` and `"-inf"`, never as invalid JSON.

use indexmap::IndexMap;
use rustpython_vm::builtins::{PyDict, PyFloat, PyInt, PyList, PyStr, PyTuple};
use rustpython_vm::{AsObject, PyObjectRef, VirtualMachine};
use serde::{Deserialize, Serialize};

use super::error::Error;
use super::limits::ValueLimits;

/// Nesting ceiling whatever the request asks for: each level of a [`SandboxValue`] is two levels
/// of JSON, and the parent's JSON parser refuses more than 128.
const MAX_DEPTH_CEILING: usize = 48;

/// A program's result in plain data. Serialised adjacently tagged: `{"type": "int", "value": 3}`.
#[derive(Debug, Clone, PartialEq, Serialize, Deserialize)]
#[serde(tag = "type", content = "value", rename_all = "snake_case")]
pub enum SandboxValue {
    /// Python `None`.
    None,
    /// `True` / `False`.
    Bool(bool),
    /// An `int` of any size.
    Int(IntValue),
    /// A `float`; NaN and infinities are kept (and serialised as strings).
    Float(#[serde(with = "float_serde")] f64),
    /// A `str` (lone surrogates replaced by U+FFFD).
    Str(String),
    /// A `list`.
    List(Vec<SandboxValue>),
    /// A `tuple`.
    Tuple(Vec<SandboxValue>),
    /// A `dict` whose keys are all strings, in insertion order.
    Dict(IndexMap<String, SandboxValue>),
    /// Anything else (host objects, sets, user classes, dicts with non-string keys): its type
    /// name and a bounded `repr`.
    Object {
        /// `type(value).__name__`.
        type_name: String,
        /// `repr(value)`, cut to [`ValueLimits::max_repr_chars`].
        repr: String,
    },
}

/// An integer: an `i64` when it fits, otherwise its decimal digits.
#[derive(Debug, Clone, PartialEq, Eq, Serialize, Deserialize)]
#[serde(untagged)]
pub enum IntValue {
    /// Fits in 64 bits.
    Small(i64),
    /// Decimal digits, with a leading `-` when negative.
    Big(String),
}

impl SandboxValue {
    /// The value as plain JSON, the form predictions store and answers are read from: `None` →
    /// null, numbers as numbers (non-finite floats and integers beyond 64 bits as strings),
    /// lists and tuples as arrays, dicts as objects, other objects as `{"type", "repr"}`.
    pub fn to_plain_json(&self) -> serde_json::Value {
        use serde_json::Value;
        match self {
            SandboxValue::None => Value::Null,
            SandboxValue::Bool(flag) => Value::Bool(*flag),
            SandboxValue::Int(IntValue::Small(number)) => Value::from(*number),
            SandboxValue::Int(IntValue::Big(digits)) => Value::String(digits.clone()),
            SandboxValue::Float(number) => serde_json::Number::from_f64(*number).map_or_else(
                || Value::String(format!("{number}").to_lowercase()),
                Value::Number,
            ),
            SandboxValue::Str(text) => Value::String(text.clone()),
            SandboxValue::List(items) | SandboxValue::Tuple(items) => {
                Value::Array(items.iter().map(SandboxValue::to_plain_json).collect())
            }
            SandboxValue::Dict(entries) => Value::Object(
                entries
                    .iter()
                    .map(|(key, value)| (key.clone(), value.to_plain_json()))
                    .collect(),
            ),
            SandboxValue::Object { type_name, repr } => {
                serde_json::json!({ "type": type_name, "repr": repr })
            }
        }
    }

    /// The Python type name of the value, as `type(value).__name__` would say.
    pub fn type_name(&self) -> &str {
        match self {
            SandboxValue::None => "NoneType",
            SandboxValue::Bool(_) => "bool",
            SandboxValue::Int(_) => "int",
            SandboxValue::Float(_) => "float",
            SandboxValue::Str(_) => "str",
            SandboxValue::List(_) => "list",
            SandboxValue::Tuple(_) => "tuple",
            SandboxValue::Dict(_) => "dict",
            SandboxValue::Object { type_name, .. } => type_name,
        }
    }
}

/// Serde helpers that keep non-finite floats out of JSON numbers.
mod float_serde {
    use serde::{Deserialize, Deserializer, Serializer};

    #[derive(Deserialize)]
    #[serde(untagged)]
    enum FloatRepr {
        Number(f64),
        Named(String),
    }

    #[expect(
        clippy::trivially_copy_pass_by_ref,
        reason = "serde's `with` attribute passes the field by reference"
    )]
    pub(super) fn serialize<S: Serializer>(value: &f64, serializer: S) -> Result<S::Ok, S::Error> {
        if value.is_nan() {
            serializer.serialize_str("nan")
        } else if value.is_infinite() {
            serializer.serialize_str(if *value > 0.0 { "inf" } else { "-inf" })
        } else {
            serializer.serialize_f64(*value)
        }
    }

    pub(super) fn deserialize<'de, D: Deserializer<'de>>(deserializer: D) -> Result<f64, D::Error> {
        match FloatRepr::deserialize(deserializer)? {
            FloatRepr::Number(value) => Ok(value),
            FloatRepr::Named(name) => match name.as_str() {
                "nan" => Ok(f64::NAN),
                "inf" => Ok(f64::INFINITY),
                "-inf" => Ok(f64::NEG_INFINITY),
                other => Err(serde::de::Error::custom(format!(
                    "expected a number, `nan`, `inf` or `-inf`, found `{other}`"
                ))),
            },
        }
    }
}

/// Copies `object` out of the interpreter within `limits`. Runs Python code (`__repr__` of
/// objects), so it must run under the program's watchdog.
pub(crate) fn to_sandbox_value(
    vm: &VirtualMachine,
    object: &PyObjectRef,
    limits: &ValueLimits,
) -> Result<SandboxValue, Error> {
    let mut converter = Converter {
        vm,
        limits,
        max_depth: limits.max_depth.min(MAX_DEPTH_CEILING),
        nodes: 0,
        text_bytes: 0,
    };
    converter.convert(object, 0)
}

/// Running totals of one conversion, checked against the limits at every node.
struct Converter<'a> {
    vm: &'a VirtualMachine,
    limits: &'a ValueLimits,
    max_depth: usize,
    nodes: usize,
    text_bytes: usize,
}

impl Converter<'_> {
    fn convert(&mut self, object: &PyObjectRef, depth: usize) -> Result<SandboxValue, Error> {
        self.nodes += 1;
        if self.nodes > self.limits.max_nodes {
            return Err(too_large(format!(
                "more than {} values",
                self.limits.max_nodes
            )));
        }
        if depth > self.max_depth {
            return Err(too_large(format!("nested deeper than {}", self.max_depth)));
        }
        let vm = self.vm;
        if vm.is_none(object) {
            return Ok(SandboxValue::None);
        }
        if object.class().is(vm.ctx.types.bool_type) {
            return Ok(SandboxValue::Bool(object.is(&vm.ctx.true_value)));
        }
        if let Some(int) = object.downcast_ref::<PyInt>() {
            return self.convert_int(int);
        }
        if let Some(float) = object.downcast_ref::<PyFloat>() {
            return Ok(SandboxValue::Float(float.to_f64()));
        }
        if let Some(string) = object.downcast_ref::<PyStr>() {
            return Ok(SandboxValue::Str(self.text(&string.to_string_lossy())?));
        }
        if let Some(list) = object.downcast_ref::<PyList>() {
            // Copy the element references first: converting an element may run `__repr__`,
            // which could try to mutate the list while we hold its lock.
            let items: Vec<PyObjectRef> = list.borrow_vec().to_vec();
            return Ok(SandboxValue::List(self.convert_all(&items, depth)?));
        }
        if let Some(tuple) = object.downcast_ref::<PyTuple>() {
            return Ok(SandboxValue::Tuple(
                self.convert_all(tuple.as_slice(), depth)?,
            ));
        }
        if let Some(dict) = object.downcast_ref::<PyDict>() {
            let items = dict.items_vec();
            if items
                .iter()
                .all(|(key, _)| key.downcast_ref::<PyStr>().is_some())
            {
                let mut map = IndexMap::with_capacity(items.len());
                for (key, value) in &items {
                    let key = key
                        .downcast_ref::<PyStr>()
                        .map(|key| key.to_string_lossy().into_owned())
                        .unwrap_or_default();
                    let key = self.text(&key)?;
                    map.insert(key, self.convert(value, depth + 1)?);
                }
                return Ok(SandboxValue::Dict(map));
            }
        }
        self.opaque(object)
    }

    fn convert_all(
        &mut self,
        items: &[PyObjectRef],
        depth: usize,
    ) -> Result<Vec<SandboxValue>, Error> {
        items
            .iter()
            .map(|item| self.convert(item, depth + 1))
            .collect()
    }

    fn convert_int(&mut self, int: &PyInt) -> Result<SandboxValue, Error> {
        if let Ok(small) = int.try_to_primitive::<i64>(self.vm) {
            return Ok(SandboxValue::Int(IntValue::Small(small)));
        }
        // Estimate the digits from the bit length before formatting: formatting a
        // hundred-million-digit integer would itself take minutes.
        let bits = int.as_bigint().bits();
        let estimated_digits = bits.saturating_mul(30_103) / 100_000;
        let max_digits = u64::try_from(self.limits.max_int_digits).unwrap_or(u64::MAX);
        if estimated_digits > max_digits {
            return Err(too_large(format!(
                "an integer of about {estimated_digits} digits (limit {max_digits})"
            )));
        }
        let digits = int.as_bigint().to_string();
        Ok(SandboxValue::Int(IntValue::Big(self.text(&digits)?)))
    }

    /// A value with no structural conversion: its type name and a bounded `repr`.
    fn opaque(&mut self, object: &PyObjectRef) -> Result<SandboxValue, Error> {
        let vm = self.vm;
        let type_name = object.class().name().to_string();
        let repr = match object.repr(vm) {
            Ok(repr) => truncate_chars(&repr.to_string_lossy(), self.limits.max_repr_chars),
            // A failing `__repr__` does not fail the result: the type name still identifies it.
            Err(exception) => format!("<repr raised {}>", exception.class().name()),
        };
        Ok(SandboxValue::Object {
            type_name: self.text(&type_name)?,
            repr: self.text(&repr)?,
        })
    }

    /// Counts `text` against the text budget and returns an owned copy.
    fn text(&mut self, text: &str) -> Result<String, Error> {
        self.text_bytes = self.text_bytes.saturating_add(text.len());
        if self.text_bytes > self.limits.max_text_bytes {
            return Err(too_large(format!(
                "more than {} bytes of text",
                self.limits.max_text_bytes
            )));
        }
        Ok(text.to_owned())
    }
}

fn too_large(message: String) -> Error {
    Error::ResultTooLarge { message }
}

fn truncate_chars(text: &str, max_chars: usize) -> String {
    match text.char_indices().nth(max_chars) {
        Some((cut, _)) => format!("{}…", &text[..cut]),
        None => text.to_owned(),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn serialises_adjacently_tagged_and_round_trips() {
        let value = SandboxValue::List(vec![
            SandboxValue::None,
            SandboxValue::Bool(true),
            SandboxValue::Int(IntValue::Small(-3)),
            SandboxValue::Int(IntValue::Big("123456789012345678901234567890".into())),
            SandboxValue::Float(0.5),
            SandboxValue::Str("yes".into()),
            SandboxValue::Tuple(vec![]),
            SandboxValue::Dict(IndexMap::from([(
                "b".to_owned(),
                SandboxValue::Int(IntValue::Small(1)),
            )])),
            SandboxValue::Object {
                type_name: "set".into(),
                repr: "{1}".into(),
            },
        ]);
        let json = serde_json::to_value(&value).unwrap();
        assert_eq!(json["type"], "list");
        assert_eq!(json["value"][0], json!({"type": "none"}));
        assert_eq!(json["value"][2], json!({"type": "int", "value": -3}));
        assert_eq!(
            json["value"][3],
            json!({"type": "int", "value": "123456789012345678901234567890"})
        );
        assert_eq!(
            json["value"][8],
            json!({"type": "object", "value": {"type_name": "set", "repr": "{1}"}})
        );
        let back: SandboxValue = serde_json::from_value(json).unwrap();
        assert_eq!(back, value);
    }

    #[test]
    fn non_finite_floats_become_strings() {
        let cases = [
            (f64::INFINITY, json!("inf")),
            (f64::NEG_INFINITY, json!("-inf")),
            (f64::NAN, json!("nan")),
            (1.25, json!(1.25)),
        ];
        for (float, expected) in cases {
            let text = serde_json::to_string(&SandboxValue::Float(float)).unwrap();
            let json: serde_json::Value = serde_json::from_str(&text).unwrap();
            assert_eq!(json["value"], expected, "{float}");
            let SandboxValue::Float(back) = serde_json::from_str(&text).unwrap() else {
                panic!("not a float: {text}");
            };
            assert_eq!(back.to_bits(), float.to_bits(), "{float}");
        }
    }

    #[test]
    fn truncates_on_char_boundaries() {
        assert_eq!(truncate_chars("héllo", 2), "hé…");
        assert_eq!(truncate_chars("hé", 2), "hé");
    }
}

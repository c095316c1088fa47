//! Stable content hashes (blake3) over canonical bytes.
//!
//! `std::hash` is never used for anything persisted: its output may change between Rust releases
//! and with the process's random state. Canonical JSON sorts object keys recursively so that two
//! equal values always hash the same, whatever the insertion order of their maps.

use serde_json::Value;

/// Hex-encoded blake3 digest of `bytes`.
pub fn content_hash(bytes: &[u8]) -> String {
    blake3::hash(bytes).to_hex().to_string()
}

/// Hex-encoded blake3 digest of the canonical encoding of `value` (see [`canonical_json`]).
pub fn content_hash_json(value: &Value) -> String {
    content_hash(canonical_json(value).as_bytes())
}

/// Compact JSON with object keys sorted recursively; the encoding that persisted keys hash.
pub fn canonical_json(value: &Value) -> String {
    let mut out = String::new();
    write_canonical(value, &mut out);
    out
}

fn write_canonical(value: &Value, out: &mut String) {
    match value {
        Value::Object(map) => {
            let mut keys: Vec<&String> = map.keys().collect();
            keys.sort();
            out.push('{');
            for (index, key) in keys.into_iter().enumerate() {
                if index > 0 {
                    out.push(',');
                }
                out.push_str(&Value::String(key.clone()).to_string());
                out.push(':');
                write_canonical(&map[key], out);
            }
            out.push('}');
        }
        Value::Array(items) => {
            out.push('[');
            for (index, item) in items.iter().enumerate() {
                if index > 0 {
                    out.push(',');
                }
                write_canonical(item, out);
            }
            out.push(']');
        }
        scalar => out.push_str(&scalar.to_string()),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use serde_json::json;

    #[test]
    fn canonical_json_sorts_keys_at_every_depth() {
        let a = json!({"b": 1, "a": {"y": [1, {"d": 2, "c": 3}], "x": null}});
        let b = json!({"a": {"x": null, "y": [1, {"c": 3, "d": 2}]}, "b": 1});
        assert_eq!(
            canonical_json(&a),
            r#"{"a":{"x":null,"y":[1,{"c":3,"d":2}]},"b":1}"#
        );
        assert_eq!(content_hash_json(&a), content_hash_json(&b));
    }

    #[test]
    fn content_hash_is_blake3_hex() {
        // Known blake3 digest of the empty input.
        assert_eq!(
            content_hash(b""),
            "af1349b9f5f9a1a6a0404dea36dcc9499bcb25c9adc112b7cc9a93cae41f3262"
        );
    }
}

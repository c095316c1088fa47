//! Reading NumPy `.npy` files of 2-D points: an `(N, 2)` array of little-endian `float32` or
//! `float64` in C order, as `bench mpm88 --init` takes and Taichi's side writes. Input: the
//! file's bytes. Output: the points as f64 (float32 values convert exactly).

/// Why a `.npy` file could not be read as points.
#[derive(Debug, thiserror::Error, PartialEq)]
pub enum NpyError {
    /// The magic string or the header is malformed.
    #[error("not a .npy file: {0}")]
    Format(String),
    /// The array is not what is needed.
    #[error(".npy array: {0}")]
    Array(String),
}

/// Reads an `(N, 2)` array of `<f4` or `<f8` as points.
pub fn read_points(bytes: &[u8]) -> Result<Vec<[f64; 2]>, NpyError> {
    let (header, data) = split_header(bytes)?;
    let descr = header_value(&header, "descr")?;
    let width = match descr.trim_matches(|c| c == '\'' || c == '"') {
        "<f4" => 4,
        "<f8" => 8,
        other => {
            return Err(NpyError::Array(format!(
                "dtype {other}: need little-endian float32 (<f4) or float64 (<f8)"
            )));
        }
    };
    if header_value(&header, "fortran_order")? != "False" {
        return Err(NpyError::Array("Fortran order: need C order".to_string()));
    }
    let shape = header_value(&header, "shape")?;
    let dimensions: Vec<&str> = shape
        .trim_matches(|c| c == '(' || c == ')')
        .split(',')
        .map(str::trim)
        .filter(|part| !part.is_empty())
        .collect();
    let rows = match dimensions.as_slice() {
        [rows, "2"] => rows
            .parse::<usize>()
            .map_err(|_| NpyError::Format(format!("shape {shape}")))?,
        _ => return Err(NpyError::Array(format!("shape {shape}: need (N, 2)"))),
    };
    let needed = rows * 2 * width;
    if data.len() != needed {
        return Err(NpyError::Array(format!(
            "{} data bytes for shape {shape}, expected {needed}",
            data.len()
        )));
    }
    let values: Vec<f64> = data
        .chunks_exact(width)
        .map(|chunk| {
            if let [a, b, c, d] = chunk {
                f64::from(f32::from_le_bytes([*a, *b, *c, *d]))
            } else {
                let mut array = [0u8; 8];
                array.copy_from_slice(chunk);
                f64::from_le_bytes(array)
            }
        })
        .collect();
    Ok(values
        .chunks_exact(2)
        .map(|pair| [pair[0], pair[1]])
        .collect())
}

/// Writes points as an `(N, 2)` `<f8` array.
pub fn write_points(points: &[[f64; 2]]) -> Vec<u8> {
    let mut header = format!(
        "{{'descr': '<f8', 'fortran_order': False, 'shape': ({}, 2), }}",
        points.len()
    );
    // Magic (6) + version (2) + length (2) + header + newline, padded to 64 bytes.
    while (10 + header.len() + 1) % 64 != 0 {
        header.push(' ');
    }
    header.push('\n');
    let mut bytes = b"\x93NUMPY\x01\x00".to_vec();
    // The header is a short fixed text padded to 64 bytes: it fits a u16.
    let length = u16::try_from(header.len()).unwrap_or(u16::MAX);
    bytes.extend_from_slice(&length.to_le_bytes());
    bytes.extend_from_slice(header.as_bytes());
    for point in points {
        bytes.extend_from_slice(&point[0].to_le_bytes());
        bytes.extend_from_slice(&point[1].to_le_bytes());
    }
    bytes
}

fn split_header(bytes: &[u8]) -> Result<(String, &[u8]), NpyError> {
    let Some(rest) = bytes.strip_prefix(b"\x93NUMPY") else {
        return Err(NpyError::Format("missing the \\x93NUMPY magic".to_string()));
    };
    let (length, rest) = match rest {
        [1, _, a, b, rest @ ..] => (usize::from(u16::from_le_bytes([*a, *b])), rest),
        [2 | 3, _, a, b, c, d, rest @ ..] => {
            let length = u32::from_le_bytes([*a, *b, *c, *d]);
            (usize::try_from(length).unwrap_or(usize::MAX), rest)
        }
        _ => return Err(NpyError::Format("unknown version".to_string())),
    };
    if rest.len() < length {
        return Err(NpyError::Format("header longer than the file".to_string()));
    }
    let (header, data) = rest.split_at(length);
    let header = std::str::from_utf8(header)
        .map_err(|_| NpyError::Format("header is not text".to_string()))?;
    Ok((header.to_string(), data))
}

/// The text of `key`'s value in the header dict (`'key': value,`).
fn header_value(header: &str, key: &str) -> Result<String, NpyError> {
    let pattern = format!("'{key}':");
    let Some(start) = header.find(&pattern) else {
        return Err(NpyError::Format(format!("header has no '{key}'")));
    };
    let rest = header[start + pattern.len()..].trim_start();
    let end = if rest.starts_with('(') {
        rest.find(')').map(|index| index + 1)
    } else {
        rest.find([',', '}'])
    };
    let Some(end) = end else {
        return Err(NpyError::Format(format!(
            "header value of '{key}' is unterminated"
        )));
    };
    Ok(rest[..end].trim().to_string())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn points_round_trip_through_float64() {
        let points = vec![[0.25, -1.5], [3.0, 1e-300]];
        assert_eq!(read_points(&write_points(&points)).unwrap(), points);
        assert_eq!(
            read_points(&write_points(&[])).unwrap(),
            Vec::<[f64; 2]>::new()
        );
    }

    #[test]
    fn float32_files_from_numpy_read_exactly() {
        // np.array([[0.5, 0.25], [0.1, 2.0]], dtype=np.float32), saved by numpy 2.
        let mut bytes = b"\x93NUMPY\x01\x00v\x00".to_vec();
        let mut header = "{'descr': '<f4', 'fortran_order': False, 'shape': (2, 2), }".to_string();
        while header.len() < 117 {
            header.push(' ');
        }
        header.push('\n');
        bytes.extend_from_slice(header.as_bytes());
        for value in [0.5f32, 0.25, 0.1, 2.0] {
            bytes.extend_from_slice(&value.to_le_bytes());
        }
        let points = read_points(&bytes).unwrap();
        assert_eq!(points, vec![[0.5, 0.25], [f64::from(0.1f32), 2.0]]);
    }

    #[test]
    fn wrong_shapes_and_types_are_named() {
        let bad = write_points(&[[1.0, 2.0]]);
        let replace = |from: &[u8], to: &[u8]| {
            let at = bad
                .windows(from.len())
                .position(|window| window == from)
                .expect("in the header");
            let mut bytes = bad.clone();
            bytes[at..at + to.len()].copy_from_slice(to);
            bytes
        };
        assert!(matches!(
            read_points(&replace(b"(1, 2)", b"(2, 1)")),
            Err(NpyError::Array(_))
        ));
        assert_eq!(
            read_points(&replace(b"<f8", b"<i8")),
            Err(NpyError::Array(
                "dtype <i8: need little-endian float32 (<f4) or float64 (<f8)".to_string()
            ))
        );
        assert!(matches!(
            read_points(b"PK\x03\x04"),
            Err(NpyError::Format(_))
        ));
        let mut short = bad.clone();
        short.pop();
        assert!(matches!(read_points(&short), Err(NpyError::Array(_))));
    }
}

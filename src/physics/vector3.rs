//! 3-vectors, 3 × 3 matrices and unit quaternions for the 3-D solvers (shape matching, cloth and
//! rigid boxes): products, determinant, inverse, and the rotation part of a matrix by Müller et
//! al.'s iterative extraction ("A Robust Method to Extract the Rotational Part of Deformations",
//! 2016).
//!
//! Matrices are row-major `[[f64; 3]; 3]`. The rotation extraction is warm-started from the last
//! substep's rotation, so a few iterations suffice, and it never divides by a vanishing number:
//! a degenerate matrix (a ball squashed flat) keeps the warm start instead of turning into NaN.

/// A 3-vector.
pub type Vector = [f64; 3];
/// A 3 × 3 matrix, row-major.
pub type Matrix = [[f64; 3]; 3];

/// The identity.
pub const IDENTITY: Matrix = [[1.0, 0.0, 0.0], [0.0, 1.0, 0.0], [0.0, 0.0, 1.0]];

/// `a + b`.
pub fn add(a: Vector, b: Vector) -> Vector {
    [a[0] + b[0], a[1] + b[1], a[2] + b[2]]
}

/// `a − b`.
pub fn sub(a: Vector, b: Vector) -> Vector {
    [a[0] - b[0], a[1] - b[1], a[2] - b[2]]
}

/// `s · a`.
pub fn scale(a: Vector, s: f64) -> Vector {
    [a[0] * s, a[1] * s, a[2] * s]
}

/// `a · b`.
pub fn dot(a: Vector, b: Vector) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// `a × b`.
pub fn cross(a: Vector, b: Vector) -> Vector {
    [
        a[1] * b[2] - a[2] * b[1],
        a[2] * b[0] - a[0] * b[2],
        a[0] * b[1] - a[1] * b[0],
    ]
}

/// `|a|`.
pub fn norm(a: Vector) -> f64 {
    dot(a, a).sqrt()
}

/// `m · v`.
pub fn apply(m: &Matrix, v: Vector) -> Vector {
    [dot(m[0], v), dot(m[1], v), dot(m[2], v)]
}

/// `a · b`.
pub fn multiply(a: &Matrix, b: &Matrix) -> Matrix {
    let mut out = [[0.0; 3]; 3];
    for (row, out_row) in out.iter_mut().enumerate() {
        for (column, value) in out_row.iter_mut().enumerate() {
            *value = a[row][0] * b[0][column] + a[row][1] * b[1][column] + a[row][2] * b[2][column];
        }
    }
    out
}

/// `mᵀ`.
pub fn transpose(m: &Matrix) -> Matrix {
    let mut out = [[0.0; 3]; 3];
    for (row, values) in m.iter().enumerate() {
        for (column, value) in values.iter().enumerate() {
            out[column][row] = *value;
        }
    }
    out
}

/// `a + s · b`, entry by entry.
pub fn add_scaled(a: &Matrix, b: &Matrix, s: f64) -> Matrix {
    let mut out = *a;
    for (row, values) in out.iter_mut().enumerate() {
        for (column, value) in values.iter_mut().enumerate() {
            *value += s * b[row][column];
        }
    }
    out
}

/// `s · m`.
pub fn scale_matrix(m: &Matrix, s: f64) -> Matrix {
    m.map(|row| row.map(|value| value * s))
}

/// The Frobenius norm of `a − b`.
pub fn distance(a: &Matrix, b: &Matrix) -> f64 {
    let mut sum = 0.0;
    for (row_a, row_b) in a.iter().zip(b) {
        for (x, y) in row_a.iter().zip(row_b) {
            sum += (x - y) * (x - y);
        }
    }
    sum.sqrt()
}

/// `det m`.
pub fn determinant(m: &Matrix) -> f64 {
    dot(m[0], cross(m[1], m[2]))
}

/// `m⁻¹`, or `None` when `|det m|` is below `1e-12` times the cube of its largest entry.
pub fn inverse(m: &Matrix) -> Option<Matrix> {
    let det = determinant(m);
    let largest = m.iter().flatten().fold(0.0_f64, |acc, v| acc.max(v.abs()));
    if !det.is_finite() || det.abs() <= 1e-12 * largest * largest * largest || largest == 0.0 {
        return None;
    }
    // The adjugate's rows are cross products of the columns, transposed.
    let columns = transpose(m);
    let adjugate_rows = [
        cross(columns[1], columns[2]),
        cross(columns[2], columns[0]),
        cross(columns[0], columns[1]),
    ];
    Some(scale_matrix(&adjugate_rows, 1.0 / det))
}

/// The outer product `a bᵀ`.
pub fn outer(a: Vector, b: Vector) -> Matrix {
    [scale(b, a[0]), scale(b, a[1]), scale(b, a[2])]
}

/// A unit quaternion `[w, x, y, z]`.
pub type Quaternion = [f64; 4];

/// The identity rotation.
pub const NO_ROTATION: Quaternion = [1.0, 0.0, 0.0, 0.0];

/// The rotation matrix of unit quaternion `q`.
pub fn rotation_matrix(quaternion: Quaternion) -> Matrix {
    let [w, x, y, z] = quaternion;
    [
        [
            1.0 - 2.0 * (y * y + z * z),
            2.0 * (x * y - w * z),
            2.0 * (x * z + w * y),
        ],
        [
            2.0 * (x * y + w * z),
            1.0 - 2.0 * (x * x + z * z),
            2.0 * (y * z - w * x),
        ],
        [
            2.0 * (x * z - w * y),
            2.0 * (y * z + w * x),
            1.0 - 2.0 * (x * x + y * y),
        ],
    ]
}

/// `a b` (apply `b` first).
pub fn quaternion_product(a: Quaternion, b: Quaternion) -> Quaternion {
    [
        a[0] * b[0] - a[1] * b[1] - a[2] * b[2] - a[3] * b[3],
        a[0] * b[1] + a[1] * b[0] + a[2] * b[3] - a[3] * b[2],
        a[0] * b[2] - a[1] * b[3] + a[2] * b[0] + a[3] * b[1],
        a[0] * b[3] + a[1] * b[2] - a[2] * b[1] + a[3] * b[0],
    ]
}

/// The rotation closest to `m` (its polar factor when `det m > 0`), by at most `iterations`
/// steps of Müller et al.'s extraction from the warm start `q`; returns the new quaternion.
///
/// Each step rotates `q` by `ω = Σ rᵢ × mᵢ / |Σ rᵢ · mᵢ|` (the columns of the current rotation
/// and of `m`), which vanishes at the polar factor. A step whose ω is not finite (a zero matrix)
/// stops with the last rotation.
pub fn extract_rotation(m: &Matrix, mut q: Quaternion, iterations: usize) -> Quaternion {
    let columns = transpose(m);
    for _ in 0..iterations {
        let r = transpose(&rotation_matrix(q));
        let torque = add(
            add(cross(r[0], columns[0]), cross(r[1], columns[1])),
            cross(r[2], columns[2]),
        );
        let alignment =
            (dot(r[0], columns[0]) + dot(r[1], columns[1]) + dot(r[2], columns[2])).abs() + 1e-9;
        let omega = scale(torque, 1.0 / alignment);
        let angle = norm(omega);
        if !angle.is_finite() || angle < 1e-12 {
            break;
        }
        let axis = scale(omega, 1.0 / angle);
        let half = 0.5 * angle;
        let step = [
            half.cos(),
            axis[0] * half.sin(),
            axis[1] * half.sin(),
            axis[2] * half.sin(),
        ];
        let next = quaternion_product(step, q);
        let length = next.iter().map(|v| v * v).sum::<f64>().sqrt();
        if !length.is_finite() || length == 0.0 {
            break;
        }
        q = next.map(|v| v / length);
    }
    q
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Matrix, b: &Matrix, tolerance: f64) -> bool {
        distance(a, b) < tolerance
    }

    #[test]
    fn the_inverse_undoes_the_matrix() {
        let m = [[2.0, 1.0, 0.0], [0.5, 3.0, -1.0], [0.0, 0.25, 1.5]];
        let inverse = inverse(&m).unwrap();
        assert!(close(&multiply(&m, &inverse), &IDENTITY, 1e-14));
        assert!(super::inverse(&[[1.0, 2.0, 3.0], [2.0, 4.0, 6.0], [0.0, 0.0, 1.0]]).is_none());
        assert!(super::inverse(&[[0.0; 3]; 3]).is_none());
    }

    #[test]
    fn the_rotation_of_a_rotated_stretch_is_the_rotation() {
        // R · S with S symmetric positive definite: the polar factor is R.
        let angle: f64 = 0.7;
        let axis = [0.3, -0.5, 0.8];
        let length = norm(axis);
        let half = angle / 2.0;
        let q = [
            half.cos(),
            axis[0] / length * half.sin(),
            axis[1] / length * half.sin(),
            axis[2] / length * half.sin(),
        ];
        let rotation = rotation_matrix(q);
        let stretch = [[1.4, 0.1, 0.0], [0.1, 0.7, 0.05], [0.0, 0.05, 1.0]];
        let m = multiply(&rotation, &stretch);
        let found = rotation_matrix(extract_rotation(&m, NO_ROTATION, 40));
        assert!(close(&found, &rotation, 1e-9), "{found:?}");
        // A rotation matrix is orthonormal with determinant 1.
        assert!(close(
            &multiply(&found, &transpose(&found)),
            &IDENTITY,
            1e-12
        ));
        assert!((determinant(&found) - 1.0).abs() < 1e-12);
    }

    #[test]
    fn a_zero_matrix_keeps_the_warm_start() {
        let q = [0.9, 0.1, 0.3, 0.2];
        let length = q.iter().map(|v: &f64| v * v).sum::<f64>().sqrt();
        let q = q.map(|v| v / length);
        let found = extract_rotation(&[[0.0; 3]; 3], q, 10);
        assert!(found.iter().zip(q).all(|(a, b)| a.to_bits() == b.to_bits()));
    }
}

//! Elastoplastic solids on the MPM core: fixed-corotated elasticity (Stomakhin et al. 2012) with a
//! von Mises return mapping on the Hencky (logarithmic) strain (Klár et al. 2016; the "von Mises"
//! material of PAC-NeRF that ContPRO fits to each ball). Input: a particle's deformation gradient
//! `F` (row-major 2 × 2) and the material's Lamé parameters. Output: its Kirchhoff stress, its
//! elastic energy density, and `F` projected back onto the yield surface.
//!
//! Units are the caller's: stresses in the units of the Young's modulus (force per length in 2D),
//! `F` dimensionless.
//!
//! **Why this pair.** Fixed-corotated elasticity is the MPM workhorse for solids: its stress needs
//! only the polar rotation of `F` (closed form in 2D) and it stays defined under large rotations,
//! which a ball rolling down a ramp goes through. The return mapping needs the singular values, so
//! it works on `log σ`, where von Mises' deviatoric projection is exact and volume-preserving
//! (plastic flow changes shape, not area). For small strains the deviatoric Kirchhoff stress of
//! fixed-corotated elasticity is `2μ ε̂`, the stress the yield test compares with.
//!
//! **Inverted or crushed particles.** Singular values are kept in [`SINGULAR_VALUE_RANGE`] (counted
//! by the solver): an explicit step far beyond its stable size could otherwise invert a particle,
//! and the logarithm of a non-positive stretch is not a number.

/// Singular values of `F` are clamped into this range after each update (a particle squeezed to
/// a twentieth of its length or stretched twentyfold is outside anything a ball does).
pub const SINGULAR_VALUE_RANGE: (f64, f64) = (0.05, 20.0);

/// A 2 × 2 matrix, row-major `[a00, a01, a10, a11]`.
pub type Matrix2 = [f64; 4];

/// The identity.
pub const IDENTITY: Matrix2 = [1.0, 0.0, 0.0, 1.0];

/// `a · b`.
#[inline]
pub fn multiply(a: &Matrix2, b: &Matrix2) -> Matrix2 {
    [
        a[0] * b[0] + a[1] * b[2],
        a[0] * b[1] + a[1] * b[3],
        a[2] * b[0] + a[3] * b[2],
        a[2] * b[1] + a[3] * b[3],
    ]
}

/// Determinant.
#[inline]
pub fn determinant(a: &Matrix2) -> f64 {
    a[0] * a[3] - a[1] * a[2]
}

/// The rotation of the polar decomposition `F = R·S` (`S` symmetric), as `(cos θ, sin θ)`.
/// In 2D, `θ = atan2(F₁₀ − F₀₁, F₀₀ + F₁₁)` (the rotation closest to `F`); a matrix with no
/// rotational part (`F₀₀ + F₁₁ = F₁₀ − F₀₁ = 0`) gets the identity.
#[inline]
pub fn polar_rotation(f: &Matrix2) -> (f64, f64) {
    let x = f[0] + f[3];
    let y = f[2] - f[1];
    let length = x.hypot(y);
    if length > 0.0 {
        (x / length, y / length)
    } else {
        (1.0, 0.0)
    }
}

/// A singular value decomposition `F = U·diag(σ)·Vᵀ` with `U`, `V` rotations (σ₂ may be negative
/// for an inverted `F`).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct Decomposition {
    /// Left rotation.
    pub u: Matrix2,
    /// Singular values.
    pub sigma: [f64; 2],
    /// Right rotation.
    pub v: Matrix2,
}

/// The SVD of `F` from its polar decomposition: `S = Rᵀ·F` is symmetric, its eigenvectors (one
/// Jacobi rotation, closed form) give `V` and its eigenvalues `σ`; `U = R·V`.
pub fn decompose(f: &Matrix2) -> Decomposition {
    let (c, s) = polar_rotation(f);
    // S = Rᵀ F with R = [[c, −s], [s, c]].
    let s00 = c * f[0] + s * f[2];
    let s01 = c * f[1] + s * f[3];
    let s11 = -s * f[1] + c * f[3];
    // Jacobi angle φ diagonalising the symmetric S: tan 2φ = 2 s01 / (s00 − s11).
    let phi = 0.5 * (2.0 * s01).atan2(s00 - s11);
    let (sin_phi, cos_phi) = phi.sin_cos();
    let v = [cos_phi, -sin_phi, sin_phi, cos_phi];
    // σ = Vᵀ S V, diagonal entries.
    let sigma0 = cos_phi * cos_phi * s00 + 2.0 * cos_phi * sin_phi * s01 + sin_phi * sin_phi * s11;
    let sigma1 = sin_phi * sin_phi * s00 - 2.0 * cos_phi * sin_phi * s01 + cos_phi * cos_phi * s11;
    let rotation = [c, -s, s, c];
    Decomposition {
        u: multiply(&rotation, &v),
        sigma: [sigma0, sigma1],
        v,
    }
}

/// `U·diag(σ)·Vᵀ`.
pub fn compose(u: &Matrix2, sigma: [f64; 2], v: &Matrix2) -> Matrix2 {
    let scaled = [
        u[0] * sigma[0],
        u[1] * sigma[1],
        u[2] * sigma[0],
        u[3] * sigma[1],
    ];
    // scaled · Vᵀ
    [
        scaled[0] * v[0] + scaled[1] * v[1],
        scaled[0] * v[2] + scaled[1] * v[3],
        scaled[2] * v[0] + scaled[3] * v[1],
        scaled[2] * v[2] + scaled[3] * v[3],
    ]
}

/// Fixed-corotated Kirchhoff stress `τ = 2μ(F − R)Fᵀ + λ(J − 1)J·I`.
#[inline]
pub fn corotated_stress(f: &Matrix2, mu: f64, lambda: f64) -> Matrix2 {
    let (c, s) = polar_rotation(f);
    let difference = [f[0] - c, f[1] + s, f[2] - s, f[3] - c];
    // (F − R) Fᵀ
    let product = [
        difference[0] * f[0] + difference[1] * f[1],
        difference[0] * f[2] + difference[1] * f[3],
        difference[2] * f[0] + difference[3] * f[1],
        difference[2] * f[2] + difference[3] * f[3],
    ];
    let j = determinant(f);
    let pressure = lambda * (j - 1.0) * j;
    [
        2.0 * mu * product[0] + pressure,
        2.0 * mu * product[1],
        2.0 * mu * product[2],
        2.0 * mu * product[3] + pressure,
    ]
}

/// Fixed-corotated energy per unit reference area, `μ‖F − R‖² + λ/2·(J − 1)²`.
pub fn corotated_energy_density(f: &Matrix2, mu: f64, lambda: f64) -> f64 {
    let (c, s) = polar_rotation(f);
    let difference = [f[0] - c, f[1] + s, f[2] - s, f[3] - c];
    let norm_squared: f64 = difference.iter().map(|value| value * value).sum();
    let j = determinant(f);
    mu * norm_squared + 0.5 * lambda * (j - 1.0) * (j - 1.0)
}

/// What [`return_map`] did to `F`.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Projection {
    /// Inside the yield surface and the stretch range: unchanged.
    Elastic,
    /// Projected onto the yield surface (plastic flow).
    Yielded,
    /// A singular value was outside [`SINGULAR_VALUE_RANGE`] and was clamped.
    Clamped,
}

/// Projects `F` onto the von Mises yield surface `2μ‖ε̂‖ ≤ τ_y` of the Hencky strain `ε = log σ`
/// (`ε̂` its deviatoric part), and its singular values into [`SINGULAR_VALUE_RANGE`]. An infinite
/// `yield_stress` only clamps.
pub fn return_map(f: &mut Matrix2, mu: f64, yield_stress: f64) -> Projection {
    let decomposition = decompose(f);
    let mut sigma = decomposition.sigma;
    let mut outcome = Projection::Elastic;
    for value in &mut sigma {
        if !(*value >= SINGULAR_VALUE_RANGE.0 && *value <= SINGULAR_VALUE_RANGE.1) {
            *value = value.clamp(SINGULAR_VALUE_RANGE.0, SINGULAR_VALUE_RANGE.1);
            outcome = Projection::Clamped;
        }
    }
    if yield_stress.is_finite() && mu > 0.0 {
        let strain = [sigma[0].ln(), sigma[1].ln()];
        let mean = 0.5 * (strain[0] + strain[1]);
        let deviatoric = [strain[0] - mean, strain[1] - mean];
        let norm = deviatoric[0].hypot(deviatoric[1]);
        let excess = norm - yield_stress / (2.0 * mu);
        if excess > 0.0 {
            let keep = 1.0 - excess / norm;
            sigma = [
                (mean + keep * deviatoric[0]).exp(),
                (mean + keep * deviatoric[1]).exp(),
            ];
            if outcome == Projection::Elastic {
                outcome = Projection::Yielded;
            }
        }
    }
    if outcome != Projection::Elastic {
        *f = compose(&decomposition.u, sigma, &decomposition.v);
    }
    outcome
}

#[cfg(test)]
mod tests {
    use super::*;

    fn close(a: &Matrix2, b: &Matrix2, tolerance: f64) -> bool {
        a.iter().zip(b).all(|(x, y)| (x - y).abs() <= tolerance)
    }

    const SAMPLES: [Matrix2; 5] = [
        [1.2, 0.3, -0.1, 0.9],
        [0.0, -1.0, 1.0, 0.0],
        [2.0, 0.0, 0.0, 0.5],
        [0.7, 0.7, -0.7, 0.7],
        [1.0, 0.4, 0.0, 1.0],
    ];

    #[test]
    fn decomposition_recomposes_and_its_factors_are_rotations() {
        for f in SAMPLES {
            let d = decompose(&f);
            assert!(close(&compose(&d.u, d.sigma, &d.v), &f, 1e-12), "{f:?}");
            for rotation in [d.u, d.v] {
                assert!((determinant(&rotation) - 1.0).abs() < 1e-12);
                let transpose = [rotation[0], rotation[2], rotation[1], rotation[3]];
                assert!(close(&multiply(&rotation, &transpose), &IDENTITY, 1e-12));
            }
            assert!((d.sigma[0] * d.sigma[1] - determinant(&f)).abs() < 1e-12);
        }
    }

    #[test]
    fn a_rotation_has_no_stress_and_no_energy() {
        let (s, c) = 0.7f64.sin_cos();
        let rotation = [c, -s, s, c];
        assert!(close(
            &corotated_stress(&rotation, 3.0, 5.0),
            &[0.0; 4],
            1e-12
        ));
        assert!(corotated_energy_density(&rotation, 3.0, 5.0).abs() < 1e-12);
    }

    #[test]
    fn small_strain_stress_is_hookes_law() {
        // F = I + ε with ε symmetric and small: τ ≈ 2μ ε + λ tr(ε) I.
        let (mu, lambda, e) = (2.0, 3.0, 1e-6);
        let f = [1.0 + e, 0.5 * e, 0.5 * e, 1.0 - 2.0 * e];
        let stress = corotated_stress(&f, mu, lambda);
        let expected = [
            2.0 * mu * e - lambda * e,
            2.0 * mu * 0.5 * e,
            2.0 * mu * 0.5 * e,
            -2.0 * mu * 2.0 * e - lambda * e,
        ];
        assert!(close(&stress, &expected, 1e-10), "{stress:?}");
    }

    #[test]
    fn stress_is_the_energy_gradient_times_f_transpose() {
        // τ = (∂ψ/∂F)·Fᵀ, checked by central differences on a general F.
        let (mu, lambda) = (1.5, 2.5);
        let f = SAMPLES[0];
        let h = 1e-6;
        let mut gradient = [0.0; 4];
        for (index, slot) in gradient.iter_mut().enumerate() {
            let mut plus = f;
            let mut minus = f;
            plus[index] += h;
            minus[index] -= h;
            *slot = (corotated_energy_density(&plus, mu, lambda)
                - corotated_energy_density(&minus, mu, lambda))
                / (2.0 * h);
        }
        let transpose = [f[0], f[2], f[1], f[3]];
        let expected = multiply(&gradient, &transpose);
        assert!(
            close(&corotated_stress(&f, mu, lambda), &expected, 1e-7),
            "{expected:?}"
        );
    }

    #[test]
    fn return_mapping_keeps_volume_and_lands_on_the_yield_surface() {
        let (mu, yield_stress) = (10.0, 0.5);
        let mut f = [1.3, 0.2, 0.0, 0.8];
        let before = determinant(&f);
        assert_eq!(return_map(&mut f, mu, yield_stress), Projection::Yielded);
        assert!((determinant(&f) - before).abs() < 1e-12);
        let d = decompose(&f);
        let strain = [d.sigma[0].ln(), d.sigma[1].ln()];
        let mean = 0.5 * (strain[0] + strain[1]);
        let norm = (strain[0] - mean).hypot(strain[1] - mean);
        assert!((2.0 * mu * norm - yield_stress).abs() < 1e-12);
        // Inside the surface now: a second projection leaves it.
        let again = f;
        assert_eq!(return_map(&mut f, mu, yield_stress), Projection::Elastic);
        assert_eq!(f.map(f64::to_bits), again.map(f64::to_bits));
    }

    #[test]
    fn an_infinite_yield_stress_only_clamps_extreme_stretches() {
        let mut f = [1.5, 0.0, 0.0, 0.7];
        assert_eq!(return_map(&mut f, 1.0, f64::INFINITY), Projection::Elastic);
        let mut inverted = [1.0, 0.0, 0.0, -0.5];
        assert_eq!(
            return_map(&mut inverted, 1.0, f64::INFINITY),
            Projection::Clamped
        );
        assert!(determinant(&inverted) > 0.0);
    }
}

//! MPM materials: what each contributes to the particle-to-grid transfer (its Kirchhoff stress)
//! and to the time step (its wave speed and diffusion limit). Input: particle state (volume ratio
//! `J`, velocity gradient `C`). Output: a 2 × 2 stress, row-major.

use super::MpmError;

/// A material of the MPM core. Elastoplastic materials (the ball scenario) are added here.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// A weakly compressible liquid (the fluid scenario's fluids).
    Liquid(LiquidMaterial),
}

/// A weakly compressible viscous liquid: Kirchhoff stress `τ = κ(J − 1)·I + μ·J·(C + Cᵀ)`, the
/// pressure of Taichi's `mpm88` (`E(J − 1)`) plus Newtonian viscosity with the APIC matrix `C` as
/// the velocity gradient.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct LiquidMaterial {
    /// Rest density ρ, mass per unit area (2D).
    pub density: f64,
    /// Bulk modulus κ, stress units.
    pub bulk_modulus: f64,
    /// Dynamic viscosity μ, stress × time.
    pub viscosity: f64,
}

/// The volume ratio `J` is kept in this range: outside it the linear pressure law means nothing
/// and an explicit step may invert a cell. Reached only by runs far outside their stable step.
pub const VOLUME_RATIO_RANGE: (f64, f64) = (0.05, 20.0);

impl Material {
    /// Checks the parameters; `index` names the material in errors.
    pub fn validate(&self, index: usize) -> Result<(), MpmError> {
        let invalid = |reason: String| MpmError::InvalidMaterial { index, reason };
        match self {
            Material::Liquid(liquid) => {
                if !(liquid.density.is_finite() && liquid.density > 0.0) {
                    return Err(invalid(format!(
                        "density {} is not positive and finite",
                        liquid.density
                    )));
                }
                if !(liquid.bulk_modulus.is_finite() && liquid.bulk_modulus > 0.0) {
                    return Err(invalid(format!(
                        "bulk modulus {} is not positive and finite",
                        liquid.bulk_modulus
                    )));
                }
                if !(liquid.viscosity.is_finite() && liquid.viscosity >= 0.0) {
                    return Err(invalid(format!(
                        "viscosity {} is not finite and non-negative",
                        liquid.viscosity
                    )));
                }
                Ok(())
            }
        }
    }

    /// Rest density.
    pub fn density(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => liquid.density,
        }
    }

    /// Speed of its pressure (or elastic) waves, `√(κ/ρ)`.
    pub fn wave_speed(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => (liquid.bulk_modulus / liquid.density).sqrt(),
        }
    }

    /// Kinematic viscosity `μ/ρ`, which bounds an explicit step by `dx²/(4ν)` in 2D.
    pub fn kinematic_viscosity(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => liquid.viscosity / liquid.density,
        }
    }

    /// Kirchhoff stress for volume ratio `j` and velocity gradient `c` (row-major).
    #[inline]
    pub fn kirchhoff_stress(&self, j: f64, c: &[f64; 4]) -> [f64; 4] {
        match self {
            Material::Liquid(liquid) => {
                let pressure = liquid.bulk_modulus * (j - 1.0);
                if liquid.viscosity == 0.0 {
                    return [pressure, 0.0, 0.0, pressure];
                }
                let scale = liquid.viscosity * j;
                let shear = scale * (c[1] + c[2]);
                [
                    pressure + 2.0 * scale * c[0],
                    shear,
                    shear,
                    pressure + 2.0 * scale * c[3],
                ]
            }
        }
    }
}

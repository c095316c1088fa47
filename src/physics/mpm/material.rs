//! MPM materials: what each contributes to the particle-to-grid transfer (its Kirchhoff stress),
//! to the grid-to-particle update (whether it carries a deformation gradient, its plastic
//! projection) and to the time step (its wave speed and diffusion limit). Input: particle state
//! (volume ratio `J`, deformation gradient `F`, velocity gradient `C`). Output: a 2 × 2 stress,
//! row-major.

use super::MpmError;
use super::elastic::{Matrix2, Projection, corotated_energy_density, corotated_stress, return_map};

/// A material of the MPM core.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum Material {
    /// A weakly compressible liquid (the fluid scenario's fluids).
    Liquid(LiquidMaterial),
    /// An elastoplastic solid (the ball scenario's soft balls).
    Elastoplastic(ElastoplasticMaterial),
    /// Rigid discs ([`Solver::add_rigid_body`](super::Solver::add_rigid_body)): moving colliders
    /// of the grid, two-way coupled; no stress, so they never limit the time step.
    Rigid(RigidMaterial),
}

/// An elastoplastic solid: fixed-corotated elasticity with Young's modulus `E` and Poisson's ratio
/// `ν` (Lamé `μ = E/(2(1 + ν))`, `λ = Eν/((1 + ν)(1 − 2ν))`), von Mises plasticity with a yield
/// stress on the Hencky strain (see [`super::elastic`]).
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct ElastoplasticMaterial {
    /// Rest density ρ, mass per unit area (2D).
    pub density: f64,
    /// Young's modulus `E`, stress units (force per length in 2D).
    pub youngs_modulus: f64,
    /// Poisson's ratio `ν`, in [0, 0.5).
    pub poisson_ratio: f64,
    /// Von Mises yield stress, stress units; `f64::INFINITY` for a purely elastic solid, 0 for
    /// one that flows under any shear.
    pub yield_stress: f64,
}

impl ElastoplasticMaterial {
    /// Lamé parameters `(μ, λ)`.
    pub fn lame(&self) -> (f64, f64) {
        let (e, nu) = (self.youngs_modulus, self.poisson_ratio);
        (
            e / (2.0 * (1.0 + nu)),
            e * nu / ((1.0 + nu) * (1.0 - 2.0 * nu)),
        )
    }
}

/// The material of rigid discs.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct RigidMaterial {
    /// Density ρ, mass per unit area (2D).
    pub density: f64,
    /// Coulomb friction between the disc and other material at its surface (ContPRO used 0).
    pub friction: f64,
    /// Rolling resistance against the static colliders (0: an ideal disc rolls at ⅔ g sin θ).
    pub rolling_resistance: f64,
    /// Coulomb friction against the static colliders, in place of their boundary condition's
    /// (`None`: theirs). Lets the grid's nodes slip along a collider while the disc grips it.
    pub collider_friction: Option<f64>,
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
                positive_density(liquid.density, &invalid)?;
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
            Material::Elastoplastic(solid) => {
                positive_density(solid.density, &invalid)?;
                if !(solid.youngs_modulus.is_finite() && solid.youngs_modulus > 0.0) {
                    return Err(invalid(format!(
                        "Young's modulus {} is not positive and finite",
                        solid.youngs_modulus
                    )));
                }
                if !(solid.poisson_ratio >= 0.0 && solid.poisson_ratio < 0.5) {
                    return Err(invalid(format!(
                        "Poisson's ratio {} is not in [0, 0.5)",
                        solid.poisson_ratio
                    )));
                }
                if solid.yield_stress.is_nan() || solid.yield_stress < 0.0 {
                    return Err(invalid(format!(
                        "yield stress {} is not non-negative (infinity: never yields)",
                        solid.yield_stress
                    )));
                }
                Ok(())
            }
            Material::Rigid(rigid) => {
                positive_density(rigid.density, &invalid)?;
                let collider_friction = rigid.collider_friction.unwrap_or(0.0);
                if [rigid.friction, rigid.rolling_resistance, collider_friction]
                    .iter()
                    .all(|value| value.is_finite() && *value >= 0.0)
                {
                    Ok(())
                } else {
                    Err(invalid(format!(
                        "friction {}, rolling resistance {} or collider friction {} is not \
                         finite and non-negative",
                        rigid.friction, rigid.rolling_resistance, collider_friction
                    )))
                }
            }
        }
    }

    /// Rest density.
    pub fn density(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => liquid.density,
            Material::Elastoplastic(solid) => solid.density,
            Material::Rigid(rigid) => rigid.density,
        }
    }

    /// Speed of its pressure (or elastic) waves: `√(κ/ρ)` for a liquid, the P-wave speed
    /// `√((λ + 2μ)/ρ)` for a solid, 0 for rigid bodies (no stress).
    pub fn wave_speed(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => (liquid.bulk_modulus / liquid.density).sqrt(),
            Material::Elastoplastic(solid) => {
                let (mu, lambda) = solid.lame();
                ((lambda + 2.0 * mu) / solid.density).sqrt()
            }
            Material::Rigid(_) => 0.0,
        }
    }

    /// Kinematic viscosity `μ/ρ`, which bounds an explicit step by `dx²/(4ν)` in 2D.
    pub fn kinematic_viscosity(&self) -> f64 {
        match self {
            Material::Liquid(liquid) => liquid.viscosity / liquid.density,
            Material::Elastoplastic(_) | Material::Rigid(_) => 0.0,
        }
    }

    /// Whether its particles give the grid mass and momentum (rigid discs' markers do not).
    #[inline]
    pub fn scatters(&self) -> bool {
        !matches!(self, Material::Rigid(_))
    }

    /// Whether its particles carry a deformation gradient (updated and projected each gather).
    #[inline]
    pub fn has_deformation(&self) -> bool {
        matches!(self, Material::Elastoplastic(_))
    }

    /// Plastic projection of a deformation gradient (see [`return_map`]); liquids and rigid
    /// bodies leave it alone.
    #[inline]
    pub fn project(&self, f: &mut Matrix2) -> Projection {
        match self {
            Material::Elastoplastic(solid) => return_map(f, solid.lame().0, solid.yield_stress),
            Material::Liquid(_) | Material::Rigid(_) => Projection::Elastic,
        }
    }

    /// Elastic energy per unit reference area for deformation gradient `f` (solids; 0 otherwise).
    pub fn energy_density(&self, f: &Matrix2) -> f64 {
        match self {
            Material::Elastoplastic(solid) => {
                let (mu, lambda) = solid.lame();
                corotated_energy_density(f, mu, lambda)
            }
            Material::Liquid(_) | Material::Rigid(_) => 0.0,
        }
    }

    /// Kirchhoff stress for volume ratio `j`, deformation gradient `f` and velocity gradient `c`
    /// (row-major).
    #[inline]
    pub fn kirchhoff_stress(&self, j: f64, f: &Matrix2, c: &[f64; 4]) -> [f64; 4] {
        match self {
            Material::Rigid(_) => [0.0; 4],
            Material::Elastoplastic(solid) => {
                let (mu, lambda) = solid.lame();
                corotated_stress(f, mu, lambda)
            }
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

fn positive_density(density: f64, invalid: &impl Fn(String) -> MpmError) -> Result<(), MpmError> {
    if density.is_finite() && density > 0.0 {
        Ok(())
    } else {
        Err(invalid(format!(
            "density {density} is not positive and finite"
        )))
    }
}

//! `bench physics --scenario fluid`: the MPM fluid simulation's error against its run time over
//! grid spacing and particles per cell, each point compared with a run at a fine reference
//! (grid spacing 0.02 units, four particles per cell). One more point is the reference with
//! its emitters moved by 0.001 units: the difference that chaos alone makes, the floor no
//! resolution gets under.
//!
//! The cases are the scenes of generated videos (default: the demo video), with the fluids'
//! true materials: the factual run (every emitter, 700 updates) and the first counterfactual
//! run the release recorded (that stick removed, first emitters, 500 updates). Three error
//! measures, all shares, compared per fluid:
//! * `container_fraction_error`: the share of a fluid's particles that ends in each container
//!   (the release's counting of `perReceptorFluidStat`: 20 particles or fewer count as none);
//! * `stick_pass_error`: the share that touched each regular stick (`perEmitterStickStat`);
//! * `front_error`: the height of the fluid's leading edge (what its first 2% of volume has
//!   reached: the height of its particle of rank 2% of the emitter's budget, lowest first) at
//!   0.5, 1, 1.5, 2, 3 and 4 s after its emitter opens, as a share of the tank's height;
//! * `label_disagreement`: what the questions read, the share of the run's labels (a fluid
//!   passes a stick, enters a container, a container holds most of it) that differ from the
//!   reference's. The default setting is meant to stay within 5% of them.
//!
//! The cost of a point is its wall time and, unaffected by a loaded machine, the solver's
//! particle substeps (`work`), each also as a share of the reference's.
//!
//! Input: video folders with an `outputs.json`. Output: the cases of [`BENCH`].

use std::path::{Path, PathBuf};

use indexmap::IndexMap;

use super::simulate::{
    FluidGeometry, FluidMaterialGuess, Particles, RunKind, RunSettings, TANK_INNER, emitter_budget,
    simulate_observed,
};
use crate::dataset::fluid::outcome::is_regular_stick;
use crate::dataset::fluid::world::{
    COUNTERFACTUAL_UPDATES, EMITTER_OPEN_UPDATE, FACTUAL_UPDATES, PARTICLES_PER_EMITTER,
    PREDICTIVE_EMITTER_OPEN_UPDATE,
};
use crate::dataset::fluid::{FluidAnnotation, Viscosity};
use crate::physics::bench::{
    BenchCase, BenchError, CaseOutput, ErrorMeasure, Parameter, PhysicsBench, Reduction, Reference,
    input_digest, video_name,
};

/// Updates after an emitter opens at which its front is measured (1/60 s each).
const FRONT_UPDATES: [u32; 6] = [30, 60, 90, 120, 180, 240];

/// The share of a fluid's volume whose highest particle is its front.
const FRONT_QUANTILE: f64 = 0.02;

/// The fluid simulation's benchmark.
pub(crate) const BENCH: PhysicsBench = PhysicsBench {
    // The factual run: 700 updates of 1/60 s.
    duration: 700.0 / 60.0,
    parameters: &[
        Parameter {
            key: "grid_spacing",
            flag: "--grid-spacing",
            label: "dx",
            follows_sweep: false,
        },
        Parameter {
            key: "particles_per_cell_side",
            flag: "--particles-per-cell",
            label: "ppc",
            follows_sweep: false,
        },
        Parameter {
            key: "emitter_shift",
            flag: "--emitter-shift",
            label: "shift",
            follows_sweep: false,
        },
    ],
    sweep: &[
        &[0.1, 2.0, 0.0],
        &[0.075, 2.0, 0.0],
        &[0.05, 1.0, 0.0],
        &[0.05, 2.0, 0.0],
        &[0.05, 3.0, 0.0],
        &[0.04, 2.0, 0.0],
        &[0.03, 2.0, 0.0],
        // The reference itself with every emitter moved by a tenth of a particle: how far a
        // run can land from the reference for no reason of resolution (the flow's chaos).
        &[0.02, 2.0, 0.001],
    ],
    default: &[0.05, 2.0, 0.0],
    reference: Reference::Point(&[0.02, 2.0, 0.0]),
    confirmation: None,
    errors: &[
        ErrorMeasure {
            key: "container_fraction_error",
            reduction: Reduction::Largest,
            tolerance: None,
            plotted: true,
        },
        ErrorMeasure {
            key: "stick_pass_error",
            reduction: Reduction::Largest,
            tolerance: None,
            plotted: true,
        },
        ErrorMeasure {
            key: "front_error",
            reduction: Reduction::Largest,
            tolerance: None,
            plotted: true,
        },
        // What the questions read: a run's pass, enter and "holds most" labels; the default
        // setting should give the reference's labels but for 5%.
        ErrorMeasure {
            key: "label_disagreement",
            reduction: Reduction::Mean,
            tolerance: Some(0.05),
            plotted: false,
        },
    ],
    error_axis: "largest error, share of fluid or tank height",
    repeats: 1,
    title: "MPM fluid",
    uses_videos: true,
    cases,
};

/// The factual and first counterfactual case of every video.
fn cases(videos: &[PathBuf]) -> Result<Vec<BenchCase>, BenchError> {
    let mut cases = Vec::new();
    for video in videos {
        let scene = Scene::load(video)?;
        let name = video_name(video);
        let inputs = input_digest(&name, &video.join("outputs.json"))?;
        let removed = scene
            .annotation
            .counterfactuals
            .first()
            .map(|counterfactual| counterfactual.removed_stick.clone());
        let scene = std::sync::Arc::new(scene);
        for removed in std::iter::once(None).chain(removed.map(Some)) {
            let case_name = match &removed {
                None => format!("{name} factual"),
                Some(stick) => format!("{name} without the {stick}"),
            };
            let scene = std::sync::Arc::clone(&scene);
            let label = case_name.clone();
            cases.push(BenchCase {
                name: case_name,
                exact: None,
                inputs: inputs.clone(),
                label_names: Vec::new(),
                run: Box::new(move |point| scene.measure(&label, removed.as_deref(), point)),
            });
        }
    }
    Ok(cases)
}

/// A video's scene with its true materials.
struct Scene {
    annotation: FluidAnnotation,
    geometry: FluidGeometry,
    materials: IndexMap<String, FluidMaterialGuess>,
}

impl Scene {
    fn load(video: &Path) -> Result<Scene, BenchError> {
        let case = video.display().to_string();
        let annotation = FluidAnnotation::load(&video.join("outputs.json"))
            .map_err(|e| BenchError::new(&case, e))?;
        let geometry =
            FluidGeometry::from_annotation(&annotation).map_err(|e| BenchError::new(&case, e))?;
        let materials = annotation
            .layout
            .fluids
            .iter()
            .map(|fluid| {
                let guess = FluidMaterialGuess {
                    density: fluid.density,
                    sticky: fluid.viscosity == Viscosity::Sticky,
                };
                (fluid.name.clone(), guess)
            })
            .collect();
        Ok(Scene {
            annotation,
            geometry,
            materials,
        })
    }

    /// The run without `removed` (factual when `None`) at `point` (grid spacing, particles
    /// per cell side, emitter shift along x in units): container fractions, stick passes and
    /// fronts.
    fn measure(
        &self,
        case: &str,
        removed: Option<&str>,
        point: &[f64],
    ) -> Result<CaseOutput, BenchError> {
        let [grid_spacing, per_side, shift] = *point else {
            return Err(BenchError::new(
                case,
                "a sweep point needs a grid spacing, a count and a shift",
            ));
        };
        if !shift.is_finite() || shift.abs() > 0.1 {
            return Err(BenchError::new(
                case,
                format!("an emitter shift must be within ±0.1 units, not {shift}"),
            ));
        }
        let mut geometry = self.geometry.clone();
        for emitter in &mut geometry.emitters {
            emitter.centre[0] += shift;
        }
        if !((1.0..=8.0).contains(&per_side) && per_side.fract() == 0.0) {
            return Err(BenchError::new(
                case,
                format!("particles per cell side must be 1 to 8, not {per_side}"),
            ));
        }
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "checked to be a whole number from 1 to 8"
        )]
        let settings = RunSettings {
            grid_spacing,
            particles_per_cell_side: per_side as u32,
            ..RunSettings::default()
        };
        let kind = removed.map_or(RunKind::Factual, RunKind::Without);
        let emitters: Vec<(String, u32)> = geometry
            .emitters
            .iter()
            .filter(|emitter| removed.is_none() || !emitter.later)
            .map(|emitter| {
                let opens = if emitter.later {
                    PREDICTIVE_EMITTER_OPEN_UPDATE
                } else {
                    EMITTER_OPEN_UPDATE
                };
                (emitter.key.clone(), opens)
            })
            .collect();
        let last = if removed.is_some() {
            COUNTERFACTUAL_UPDATES
        } else {
            FACTUAL_UPDATES
        };
        #[expect(
            clippy::cast_possible_truncation,
            clippy::cast_sign_loss,
            reason = "a small share of a particle count"
        )]
        let front_rank = (emitter_budget(&settings) as f64 * FRONT_QUANTILE).round() as usize;
        // Per emitter, its fronts in time order.
        let mut fronts: Vec<Vec<f64>> = vec![Vec::new(); emitters.len()];
        let mut observe = |update: u32, particles: &Particles| {
            for (index, (_, opens)) in emitters.iter().enumerate() {
                if FRONT_UPDATES
                    .iter()
                    .any(|after| opens + after == update && update <= last)
                    && let Some(list) = fronts.get_mut(index)
                {
                    list.push(front_share(particles, index, front_rank));
                }
            }
        };
        let receptors = self.annotation.layout.receptors();
        let run = simulate_observed(
            &geometry,
            &receptors,
            &self.materials,
            kind,
            &settings,
            &mut observe,
        )
        .map_err(|e| BenchError::new(case, e))?;
        let per_fluid = f64::from(PARTICLES_PER_EMITTER);
        let mut containers = Vec::new();
        let mut passes = Vec::new();
        let mut labels = Vec::new();
        let label = |holds: bool| if holds { 1.0 } else { 0.0 };
        for (fluid, _) in &emitters {
            for receptor in &receptors {
                let count = run.tracking.particles_in(receptor.name, fluid);
                containers.push(f64::from(count) / per_fluid);
                labels.push(label(count > 0));
                labels.push(label(run.tracking.holds_most(receptor.name, fluid)));
            }
            let contacts = run.tracking.contacts(fluid);
            for stick in self
                .geometry
                .colliders
                .iter()
                .filter(|collider| is_regular_stick(&collider.name))
            {
                let count = contacts
                    .and_then(|contacts| contacts.get(&stick.name))
                    .copied()
                    .unwrap_or(0);
                passes.push(f64::from(count) / per_fluid);
                labels.push(label(count > 0));
            }
        }
        Ok(CaseOutput {
            quantities: vec![containers, passes, fronts.concat(), labels],
            work: Some(run.work.particle_substeps),
        })
    }
}

/// The height of emitter `index`'s front (its particle of rank `rank`, lowest first, or its
/// highest while it has fewer) above the tank's floor, as a share of the tank's height; 1
/// before it emits.
fn front_share(particles: &Particles, index: usize, rank: usize) -> f64 {
    let mut heights: Vec<f64> = particles
        .iter()
        .filter(|(_, emitter, _)| *emitter == index)
        .map(|(state, _, _)| state.position[1])
        .collect();
    let floor = TANK_INNER[0][1];
    let height = TANK_INNER[1][1] - floor;
    heights.sort_unstable_by(f64::total_cmp);
    match heights.get(rank).or(heights.last()) {
        Some(front) => (front - floor) / height,
        None => 1.0,
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::scene_api::fluid::simulate::simulate;

    fn demo() -> PathBuf {
        Path::new(env!("CARGO_MANIFEST_DIR")).join("eval/demo/fluid_slides/0")
    }

    /// The demo video's factual case on a coarse grid: its measures count what the labelled run
    /// counts, and the fronts fall from the emitters toward the floor.
    #[test]
    fn the_factual_case_measures_what_the_labelled_run_counts_and_fronts_fall() {
        let cases = cases(&[demo()]).unwrap();
        let names: Vec<&str> = cases.iter().map(|case| case.name.as_str()).collect();
        let scene = Scene::load(&demo()).unwrap();
        let removed = &scene.annotation.counterfactuals[0].removed_stick;
        assert_eq!(
            names,
            [
                "fluid_slides/0 factual".to_string(),
                format!("fluid_slides/0 without the {removed}")
            ]
        );
        let measured = (cases[0].run)(&[0.1, 2.0, 0.0]).unwrap().quantities;
        let [containers, passes, fronts, labels] = measured.as_slice() else {
            panic!("four measures: {measured:?}");
        };
        assert!(labels.iter().all(|l| [0.0, 1.0].contains(l)), "{labels:?}");
        let emitters = scene.geometry.emitters.len();
        let receptors = scene.annotation.layout.receptors();
        let sticks = scene
            .geometry
            .colliders
            .iter()
            .filter(|collider| is_regular_stick(&collider.name))
            .count();
        assert_eq!(containers.len(), emitters * receptors.len());
        assert_eq!(passes.len(), emitters * sticks);
        // First emitters open at update 2, later ones at 460: every front time of the first
        // fits in 700 updates; a later one's last (460 + 240) is exactly 700.
        assert_eq!(fronts.len(), emitters * FRONT_UPDATES.len());
        let settings = RunSettings {
            grid_spacing: 0.1,
            ..RunSettings::default()
        };
        let run = simulate(
            &scene.geometry,
            &receptors,
            &scene.materials,
            RunKind::Factual,
            &settings,
        )
        .unwrap();
        for (index, emitter) in scene.geometry.emitters.iter().enumerate() {
            let shares = &containers[index * receptors.len()..(index + 1) * receptors.len()];
            for (share, receptor) in shares.iter().zip(&receptors) {
                let count = run.tracking.particles_in(receptor.name, &emitter.key);
                let expected = f64::from(count) / 1500.0;
                assert!((share - expected).abs() < 1e-15, "{}", emitter.key);
            }
            assert!(shares.iter().sum::<f64>() <= 1.0 + 1e-9, "{shares:?}");
            let heights = &fronts[index * FRONT_UPDATES.len()..(index + 1) * FRONT_UPDATES.len()];
            assert!(
                heights.iter().all(|height| (0.0..=1.0).contains(height)),
                "{heights:?}"
            );
            // Half a second after opening the front is still near the top (emitters sit at
            // 0.95 of the tank's height); four seconds later it has fallen a tenth of the tank
            // at least (the fluids land on sticks and slide).
            assert!(heights[0] > 0.7, "{}: {heights:?}", emitter.key);
            assert!(
                heights[5] < heights[0] - 0.1,
                "{}: {heights:?}",
                emitter.key
            );
        }
        assert!(passes.iter().any(|share| *share > 0.5), "{passes:?}");
    }

    #[test]
    fn a_bad_sweep_point_is_a_case_error() {
        let cases = cases(&[demo()]).unwrap();
        let error = (cases[0].run)(&[0.1, 0.5, 0.0]).unwrap_err();
        assert_eq!(
            error.to_string(),
            "benchmark case `fluid_slides/0 factual`: particles per cell side must be 1 to 8, not 0.5"
        );
        let missing = super::cases(&[PathBuf::from("no/such/video")]).unwrap_err();
        assert!(missing.to_string().contains("no/such/video"), "{missing}");
    }
}

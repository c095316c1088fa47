//! A run's `trackingData` (`FORMAT.md` §3.2) and the sticks its counterfactual runs remove,
//! counted from the simulated contacts and final positions by the release's rules
//! (`dataset::fluid::outcome`, shared with the simulate backend).

use indexmap::IndexMap;
use rand_chacha::ChaCha8Rng;
use serde_json::{Value, json};

use super::layout::{Layout, to_world};
use super::simulate::{FluidRun, FluidScene};
use crate::dataset::fluid::outcome::{
    ParticleCounts, Receptor, Rect, counterfactual_sticks, density_relations, emitter_stick_stat,
    receptor_fluid_stat, temperature_askable_sticks,
};

/// A run's statistics.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct Tracking {
    /// `perEmitterStickStat` (cut at the release's 20 particles, emitter parts folded).
    pub stick_stat: ParticleCounts,
    /// `perReceptorFluidStat` (cut at 20 particles).
    pub receptor_stat: ParticleCounts,
    /// `allDensityRelations` as (denser, lighter).
    pub relations: Vec<(String, String)>,
    /// `temperatureStick`: the run's regular sticks, all "Normal".
    pub temperature: IndexMap<String, String>,
}

/// Counts `run` of `scene` (built from `layout`); `removed` is the stick the run lacks, if any.
pub fn track(
    layout: &Layout,
    scene: &FluidScene,
    run: &FluidRun,
    removed: Option<&str>,
) -> Tracking {
    let keys = scene.emitters.len();
    let mut paths: Vec<Vec<Vec<&str>>> = vec![Vec::new(); keys];
    let mut finals: Vec<Vec<[f64; 2]>> = vec![Vec::new(); keys];
    for (particle, &emitter) in run.emitter_of.iter().enumerate() {
        let bits = run.touched.get(particle).copied().unwrap_or(0);
        let path: Vec<&str> = scene
            .colliders
            .iter()
            .enumerate()
            .filter(|(index, _)| bits & (1 << index) != 0)
            .map(|(_, named)| named.name.as_str())
            .collect();
        if let (Some(list), Some(&position)) =
            (paths.get_mut(emitter), run.final_positions.get(particle))
        {
            list.push(path);
            finals[emitter].push(position);
        }
    }
    let stick_stat: ParticleCounts = scene
        .emitters
        .iter()
        .zip(&paths)
        .filter(|(_, particles)| !particles.is_empty())
        .map(|(emitter, particles)| {
            (
                emitter.name.clone(),
                emitter_stick_stat(&emitter.name, particles),
            )
        })
        .collect();
    let receptors: Vec<Receptor<'_>> = layout
        .containers
        .iter()
        .map(|container| {
            let (a, b) = container.left.world();
            let (c, d) = container.right.world();
            Receptor {
                name: &container.name,
                cup: Rect::from_centre_size(to_world(container.position), container.scale),
                funnel: Rect::bounding(&[a, b, c, d]).unwrap_or(Rect { min: a, max: a }),
            }
        })
        .collect();
    let fluids: Vec<(&str, &[[f64; 2]])> = scene
        .emitters
        .iter()
        .zip(&finals)
        .map(|(emitter, positions)| (emitter.name.as_str(), positions.as_slice()))
        .collect();
    let receptor_stat = receptor_fluid_stat(&receptors, &fluids);
    let densities: Vec<(&str, f64)> = layout
        .fluids
        .iter()
        .map(|fluid| (fluid.name.as_str(), fluid.density))
        .collect();
    let relations = density_relations(&receptor_stat, &densities);
    let temperature = layout
        .sticks
        .iter()
        .filter(|stick| Some(stick.name.as_str()) != removed)
        .map(|stick| (stick.name.clone(), "Normal".to_string()))
        .collect();
    Tracking {
        stick_stat,
        receptor_stat,
        relations,
        temperature,
    }
}

impl Tracking {
    /// The `trackingData` object, keys in the release's order.
    pub fn to_json(&self) -> Value {
        json!({
            "perEmitterStickStat": self.stick_stat,
            "temperatureStick": self.temperature,
            "temperatureAskableStick": temperature_askable_sticks(&self.stick_stat, &self.temperature),
            "perReceptorFluidStat": self.receptor_stat,
            "allDensityRelations": self
                .relations
                .iter()
                .map(|(denser, lighter)| json!({"Item1": denser, "Item2": lighter}))
                .collect::<Vec<_>>(),
        })
    }

    /// The sticks the counterfactual runs remove, in run order.
    pub fn sticks_to_remove(&self, rng: &mut ChaCha8Rng) -> Vec<String> {
        let sticks: Vec<&String> = self.temperature.keys().collect();
        counterfactual_sticks(&self.stick_stat, &sticks, rng)
    }
}

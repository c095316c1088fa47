//! The simulated runs of one fluid video (`--dynamics simulate`), made on first use and kept:
//! the factual run, and one run without each stick a question removes. Each run is simulated at
//! most once per scene, and only when a question needs it; the work is counted for the run's
//! report (`simulation_work`).
//!
//! Input: the perceived geometry, the containers' boxes, the inferred materials. Output: each
//! run's `trackingData` ([`FluidTracking`]), or the solver's failure as an API error that names
//! the run.

use std::collections::BTreeMap;
use std::sync::{Mutex, PoisonError};

use indexmap::IndexMap;

use super::simulate::{
    FluidGeometry, FluidMaterialGuess, RunKind, RunSettings, SimulatedRun, simulate,
};
use crate::dataset::fluid::FluidTracking;
use crate::dataset::fluid::outcome::{Receptor, Rect};
use crate::scene_api::ApiError;

/// A container's boxes, owned.
#[derive(Debug, Clone, PartialEq)]
pub(crate) struct ReceptorBoxes {
    /// The container's name.
    pub name: String,
    /// Its cup.
    pub cup: Rect,
    /// Its funnel.
    pub funnel: Rect,
}

/// A fluid video's simulated runs.
pub(crate) struct SimulatedRuns {
    geometry: FluidGeometry,
    receptors: Vec<ReceptorBoxes>,
    materials: IndexMap<String, FluidMaterialGuess>,
    settings: RunSettings,
    /// Runs made so far, by removed stick (`None`: the factual run).
    made: Mutex<BTreeMap<Option<String>, Result<FluidTracking, ApiError>>>,
    /// (runs, particle substeps) simulated.
    work: Mutex<(u64, u64)>,
}

impl SimulatedRuns {
    /// Runs of the scene of `geometry` with `materials`, none made yet.
    pub(crate) fn new(
        geometry: FluidGeometry,
        receptors: Vec<ReceptorBoxes>,
        materials: IndexMap<String, FluidMaterialGuess>,
        settings: RunSettings,
    ) -> SimulatedRuns {
        SimulatedRuns {
            geometry,
            receptors,
            materials,
            settings,
            made: Mutex::new(BTreeMap::new()),
            work: Mutex::new((0, 0)),
        }
    }

    /// The run without `removed` (or the factual run), simulated now if it was not yet.
    pub(crate) fn run(&self, removed: Option<&str>) -> Result<FluidTracking, ApiError> {
        let key = removed.map(str::to_string);
        // The lock is held through the simulation: a second question asking for the same run
        // waits for it instead of simulating it again.
        let mut made = self.made.lock().unwrap_or_else(PoisonError::into_inner);
        if let Some(result) = made.get(&key) {
            return result.clone();
        }
        let receptors: Vec<Receptor<'_>> = self
            .receptors
            .iter()
            .map(|boxes| Receptor {
                name: &boxes.name,
                cup: boxes.cup,
                funnel: boxes.funnel,
            })
            .collect();
        let kind = match removed {
            Some(stick) => RunKind::Without(stick),
            None => RunKind::Factual,
        };
        let result = simulate(
            &self.geometry,
            &receptors,
            &self.materials,
            kind,
            &self.settings,
        )
        .map(|SimulatedRun { tracking, work }| {
            let mut total = self.work.lock().unwrap_or_else(PoisonError::into_inner);
            total.0 += 1;
            total.1 += work.particle_substeps;
            tracking
        })
        .map_err(|error| {
            let run = removed.map_or_else(
                || "the factual run".to_string(),
                |stick| format!("the run without the {}", stick.to_lowercase()),
            );
            ApiError::Unavailable(format!("the fluid simulation of {run} failed: {error}"))
        });
        made.insert(key, result.clone());
        result
    }

    /// (runs, particle substeps) simulated so far.
    pub(crate) fn work(&self) -> (u64, u64) {
        *self.work.lock().unwrap_or_else(PoisonError::into_inner)
    }
}

//! The fluid engine's view of a video: the fluids, sticks and containers it can refer to by
//! colour, and the density order the tracking data records.
//!
//! An object is referred to by its colour word alone (`pink fluid`, `gray stick`), as the
//! paper's templates do. The release gives every fluid, stick and container of a kind a distinct
//! colour; should two share one, neither is asked about (no phrase tells them apart).

use crate::dataset::engine::colour_references;
use crate::dataset::fluid::outcome::{DensityOrder, DensityOrdering};
use crate::dataset::fluid::{FluidAnnotation, later_fluid_name, parse_fluid_object_name};

pub(super) use crate::dataset::engine::Reference;

/// A fluid with a predictive emitter.
#[derive(Debug, Clone, PartialEq, Eq)]
pub(super) struct LaterFluid<'a> {
    /// The fluid the predictive emitter emits.
    pub(super) fluid: Reference<'a>,
    /// Its key in the tracking data (`Later Emitted Yellow Fluid`).
    pub(super) key: String,
}

impl LaterFluid<'_> {
    /// The program's name of it (`later emitted yellow fluid`).
    pub(super) fn program_name(&self) -> String {
        self.key.to_lowercase()
    }
}

/// The engine's view of one video.
#[derive(Debug, Clone)]
pub(super) struct FluidScene<'a> {
    /// The factual fluids, in `metaSamplingData.fluids` order.
    pub(super) fluids: Vec<Reference<'a>>,
    /// The fluids with a predictive emitter, in the same order.
    pub(super) later_fluids: Vec<LaterFluid<'a>>,
    /// The regular sticks, in `metaSamplingData.sticks` order.
    pub(super) sticks: Vec<Reference<'a>>,
    /// The containers, in `metaSamplingData.reservoirs` order.
    pub(super) containers: Vec<Reference<'a>>,
    /// `allDensityRelations` (base fluids) after transitive closure.
    density: DensityOrdering,
}

impl<'a> FluidScene<'a> {
    /// The view of `annotation`.
    pub(super) fn new(annotation: &'a FluidAnnotation) -> FluidScene<'a> {
        let layout = &annotation.layout;
        let fluids = references(layout.fluids.iter().map(|fluid| fluid.name.as_str()));
        let later_fluids = layout
            .fluids
            .iter()
            .filter(|record| record.has_predictive_emitter)
            .filter_map(|record| {
                let fluid = fluids.iter().find(|f| f.name == record.name)?.clone();
                let color = parse_fluid_object_name(&record.name)?.color?;
                Some(LaterFluid {
                    fluid,
                    key: later_fluid_name(color),
                })
            })
            .collect();
        FluidScene {
            fluids,
            later_fluids,
            sticks: references(layout.sticks.iter().map(|stick| stick.name.as_str())),
            containers: references(layout.reservoirs.iter().map(|r| r.name.as_str())),
            density: annotation.tracking.density_ordering(),
        }
    }

    /// How `first`'s density compares with `second`'s (base fluid names).
    pub(super) fn density_order(&self, first: &str, second: &str) -> DensityOrder {
        self.density.order(first, second)
    }

    /// The stick named `name`, if it can be referred to.
    pub(super) fn stick(&self, name: &str) -> Option<&Reference<'a>> {
        self.sticks.iter().find(|stick| stick.name == name)
    }
}

/// The objects of `names` with their colour words (see [`colour_references`]).
fn references<'a>(names: impl Iterator<Item = &'a str>) -> Vec<Reference<'a>> {
    colour_references(names, |name| parse_fluid_object_name(name)?.color_word())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn objects_sharing_a_colour_are_left_out() {
        let names = [
            "Pink Fluid",
            "Light Blue Fluid",
            "Pink Fluid",
            "Yellow Fluid",
        ];
        let words: Vec<String> = references(names.into_iter())
            .into_iter()
            .map(|r| r.word)
            .collect();
        assert_eq!(words, ["light blue", "yellow"]);
    }
}

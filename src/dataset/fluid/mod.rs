//! Fluid scenes (`fluid_slides`): the annotations of a video ([`FluidAnnotation`]), the grammar
//! of object names ([`parse_fluid_object_name`]), the release's fluid world ([`world`]), its
//! labelling of a run ([`outcome`]) and the words of fluid scenes ([`VOCABULARY`]).
//!
//! The format is described in `docs/data/fluid.md`. The question engine
//! (`dataset::engine::fluid`), the generator (`synth::fluid`) and the scene backend
//! (`scene_api::fluid`) read these types.

mod annotation;
mod names;
pub mod outcome;
mod vocabulary;
pub mod world;

pub use annotation::{
    DensityRelation, FluidAnnotation, FluidCounterfactual, FluidLayout, FluidRecord, FluidTracking,
    ObjectTransform, ReservoirRecord, StickRecord, TankLayout, Viscosity,
};
pub use names::{
    ContainerPart, FluidObjectKind, FluidObjectName, LATER_EMITTED_PREFIX, PALETTE_NAMES, TankWall,
    base_fluid_name, container_name, container_part_name, emitter_name, fluid_name,
    later_fluid_name, palette_name, parse_fluid_object_name, stick_name,
};
pub use vocabulary::VOCABULARY;

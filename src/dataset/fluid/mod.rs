//! Fluid scenes (`fluid_slides`): the words of fluid scenes. Their annotations, question engine,
//! scene backend and generator are not implemented yet.

mod vocabulary;

pub use vocabulary::VOCABULARY;

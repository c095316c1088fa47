//! Cloth scenes (`cloth_collision`): the words of cloth scenes. Their annotations, question engine,
//! scene backend and generator are not implemented yet.

mod vocabulary;

pub use vocabulary::VOCABULARY;

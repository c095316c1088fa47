//! Ball scenes (`soft_body`): the words of ball scenes. Their annotations, question engine,
//! scene backend and generator are not implemented yet.

mod vocabulary;

pub use vocabulary::VOCABULARY;

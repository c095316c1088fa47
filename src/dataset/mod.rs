//! The ContPhy dataset: data roots, video folders, annotations and question files.
//!
//! Inputs are files laid out as in the public release (`DATA/pulley_group/<video_id>/outputs.json`
//! and likewise `fluid_slides`, `cloth_collision`, `soft_body`; question files in the engine's
//! per-video form or the sampled list form, see `contphy/FORMAT.md` §6). Outputs are typed values:
//! [`Question`], [`VideoFolder`], [`RopeAnnotation`], [`FourDData`]. Every malformed, missing or
//! truncated input becomes a [`DatasetError`] that names the file and the field.
//!
//! The rope question engine (a Rust re-implementation of the public one) lives in [`engine`].
//! This module depends only on `util`.

pub mod engine;
mod error;
mod fields;
mod four_d;
mod question;
mod question_file;
mod rope;
mod scenario;
mod segmentation;
mod video;

pub use error::DatasetError;
pub use four_d::{FourDData, RigidBodyTrack, SoftBodyTrack};
pub use question::{
    AnswerType, Category, ChoiceOption, Family, Question, QuestionId, QuestionRecord, Split,
    VideoId,
};
pub use question_file::{
    PerVideoQuestions, QuestionSource, load_question_file, questions_file_name, sampled_file_path,
    write_per_video_file, write_sampled_file,
};
pub use rope::{
    Camera, RopeAnnotation, RopeChange, RopeCounterfactual, RopeCounterfactualPair, RopeObjectKind,
    RopeObjectName, parse_rope_object_name, world as rope_world,
};
pub use scenario::Scenario;
pub use segmentation::{PaintedInstance, SegmentationRecords};
pub use video::{DataRoot, VideoFolder, VideoListing, read_validity};

//! The ContPhy dataset: data roots, video folders, annotations and question files.
//!
//! Inputs are files laid out as in the public release (`DATA/<scenario folder>/<video_id>/
//! outputs.json`, question files in the engine's per-video form or the sampled list form; see
//! `docs/data/`). Outputs are typed values: [`Question`], [`VideoFolder`], [`FourDData`], and per
//! scenario its annotations in `dataset/<scenario>/` ([`rope::RopeAnnotation`]). Every malformed,
//! missing or truncated input becomes a [`DatasetError`] that names the file and the field.
//!
//! Shared here: the [`Scenario`] list, the [`Vocabulary`] type each scenario fills in, the camera
//! calibration, 4-D data, segmentation records, and the question engine's shared parts
//! ([`engine`]). This module depends only on `util`.

pub mod ball;
mod camera;
pub mod cloth;
pub mod engine;
mod error;
mod fields;
pub mod fluid;
mod four_d;
pub mod palette;
mod question;
mod question_file;
pub mod rope;
mod scenario;
mod segmentation;
mod video;
pub mod vocabulary;

pub use camera::Camera;
pub use error::DatasetError;
pub use four_d::{FourDData, RigidBodyTrack, SoftBodyTrack};
pub use question::{
    AnswerType, Category, ChoiceOption, Family, Question, QuestionError, QuestionId,
    QuestionRecord, Split, VideoId,
};
pub use question_file::{
    FamilyIndex, PerVideoQuestions, QuestionSource, load_question_file, questions_file_name,
    sampled_file_path, write_per_video_file, write_sampled_file,
};
pub use scenario::{PaperRow, Scenario, UnknownScenario};
pub use segmentation::{PaintedInstance, SegmentationRecords};
pub use video::{DataRoot, VideoFolder, VideoListing, read_validity};
pub use vocabulary::Vocabulary;

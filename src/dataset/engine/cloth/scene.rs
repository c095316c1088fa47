//! The cloth engine's view of a video: the boxes it can refer to, by half, with their end poses.
//!
//! A box is referred to by its colour and shape (`green plate`, `light blue pillar`), as the
//! paper's templates do (`_CLR_ _OBJ_`, `_OBJ_` a plate or a pillar). The release gives each
//! shape distinct colours over both halves, so a plate and a pillar may share a colour, which the
//! shape word tells apart. Cubes (tower layers the release practically never leaves unmerged)
//! are not asked about: the templates and the scene words know plates and pillars only. Should
//! two boxes share a phrase, neither is asked about.

use crate::dataset::cloth::names::{Shape, Side, parse_box_name};
use crate::dataset::cloth::outcome::Pose;
use crate::dataset::cloth::{BoxRecord, ClothAnnotation};
use crate::dataset::engine::colour_references;

pub(super) use crate::dataset::engine::Reference;

/// A box the engine can ask about.
#[derive(Debug, Clone, PartialEq)]
pub(super) struct BoxReference<'a> {
    /// Its name and its phrase in questions (`word`: `green plate`).
    pub(super) reference: Reference<'a>,
    /// Its half.
    pub(super) side: Side,
    /// Its record.
    pub(super) record: &'a BoxRecord,
}

impl BoxReference<'_> {
    /// Its end pose.
    pub(super) fn pose(&self) -> Pose {
        self.record.end_pose
    }
}

/// The engine's view of one video.
#[derive(Debug, Clone)]
pub(super) struct ClothScene<'a> {
    /// The askable boxes: the left half's in file order, then the right half's.
    pub(super) boxes: Vec<BoxReference<'a>>,
}

impl<'a> ClothScene<'a> {
    /// The view of `annotation`.
    pub(super) fn new(annotation: &'a ClothAnnotation) -> ClothScene<'a> {
        let askable: Vec<(Side, &BoxRecord)> = annotation
            .boxes()
            .filter(|(_, record)| {
                parse_box_name(&record.name).is_some_and(|name| name.shape != Shape::Cube)
            })
            .collect();
        let references = colour_references(
            askable.iter().map(|(_, record)| record.name.as_str()),
            |name| {
                let parsed = parse_box_name(name)?;
                Some(format!(
                    "{} {}",
                    parsed.color.to_lowercase(),
                    parsed.shape.word()
                ))
            },
        );
        let boxes = askable
            .into_iter()
            .filter_map(|(side, record)| {
                let reference = references
                    .iter()
                    .find(|reference| reference.name == record.name)?
                    .clone();
                Some(BoxReference {
                    reference,
                    side,
                    record,
                })
            })
            .collect();
        ClothScene { boxes }
    }

    /// Every unordered pair of askable boxes in one half, in file order (a box of one half
    /// cannot reach a box of the other: they stand 4.8 units apart and fall along the pull).
    pub(super) fn pairs(&self) -> Vec<(&BoxReference<'a>, &BoxReference<'a>)> {
        let mut pairs = Vec::new();
        for (index, first) in self.boxes.iter().enumerate() {
            for second in self.boxes.iter().skip(index + 1) {
                if first.side == second.side {
                    pairs.push((first, second));
                }
            }
        }
        pairs
    }
}

//! The property families: `elasticity` and `bending`, each comparing one cloth with the other.
//!
//! The release draws each property from two values and always gives the two cloths different
//! ones, so every comparison has an answer:
//!
//! * elasticity: the cloth with the larger `stretchingCompliance` (0.011 against 0) stretches
//!   under the pull and is the more elastic one, "elastic" in the everyday sense of stretchy;
//! * bending: the cloth with the larger `bendingCompliance` (really Obi's maximum bending, 0.035
//!   against 0.013) bends and wrinkles more easily; the other is harder to bend.
//!
//! Each cloth (`_POS_` left, then right) is asked about once per family, the comparator a coin
//! flip, so "yes" and "no" are equally likely. Cloths with equal values are not compared: "much
//! greater" would be neither true nor what the scene shows.

use std::cmp::Ordering;

use rand::Rng;

use super::templates::{BENDING, BENDING_TITLE, ELASTICITY, ELASTICITY_TITLE, fill};
use crate::dataset::QuestionRecord;
use crate::dataset::cloth::names::Side;
use crate::dataset::cloth::{ClothAnnotation, ClothProperties};
use crate::dataset::engine::record::open_ended_record;

/// A family's comparators: the one that holds when the asked cloth's value is larger, then the
/// one that holds when it is smaller.
type Comparators = [&'static str; 2];

/// `elasticity`: a larger stretching compliance is "greater".
const ELASTICITY_COMPARATORS: Comparators = ["greater than", "less than"];
/// `bending`: a larger maximum bending is "easier".
const BENDING_COMPARATORS: Comparators = ["easier", "harder"];

fn comparison_questions(
    annotation: &ClothAnnotation,
    family: &str,
    title: &str,
    comparators: Comparators,
    value: fn(&ClothProperties) -> f64,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for side in Side::BOTH {
        let asked = value(annotation.cloth(side));
        let other = value(annotation.cloth(side.other()));
        let larger = match asked.partial_cmp(&other) {
            Some(Ordering::Greater) => true,
            Some(Ordering::Less) => false,
            Some(Ordering::Equal) | None => continue,
        };
        let comparator = comparators[rng.random_range(0..comparators.len())];
        let holds = larger == (comparator == comparators[0]);
        records.push(open_ended_record(
            family,
            fill(title, &[side.word(), comparator]),
            if holds { "yes" } else { "no" },
            &[
                side.word(),
                "cloth",
                comparator,
                side.other().word(),
                "cloth",
            ],
        ));
    }
    records
}

/// `elasticity`: "Is the elasticity of the {left|right} cloth much {greater than|less than} that
/// of the other?" Program: `[side, "cloth", comparator, other side, "cloth"]`.
pub(super) fn elasticity_questions(
    annotation: &ClothAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    comparison_questions(
        annotation,
        ELASTICITY,
        ELASTICITY_TITLE,
        ELASTICITY_COMPARATORS,
        |cloth| cloth.stretching_compliance,
        rng,
    )
}

/// `bending`: "Is the {left|right} cloth much {harder|easier} to bend or have wrinkles than the
/// other?" Program as [`elasticity_questions`], the comparator `harder` or `easier`.
pub(super) fn bending_questions(
    annotation: &ClothAnnotation,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    comparison_questions(
        annotation,
        BENDING,
        BENDING_TITLE,
        BENDING_COMPARATORS,
        |cloth| cloth.bending_compliance,
        rng,
    )
}

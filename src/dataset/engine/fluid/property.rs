//! The property families: `density` and `stick_number`.
//!
//! `density` asks, for every ordered pair of fluids, whether the first is denser or lighter than
//! the second. The comparator is a coin flip, so a related pair is a "yes" or a "no" with equal
//! chance (the rope `mass` family's balance). The answer comes from `allDensityRelations` after
//! transitive closure, not from the layout's densities: the release records only what the
//! containers show (two fluids settling in one container), and a pair no relation links is
//! "can not answer", kept with probability [`CANNOT_ANSWER_PROBABILITY`] as rope keeps its
//! unrelated pairs.

use rand::Rng;

use super::scene::FluidScene;
use super::templates::{
    CANNOT_ANSWER, DENSITY, DENSITY_TITLE, STICK_NUMBER, STICK_NUMBER_TITLE, fill,
};
use crate::dataset::QuestionRecord;
use crate::dataset::engine::record::open_ended_record;
use crate::dataset::fluid::outcome::DensityOrder;

/// Probability that a pair of fluids no relation links yields a "can not answer" question (else
/// skipped), as in the rope engine.
const CANNOT_ANSWER_PROBABILITY: f64 = 0.3;

/// The comparators of the density template.
const COMPARATORS: [&str; 2] = ["greater than", "less than"];

/// `density`: "Is the fluid density of the {c1} fluid {greater than|less than} that of the {c2}
/// fluid?" for each ordered pair of fluids. Program: `[c1, "fluid", comparator, c2, "fluid"]`.
pub(super) fn density_questions(scene: &FluidScene<'_>, rng: &mut impl Rng) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for first in &scene.fluids {
        for second in &scene.fluids {
            if first.name == second.name {
                continue;
            }
            let comparator = COMPARATORS[rng.random_range(0..COMPARATORS.len())];
            let greater = comparator == COMPARATORS[0];
            let answer = match scene.density_order(first.name, second.name) {
                DensityOrder::Heavier => yes_no(greater),
                DensityOrder::Lighter => yes_no(!greater),
                DensityOrder::Unknown => {
                    if rng.random::<f64>() >= CANNOT_ANSWER_PROBABILITY {
                        continue;
                    }
                    CANNOT_ANSWER
                }
                // Relations both ways have no sound answer (the reader already drops a fluid
                // related to itself); the pair is not asked about.
                DensityOrder::Contradictory => continue,
            };
            let question = fill(DENSITY_TITLE, &[&first.word, comparator, &second.word]);
            records.push(open_ended_record(
                DENSITY,
                question,
                answer,
                &[&first.word, "fluid", comparator, &second.word, "fluid"],
            ));
        }
    }
    records
}

fn yes_no(holds: bool) -> &'static str {
    if holds { "yes" } else { "no" }
}

/// `stick_number`: "How many sticks are there in the video?", the regular sticks of the layout
/// (a container's guided sticks are part of the container). Program: `["stick"]`.
pub(super) fn stick_number_questions(stick_count: usize) -> Vec<QuestionRecord> {
    vec![open_ended_record(
        STICK_NUMBER,
        STICK_NUMBER_TITLE.to_string(),
        &stick_count.to_string(),
        &["stick"],
    )]
}

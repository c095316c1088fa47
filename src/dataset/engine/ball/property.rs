//! The property families: `elasticity` and `plasticity`.
//!
//! The release sets each ball's material, not a number, so an order holds only where the
//! materials decide it. Elasticity: the `Elastic` ball ("Ball More Elastic") is more elastic
//! than the `Rigid` one ("Ball Less Elastic") and than the `Plastic` one (which keeps its
//! dents); the `Rigid` and `Plastic` balls are not compared (neither springs back, and which
//! bounces less depends on the drop). Plasticity: only the `Plastic` ball has any, so it is
//! compared with each other ball. Every ordered pair of comparable balls is asked, the
//! comparator a coin flip, so "yes" and "no" are equally likely.

use rand::Rng;

use super::scene::{BallReference, BallScene};
use super::templates::{ELASTICITY, ELASTICITY_TITLE, PLASTICITY, PLASTICITY_TITLE, fill};
use crate::dataset::QuestionRecord;
use crate::dataset::ball::ElasticityType;
use crate::dataset::engine::record::open_ended_record;

/// The comparators of the templates.
const COMPARATORS: [&str; 2] = ["greater than", "less than"];

/// A ball's rank on one property (higher is more), or `None` where the materials do not order it.
type Rank = fn(ElasticityType, ElasticityType) -> Option<bool>;

/// Whether `first` is more elastic than `second`, where the materials say.
fn more_elastic(first: ElasticityType, second: ElasticityType) -> Option<bool> {
    use ElasticityType::{Elastic, Plastic, Rigid};
    match (first, second) {
        (Elastic, Rigid | Plastic) => Some(true),
        (Rigid | Plastic, Elastic) => Some(false),
        _ => None,
    }
}

/// Whether `first` is more plastic than `second`, where the materials say.
fn more_plastic(first: ElasticityType, second: ElasticityType) -> Option<bool> {
    use ElasticityType::Plastic;
    match (first, second) {
        (Plastic, other) if other != Plastic => Some(true),
        (other, Plastic) if other != Plastic => Some(false),
        _ => None,
    }
}

fn pair_questions(
    balls: &[BallReference<'_>],
    family: &str,
    title: &str,
    rank: Rank,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for first in balls {
        for second in balls {
            if first.reference.name == second.reference.name {
                continue;
            }
            let Some(first_more) = rank(first.elasticity, second.elasticity) else {
                continue;
            };
            let comparator = COMPARATORS[rng.random_range(0..COMPARATORS.len())];
            let holds = first_more == (comparator == COMPARATORS[0]);
            let (a, b) = (&first.reference.word, &second.reference.word);
            records.push(open_ended_record(
                family,
                fill(title, &[a, comparator, b]),
                if holds { "yes" } else { "no" },
                &[a, "ball", comparator, b, "ball"],
            ));
        }
    }
    records
}

/// `elasticity`: "Is the elasticity of the {c1} ball much {greater than|less than} the {c2}
/// ball?" Program: `[c1, "ball", comparator, c2, "ball"]`.
pub(super) fn elasticity_questions(
    scene: &BallScene<'_>,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    pair_questions(
        &scene.balls,
        ELASTICITY,
        ELASTICITY_TITLE,
        more_elastic,
        rng,
    )
}

/// `plasticity`: as [`elasticity_questions`], of plasticity.
pub(super) fn plasticity_questions(
    scene: &BallScene<'_>,
    rng: &mut impl Rng,
) -> Vec<QuestionRecord> {
    pair_questions(
        &scene.balls,
        PLASTICITY,
        PLASTICITY_TITLE,
        more_plastic,
        rng,
    )
}

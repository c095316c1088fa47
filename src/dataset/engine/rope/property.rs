//! The property families: `mass`, `tension`, `shape`, `color` and `existence`
//! (`docs/data/rope.md`, question engine). One function per family; each takes the scene and the
//! video's RNG and returns the family's records in generation order.
//!
//! Mass and tension statements are drawn as in the public `_fetch_comp_factor`: a comparator and
//! a factor chosen per branch with the same probabilities, then the true or the false statement
//! 50/50. The answer, though, is computed here from the masses (`m1 <cmp> factor·m2`, tolerance
//! [`MASS_EPSILON`]) instead of copied from the branch's hard-coded label, so every statement's
//! truth is checkable.

use rand::Rng;

use super::scene::{MASS_EPSILON, RopeScene};
use super::templates::{
    CANNOT_ANSWER, COLOR, COLORS, EXACT_SHAPES, EXISTENCE, MASS, SHAPE, SHAPES, TENSION,
};
use crate::dataset::QuestionRecord;
use crate::dataset::engine::record::open_ended_record;
use crate::dataset::rope::RopeObjectKind;

/// Probability that a pair of unrelated loads yields a "can not answer" question (else skipped).
const CANNOT_ANSWER_PROBABILITY: f64 = 0.3;
/// Probability of asking the true statement rather than the false one.
const TRUE_STATEMENT_PROBABILITY: f64 = 0.5;
/// Probability that a statement about a load under a movable pulley swaps its base factor for
/// another one ("diverse" statements of the public engine).
const DIVERSE_FACTOR_PROBABILITY: f64 = 0.1;

/// How two masses are compared.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Comparator {
    GreaterThan,
    LessThan,
    EqualTo,
}

impl Comparator {
    /// In the public engine's `comp_dict` order, which `random.choice` picks from.
    const ALL: [Comparator; 3] = [
        Comparator::GreaterThan,
        Comparator::LessThan,
        Comparator::EqualTo,
    ];

    pub(super) fn text(self) -> &'static str {
        match self {
            Comparator::GreaterThan => "greater than",
            Comparator::LessThan => "less than",
            Comparator::EqualTo => "equal to",
        }
    }
}

/// The factor applied to the second mass.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) enum Factor {
    One,
    Twice,
    Half,
}

impl Factor {
    /// As written in the question, trailing space included (`"twice "`), or empty.
    pub(super) fn text(self) -> &'static str {
        match self {
            Factor::One => "",
            Factor::Twice => "twice ",
            Factor::Half => "half ",
        }
    }

    fn value(self) -> f64 {
        match self {
            Factor::One => 1.0,
            Factor::Twice => 2.0,
            Factor::Half => 0.5,
        }
    }
}

/// "the first mass is `comparator` `factor` the second".
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(super) struct Statement {
    pub(super) comparator: Comparator,
    pub(super) factor: Factor,
}

impl Statement {
    const fn new(comparator: Comparator, factor: Factor) -> Statement {
        Statement { comparator, factor }
    }

    /// Whether the statement holds for these masses (kg), with the public engine's tolerance.
    pub(super) fn holds(self, first_kg: f64, second_kg: f64) -> bool {
        let scaled = second_kg * self.factor.value();
        match self.comparator {
            Comparator::GreaterThan => first_kg > scaled + MASS_EPSILON,
            Comparator::LessThan => first_kg < scaled - MASS_EPSILON,
            Comparator::EqualTo => (first_kg - scaled).abs() < MASS_EPSILON,
        }
    }
}

/// What a pair of loads yields.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
enum PairQuestion {
    /// The loads are in different related groups: nothing links their masses.
    CannotAnswer(Statement),
    /// The loads are related: the statement's truth follows from their masses.
    Answerable(Statement),
}

impl PairQuestion {
    fn statement(self) -> Statement {
        match self {
            PairQuestion::CannotAnswer(statement) | PairQuestion::Answerable(statement) => {
                statement
            }
        }
    }

    fn answer(self, first_kg: f64, second_kg: f64) -> &'static str {
        match self {
            PairQuestion::CannotAnswer(_) => CANNOT_ANSWER,
            PairQuestion::Answerable(statement) if statement.holds(first_kg, second_kg) => "yes",
            PairQuestion::Answerable(_) => "no",
        }
    }
}

fn pick<T: Copy, const N: usize>(rng: &mut impl Rng, items: [T; N]) -> T {
    items[rng.random_range(0..N)]
}

/// The public engine's `_fetch_comp_factor` for the ordered pair (`first`, `second`): `None`
/// when the pair is skipped.
fn draw_pair_question(
    scene: &RopeScene,
    first: usize,
    second: usize,
    rng: &mut impl Rng,
) -> Option<PairQuestion> {
    use Comparator::{EqualTo, GreaterThan, LessThan};
    use Factor::{Half, One, Twice};

    if !scene.are_related(first, second) {
        let comparator = pick(rng, Comparator::ALL);
        let kept = rng.random::<f64>() < CANNOT_ANSWER_PROBABILITY;
        return kept.then_some(PairQuestion::CannotAnswer(Statement::new(comparator, One)));
    }
    let first_kg = scene.object(first)?.nominal_mass_kg?;
    let second_kg = scene.object(second)?.nominal_mass_kg?;
    let mut first_linked = scene.hangs_under_movable_pulley(first);
    let mut second_linked = scene.hangs_under_movable_pulley(second);
    // Both under movable pulleys: their masses carry the same factor, compare them plainly.
    if first_linked && second_linked {
        (first_linked, second_linked) = (false, false);
    }
    let (true_statement, false_statement) = if first_linked {
        // The first mass is about double: compare it with twice the second.
        let doubled = 2.0 * second_kg;
        if first_kg > doubled + MASS_EPSILON {
            let mut true_statement = Statement::new(GreaterThan, Twice);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                true_statement.factor = pick(rng, [Half, One]);
            }
            let mut false_statement = Statement::new(pick(rng, [EqualTo, LessThan]), Twice);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                false_statement.factor = pick(rng, [Half, One]);
            }
            (true_statement, false_statement)
        } else if first_kg < doubled - MASS_EPSILON {
            (
                Statement::new(LessThan, Twice),
                Statement::new(pick(rng, [GreaterThan, EqualTo]), Twice),
            )
        } else {
            let mut false_statement = Statement::new(pick(rng, [GreaterThan, LessThan]), Twice);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                false_statement = Statement::new(EqualTo, pick(rng, [Half, One]));
            }
            (Statement::new(EqualTo, Twice), false_statement)
        }
    } else if second_linked {
        // The second mass is about double: compare the first with half of it.
        let halved = 0.5 * second_kg;
        if first_kg > halved + MASS_EPSILON {
            (
                Statement::new(GreaterThan, Half),
                Statement::new(pick(rng, [LessThan, EqualTo]), Half),
            )
        } else if first_kg < halved - MASS_EPSILON {
            let mut true_statement = Statement::new(LessThan, Half);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                true_statement.factor = pick(rng, [Twice, One]);
            }
            let mut false_statement = Statement::new(pick(rng, [EqualTo, GreaterThan]), Half);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                false_statement.factor = pick(rng, [Twice, One]);
            }
            (true_statement, false_statement)
        } else {
            let mut false_statement = Statement::new(pick(rng, [GreaterThan, LessThan]), Half);
            if rng.random::<f64>() < DIVERSE_FACTOR_PROBABILITY {
                false_statement = Statement::new(EqualTo, pick(rng, [Twice, One]));
            }
            (Statement::new(EqualTo, Half), false_statement)
        }
    } else if first_kg > second_kg + MASS_EPSILON {
        (
            Statement::new(GreaterThan, One),
            Statement::new(pick(rng, [LessThan, EqualTo]), One),
        )
    } else if first_kg < second_kg - MASS_EPSILON {
        (
            Statement::new(LessThan, One),
            Statement::new(pick(rng, [GreaterThan, EqualTo]), One),
        )
    } else {
        (
            Statement::new(EqualTo, One),
            Statement::new(pick(rng, [LessThan, GreaterThan]), One),
        )
    };
    let statement = if rng.random::<f64>() < TRUE_STATEMENT_PROBABILITY {
        true_statement
    } else {
        false_statement
    };
    Some(PairQuestion::Answerable(statement))
}

/// Ordered pairs of distinct loads, in object order (`itertools.permutations` over the object
/// list, non-loads skipped).
fn load_pairs(scene: &RopeScene) -> Vec<(usize, usize)> {
    let loads: Vec<usize> = scene.loads().collect();
    loads
        .iter()
        .flat_map(|&first| {
            loads
                .iter()
                .filter(move |&&second| second != first)
                .map(move |&second| (first, second))
        })
        .collect()
}

/// `mass`: "Is the mass of the {c1} {s1} {cmp} {fac}that of the {c2} {s2}?" for each ordered pair
/// of loads.
pub(super) fn mass_questions(scene: &RopeScene, rng: &mut impl Rng) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for (first, second) in load_pairs(scene) {
        let (Some(first_object), Some(second_object)) = (scene.object(first), scene.object(second))
        else {
            continue;
        };
        // Two loads with the same name cannot be told apart in the question (without the public
        // engine's de-duplication they are two objects); skip such pairs, as the public engine
        // skipped a load compared with itself.
        if scene.reference(first).is_none() || scene.reference(second).is_none() {
            continue;
        }
        let (Some(first_kg), Some(second_kg)) =
            (first_object.nominal_mass_kg, second_object.nominal_mass_kg)
        else {
            continue;
        };
        let Some(pair) = draw_pair_question(scene, first, second, rng) else {
            continue;
        };
        let statement = pair.statement();
        let program = [
            first_object.color.as_str(),
            first_object.shape.as_str(),
            statement.comparator.text(),
            statement.factor.text(),
            second_object.color.as_str(),
            second_object.shape.as_str(),
        ];
        let question = format!(
            "Is the mass of the {} {} {} {}that of the {} {}?",
            program[0], program[1], program[2], program[3], program[4], program[5]
        );
        records.push(open_ended_record(
            MASS,
            question,
            pair.answer(first_kg, second_kg),
            &program,
        ));
    }
    records
}

/// Decision (c): a rope is ambiguous when loads of different nominal mass hang on it. Its tension
/// then follows from no single load, and the public engine asked one question text with
/// conflicting answers across load pairs.
fn rope_is_ambiguous(scene: &RopeScene, rope: usize) -> bool {
    let mut masses = scene
        .loads()
        .filter(|&load| scene.rope_of(load) == Some(rope))
        .filter_map(|load| scene.object(load).and_then(|o| o.nominal_mass_kg));
    let Some(first_kg) = masses.next() else {
        return false;
    };
    masses.any(|mass_kg| (mass_kg - first_kg).abs() >= MASS_EPSILON)
}

/// `tension`: "Is the tension of the {c1} rope {cmp} {fac}that of the {c2} rope?", answered from
/// the masses of one load on each rope, for each ordered pair of loads on different ropes. As in
/// the public engine, tension is taken to follow the hanging mass and `ResultTension` is not used
/// (`docs/data/rope.md`, quirks of the release's data); two load pairs can yield the same question,
/// which is kept.
pub(super) fn tension_questions(scene: &RopeScene, rng: &mut impl Rng) -> Vec<QuestionRecord> {
    let mut records = Vec::new();
    for (first, second) in load_pairs(scene) {
        // Drawn before the rope checks, as in the public engine.
        let Some(pair) = draw_pair_question(scene, first, second, rng) else {
            continue;
        };
        let (Some(first_rope), Some(second_rope)) = (scene.rope_of(first), scene.rope_of(second))
        else {
            continue;
        };
        if first_rope == second_rope
            || scene.reference(first_rope).is_none()
            || scene.reference(second_rope).is_none()
        {
            continue;
        }
        let answerable = matches!(pair, PairQuestion::Answerable(_));
        if answerable
            && (rope_is_ambiguous(scene, first_rope) || rope_is_ambiguous(scene, second_rope))
        {
            continue;
        }
        let masses = (
            scene.object(first).and_then(|o| o.nominal_mass_kg),
            scene.object(second).and_then(|o| o.nominal_mass_kg),
        );
        let (Some(first_kg), Some(second_kg)) = masses else {
            continue;
        };
        let (Some(first_rope_object), Some(second_rope_object)) =
            (scene.object(first_rope), scene.object(second_rope))
        else {
            continue;
        };
        let statement = pair.statement();
        let rope_word = RopeObjectKind::Rope.word();
        let program = [
            first_rope_object.color.as_str(),
            rope_word,
            statement.comparator.text(),
            statement.factor.text(),
            second_rope_object.color.as_str(),
            rope_word,
        ];
        let question = format!(
            "Is the tension of the {} {} {} {}that of the {} {}?",
            program[0], program[1], program[2], program[3], program[4], program[5]
        );
        records.push(open_ended_record(
            TENSION,
            question,
            pair.answer(first_kg, second_kg),
            &program,
        ));
    }
    records
}

/// `shape`: "How many {shape}s are there in the video?" for each shape; an object counts when its
/// shape contains the word (so `pulley` counts solid and hollow pulleys).
pub(super) fn shape_questions(scene: &RopeScene) -> Vec<QuestionRecord> {
    SHAPES
        .iter()
        .map(|&shape| {
            let count = scene
                .objects()
                .iter()
                .filter(|o| o.shape.contains(shape))
                .count();
            let question = format!("How many {shape}s are there in the video?");
            open_ended_record(SHAPE, question, &count.to_string(), &[shape])
        })
        .collect()
}

/// `color`: "How many {color} objects are there in the video?" for each colour; exact colour
/// match, so a light blue object is not blue.
pub(super) fn color_questions(scene: &RopeScene) -> Vec<QuestionRecord> {
    COLORS
        .iter()
        .map(|&color| {
            let count = scene.objects().iter().filter(|o| o.color == color).count();
            let question = format!("How many {color} objects are there in the video?");
            open_ended_record(COLOR, question, &count.to_string(), &[color])
        })
        .collect()
}

/// `existence`: "Is there any {color} {shape} in the video?" for every colour and exact shape,
/// colour-major.
///
/// Decision (b): the colour must match exactly, as in the `color` count. The public engine used
/// substring matching here, so a light blue cube made "blue cube" exist while not counting as
/// blue.
pub(super) fn existence_questions(scene: &RopeScene) -> Vec<QuestionRecord> {
    let mut records = Vec::with_capacity(COLORS.len() * EXACT_SHAPES.len());
    for color in COLORS {
        for shape in EXACT_SHAPES {
            let exists = scene
                .objects()
                .iter()
                .any(|o| o.color == color && o.shape == shape);
            let question = format!("Is there any {color} {shape} in the video?");
            records.push(open_ended_record(
                EXISTENCE,
                question,
                if exists { "yes" } else { "no" },
                &[color, shape],
            ));
        }
    }
    records
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn statements_hold_by_arithmetic_with_tolerance() {
        use Comparator::{EqualTo, GreaterThan, LessThan};
        use Factor::{Half, One, Twice};
        let cases = [
            (Statement::new(GreaterThan, One), 0.25, 0.2, true),
            (Statement::new(GreaterThan, One), 0.2, 0.2, false),
            (Statement::new(EqualTo, One), 0.2, 0.2 + 5e-6, true),
            (Statement::new(LessThan, One), 0.2, 0.2 + 5e-6, false),
            (Statement::new(EqualTo, Twice), 0.4, 0.2, true),
            (Statement::new(LessThan, Twice), 0.4, 0.25, true),
            (Statement::new(EqualTo, Half), 0.2, 0.4, true),
            (Statement::new(GreaterThan, Half), 0.25, 0.4, true),
            (Statement::new(LessThan, Half), 0.15, 0.4, true),
            (Statement::new(GreaterThan, Half), 0.15, 0.4, false),
        ];
        for (statement, first_kg, second_kg, expected) in cases {
            assert_eq!(
                statement.holds(first_kg, second_kg),
                expected,
                "{statement:?} {first_kg} {second_kg}"
            );
        }
    }
}

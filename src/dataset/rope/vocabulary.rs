//! The words of rope scenes (`pulley_group`): what `find` understands, what each object carries,
//! and what the prompt lists.

use crate::dataset::vocabulary::{Attribute, KindGroup, Suffix, Vocabulary};

/// Rope scenes: loads (cubes, spheres), pulleys (solid or hollow, static or movable), ropes and
/// fixed points; pulleys carry their grid id `(layer column)`.
pub const VOCABULARY: Vocabulary = Vocabulary {
    kinds: &["cube", "sphere", "pulley", "rope", "fixed point"],
    kind_groups: &[KindGroup {
        word: "load",
        kinds: &["cube", "sphere"],
    }],
    attributes: &[
        Attribute {
            name: "shape",
            plural: "pulley shapes",
            // The generator's solid pulleys are the little ones, hollow pulleys the big ones.
            words: &[
                ("solid", "solid"),
                ("little", "solid"),
                ("small", "solid"),
                ("hollow", "hollow"),
                ("big", "hollow"),
                ("large", "hollow"),
            ],
            implies_kind: Some("pulley"),
            in_name: true,
        },
        Attribute {
            name: "dynamic",
            plural: "dynamics",
            words: &[
                ("static", "static"),
                ("stationary", "static"),
                ("dynamic", "dynamic"),
                ("movable", "dynamic"),
                ("moveable", "dynamic"),
                ("moving", "dynamic"),
            ],
            implies_kind: None,
            in_name: false,
        },
    ],
    unfindable: &[],
    suffix: Some(Suffix {
        attribute: "grid",
        form: "(layer column)",
        example: "(0 1)",
        parse: parse_grid,
    }),
};

/// A grid id `layer column` (two whole numbers; columns can be negative in the release), as the
/// attribute value `layer column`.
fn parse_grid(text: &str) -> Option<String> {
    let numbers: Vec<i32> = text
        .split_whitespace()
        .map(str::parse)
        .collect::<Result<_, _>>()
        .ok()?;
    match numbers.as_slice() {
        [layer, column] => Some(format!("{layer} {column}")),
        _ => None,
    }
}

//! `bench physics --confirm`: which of the reference's decided labels a finer setting confirms.
//!
//! A decided label is one every run of the reference's ensemble agrees on. That makes it robust
//! to the runs' chaos (their spawns a millimetre apart), not converged: a box on a knife-edge can
//! fall one way in every run at the reference's substeps and the other way in some runs at
//! twice as many. No setting cheaper than the reference can be expected to repeat such a label,
//! so with `--confirm` the simulator's confirmation point ([`PhysicsBench::confirmation`], finer
//! than the reference) runs too, and a decided label counts only where its ensemble repeats it
//! in every run. The labels dropped are listed by name in the report.
//!
//! Input: a case's reference quantities and the confirmation's. Output: the reference with the
//! unconfirmed labels made undecided, and their report entries.
//!
//! [`PhysicsBench::confirmation`]: crate::physics::bench::PhysicsBench::confirmation

use serde_json::{Value, json};

use super::bench_physics::decided_labels;
use crate::physics::bench::{ErrorMeasure, Measured};

/// A share no decided reduction counts: a label set to it is undecided.
const UNDECIDED: f64 = 0.5;

/// The name of label `label` of measure `measure` (`touch Red Pillar – Blue Plate`), or
/// `#label` where the case names none.
pub(super) fn label_name(names: &[Vec<String>], measure: usize, label: usize) -> String {
    names
        .get(measure)
        .and_then(|names| names.get(label))
        .cloned()
        .unwrap_or_else(|| format!("#{label}"))
}

/// `reference` with its decided labels that `confirmation` does not repeat in every run made
/// undecided, and per such label its measure, name, the reference's share and the
/// confirmation's. A measure whose confirmation quantities are missing confirms none of its
/// labels. Measures that are not decided are left as they are.
pub(super) fn confirmed(
    measures: &[ErrorMeasure],
    names: &[Vec<String>],
    reference: &Measured,
    confirmation: &Measured,
) -> (Measured, Vec<Value>) {
    let mut kept = reference.clone();
    let mut dropped = Vec::new();
    for (index, (measure, expected)) in measures.iter().zip(reference).enumerate() {
        let Some(slot) = kept.get_mut(index) else {
            continue;
        };
        let got = confirmation
            .get(index)
            .filter(|got| got.len() == expected.len());
        let share_of = |label: usize| got.and_then(|got| got.get(label)).copied();
        let mut drop = |label: usize, reference: f64, share: Option<f64>| {
            dropped.push(json!({
                "measure": measure.key,
                "label": label_name(names, index, label),
                "reference": reference,
                "confirmation": share,
            }));
        };
        for decided in decided_labels(measure.reduction, expected) {
            let share = share_of(decided.index);
            if !share.is_some_and(|share| (share - decided.share).abs() < 1e-9) {
                drop(decided.index, decided.share, share);
                for share in &mut slot[decided.span] {
                    *share = UNDECIDED;
                }
            }
        }
    }
    (kept, dropped)
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::bench::Reduction;

    fn measure(key: &'static str, reduction: Reduction) -> ErrorMeasure {
        ErrorMeasure {
            key,
            reduction,
            tolerance: None,
            plotted: true,
        }
    }

    #[test]
    fn a_decided_label_the_confirmation_changes_in_some_run_is_made_undecided() {
        let measures = [
            measure("pose", Reduction::DecidedCategories(2)),
            measure("contact", Reduction::DecidedMean),
            measure("position", Reduction::Mean),
        ];
        let names = vec![
            vec![
                "A up".into(),
                "A down".into(),
                "B up".into(),
                "B down".into(),
            ],
            vec!["touch A – B".into(), "collide A – B".into(), "x".into()],
        ];
        // Box A is up in every reference run, box B down; the confirmation keeps A up in 11 of
        // 15 runs. Contacts: decided 1, decided 0, undecided 0.4; the confirmation repeats the
        // first and calls the second in 2 of 15 runs.
        let reference = vec![
            vec![1.0, 0.0, 0.0, 1.0],
            vec![1.0, 0.0, 0.4],
            vec![3.0, 4.0],
        ];
        let confirmation = vec![
            vec![11.0 / 15.0, 4.0 / 15.0, 0.0, 1.0],
            vec![1.0, 2.0 / 15.0, 0.2],
            vec![9.0, 9.0],
        ];
        let (kept, dropped) = confirmed(&measures, &names, &reference, &confirmation);
        assert_eq!(
            kept,
            vec![
                vec![0.5, 0.5, 0.0, 1.0],
                vec![1.0, 0.5, 0.4],
                vec![3.0, 4.0]
            ]
        );
        assert_eq!(
            dropped,
            vec![
                json!({"measure": "pose", "label": "A up", "reference": 1.0,
                       "confirmation": 11.0 / 15.0}),
                json!({"measure": "contact", "label": "collide A – B", "reference": 0.0,
                       "confirmation": 2.0 / 15.0}),
            ]
        );
        // What is left decided is what the errors are taken over: box B's pose, the touch.
        let left = |measure: usize| -> Vec<usize> {
            decided_labels(measures[measure].reduction, &kept[measure])
                .iter()
                .map(|decided| decided.index)
                .collect()
        };
        assert_eq!(left(0), vec![3]);
        assert_eq!(left(1), vec![0]);
    }

    #[test]
    fn a_confirmation_that_repeats_every_label_keeps_the_reference_and_a_missing_one_keeps_none() {
        let measures = [measure("contact", Reduction::DecidedMean)];
        let reference = vec![vec![1.0, 0.0]];
        let (kept, dropped) = confirmed(&measures, &[], &reference, &reference.clone());
        assert_eq!(kept, reference);
        assert!(dropped.is_empty());
        let (kept, dropped) = confirmed(&measures, &[], &reference, &vec![vec![1.0]]);
        assert_eq!(kept, vec![vec![0.5, 0.5]]);
        assert_eq!(dropped.len(), 2);
        assert_eq!(dropped[1]["label"], "#1");
        assert_eq!(dropped[1]["confirmation"], Value::Null);
    }
}

//! The verdicts on a judged group: whether the near-best assignments agree on a pair's class or
//! a body's mass, and if not, why the motion cannot tell.

use super::super::GRAVITY;
use super::{
    BodyVerdict, Judged, MAX_MEAN_SCORE, MOTION_RESOLUTION, NEAR_BEST, PairVerdict, RatioClass,
    Trial, Undecidable, Unknown, Window,
};

/// Why a group cannot be judged at all: no track, no clean window, or no candidate fits.
fn unjudgeable(judged: &Judged, name: &dyn Fn(usize) -> String) -> Option<Undecidable> {
    let group = &judged.group;
    match group.window {
        Window::Untracked => {
            return Some(Undecidable::Untracked {
                body: name(group.bodies[0]),
            });
        }
        Window::TooShort { body, frames } => {
            return Some(Undecidable::NoCleanWindow {
                body: name(body),
                frames,
            });
        }
        Window::Clean { .. } => {}
    }
    let best = judged.trials.first()?;
    let mean_score = best.score / group.fits.len().max(1) as f64;
    (mean_score > MAX_MEAN_SCORE).then_some(Undecidable::Unexplained { mean_score })
}

/// The near-best trials of a judged group.
fn near_best(judged: &Judged) -> impl Iterator<Item = &Trial> {
    let best = judged.trials.first().map_or(f64::INFINITY, |t| t.score);
    judged
        .trials
        .iter()
        .take_while(move |t| t.score <= best + NEAR_BEST)
}

pub(super) fn pair_verdict(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    (first, second): (usize, usize),
    name: &dyn Fn(usize) -> String,
) -> PairVerdict {
    if let Some(reason) = unjudgeable(judged, name) {
        return PairVerdict::Undecidable(reason);
    }
    let at = |u: usize| judged.group.unknowns.iter().position(|&m| m == u);
    let (Some(a), Some(b), Some(best)) = (at(first), at(second), judged.trials.first()) else {
        return PairVerdict::Undecidable(Undecidable::DifferentMechanisms);
    };
    let mut classes: Vec<RatioClass> = near_best(judged)
        .map(|t| RatioClass::of(t.masses[a], t.masses[b]))
        .collect();
    classes.sort_unstable();
    classes.dedup();
    if let [class] = classes.as_slice() {
        return PairVerdict::Decided {
            masses: [best.masses[a], best.masses[b]],
            class: *class,
        };
    }
    PairVerdict::Undecidable(reason(
        judged,
        unknowns,
        ropes_of,
        &[(first, a), (second, b)],
        classes.len(),
        name,
    ))
}

/// Why the near-best assignments disagree about `blamed` (unknown index, position in the
/// group): a stop holds one, one falls freely, one's mass changes nothing, the motion is too
/// small, or none of these.
fn reason(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    blamed: &[(usize, usize)],
    classes: usize,
    name: &dyn Fn(usize) -> String,
) -> Undecidable {
    let body_of = |u: usize| unknowns[u].body;
    for &(u, _) in blamed {
        if near_best(judged).any(|t| t.instant.stopped[body_of(u)]) {
            return Undecidable::RestsAgainstStop {
                body: name(body_of(u)),
            };
        }
    }
    if let Some(best) = judged.trials.first() {
        for &(u, _) in blamed {
            let body = body_of(u);
            let slack = ropes_of[body].iter().all(|&rope| !best.instant.taut[rope]);
            if slack && (best.instant.accelerations[body] + GRAVITY).abs() <= 1e-6 * GRAVITY {
                return Undecidable::FreeFall { body: name(body) };
            }
        }
        for &(u, at) in blamed {
            // Hidden: every candidate of this body, the others as in the best, is near-best.
            let hidden = judged
                .trials
                .iter()
                .filter(|t| {
                    t.choice
                        .iter()
                        .zip(&best.choice)
                        .enumerate()
                        .all(|(i, (c, b))| i == at || c == b)
                })
                .all(|t| t.score <= best.score + NEAR_BEST);
            if hidden {
                return Undecidable::MassHidden {
                    body: name(body_of(u)),
                };
            }
        }
    }
    let travel = judged
        .group
        .fits
        .iter()
        .map(|f| f.travel)
        .fold(0.0, f64::max);
    if travel < MOTION_RESOLUTION {
        return Undecidable::MotionTooSmall { travel };
    }
    Undecidable::Ambiguous { classes }
}

pub(super) fn body_verdict(
    judged: &Judged,
    unknowns: &[Unknown],
    ropes_of: &[Vec<usize>],
    u: usize,
    pairs: &[((usize, usize), PairVerdict)],
    name: &dyn Fn(usize) -> String,
) -> BodyVerdict {
    if let Some(reason) = unjudgeable(judged, name) {
        return BodyVerdict::Undetermined(reason);
    }
    let group = &judged.group;
    let (Some(at), Some(best)) = (
        group.unknowns.iter().position(|&m| m == u),
        judged.trials.first(),
    ) else {
        return BodyVerdict::Undetermined(Undecidable::Untracked {
            body: name(unknowns[u].body),
        });
    };
    if group.unknowns.len() > 1 {
        // Pinned against every other unknown of the group.
        for ((i, j), verdict) in pairs {
            if (*i == u || *j == u)
                && let PairVerdict::Undecidable(reason) = verdict
                && group.unknowns.contains(i)
                && group.unknowns.contains(j)
            {
                return BodyVerdict::Undetermined(reason.clone());
            }
        }
        return BodyVerdict::Determined {
            mass: best.masses[at],
        };
    }
    let mut masses: Vec<f64> = near_best(judged).map(|t| t.masses[at]).collect();
    masses.sort_by(f64::total_cmp);
    masses.dedup();
    if masses.len() == 1 {
        BodyVerdict::Determined {
            mass: best.masses[at],
        }
    } else {
        BodyVerdict::Undetermined(reason(
            judged,
            unknowns,
            ropes_of,
            &[(u, at)],
            masses.len(),
            name,
        ))
    }
}

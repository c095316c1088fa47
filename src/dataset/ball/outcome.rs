//! The release's labelling of a ball run (`SoftBodyManager`, `docs/data/ball.md`): which pit a
//! ball drops into and when, used by both the generator and the simulate backend so that truth
//! and prediction are counted one way.
//!
//! A ball has dropped into a pit at the first update its centre is below [`FALL_HEIGHT`] (the
//! floor's level); the pit is the left one when its centre's x is negative then, the right one
//! otherwise. In the factual run a drop within the captured [`CAPTURE_UPDATES`] is "Observed",
//! a later one "to Predict"; counterfactual runs only say "Observed" or no pit. `pitFrame` is
//! the update halved (video frames are every second update), 0 when the ball never dropped.

use serde::Serialize;

/// The height (units) below which a ball's centre has dropped into a pit: the floor's level.
pub const FALL_HEIGHT: f64 = -0.5;
/// Updates the factual video captures (120 frames, one every second update).
pub const CAPTURE_UPDATES: usize = 240;
/// The most updates a run lasts.
pub const MAX_UPDATES: usize = 2000;
/// A run ends early once every ball's centre is below this, units.
pub const GONE_HEIGHT: f64 = -1.0;
/// Updates over which a ball that moved less than [`REST_DISTANCE`] lies still.
pub const REST_UPDATES: usize = 60;
/// See [`REST_UPDATES`], units.
pub const REST_DISTANCE: f64 = 0.01;

/// Whether a ball's track of centres (one per update) has ended: dropped out of the stadium
/// (below [`GONE_HEIGHT`]), or still for [`REST_UPDATES`] updates (its centre within
/// [`REST_DISTANCE`] of where it was). A ball lying still in a static scene never moves again,
/// so its label is the one the release's longer run gives.
pub fn track_finished(track: &[[f64; 2]]) -> bool {
    let Some(last) = track.last() else {
        return true;
    };
    if last[1] < GONE_HEIGHT {
        return true;
    }
    track.len() > REST_UPDATES
        && track
            .get(track.len() - 1 - REST_UPDATES)
            .is_some_and(|before| (last[0] - before[0]).hypot(last[1] - before[1]) < REST_DISTANCE)
}

/// Which pit.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Pit {
    /// The pit at negative x.
    Left,
    /// The pit at positive x.
    Right,
}

impl Pit {
    /// The pit a ball dropping at `x` falls into.
    pub fn at(x: f64) -> Pit {
        if x < 0.0 { Pit::Left } else { Pit::Right }
    }

    /// `left` or `right`, as questions say it.
    pub fn word(self) -> &'static str {
        match self {
            Pit::Left => "left",
            Pit::Right => "right",
        }
    }

    /// Both pits, left first.
    pub const BOTH: [Pit; 2] = [Pit::Left, Pit::Right];
}

/// A run's `pitResult` for one ball.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum PitResult {
    /// Dropped into a pit within the captured updates (`Left Pit Observed`, …).
    Observed(Pit),
    /// Dropped into a pit after the video ended (`Left Pit to Predict`, factual runs only).
    ToPredict(Pit),
    /// Never dropped (`No Pit Observed or to Predict`).
    NoPit,
}

impl PitResult {
    /// The release's string.
    pub fn as_str(self) -> &'static str {
        match self {
            PitResult::Observed(Pit::Left) => "Left Pit Observed",
            PitResult::Observed(Pit::Right) => "Right Pit Observed",
            PitResult::ToPredict(Pit::Left) => "Left Pit to Predict",
            PitResult::ToPredict(Pit::Right) => "Right Pit to Predict",
            PitResult::NoPit => "No Pit Observed or to Predict",
        }
    }

    /// Parses the release's string.
    pub fn parse(text: &str) -> Option<PitResult> {
        [
            PitResult::Observed(Pit::Left),
            PitResult::Observed(Pit::Right),
            PitResult::ToPredict(Pit::Left),
            PitResult::ToPredict(Pit::Right),
            PitResult::NoPit,
        ]
        .into_iter()
        .find(|result| result.as_str() == text)
    }

    /// The pit the ball finally drops into, if any.
    pub fn pit(self) -> Option<Pit> {
        match self {
            PitResult::Observed(pit) | PitResult::ToPredict(pit) => Some(pit),
            PitResult::NoPit => None,
        }
    }
}

/// One ball's outcome in a run: `{pitResult, pitFrame}`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, Serialize)]
pub struct PitRecord {
    /// Where it dropped.
    pub result: PitResult,
    /// The update it dropped at, halved (video-frame units; may exceed the video); 0 if never.
    pub frame: u32,
}

/// Whether the run records "to Predict" (the factual run) or only what it sees (counterfactual
/// runs).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum RunMode {
    /// The factual run: drops after [`CAPTURE_UPDATES`] are "to Predict".
    Factual,
    /// A counterfactual run: every drop is "Observed".
    Counterfactual,
}

/// Where and at which update a ball first dropped into a pit: the pit under its centre the
/// first time the centre is below [`FALL_HEIGHT`], and that centre's index plus one
/// (`centres[k]` is after update `k + 1`, as `(x, y)`); `None` if it never did.
pub fn first_drop(centres: &[[f64; 2]]) -> Option<(Pit, usize)> {
    centres
        .iter()
        .position(|centre| centre[1] < FALL_HEIGHT)
        .and_then(|index| {
            centres
                .get(index)
                .map(|centre| (Pit::at(centre[0]), index + 1))
        })
}

/// Labels one ball from its centre after each update (`centres[k]` after update `k + 1`, as
/// `(x, y)`).
pub fn label_ball(centres: &[[f64; 2]], mode: RunMode) -> PitRecord {
    let Some((pit, update)) = first_drop(centres) else {
        return PitRecord {
            result: PitResult::NoPit,
            frame: 0,
        };
    };
    let result = if mode == RunMode::Factual && update > CAPTURE_UPDATES {
        PitResult::ToPredict(pit)
    } else {
        PitResult::Observed(pit)
    };
    PitRecord {
        result,
        frame: u32::try_from(update / 2).unwrap_or(u32::MAX),
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn a_ball_is_labelled_by_where_and_when_its_centre_drops_below_the_floor() {
        // Rolls right, drops at update 300 (after the video): right, to predict, frame 150.
        let mut centres: Vec<[f64; 2]> = (1..=299).map(|k| [0.01 * f64::from(k), 0.4]).collect();
        centres.push([2.5, -0.6]);
        let record = label_ball(&centres, RunMode::Factual);
        assert_eq!(record.result, PitResult::ToPredict(Pit::Right));
        assert_eq!(record.frame, 150);
        assert_eq!(record.result.as_str(), "Right Pit to Predict");
        // The same drop in a counterfactual run is observed.
        let record = label_ball(&centres, RunMode::Counterfactual);
        assert_eq!(record.result, PitResult::Observed(Pit::Right));
        // At update 240, the video's last, it is observed; left of x = 0 is the left pit.
        let drop = vec![[0.0, 0.2]; 239]
            .into_iter()
            .chain([[-1.5, -0.51]])
            .collect::<Vec<_>>();
        let record = label_ball(&drop, RunMode::Factual);
        assert_eq!(record.result, PitResult::Observed(Pit::Left));
        assert_eq!(record.frame, 120);
        // Exactly at the floor's level is not below it; never dropping is frame 0.
        let record = label_ball(&[[1.0, FALL_HEIGHT]; 10], RunMode::Factual);
        assert_eq!(
            record,
            PitRecord {
                result: PitResult::NoPit,
                frame: 0
            }
        );
    }

    #[test]
    fn results_read_back_from_the_release_strings() {
        for result in [
            PitResult::Observed(Pit::Left),
            PitResult::Observed(Pit::Right),
            PitResult::ToPredict(Pit::Left),
            PitResult::ToPredict(Pit::Right),
            PitResult::NoPit,
        ] {
            assert_eq!(PitResult::parse(result.as_str()), Some(result));
        }
        assert_eq!(PitResult::parse("Left Pit"), None);
    }
}

//! The release's outcome labels of a rope run (`ResultMotion`, `ResultRotation`): each body's
//! motion and each pulley's rotation is the sign of its first crossing of the threshold
//! ([`MOTION_THRESHOLD`] units, [`ROTATION_THRESHOLD_DEG`] degrees) measured from the change,
//! checked once per update and kept from then on.
//!
//! One labelling for both users: the generator labels its truth with it (`synth::rope`), and
//! `--dynamics simulate` labels its predictions with it (`scene_api::rope`), so the two can only
//! differ in the motion they label.
//!
//! Input: heights (units) and pulley angles (radians, counter-clockwise positive as simulated)
//! after every update. Output: −1, 0 or +1 per body and per pulley.

use super::world::{MOTION_THRESHOLD, ROTATION_THRESHOLD_DEG};

/// Motion and rotation labels of one run, latched at their first threshold crossing.
#[derive(Debug, Clone, PartialEq)]
pub struct OutcomeLatch {
    start_heights: Vec<f64>,
    start_angles: Vec<f64>,
    motion: Vec<i8>,
    rotation: Vec<i8>,
}

impl OutcomeLatch {
    /// A latch measuring from these heights (units) and angles (radians), the state at the
    /// change.
    pub fn new(heights: &[f64], angles: &[f64]) -> OutcomeLatch {
        OutcomeLatch {
            start_heights: heights.to_vec(),
            start_angles: angles.to_vec(),
            motion: vec![0; heights.len()],
            rotation: vec![0; angles.len()],
        }
    }

    /// Looks at the state after one update; a label already set is kept.
    pub fn observe(&mut self, heights: &[f64], angles: &[f64]) {
        let rotation_threshold = ROTATION_THRESHOLD_DEG.to_radians();
        for ((label, height), start) in self.motion.iter_mut().zip(heights).zip(&self.start_heights)
        {
            if *label == 0 {
                *label = threshold_sign(height - start, MOTION_THRESHOLD);
            }
        }
        for ((label, angle), start) in self.rotation.iter_mut().zip(angles).zip(&self.start_angles)
        {
            if *label == 0 {
                *label = threshold_sign(angle - start, rotation_threshold);
            }
        }
    }

    /// Body `index`: +1 moved up, −1 down, 0 stayed within the threshold.
    pub fn motion(&self, index: usize) -> i8 {
        self.motion.get(index).copied().unwrap_or(0)
    }

    /// Pulley `index`: +1 turned counter-clockwise as simulated, −1 clockwise, 0 neither; see
    /// [`seen_rotation`] for the video's sense.
    pub fn rotation(&self, index: usize) -> i8 {
        self.rotation.get(index).copied().unwrap_or(0)
    }
}

/// A simulated rotation label as the release records it: +1 is clockwise as seen in the video.
/// Counter-clockwise is positive in the simulation; a mirrored camera (at −z) sees the
/// simulation's orientation, the other one sees it reversed.
pub fn seen_rotation(simulated: i8, mirrored: bool) -> i8 {
    if mirrored { -simulated } else { simulated }
}

/// The release's motion record of a static pulley or fixed point pulled at `velocity` (units/s,
/// up positive): the sign of the pull (the pull moves it 3.5 or 7 units, far past the motion
/// threshold, within every run's updates).
pub fn pulled_motion(velocity: f64) -> i8 {
    threshold_sign(velocity, 0.0)
}

/// +1 above `threshold`, −1 below `-threshold`, 0 between.
fn threshold_sign(delta: f64, threshold: f64) -> i8 {
    if delta > threshold {
        1
    } else if delta < -threshold {
        -1
    } else {
        0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn labels_latch_at_the_first_crossing_and_keep_their_sign() {
        let mut latch = OutcomeLatch::new(&[0.0, 5.0], &[0.0]);
        latch.observe(&[1.0, 5.0], &[0.5]);
        assert_eq!(
            (latch.motion(0), latch.motion(1), latch.rotation(0)),
            (0, 0, 0)
        );
        latch.observe(&[1.3, 3.7], &[0.62]);
        assert_eq!(
            (latch.motion(0), latch.motion(1), latch.rotation(0)),
            (1, -1, 1)
        );
        // Coming back does not undo a label.
        latch.observe(&[-2.0, 9.0], &[-1.0]);
        assert_eq!(
            (latch.motion(0), latch.motion(1), latch.rotation(0)),
            (1, -1, 1)
        );
        assert_eq!(latch.motion(7), 0);
    }

    #[test]
    fn the_rotation_threshold_is_35_degrees_and_the_video_sees_it_mirrored_or_not() {
        let mut latch = OutcomeLatch::new(&[], &[0.0, 0.0]);
        latch.observe(&[], &[34.9_f64.to_radians(), -35.1_f64.to_radians()]);
        assert_eq!((latch.rotation(0), latch.rotation(1)), (0, -1));
        assert_eq!(seen_rotation(-1, true), 1);
        assert_eq!(seen_rotation(-1, false), -1);
    }
}

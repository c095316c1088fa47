//! The release's labelling of how a cloth run ends for a box (`ClothCollisionManager`,
//! `docs/data/cloth.md`): its end pose (`endPoseDescription`) from where its local up axis points,
//! shared by the generator (which writes the label) and the backends and the question engine
//! (which read it), so truth and prediction are labelled one way. Also the words questions use for
//! each pose, and which poses count as having fallen over.
//!
//! The rule, on the box's unit local up axis `(x, y, z)` in world space (y up), with the release's
//! tolerance [`POSE_TOLERANCE`]: |y| < 0.02 → `Supine`; otherwise |x| or |z| > 0.02 → `Swooping`
//! if y < 0, else `Reclining`; otherwise y > 0 → `Upright`, else `Other`.

use serde::Serialize;

/// The release's tolerance on the up axis's components.
pub const POSE_TOLERANCE: f64 = 0.02;

/// A box's end pose, the release's `endPoseDescription`.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash, Serialize)]
#[serde(rename_all = "snake_case")]
pub enum Pose {
    /// The up axis points straight up (within the tolerance): the box stands as it was placed.
    Upright,
    /// The up axis is tilted but still points upwards: the box leans.
    Reclining,
    /// The up axis is horizontal: the box lies on a side (a plate on its face or back).
    Supine,
    /// The up axis is tilted and points downwards: the box is tipped over past lying flat.
    Swooping,
    /// The up axis points straight down: the box stands on its top.
    Other,
}

impl Pose {
    /// Every pose, in the release's order.
    pub const ALL: [Pose; 5] = [
        Pose::Upright,
        Pose::Reclining,
        Pose::Supine,
        Pose::Swooping,
        Pose::Other,
    ];

    /// The pose of a box whose unit local up axis points along `up` in world space (y up), by
    /// the release's rule. A non-finite axis (which a solver's finite check rules out) falls
    /// through every test to `Other`.
    pub fn from_up_axis(up: [f64; 3]) -> Pose {
        let [x, y, z] = up;
        if y.abs() < POSE_TOLERANCE {
            Pose::Supine
        } else if x.abs() > POSE_TOLERANCE || z.abs() > POSE_TOLERANCE {
            if y < 0.0 {
                Pose::Swooping
            } else {
                Pose::Reclining
            }
        } else if y > 0.0 {
            Pose::Upright
        } else {
            Pose::Other
        }
    }

    /// The release's label (`Upright`).
    pub fn as_str(self) -> &'static str {
        match self {
            Pose::Upright => "Upright",
            Pose::Reclining => "Reclining",
            Pose::Supine => "Supine",
            Pose::Swooping => "Swooping",
            Pose::Other => "Other",
        }
    }

    /// The pose the release's label names.
    pub fn parse(text: &str) -> Option<Pose> {
        Pose::ALL.into_iter().find(|pose| pose.as_str() == text)
    }

    /// The option text of the pose question: what a viewer sees, in plain words, rather than the
    /// release's labels ("Supine" and "Swooping" are not how anyone describes a box).
    pub fn phrase(self) -> &'static str {
        match self {
            Pose::Upright => "It stands upright",
            Pose::Reclining => "It leans at an angle, its top still pointing up",
            Pose::Supine => "It lies flat on its back, front or side",
            Pose::Swooping => "It is tilted upside down at an angle, its top pointing down",
            Pose::Other => "It stands upside down on its top",
        }
    }

    /// The pose whose [`Pose::phrase`] is `text` (case and surrounding spaces ignored).
    pub fn from_phrase(text: &str) -> Option<Pose> {
        let text = text.trim();
        Pose::ALL
            .into_iter()
            .find(|pose| pose.phrase().eq_ignore_ascii_case(text))
    }

    /// Whether a box ending in this pose has fallen over: `Upright` has not; `Supine`,
    /// `Swooping` and `Other` have (the up axis is horizontal or points down). `Reclining` is
    /// `None`: a box that ends leaning, from barely off vertical to resting on a neighbour, has
    /// not clearly fallen over or stayed up, so the question is not asked about it.
    pub fn fell_over(self) -> Option<bool> {
        match self {
            Pose::Upright => Some(false),
            Pose::Reclining => None,
            Pose::Supine | Pose::Swooping | Pose::Other => Some(true),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A unit axis tilted `degrees` from straight up towards +z.
    fn tilted(degrees: f64) -> [f64; 3] {
        let angle = degrees.to_radians();
        [0.0, angle.cos(), angle.sin()]
    }

    #[test]
    fn a_horizontal_up_axis_is_supine() {
        assert_eq!(Pose::from_up_axis([1.0, 0.0, 0.0]), Pose::Supine);
        assert_eq!(Pose::from_up_axis(tilted(90.0)), Pose::Supine);
        // |y| = 0.0175 < 0.02, whichever way it points.
        assert_eq!(Pose::from_up_axis(tilted(91.0)), Pose::Supine);
        assert_eq!(Pose::from_up_axis(tilted(89.0)), Pose::Supine);
    }

    #[test]
    fn a_tilted_axis_pointing_up_reclines() {
        assert_eq!(Pose::from_up_axis(tilted(30.0)), Pose::Reclining);
        // sin 1.5° = 0.026 > 0.02: already reclining.
        assert_eq!(Pose::from_up_axis(tilted(1.5)), Pose::Reclining);
        assert_eq!(Pose::from_up_axis([-0.5, 0.8, 0.0]), Pose::Reclining);
    }

    #[test]
    fn a_tilted_axis_pointing_down_swoops() {
        assert_eq!(Pose::from_up_axis(tilted(120.0)), Pose::Swooping);
        assert_eq!(Pose::from_up_axis([0.3, -0.9, 0.0]), Pose::Swooping);
    }

    #[test]
    fn a_vertical_axis_is_upright_or_other() {
        assert_eq!(Pose::from_up_axis([0.0, 1.0, 0.0]), Pose::Upright);
        // sin 1° = 0.0175 ≤ 0.02: still upright.
        assert_eq!(Pose::from_up_axis(tilted(1.0)), Pose::Upright);
        assert_eq!(Pose::from_up_axis([0.0, -1.0, 0.0]), Pose::Other);
        assert_eq!(Pose::from_up_axis(tilted(179.0)), Pose::Other);
        assert_eq!(Pose::from_up_axis([f64::NAN; 3]), Pose::Other);
    }

    #[test]
    fn labels_and_phrases_name_one_pose_each() {
        for pose in Pose::ALL {
            assert_eq!(Pose::parse(pose.as_str()), Some(pose));
            assert_eq!(Pose::from_phrase(pose.phrase()), Some(pose));
            assert_eq!(
                Pose::from_phrase(&format!(" {} ", pose.phrase().to_uppercase())),
                Some(pose)
            );
        }
        assert_eq!(Pose::parse("upright"), None);
        assert_eq!(
            Pose::ALL.map(Pose::fell_over),
            [Some(false), None, Some(true), Some(true), Some(true)]
        );
    }
}

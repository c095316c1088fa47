//! The rope engine's error type. Generation itself never fails: a question that cannot be built
//! soundly is skipped. Only an annotation the engine cannot read into its object list is an
//! error, and the error names the video and the offending object.

/// An annotation the rope question engine cannot turn into its object list.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum RopeEngineError {
    /// A load's mass does not round up to a nominal mass: the generator only draws
    /// {0.15, 0.20, 0.25} kg, times 1.975 under a movable pulley, and every such value rounds up
    /// (`ceil(m·100)/100`) to a second decimal of 0 or 5. The public engine stopped in
    /// `breakpoint()` here.
    #[error(
        "video `{video_id}`: load `{load}` has mass {mass_kg} kg, which rounds up to {nominal_kg} kg; a nominal rope mass ends in 0 or 5 in the second decimal"
    )]
    UnexpectedMass {
        /// The video.
        video_id: String,
        /// The load's annotation name.
        load: String,
        /// `outputMass` as written, kg.
        mass_kg: f64,
        /// The rounded-up mass, kg.
        nominal_kg: f64,
    },
    /// `outputMass` names something that is not a cube or a sphere.
    #[error("video `{video_id}`: `outputMass` names `{name}`, which is not a cube or a sphere")]
    NotALoad {
        /// The video.
        video_id: String,
        /// The name found.
        name: String,
    },
    /// A rope, pulley or fixed point name does not follow the generator's name grammar.
    #[error(
        "video `{video_id}`: `{field}` names `{name}`, which is not `<Colour> <Kind>` as the generator writes names"
    )]
    UnparsableName {
        /// The video.
        video_id: String,
        /// The annotation field the name came from.
        field: &'static str,
        /// The name found.
        name: String,
    },
}

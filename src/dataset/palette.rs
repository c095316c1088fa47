//! The release's colour names (`PlacementConfig.SoftColor`, `docs/data/common.md`): the words
//! every scenario's object names spell colours with, by the palette id the annotations record.

/// The release's palette names (`PlacementConfig.SoftColor`) by colour id, as object names spell
/// them. The `color` integers of `metaSamplingData` index this list. (The same palette,
/// with its RGB values, is `perception::palette`; the dataset layer cannot name perception.)
pub const PALETTE_NAMES: [&str; 17] = [
    "Red",
    "Orange",
    "Yellow",
    "Green",
    "Cyan",
    "Blue",
    "Purple",
    "Pink",
    "Brown",
    "Gray",
    "Black",
    "White",
    "Light Blue",
    "Light Green",
    "Light Yellow",
    "Light Coral",
    "Light Purple",
];

/// The palette name of colour id `id`, if it is one.
pub fn palette_name(id: i64) -> Option<&'static str> {
    usize::try_from(id)
        .ok()
        .and_then(|index| PALETTE_NAMES.get(index))
        .copied()
}

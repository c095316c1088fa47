//! Colours of the release: the generator's object palette (`PlacementConfig.SoftColor`,
//! shared by every scenario) and Unity Perception's instance-segmentation colours.

/// One palette entry: its id (the `color` fields of `metaSampling`), name and sRGB bytes.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub struct PaletteColor {
    /// `SoftColor` id.
    pub id: u8,
    /// Name as written in object names (`Light Blue`).
    pub name: &'static str,
    /// The colour word questions and `find` use (`light blue`).
    pub word: &'static str,
    /// sRGB, 0–255.
    pub rgb: [u8; 3],
}

impl PaletteColor {
    /// sRGB in `[0, 1]`.
    pub fn unit_rgb(self) -> [f64; 3] {
        self.rgb.map(|c| f64::from(c) / 255.0)
    }
}

/// `SoftColor`, in id order.
pub const PALETTE: [PaletteColor; 17] = [
    PaletteColor {
        id: 0,
        name: "Red",
        word: "red",
        rgb: [201, 0, 22],
    },
    PaletteColor {
        id: 1,
        name: "Orange",
        word: "orange",
        rgb: [229, 131, 8],
    },
    PaletteColor {
        id: 2,
        name: "Yellow",
        word: "yellow",
        rgb: [244, 208, 0],
    },
    PaletteColor {
        id: 3,
        name: "Green",
        word: "green",
        rgb: [101, 147, 74],
    },
    PaletteColor {
        id: 4,
        name: "Cyan",
        word: "cyan",
        rgb: [35, 235, 185],
    },
    PaletteColor {
        id: 5,
        name: "Blue",
        word: "blue",
        rgb: [56, 118, 248],
    },
    PaletteColor {
        id: 6,
        name: "Purple",
        word: "purple",
        rgb: [154, 78, 174],
    },
    PaletteColor {
        id: 7,
        name: "Pink",
        word: "pink",
        rgb: [255, 137, 153],
    },
    PaletteColor {
        id: 8,
        name: "Brown",
        word: "brown",
        rgb: [118, 77, 57],
    },
    PaletteColor {
        id: 9,
        name: "Gray",
        word: "gray",
        rgb: [128, 128, 128],
    },
    PaletteColor {
        id: 10,
        name: "Black",
        word: "black",
        rgb: [0, 0, 0],
    },
    PaletteColor {
        id: 11,
        name: "White",
        word: "white",
        rgb: [245, 245, 245],
    },
    PaletteColor {
        id: 12,
        name: "Light Blue",
        word: "light blue",
        rgb: [202, 235, 216],
    },
    PaletteColor {
        id: 13,
        name: "Light Green",
        word: "light green",
        rgb: [240, 255, 240],
    },
    PaletteColor {
        id: 14,
        name: "Light Yellow",
        word: "light yellow",
        rgb: [255, 255, 224],
    },
    PaletteColor {
        id: 15,
        name: "Light Coral",
        word: "light coral",
        rgb: [240, 128, 128],
    },
    PaletteColor {
        id: 16,
        name: "Light Purple",
        word: "light purple",
        rgb: [221, 160, 221],
    },
];

/// The colour words of the palette, in id order (`red`, …, `light purple`): the colours `find`
/// understands and the prompt lists, in every scenario.
pub fn color_words() -> &'static [&'static str] {
    static WORDS: std::sync::OnceLock<Vec<&'static str>> = std::sync::OnceLock::new();
    WORDS.get_or_init(|| PALETTE.iter().map(|color| color.word).collect())
}

/// The palette entry of `id`.
pub fn palette_color(id: u8) -> Option<PaletteColor> {
    PALETTE.get(usize::from(id)).copied()
}

/// The light colours that follow a category's pool once it runs out (ids 12–16).
pub const LIGHT_COLORS: [u8; 5] = [12, 13, 14, 15, 16];

/// Unity Perception's colour for an instance id (its `InstanceIdToColorMapping`): ids 1–64 walk
/// the hue circle by the golden ratio at full saturation, dropping the value every 30 ids; id 0
/// is black. The arithmetic is single precision, as in Unity, so the bytes match the release.
pub fn instance_color(id: u32) -> [u8; 4] {
    if id == 0 || id > 64 {
        return [0, 0, 0, 255];
    }
    let golden = f32::midpoint(1.0, 5.0_f32.sqrt());
    let count = id - 1;
    #[expect(clippy::cast_precision_loss, reason = "ids are at most 64")]
    let ratio = count as f32 * golden;
    let hue = ratio - ratio.floor();
    #[expect(clippy::cast_precision_loss, reason = "ids are at most 64")]
    let ratio = (count / 30) as f32 * golden;
    let value = 1.0 - (ratio - ratio.floor());
    let [r, g, b] = hsv_to_rgb(hue, 1.0, value);
    [to_byte(r), to_byte(g), to_byte(b), 255]
}

fn hsv_to_rgb(hue: f32, saturation: f32, value: f32) -> [f32; 3] {
    let h = hue * 6.0;
    let sector = h.floor();
    let fraction = h - sector;
    let p = value * (1.0 - saturation);
    let q = value * (1.0 - saturation * fraction);
    let t = value * (1.0 - saturation * (1.0 - fraction));
    #[expect(clippy::cast_possible_truncation, reason = "a sector index 0..=6")]
    match sector as i32 {
        0 | 6 => [value, t, p],
        1 => [q, value, p],
        2 => [p, value, t],
        3 => [p, q, value],
        4 => [t, p, value],
        _ => [value, p, q],
    }
}

fn to_byte(c: f32) -> u8 {
    #[expect(
        clippy::cast_possible_truncation,
        clippy::cast_sign_loss,
        reason = "clamped to [0, 255]"
    )]
    let byte = (c.clamp(0.0, 1.0) * 255.0).round() as u8;
    byte
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn instance_colors_match_the_real_video() {
        // `instances[].color` of the real rope video, ids 1–10.
        let recorded: [[u8; 3]; 10] = [
            [255, 0, 0],
            [0, 74, 255],
            [149, 255, 0],
            [255, 0, 223],
            [0, 255, 212],
            [255, 138, 0],
            [64, 0, 255],
            [11, 255, 0],
            [255, 0, 85],
            [0, 160, 255],
        ];
        for (index, rgb) in recorded.iter().enumerate() {
            let id = u32::try_from(index + 1).unwrap();
            assert_eq!(&instance_color(id)[..3], rgb, "id {id}");
        }
        assert_eq!(instance_color(0), [0, 0, 0, 255]);
        // Colours stay distinct over every id a scene can use.
        let mut seen: Vec<[u8; 4]> = (1..=64).map(instance_color).collect();
        seen.sort_unstable();
        seen.dedup();
        assert_eq!(seen.len(), 64);
    }

    #[test]
    fn palette_ids_are_positions() {
        for (index, color) in PALETTE.iter().enumerate() {
            assert_eq!(usize::from(color.id), index);
        }
        assert_eq!(palette_color(12).unwrap().name, "Light Blue");
        assert!(palette_color(17).is_none());
    }
}

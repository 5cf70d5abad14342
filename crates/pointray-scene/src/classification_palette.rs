//! Colour from the LAS classification: the ASPRS standard classes (LAS 1.4, codes 0-18) in
//! the colours GIS viewers give them by default (QGIS's classified point-cloud renderer), so
//! that a tile looks as its users know it. The colours become the points' own before prep,
//! and both renderers show them as point colours.

/// One ASPRS class: its code, its name and its sRGB colour.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct AsprsClass {
    pub code: u8,
    pub name: &'static str,
    pub srgb: [u8; 3],
}

const fn class(code: u8, name: &'static str, hex: u32) -> AsprsClass {
    AsprsClass { code, name, srgb: [(hex >> 16) as u8, (hex >> 8) as u8, hex as u8] }
}

/// The standard classes, by code.
pub const ASPRS_CLASSES: [AsprsClass; 19] = [
    class(0, "created, never classified", 0xBABABA),
    class(1, "unclassified", 0xAAAAAA),
    class(2, "ground", 0xAA5500),
    class(3, "low vegetation", 0x00AAAA),
    class(4, "medium vegetation", 0x55FF55),
    class(5, "high vegetation", 0x00AA00),
    class(6, "building", 0xFF5555),
    class(7, "low point (noise)", 0xAA0000),
    class(8, "reserved (model key-point before LAS 1.4)", 0x555555),
    class(9, "water", 0x55FFFF),
    class(10, "rail", 0xAA00AA),
    class(11, "road surface", 0x000000),
    class(12, "reserved (overlap before LAS 1.4)", 0x555555),
    class(13, "wire, guard (shield)", 0xFFFF55),
    class(14, "wire, conductor (phase)", 0xFFFF55),
    class(15, "transmission tower", 0xFF55FF),
    class(16, "wire-structure connector (insulator)", 0xFFFF55),
    class(17, "bridge deck", 0x5555FF),
    class(18, "high noise", 0x646464),
];

/// Codes 19-63 are reserved and 64-255 user-defined: white, unlike every standard class.
pub const OTHER_CLASS_SRGB: [u8; 3] = [255, 255, 255];

/// The sRGB colour of classification `code`.
pub fn classification_color(code: u8) -> [u8; 3] {
    ASPRS_CLASSES.get(usize::from(code)).map_or(OTHER_CLASS_SRGB, |class| class.srgb)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_index_the_table_and_others_are_white() {
        assert!(ASPRS_CLASSES.iter().enumerate().all(|(index, class)| usize::from(class.code) == index));
        assert_eq!(classification_color(2), [0xAA, 0x55, 0x00], "ground is brown");
        assert_eq!(classification_color(6), [0xFF, 0x55, 0x55], "buildings are red");
        assert_eq!(classification_color(19), OTHER_CLASS_SRGB);
        assert_eq!(classification_color(255), OTHER_CLASS_SRGB);
    }
}

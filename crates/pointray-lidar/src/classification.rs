//! The class each return records, as an ASPRS LAS classification code, taken from the name
//! of the object it hit.
//!
//! | code | class | object names (the name's first word, any case, singular or plural) |
//! |---|---|---|
//! | 1 | unclassified | anything else (the scanned models on the street) |
//! | 2 | ground | `ground`, `road`, `sidewalk`, `kerb`, `curb`, `floor`, `terrain` |
//! | 5 | high vegetation | `tree`, `vegetation`, `bush` |
//! | 6 | building | `building`, `facade`, `wall`, `roof` |
//! | 9 | water | `water` |
//! | 64 | vehicle | `car`, `vehicle`, `truck`, `bus` |
//! | 65 | pole | `pole`, `post`, `lamp`, `sign` |
//!
//! Codes 1 to 9 are the standard classes of the LAS 1.4 specification (ASPRS, R15, table
//! 17). It has no class for vehicles or poles, so they take the first two codes it leaves to
//! users (64 and up), as mobile-mapping exports commonly do.

/// An ASPRS LAS classification code.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub struct Classification(pub u8);

impl Classification {
    pub const UNCLASSIFIED: Self = Self(1);
    pub const GROUND: Self = Self(2);
    pub const HIGH_VEGETATION: Self = Self(5);
    pub const BUILDING: Self = Self(6);
    pub const WATER: Self = Self(9);
    pub const VEHICLE: Self = Self(64);
    pub const POLE: Self = Self(65);

    /// The class of an object called `name`, by its first word, singular or plural (see the
    /// module's table).
    pub fn of_object_named(name: &str) -> Self {
        let first_word = name.split(|c: char| !c.is_ascii_alphabetic()).find(|word| !word.is_empty());
        let Some(word) = first_word.map(str::to_ascii_lowercase) else {
            return Self::UNCLASSIFIED;
        };
        Self::of_word(&word)
            .or_else(|| word.strip_suffix('s').and_then(Self::of_word))
            .unwrap_or(Self::UNCLASSIFIED)
    }

    fn of_word(word: &str) -> Option<Self> {
        match word {
            "ground" | "road" | "sidewalk" | "kerb" | "curb" | "floor" | "terrain" => Some(Self::GROUND),
            "tree" | "vegetation" | "bush" => Some(Self::HIGH_VEGETATION),
            "building" | "facade" | "wall" | "roof" => Some(Self::BUILDING),
            "water" => Some(Self::WATER),
            "car" | "vehicle" | "truck" | "bus" => Some(Self::VEHICLE),
            "pole" | "post" | "lamp" | "sign" => Some(Self::POLE),
            _ => None,
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn classes_come_from_the_first_word_of_the_name() {
        assert_eq!(Classification::of_object_named("Road"), Classification::GROUND);
        assert_eq!(Classification::of_object_named("building 3"), Classification::BUILDING);
        assert_eq!(Classification::of_object_named("car_2"), Classification::VEHICLE);
        assert_eq!(Classification::of_object_named("Poles"), Classification::POLE);
        assert_eq!(Classification::of_object_named("  pole"), Classification::POLE);
        assert_eq!(Classification::of_object_named("bunny"), Classification::UNCLASSIFIED);
        assert_eq!(Classification::of_object_named("carpet"), Classification::UNCLASSIFIED);
        assert_eq!(Classification::of_object_named(""), Classification::UNCLASSIFIED);
    }
}

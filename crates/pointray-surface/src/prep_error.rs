//! Why `prep` refuses a point set.

#[derive(Debug, thiserror::Error, PartialEq)]
pub enum PrepError {
    #[error("tile {index} asked for, but the cloud is cut into {count} tiles (0 to {})", count.saturating_sub(1))]
    NoSuchTile { index: usize, count: usize },
    #[error(
        "{tiles} tiles asked for, but the cloud has only {points} points: a tile needs points of its own"
    )]
    TooManyTiles { tiles: usize, points: u64 },
    #[error("point {index} has a coordinate that is NaN or infinite")]
    NonFiniteCoordinate { index: usize },
    #[error("point {index} has an intensity that is NaN or infinite")]
    NonFiniteIntensity { index: usize },
    #[error("{found} points, but k = {k} needs at least {} distinct points", k + 1)]
    TooFewPoints { found: usize, k: usize },
    #[error("{found} distinct points after merging duplicates, but k = {k} needs at least {}", k + 1)]
    TooFewDistinctPoints { found: usize, k: usize },
    #[error("all {count} points are identical: there is no surface to fit")]
    AllPointsIdentical { count: usize },
    #[error("all {count} points lie on one line: there is no surface to fit")]
    AllPointsCollinear { count: usize },
    #[error("{problem}")]
    ExtentOutOfRange { problem: String },
    #[error("the cloud has {found} {attribute} for {expected} points")]
    AttributeLength { attribute: &'static str, found: usize, expected: usize },
    #[error("invalid setting `{setting}`: {problem}")]
    InvalidSetting { setting: &'static str, problem: String },
    #[error("too large: {problem}")]
    TooLarge { problem: String },
}

impl PrepError {
    /// This error of a tile made of the cloud's points `members` (tile point `i` is the
    /// cloud's `members[i]`), naming the cloud's point instead of the tile's.
    pub(crate) fn of_tile(self, members: &[u32]) -> Self {
        let in_cloud = |index: usize| members.get(index).map_or(index, |&member| member as usize);
        match self {
            Self::NonFiniteCoordinate { index } => Self::NonFiniteCoordinate { index: in_cloud(index) },
            Self::NonFiniteIntensity { index } => Self::NonFiniteIntensity { index: in_cloud(index) },
            other => other,
        }
    }
}

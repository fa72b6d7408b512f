//! The five cell classes and their codes and colours.

/// What occupies a cell, in Tamura's terms, plus what has never been seen.
///
/// The discriminant is the cell's class code in [`super::ObstacleGrid::class_codes`] and in recordings.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
#[repr(u8)]
pub enum CellClass {
    /// Never observed, or observed occupied but not yet classified (a tentative obstacle).
    Unknown = 0,
    /// Seen free: a ray passed through it with nothing there.
    Free = 1,
    /// An obstacle that cannot move (a wall, a column, a table proved static by a push).
    Stationary = 2,
    /// An obstacle that cannot move by itself but can be moved (a suitcase left behind, a pushed chair).
    Movable = 3,
    /// An obstacle that moves by itself (a person, another robot).
    Moving = 4,
}

impl CellClass {
    /// Every class, in code order.
    pub const ALL: [CellClass; 5] = [
        CellClass::Unknown,
        CellClass::Free,
        CellClass::Stationary,
        CellClass::Movable,
        CellClass::Moving,
    ];

    /// The class code (0–4).
    pub const fn code(self) -> u8 {
        self as u8
    }

    /// The class with code `code`, or `None` for a code above 4.
    pub const fn from_code(code: u8) -> Option<Self> {
        match code {
            0 => Some(CellClass::Unknown),
            1 => Some(CellClass::Free),
            2 => Some(CellClass::Stationary),
            3 => Some(CellClass::Movable),
            4 => Some(CellClass::Moving),
            _ => None,
        }
    }

    /// True for the three obstacle classes.
    pub const fn is_obstacle(self) -> bool {
        matches!(
            self,
            CellClass::Stationary | CellClass::Movable | CellClass::Moving
        )
    }

    /// The snapshot colour (RGBA).
    ///
    /// Palette: Unknown mid grey (128,128,128), Free white, Stationary black (Tamura's Fig. 12 and Chen's
    /// figures draw static obstacles black), Movable blue (40,90,230), Moving red (220,30,30) (Chen draws
    /// dynamic obstacles red). Chosen to stay distinguishable in greyscale too: the luminances are
    /// 128, 255, 0, ~87 and ~84, and movable/moving differ strongly in hue.
    pub const fn colour(self) -> [u8; 4] {
        match self {
            CellClass::Unknown => [128, 128, 128, 255],
            CellClass::Free => [255, 255, 255, 255],
            CellClass::Stationary => [0, 0, 0, 255],
            CellClass::Movable => [40, 90, 230, 255],
            CellClass::Moving => [220, 30, 30, 255],
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn codes_round_trip_and_colours_differ() {
        // Invariant: every class has a distinct code that decodes back, and a distinct colour.
        for (i, c) in CellClass::ALL.iter().enumerate() {
            assert_eq!(c.code() as usize, i);
            assert_eq!(CellClass::from_code(c.code()), Some(*c));
            for d in &CellClass::ALL[i + 1..] {
                assert_ne!(c.colour(), d.colour());
            }
        }
        assert_eq!(CellClass::from_code(5), None);
    }
}

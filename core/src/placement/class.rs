//! The placement classes and how the Oxford positions and the simulator's placements
//! (`stridekit_sim::PhonePlacement`, which maps itself onto these) fall into them.
//!
//! | `Placement`   | Oxford Step Counter position | simulator placement          |
//! |---------------|------------------------------|------------------------------|
//! | `InHand`      | InHand (held in front, screen up) | InHand                  |
//! | `Pocket`      | FrontPocket, BackPocket      | FrontPocket, BackPocket      |
//! | `Bag`         | Purse                        | Bag                          |
//! | `NeckPouch`   | NeckPouch                    | NeckPouch                    |
//! | `Armband`     | Armband                      | Armband                      |
//! | `SwingingArm` | SwingingArm (hand, arm swinging) | SwingingArm              |
//!
//! Front and back trouser pockets are one class: both hold the phone upright against
//! the thigh or buttock and move with the same leg; the SDK's consumers (step length,
//! heading) treat them alike, and two users' worth of data is too little to separate
//! them reliably (see docs/odometry.md).

/// Number of placement classes.
pub const CLASSES: usize = 6;

/// Where a phone is carried.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash, PartialOrd, Ord)]
pub enum Placement {
    /// Held in front of the body (reading the screen).
    InHand,
    /// In a trouser pocket (front or back).
    Pocket,
    /// In a bag or purse.
    Bag,
    /// In a pouch hanging from the neck, on the chest.
    NeckPouch,
    /// Strapped to the upper arm.
    Armband,
    /// In the hand of a swinging arm.
    SwingingArm,
}

impl Placement {
    /// All classes, in model-file and table order (the index is the class id).
    pub const ALL: [Placement; CLASSES] = [
        Placement::InHand,
        Placement::Pocket,
        Placement::Bag,
        Placement::NeckPouch,
        Placement::Armband,
        Placement::SwingingArm,
    ];

    /// Class id (index in [`ALL`](Self::ALL) and in probability arrays).
    pub fn index(self) -> usize {
        self as usize
    }

    /// Name used in model files and tables.
    pub fn name(self) -> &'static str {
        match self {
            Placement::InHand => "InHand",
            Placement::Pocket => "Pocket",
            Placement::Bag => "Bag",
            Placement::NeckPouch => "NeckPouch",
            Placement::Armband => "Armband",
            Placement::SwingingArm => "SwingingArm",
        }
    }

    /// Inverse of [`name`](Self::name).
    pub fn from_name(name: &str) -> Option<Self> {
        Self::ALL.into_iter().find(|p| p.name() == name)
    }

    /// Class of an Oxford Step Counter position token (folder-name spelling, any
    /// case: `InHand`, `FrontPocket`, `BackPocket`/`Backpocket`, `Purse`, `NeckPouch`,
    /// `Armband`/`ArmBand`, `SwingingArm`).
    pub fn from_oxford_position(token: &str) -> Option<Self> {
        match token.to_ascii_lowercase().as_str() {
            "inhand" => Some(Placement::InHand),
            "frontpocket" | "backpocket" => Some(Placement::Pocket),
            "purse" => Some(Placement::Bag),
            "neckpouch" => Some(Placement::NeckPouch),
            "armband" => Some(Placement::Armband),
            "swingingarm" => Some(Placement::SwingingArm),
            _ => None,
        }
    }
}

impl std::fmt::Display for Placement {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip_and_mappings_cover_everything() {
        for (i, p) in Placement::ALL.into_iter().enumerate() {
            assert_eq!(p.index(), i);
            assert_eq!(Placement::from_name(p.name()), Some(p));
        }
        for t in [
            "InHand",
            "FrontPocket",
            "BackPocket",
            "Backpocket",
            "Purse",
            "NeckPouch",
            "Armband",
            "ArmBand",
            "SwingingArm",
        ] {
            assert!(Placement::from_oxford_position(t).is_some(), "{t}");
        }
        assert_eq!(Placement::from_oxford_position("Pocket"), None);
    }
}

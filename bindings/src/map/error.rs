//! `MapError` at the FFI (Kotlin `MapException`, Swift `MapError`): the typed input
//! causes every engine shares, then the map engine's own.

use stridekit_core::input::InputError;
use stridekit_core::map as core;

crate::error::engine_error! {
    /// Why a plan, a start, a fix, an IMU buffer, a configuration or a snapshot was
    /// refused. A refused input changes nothing.
    pub enum MapError {
        /// The GeoJSON is not a floor plan (not JSON, not a FeatureCollection, the
        /// outline not a polygon, open rings, no walkable area, absurd sizes...).
        #[error("invalid floor plan: {reason}")]
        InvalidPlan { reason: String },
        /// A start or a fix lies too far from the walkable area (the sentence says how
        /// far), or a fix in latitude/longitude on a plan without a geographic
        /// reference.
        #[error("off the plan: {reason}")]
        OffPlan { reason: String },
        /// A floor no plan was given for, or two plans for one floor.
        #[error("floor {floor}: {reason}")]
        Floor { floor: i32, reason: String },
        /// An IMU sample was refused for a reason of the navigator's own.
        #[error("IMU sample rejected: {reason}")]
        InvalidImuSample { reason: String },
        /// Snapshot bytes could not be restored (corrupted, truncated, other engine,
        /// version or plans).
        #[error("cannot restore snapshot: {reason}")]
        InvalidSnapshot { reason: String },
        /// A packed buffer is not a whole number of 80-byte records.
        #[error("invalid packed buffer: {reason}")]
        InvalidBuffer { reason: String },
        /// A configuration was refused (the sentence names the setting).
        #[error("invalid map configuration: {reason}")]
        InvalidConfig { reason: String },
        /// A bug inside stridekit (a caught panic). The engine stays usable.
        #[error("internal error in stridekit: {reason}")]
        Internal { reason: String },
    }
}

impl From<core::MapError> for MapError {
    fn from(e: core::MapError) -> Self {
        use core::MapError as M;
        let reason = e.to_string();
        match e {
            M::Input(i) => i.into(),
            M::Nav(n) => nav_input(crate::phone::navigator::NavError::from(n)),
            M::Config { .. } => Self::InvalidConfig { reason },
            M::OffPlan { .. } | M::NoGeoReference { .. } => Self::OffPlan { reason },
            M::UnknownFloor { floor } | M::DuplicateFloor { floor } => {
                Self::Floor { floor, reason }
            }
            M::Snapshot(s) => Self::InvalidSnapshot {
                reason: s.to_string(),
            },
        }
    }
}

/// The navigator's input refusals, in this error's words.
fn nav_input(e: crate::phone::navigator::NavError) -> MapError {
    use crate::phone::navigator::NavError as N;
    match e {
        N::NonFinite { field } => MapError::NonFinite { field },
        N::OutOfRange {
            field,
            value,
            expected,
        } => MapError::OutOfRange {
            field,
            value,
            expected,
        },
        N::TimeNotIncreasing {
            stream,
            t_s,
            last_t_s,
        } => MapError::TimeNotIncreasing {
            stream,
            t_s,
            last_t_s,
        },
        N::AccelerationNotInMps2 { mean_magnitude } => {
            MapError::AccelerationNotInMps2 { mean_magnitude }
        }
        N::TimeNotInSeconds {
            stream,
            t_s,
            likely_unit,
        } => MapError::TimeNotInSeconds {
            stream,
            t_s,
            likely_unit,
        },
        N::TimeTooFine {
            stream,
            t_s,
            interval_s,
        } => MapError::TimeTooFine {
            stream,
            t_s,
            interval_s,
        },
        N::TimeJump {
            stream,
            t_s,
            last_t_s,
        } => MapError::TimeJump {
            stream,
            t_s,
            last_t_s,
        },
        N::InvalidImuSample { reason } => MapError::InvalidImuSample { reason },
        N::InvalidBuffer { reason } => MapError::InvalidBuffer { reason },
        N::InvalidSnapshot { reason } => MapError::InvalidSnapshot { reason },
        N::InvalidConfig { reason } | N::InvalidCalibration { reason } => {
            MapError::InvalidConfig { reason }
        }
        N::Internal { reason } => MapError::Internal { reason },
    }
}

impl crate::error::InputCause for core::MapError {
    fn input(&self) -> Option<&InputError> {
        match self {
            Self::Input(e) | Self::Nav(stridekit_core::pdr::NavError::Input(e)) => Some(e),
            _ => None,
        }
    }
}

pub(crate) fn guard<T>(f: impl FnOnce() -> Result<T, MapError>) -> Result<T, MapError> {
    crate::error::guard_with(f, |reason| MapError::Internal { reason })
}

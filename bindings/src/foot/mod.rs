//! `FootNavigator` at the FFI: foot-mounted inertial navigation (core:
//! `stridekit_core::foot`; method and measured accuracy in `docs/foot.md`).
//!
//! Kotlin, as an app writes it (IMU on the shoe, axes x forward, y right, z down):
//!
//! ```kotlin
//! val config = footConfigDefault().copy(
//!     axisRemap = footAxesPyshoe(),
//!     detector = footDetectorDefault(FootDetectorKind.SVM),
//! )
//! FootNavigator(config).use { nav ->
//!     // 56-byte little-endian records: t_s, ax, ay, az (m/s²), gx, gy, gz (rad/s)
//!     val r = nav.pushPacked(buffer, FootOutput.STRIDE_ENDS)
//!     r.estimates.forEach { e -> println("stride ${e.stride?.lengthM} m") }
//!     val pos = r.latest?.positionM             // EnuVector(east, north, up)
//!     val saved = nav.snapshot()                // later: FootNavigator.restore(saved)
//! }
//! ```
//!
//! # Samples
//!
//! `push`, `pushWithStance` and `pushSamples` take the SDK's one `ImuSample` record
//! (the magnetometer fields are not used); `pushPacked` takes the 6-axis packed
//! layout of [`crate::packed`] ([`crate::packed::IMU6_RECORD_BYTES`] = 56 bytes per
//! sample, seven f64 LE: `t_s`, `accel_x/y/z_mps2` (specific force, gravity
//! included), `gyro_x/y/z_rads`), the first 56 bytes of the phone engines' 80-byte
//! record. Sensor axes as the IMU reports them; `FootConfig.axisRemap` maps them to
//! the body frame (x forward, y left, z up). Kotlin: `ByteBuffer.allocate(n * 56)
//! .order(ByteOrder.LITTLE_ENDIAN)` and `putDouble` seven times per sample
//! (`packFootSamples` does it from records). A buffer whose length is not a multiple of
//! 56 is rejected as a whole ([`FootError::InvalidBuffer`]); otherwise every record is
//! checked and pushed like its record counterpart and bad records are reported by index.
//!
//! # Errors
//!
//! [`FootError`] (Kotlin `FootException`, one subclass per variant). A rejected sample
//! leaves the navigator byte-for-byte unchanged. No panic crosses the FFI: calls that
//! return `Result` turn a caught panic into [`FootError::Internal`], batch pushes
//! report a panicking sample as rejected, and a mutex poisoned by a panic is recovered.

mod config;
mod error;
mod navigator;
mod records;

pub use config::*;
pub use error::*;
pub use navigator::*;
pub use records::*;

//! Positioning on a floor plan at the FFI (core: `stridekit_core::map`; method,
//! frames and measured accuracy in `docs/map.md`): a [`plan::FloorPlan`] built from
//! GeoJSON text, and the [`navigator::MapNavigator`] that runs the phone navigator's
//! steps on plans (one per floor) with fixes from any source.
//!
//! Kotlin, as an app writes it:
//!
//! ```kotlin
//! val plan = FloorPlan.fromCompetitionGeojson(geojsonText, floorInfoText)   // or FloorPlan.fromGeojson(...)
//! MapNavigator.withDefaults(listOf(plan)).use { nav ->
//!     nav.startAt(x = 12.0, y = 40.5, sigmaM = 1.0, floor = null)          // plan metres
//!     val r = nav.pushImuPacked(buffer)                   // 80-byte IMU records
//!     r.latest?.let { e -> draw(e.xM, e.yM, e.positionStdM) }
//!     path.addAll(r.smoothedFixed)                       // + nav.smoothedWindow() for the open end
//!     nav.pushFix(MapFix(tS = t, position = FixPosition.LatLon(lat, lon), accuracyM = 4.0, floor = 2))
//! }
//! ```

pub mod error;
pub mod navigator;
pub mod plan;
pub mod records;

//! `FloorPlan` at the FFI: one floor's plan, built once from GeoJSON text (the
//! readers of `stridekit-formats`) and shared by any number of map navigators.

use std::sync::Arc;

use stridekit_core::map as core;

use super::error::{guard, MapError};

fn invalid(e: impl std::fmt::Display) -> MapError {
    MapError::InvalidPlan {
        reason: e.to_string(),
    }
}

/// A point of the plan, metres (x east, y north).
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct PlanPoint {
    pub x_m: f64,
    pub y_m: f64,
}

/// A WGS84 position, degrees.
#[derive(Clone, Copy, Debug, PartialEq, uniffi::Record)]
pub struct LatLon {
    pub lat_deg: f64,
    pub lon_deg: f64,
}

/// One floor's plan: walls and walkable area, in metres (x east, y north). Immutable
/// and safe to share between threads and navigators.
#[derive(Debug, uniffi::Object)]
pub struct FloorPlan {
    pub(crate) inner: Arc<core::FloorPlan>,
}

#[uniffi::export]
impl FloorPlan {
    /// The indoor-location competition's plan: `geojson_map.json`'s text (the first
    /// feature the outline, the others units to walk around) and `floor_info.json`'s
    /// (the outline's bounding box maps onto `map_info.width` × `height` metres).
    #[uniffi::constructor]
    pub fn from_competition_geojson(
        geojson: String,
        floor_info_json: String,
    ) -> Result<Arc<Self>, MapError> {
        guard(|| {
            let f = stridekit_formats::parse_competition_plan(&geojson, &floor_info_json)
                .map_err(invalid)?;
            Ok(Arc::new(Self {
                inner: Arc::new(f.build().map_err(invalid)?),
            }))
        })
    }

    /// A plan in WGS84 GeoJSON (features with `"walkable": true/false`, else the first
    /// is the outline and the others are obstacles), in metres East-North-Up around
    /// `reference` (default: the south-west corner of the outline), on `floor`
    /// (default: the outline's `floor_num`, else 0).
    #[uniffi::constructor(default(reference = None, floor = None))]
    pub fn from_geojson(
        geojson: String,
        reference: Option<LatLon>,
        floor: Option<i32>,
    ) -> Result<Arc<Self>, MapError> {
        guard(|| {
            let f = stridekit_formats::parse_geojson_plan(
                &geojson,
                reference.map(|r| (r.lat_deg, r.lon_deg)),
                floor,
            )
            .map_err(invalid)?;
            Ok(Arc::new(Self {
                inner: Arc::new(f.build().map_err(invalid)?),
            }))
        })
    }

    /// The floor this plan is of (the competition's `floor_num`, or the one given).
    pub fn floor(&self) -> i32 {
        self.inner.floor()
    }

    /// The walkable area, m².
    pub fn walkable_area_m2(&self) -> f64 {
        self.inner.walkable_area_m2()
    }

    /// Whether `(x_m, y_m)` is walkable (to 0.25 m).
    pub fn is_walkable(&self, x_m: f64, y_m: f64) -> bool {
        self.inner.is_walkable([x_m, y_m])
    }

    /// Whether the straight line between the two points crosses a wall.
    pub fn crosses_wall(&self, from: PlanPoint, to: PlanPoint) -> bool {
        self.inner
            .crosses_wall([from.x_m, from.y_m], [to.x_m, to.y_m])
    }

    /// Distance to the nearest wall, m (`max_m` when none is that close).
    pub fn distance_to_wall_m(&self, at: PlanPoint, max_m: f64) -> f64 {
        self.inner.distance_to_wall_m([at.x_m, at.y_m], max_m)
    }

    /// Plan metres of a WGS84 position (null without a geographic reference).
    pub fn to_plan(&self, position: LatLon) -> Option<PlanPoint> {
        self.inner.geo_reference().map(|g| {
            let (x_m, y_m) = g.to_plan(position.lat_deg, position.lon_deg);
            PlanPoint { x_m, y_m }
        })
    }

    /// WGS84 of plan metres (null without a geographic reference).
    pub fn to_lat_lon(&self, at: PlanPoint) -> Option<LatLon> {
        self.inner.geo_reference().map(|g| {
            let (lat_deg, lon_deg) = g.to_geodetic(at.x_m, at.y_m);
            LatLon { lat_deg, lon_deg }
        })
    }
}

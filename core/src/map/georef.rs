//! How a plan's metres tie to WGS84: a longitude/latitude bounding box mapped
//! linearly onto the plan's width × height (the indoor-location competition's plans),
//! or an East-North-Up tangent plane around a reference point (plans exported in WGS84).

use crate::geo::LocalFrame;

use super::error::PlanError;

/// The geographic reference of a floor plan (x east, y north in both).
#[derive(Clone, Copy, Debug, PartialEq)]
pub enum GeoReference {
    /// The box `[west, east] × [south, north]` degrees maps linearly onto
    /// `[0, width_m] × [0, height_m]` (x with longitude, y with latitude).
    BoundingBox {
        west_deg: f64,
        south_deg: f64,
        east_deg: f64,
        north_deg: f64,
        width_m: f64,
        height_m: f64,
    },
    /// The ENU tangent plane at `lat_deg, lon_deg` (the plan's 0, 0).
    Local { lat_deg: f64, lon_deg: f64 },
}

impl GeoReference {
    /// Check the numbers: finite, on the globe, a box with extent.
    pub fn validate(&self) -> Result<(), PlanError> {
        let bad = |reason: &str| {
            Err(PlanError::GeoReference {
                reason: reason.into(),
            })
        };
        let on_globe = |lat: f64, lon: f64| lat.abs() <= 90.0 && lon.abs() <= 180.0;
        match *self {
            GeoReference::BoundingBox {
                west_deg,
                south_deg,
                east_deg,
                north_deg,
                width_m,
                height_m,
            } => {
                if !(on_globe(south_deg, west_deg) && on_globe(north_deg, east_deg)) {
                    return bad("bounding box off the globe");
                }
                if !(east_deg > west_deg && north_deg > south_deg) {
                    return bad("the bounding box has no extent");
                }
                if !(width_m > 0.0 && height_m > 0.0 && width_m.is_finite() && height_m.is_finite())
                {
                    return bad("width and height must be positive metres");
                }
                Ok(())
            }
            GeoReference::Local { lat_deg, lon_deg } => {
                if on_globe(lat_deg, lon_deg) && lat_deg.abs() < 89.0 {
                    Ok(())
                } else {
                    bad("reference point off the globe (or at a pole)")
                }
            }
        }
    }

    /// Plan metres `(x, y)` of a WGS84 position.
    pub fn to_plan(&self, lat_deg: f64, lon_deg: f64) -> (f64, f64) {
        match *self {
            GeoReference::BoundingBox {
                west_deg,
                south_deg,
                east_deg,
                north_deg,
                width_m,
                height_m,
            } => (
                (lon_deg - west_deg) / (east_deg - west_deg) * width_m,
                (lat_deg - south_deg) / (north_deg - south_deg) * height_m,
            ),
            GeoReference::Local {
                lat_deg: la,
                lon_deg: lo,
            } => {
                let p = LocalFrame::new(la, lo, 0.0).to_enu(lat_deg, lon_deg, 0.0);
                (p[0], p[1])
            }
        }
    }

    /// WGS84 `(lat, lon)` of plan metres.
    pub fn to_geodetic(&self, x_m: f64, y_m: f64) -> (f64, f64) {
        match *self {
            GeoReference::BoundingBox {
                west_deg,
                south_deg,
                east_deg,
                north_deg,
                width_m,
                height_m,
            } => (
                south_deg + y_m / height_m * (north_deg - south_deg),
                west_deg + x_m / width_m * (east_deg - west_deg),
            ),
            GeoReference::Local { lat_deg, lon_deg } => {
                LocalFrame::new(lat_deg, lon_deg, 0.0).to_geodetic(x_m, y_m)
            }
        }
    }

    /// A point of the plan on the globe (its centre or reference), for the magnetic
    /// declination: `(lat, lon)`.
    pub fn location_deg(&self) -> (f64, f64) {
        match *self {
            GeoReference::BoundingBox {
                west_deg,
                south_deg,
                east_deg,
                north_deg,
                ..
            } => (0.5 * (south_deg + north_deg), 0.5 * (west_deg + east_deg)),
            GeoReference::Local { lat_deg, lon_deg } => (lat_deg, lon_deg),
        }
    }
}

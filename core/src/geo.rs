//! WGS84 geodetic coordinates to a local East-North-Up (ENU) tangent plane.
//!
//! The frame is anchored at an origin fix; x = east, y = north, z = up, metres.
//! Exact ECEF-based conversion (no flat-earth approximation), so distances stay
//! right for runs tens of kilometres from the origin.

/// WGS84 semi-major axis, metres.
pub const WGS84_A_M: f64 = 6_378_137.0;
/// WGS84 first eccentricity squared.
pub const WGS84_E2: f64 = 6.694_379_990_141_316e-3;

/// Earth-centred, earth-fixed coordinates of a geodetic point, metres.
pub fn geodetic_to_ecef(lat_deg: f64, lon_deg: f64, alt_m: f64) -> [f64; 3] {
    let (sl, cl) = lat_deg.to_radians().sin_cos();
    let (so, co) = lon_deg.to_radians().sin_cos();
    let n = WGS84_A_M / (1.0 - WGS84_E2 * sl * sl).sqrt();
    [
        (n + alt_m) * cl * co,
        (n + alt_m) * cl * so,
        (n * (1.0 - WGS84_E2) + alt_m) * sl,
    ]
}

/// A local ENU tangent plane anchored at an origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct LocalFrame {
    origin_lat_deg: f64,
    origin_lon_deg: f64,
    origin_alt_m: f64,
    origin_ecef: [f64; 3],
    sin_lat: f64,
    cos_lat: f64,
    sin_lon: f64,
    cos_lon: f64,
}

impl LocalFrame {
    pub fn new(origin_lat_deg: f64, origin_lon_deg: f64, origin_alt_m: f64) -> Self {
        let (sin_lat, cos_lat) = origin_lat_deg.to_radians().sin_cos();
        let (sin_lon, cos_lon) = origin_lon_deg.to_radians().sin_cos();
        Self {
            origin_lat_deg,
            origin_lon_deg,
            origin_alt_m,
            origin_ecef: geodetic_to_ecef(origin_lat_deg, origin_lon_deg, origin_alt_m),
            sin_lat,
            cos_lat,
            sin_lon,
            cos_lon,
        }
    }

    /// Origin as (lat°, lon°, alt m).
    pub fn origin(&self) -> (f64, f64, f64) {
        (self.origin_lat_deg, self.origin_lon_deg, self.origin_alt_m)
    }

    /// East, north, up of a geodetic point, metres.
    pub fn to_enu(&self, lat_deg: f64, lon_deg: f64, alt_m: f64) -> [f64; 3] {
        let p = geodetic_to_ecef(lat_deg, lon_deg, alt_m);
        let d = [
            p[0] - self.origin_ecef[0],
            p[1] - self.origin_ecef[1],
            p[2] - self.origin_ecef[2],
        ];
        let e = -self.sin_lon * d[0] + self.cos_lon * d[1];
        let n = -self.sin_lat * self.cos_lon * d[0] - self.sin_lat * self.sin_lon * d[1]
            + self.cos_lat * d[2];
        let u = self.cos_lat * self.cos_lon * d[0]
            + self.cos_lat * self.sin_lon * d[1]
            + self.sin_lat * d[2];
        [e, n, u]
    }

    /// Geodetic (lat°, lon°) of a local point on the tangent plane at the origin's
    /// altitude (inverse of [`to_enu`](Self::to_enu) for small heights; iterative).
    pub fn to_geodetic(&self, east_m: f64, north_m: f64) -> (f64, f64) {
        // First guess from local radii, then Newton refinement through to_enu.
        let sl = self.sin_lat;
        let w = (1.0 - WGS84_E2 * sl * sl).sqrt();
        let rn = WGS84_A_M / w;
        let rm = WGS84_A_M * (1.0 - WGS84_E2) / (w * w * w);
        let mut lat = self.origin_lat_deg + (north_m / rm).to_degrees();
        let mut lon = self.origin_lon_deg + (east_m / (rn * self.cos_lat.max(1e-9))).to_degrees();
        for _ in 0..3 {
            let enu = self.to_enu(lat, lon, self.origin_alt_m);
            lat += ((north_m - enu[1]) / rm).to_degrees();
            lon += ((east_m - enu[0]) / (rn * self.cos_lat.max(1e-9))).to_degrees();
        }
        (lat, lon)
    }
}

/// Great-circle-free distance between two geodetic points through the local plane
/// of the first one, metres (accurate to mm for points a few km apart).
pub fn horizontal_distance_m(lat1: f64, lon1: f64, lat2: f64, lon2: f64) -> f64 {
    let f = LocalFrame::new(lat1, lon1, 0.0);
    let p = f.to_enu(lat2, lon2, 0.0);
    p[0].hypot(p[1])
}

/// Snapshot codec of an optional local frame (its WGS84 origin), shared by the engines
/// that anchor one.
pub(crate) fn write_frame(w: &mut crate::snapshot::Writer, frame: Option<&LocalFrame>) {
    match frame {
        Some(f) => {
            w.bool(true);
            let (lat, lon, alt) = f.origin();
            w.f64s(&[lat, lon, alt]);
        }
        None => w.bool(false),
    }
}

/// Read what [`write_frame`] wrote; an origin off the globe or outside the altitude
/// limits of the input layer is refused.
pub(crate) fn read_frame(
    r: &mut crate::snapshot::Reader,
) -> Result<Option<LocalFrame>, crate::snapshot::SnapshotError> {
    if !r.bool()? {
        return Ok(None);
    }
    let (lat, lon, alt) = (r.f64()?, r.f64()?, r.f64()?);
    let alt_ok = (crate::input::limits::MIN_ALT_M..=crate::input::limits::MAX_ALT_M).contains(&alt);
    if !(lat.abs() <= 90.0 && lon.abs() <= 180.0 && alt_ok) {
        return Err(crate::snapshot::SnapshotError::Invalid("frame origin"));
    }
    Ok(Some(LocalFrame::new(lat, lon, alt)))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn one_degree_of_latitude() {
        // 1° of latitude at 45° N is 111.132 km on WGS84.
        let f = LocalFrame::new(44.5, 10.0, 0.0);
        let p = f.to_enu(45.5, 10.0, 0.0);
        assert!((p[1].hypot(p[2]) - 111_141.5).abs() < 200.0, "{p:?}");
        assert!(p[0].abs() < 1e-6);
    }

    #[test]
    fn roundtrip_geodetic() {
        let f = LocalFrame::new(-8.045, -34.89, 10.0);
        let (lat, lon) = f.to_geodetic(1234.5, -987.6);
        let p = f.to_enu(lat, lon, 10.0);
        assert!(
            (p[0] - 1234.5).abs() < 1e-3 && (p[1] + 987.6).abs() < 1e-3,
            "{p:?}"
        );
    }
}

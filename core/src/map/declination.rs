//! Magnetic declination (true north minus magnetic north, east positive) from the
//! World Magnetic Model's main field at its epoch: a magnetometer's heading plus the
//! declination is the heading from true north, which plans and maps are drawn to.
//!
//! The model: WMM2025 (NOAA NCEI and BGS, epoch 2025.0; coefficients are a work of
//! the US government, public domain), degree and order 12, Gauss coefficients g, h in
//! nT in the order n = 1..=12, m = 0..=n. The secular variation is left out: the
//! engine knows no calendar date (its clock is the app's monotonic one) and
//! declination moves by about 0.1° a year in most places, within a walk's heading
//! noise for a decade either side of the epoch. Evaluated once per plan or fix, never
//! per sample: the field from Schmidt semi-normalised associated Legendre functions
//! in geocentric coordinates, turned back to the geodetic vertical.

use crate::geo::{WGS84_A_M, WGS84_E2};

/// Degree and order of the model.
const N_MAX: usize = 12;
/// Geomagnetic reference radius, m.
const REFERENCE_RADIUS_M: f64 = 6_371_200.0;
/// Closest a latitude gets to a pole (the east component divides by its cosine), °.
const MAX_LAT_DEG: f64 = 89.999;

/// WMM2025 main-field Gauss coefficients (g, h), nT, n = 1..=12, m = 0..=n.
const WMM2025: [(f64, f64); 90] = [
    (-29351.8, 0.0),
    (-1410.8, 4545.4),
    (-2556.6, 0.0),
    (2951.1, -3133.6),
    (1649.3, -815.1),
    (1361.0, 0.0),
    (-2404.1, -56.6),
    (1243.8, 237.5),
    (453.6, -549.5),
    (895.0, 0.0),
    (799.5, 278.6),
    (55.7, -133.9),
    (-281.1, 212.0),
    (12.1, -375.6),
    (-233.2, 0.0),
    (368.9, 45.4),
    (187.2, 220.2),
    (-138.7, -122.9),
    (-142.0, 43.0),
    (20.9, 106.1),
    (64.4, 0.0),
    (63.8, -18.4),
    (76.9, 16.8),
    (-115.7, 48.8),
    (-40.9, -59.8),
    (14.9, 10.9),
    (-60.7, 72.7),
    (79.5, 0.0),
    (-77.0, -48.9),
    (-8.8, -14.4),
    (59.3, -1.0),
    (15.8, 23.4),
    (2.5, -7.4),
    (-11.1, -25.1),
    (14.2, -2.3),
    (23.2, 0.0),
    (10.8, 7.1),
    (-17.5, -12.6),
    (2.0, 11.4),
    (-21.7, -9.7),
    (16.9, 12.7),
    (15.0, 0.7),
    (-16.8, -5.2),
    (0.9, 3.9),
    (4.6, 0.0),
    (7.8, -24.8),
    (3.0, 12.2),
    (-0.2, 8.3),
    (-2.5, -3.3),
    (-13.1, -5.2),
    (2.4, 7.2),
    (8.6, -0.6),
    (-8.7, 0.8),
    (-12.9, 10.0),
    (-1.3, 0.0),
    (-6.4, 3.3),
    (0.2, 0.0),
    (2.0, 2.4),
    (-1.0, 5.3),
    (-0.6, -9.1),
    (-0.9, 0.4),
    (1.5, -4.2),
    (0.9, -3.8),
    (-2.7, 0.9),
    (-3.9, -9.1),
    (2.9, 0.0),
    (-1.5, 0.0),
    (-2.5, 2.9),
    (2.4, -0.6),
    (-0.6, 0.2),
    (-0.1, 0.5),
    (-0.6, -0.3),
    (-0.1, -1.2),
    (1.1, -1.7),
    (-1.0, -2.9),
    (-0.2, -1.8),
    (2.6, -2.3),
    (-2.0, 0.0),
    (-0.2, -1.3),
    (0.3, 0.7),
    (1.2, 1.0),
    (-1.3, -1.4),
    (0.6, -0.0),
    (0.6, 0.6),
    (0.5, -0.1),
    (-0.1, 0.8),
    (-0.4, 0.1),
    (-0.2, -1.0),
    (-1.3, 0.1),
    (-0.7, 0.2),
];

/// Declination at `lat_deg, lon_deg` (WGS84, sea level), rad, east positive: add it
/// to a magnetic azimuth to get the true one. NaN for a position off the globe.
pub fn declination_rad(lat_deg: f64, lon_deg: f64) -> f64 {
    if !(lat_deg.abs() <= 90.0 && lon_deg.abs() <= 360.0) {
        return f64::NAN;
    }
    let [x, y, _] = field_nt(lat_deg.clamp(-MAX_LAT_DEG, MAX_LAT_DEG), lon_deg);
    y.atan2(x)
}

/// The main field at a point: north, east, down components in nT (geodetic frame).
fn field_nt(lat_deg: f64, lon_deg: f64) -> [f64; 3] {
    // Geodetic → geocentric spherical (at the ellipsoid's surface).
    let (sl, cl) = lat_deg.to_radians().sin_cos();
    let rn = WGS84_A_M / (1.0 - WGS84_E2 * sl * sl).sqrt();
    let (px, pz) = (rn * cl, rn * (1.0 - WGS84_E2) * sl);
    let r = px.hypot(pz);
    let (sp, cp) = (pz / r, px / r);
    let (p, dp) = legendre(sp, cp);
    let lon = lon_deg.to_radians();
    let ratio = REFERENCE_RADIUS_M / r;
    let mut rn2 = ratio * ratio;
    let (mut bx, mut by, mut bz) = (0.0, 0.0, 0.0);
    let mut k = 0;
    for n in 1..=N_MAX {
        rn2 *= ratio; // (a/r)^(n+2)
        for m in 0..=n {
            let (g, h) = WMM2025[k];
            let (sm, cm) = (m as f64 * lon).sin_cos();
            let i = index(n, m);
            let gc = g * cm + h * sm;
            bx -= rn2 * gc * dp[i];
            by += rn2 * m as f64 * (g * sm - h * cm) * p[i];
            bz -= rn2 * (n + 1) as f64 * gc * p[i];
            k += 1;
        }
    }
    by /= cp;
    // Geocentric → geodetic vertical: turn north and down by the latitude difference.
    let psi = sp.atan2(cp) - lat_deg.to_radians();
    let (ss, cs) = psi.sin_cos();
    [bx * cs - bz * ss, by, bx * ss + bz * cs]
}

/// Index of (n, m) in the triangular arrays.
const fn index(n: usize, m: usize) -> usize {
    n * (n + 1) / 2 + m
}

const SIZE: usize = index(N_MAX, N_MAX) + 1;

/// Schmidt semi-normalised P(n, m)(sin φ) and their derivatives with respect to the
/// geocentric latitude φ, for `x` = sin φ, `z` = cos φ.
fn legendre(x: f64, z: f64) -> ([f64; SIZE], [f64; SIZE]) {
    // Gauss-normalised recursion, then the Schmidt factors.
    let (mut p, mut dp) = ([0.0; SIZE], [0.0; SIZE]);
    p[0] = 1.0;
    for n in 1..=N_MAX {
        for m in 0..=n {
            let i = index(n, m);
            if m == n {
                let j = index(n - 1, m - 1);
                p[i] = z * p[j];
                dp[i] = z * dp[j] + x * p[j];
            } else if n == 1 || m == n - 1 {
                let j = index(n - 1, m);
                p[i] = x * p[j];
                dp[i] = x * dp[j] - z * p[j];
            } else {
                let (j, l) = (index(n - 1, m), index(n - 2, m));
                let k = (((n - 1) * (n - 1) - m * m) as f64) / (((2 * n - 1) * (2 * n - 3)) as f64);
                p[i] = x * p[j] - k * p[l];
                dp[i] = x * dp[j] - z * p[j] - k * dp[l];
            }
        }
    }
    // Schmidt factors S(n, m): S(n, 0) = S(n−1, 0)·(2n−1)/n, then along m.
    let mut s = [0.0; SIZE];
    s[0] = 1.0;
    for n in 1..=N_MAX {
        s[index(n, 0)] = s[index(n - 1, 0)] * (2 * n - 1) as f64 / n as f64;
        for m in 1..=n {
            let twice = if m == 1 { 2.0 } else { 1.0 };
            s[index(n, m)] =
                s[index(n, m - 1)] * (((n - m + 1) as f64 * twice) / (n + m) as f64).sqrt();
        }
    }
    for i in 0..SIZE {
        p[i] *= s[i];
        // The recursion differentiates by colatitude; latitude is its negative.
        dp[i] *= -s[i];
    }
    (p, dp)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn deg(lat: f64, lon: f64) -> f64 {
        declination_rad(lat, lon).to_degrees()
    }

    #[test]
    fn declination_where_it_is_known() {
        // Charted declinations around 2025 (± the decade's change and the chart's
        // rounding): Hangzhou about −5.5°, London about +1°, New York about −13°,
        // Sydney about +12.8°, Boulder about +7.7°.
        for (lat, lon, want) in [
            (30.27, 120.16, -5.5),
            (51.5, -0.13, 1.0),
            (40.71, -74.0, -12.9),
            (-33.87, 151.21, 12.8),
            (40.01, -105.27, 7.7),
        ] {
            let d = deg(lat, lon);
            assert!(
                (d - want).abs() < 1.5,
                "({lat}, {lon}): {d:.2}° against {want}°"
            );
        }
        assert!(declination_rad(91.0, 0.0).is_nan());
        assert!(deg(90.0, 0.0).is_finite());
    }
}

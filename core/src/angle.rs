//! Angles: wrapping to (−π, π], the one helper every engine uses for the sum or the
//! difference of azimuths and headings.

use std::f64::consts::PI;

/// Wrap an angle to (−π, π]: one add for the sum or difference of two wrapped
/// angles, the general remainder otherwise.
#[inline]
pub fn wrap(a: f64) -> f64 {
    if a > -PI && a <= PI {
        a
    } else if a > PI && a <= 3.0 * PI {
        a - 2.0 * PI
    } else if a <= -PI && a > -3.0 * PI {
        a + 2.0 * PI
    } else {
        wrap_any(a)
    }
}

/// [`wrap`] for any angle (the remainder of a division by 2π).
fn wrap_any(a: f64) -> f64 {
    let mut x = (a + PI).rem_euclid(2.0 * PI) - PI;
    if x <= -PI {
        x += 2.0 * PI;
    }
    x
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn keeps_wrapped_angles_and_wraps_the_rest_into_the_half_open_range() {
        for a in [0.0, 1.0, -1.0, PI, -PI + 1e-12, 3.0] {
            assert_eq!(wrap(a), a);
        }
        assert_eq!(wrap(-PI), PI);
        assert!((wrap(PI + 0.5) - (0.5 - PI)).abs() < 1e-15);
        assert!((wrap(-PI - 0.5) - (PI - 0.5)).abs() < 1e-15);
        for k in [-7.0, -3.0, 3.0, 100.0] {
            let a = 0.25 + 2.0 * PI * k;
            assert!((wrap(a) - 0.25).abs() < 1e-12, "{a}");
        }
        for i in -2000..2000 {
            let w = wrap(i as f64 * 0.01 * PI);
            assert!(w > -PI && w <= PI, "{i}: {w}");
        }
        assert!(wrap(f64::NAN).is_nan());
    }
}

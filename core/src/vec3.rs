//! 3-vectors as plain arrays, for the code that keeps nalgebra types off its hot path:
//! the dot product, the norm and the unit vector, written once.

/// a · b.
#[inline]
pub fn dot(a: [f64; 3], b: [f64; 3]) -> f64 {
    a[0] * b[0] + a[1] * b[1] + a[2] * b[2]
}

/// |v|.
#[inline]
pub fn norm(v: [f64; 3]) -> f64 {
    dot(v, v).sqrt()
}

/// `v` / |v|; `None` when |v| is not above `min_norm` (no direction).
#[inline]
pub fn unit(v: [f64; 3], min_norm: f64) -> Option<[f64; 3]> {
    let n = norm(v);
    (n > min_norm).then(|| [v[0] / n, v[1] / n, v[2] / n])
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn norm_unit_and_dot() {
        assert_eq!(norm([3.0, 4.0, 12.0]), 13.0);
        assert_eq!(unit([0.0, 3.0, 4.0], 0.0), Some([0.0, 0.6, 0.8]));
        assert_eq!(unit([0.0; 3], 0.0), None);
        assert_eq!(unit([1e-13, 0.0, 0.0], 1e-12), None);
        assert_eq!(dot([1.0, 2.0, 3.0], [4.0, -5.0, 6.0]), 12.0);
    }

    /// The same bits as nalgebra's `try_normalize`, which parts of the engines use.
    #[test]
    fn matches_nalgebra_bit_for_bit() {
        let mut x = 0.123_f64;
        for _ in 0..1000 {
            let v = [x.sin() * 7.0, (3.0 * x).cos() * 0.3, x * x - 2.0];
            x += 0.937;
            let n = nalgebra::Vector3::from(v).try_normalize(0.0).unwrap();
            assert_eq!(unit(v, 0.0).unwrap(), [n.x, n.y, n.z]);
            assert_eq!(norm(v), nalgebra::Vector3::from(v).norm());
        }
    }
}

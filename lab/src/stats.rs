//! Small statistics shared by the evaluations.

/// Median of the finite values (NaN when there are none; the mean of the two middle
/// values for an even count).
pub fn median(values: impl IntoIterator<Item = f64>) -> f64 {
    let mut v: Vec<f64> = values.into_iter().filter(|x| x.is_finite()).collect();
    if v.is_empty() {
        return f64::NAN;
    }
    v.sort_by(f64::total_cmp);
    let n = v.len();
    if n % 2 == 1 {
        v[n / 2]
    } else {
        0.5 * (v[n / 2 - 1] + v[n / 2])
    }
}

#[cfg(test)]
mod tests {
    use super::median;

    #[test]
    fn median_skips_non_finite_values() {
        assert_eq!(median([3.0, f64::NAN, 1.0, 2.0]), 2.0);
        assert_eq!(median([4.0, 1.0, f64::INFINITY, 2.0, 3.0]), 2.5);
        assert!(median([f64::NAN]).is_nan());
        assert!(median(Vec::new()).is_nan());
    }
}

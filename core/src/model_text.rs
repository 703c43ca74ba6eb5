//! Reading the versioned text files of the shipped models (placement classifier,
//! learned odometry, zero-velocity SVMs): a header line, `#` comments, keyword lines of
//! numbers written as shortest round-trip floats. Each model names its lines and keeps
//! its own typed errors; the line numbering and the number parsing are shared here.

/// The lines of `text`, trimmed, numbered from 1.
pub(crate) fn numbered_lines(text: &str) -> impl Iterator<Item = (usize, &str)> {
    text.lines().enumerate().map(|(i, l)| (i + 1, l.trim()))
}

/// A token as a finite number.
pub(crate) fn finite(token: &str) -> Option<f64> {
    token.parse::<f64>().ok().filter(|v| v.is_finite())
}

/// The tokens as finite numbers, or the first token that is not one.
pub(crate) fn finite_numbers<'a>(tokens: &[&'a str]) -> Result<Vec<f64>, &'a str> {
    tokens.iter().map(|t| finite(t).ok_or(*t)).collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn numbers_lines_and_finite_numbers() {
        let lines: Vec<_> = numbered_lines("a\n  b  \n\nc").collect();
        assert_eq!(lines, [(1, "a"), (2, "b"), (3, ""), (4, "c")]);
        assert_eq!(finite_numbers(&["1", "-2.5e3"]), Ok(vec![1.0, -2500.0]));
        assert_eq!(finite_numbers(&["1", "inf", "x"]), Err("inf"));
        assert_eq!(finite("NaN"), None);
    }
}

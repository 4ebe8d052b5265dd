//! Medians and percentiles: one definition for the library, the commands and the benches.
//!
//! A quantile `q` of `n` values is the one at index `round((n − 1) q)` in sorted order: the
//! median of an even count is its upper middle value. Values are compared by
//! `f64::total_cmp` (a NaN sorts after every number).

/// The value at quantile `q` (`0..=1`) of `v`, reordering `v`; `None` for no values.
pub fn quantile(v: &mut [f64], q: f64) -> Option<f64> {
    if v.is_empty() {
        return None;
    }
    let at = ((v.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize;
    Some(*v.select_nth_unstable_by(at, f64::total_cmp).1)
}

/// The median of `v` (see the module docs), reordering `v`; `None` for no values.
pub fn median(v: &mut [f64]) -> Option<f64> {
    quantile(v, 0.5)
}

/// The median and the 95th percentile of `v` (NaN for no values).
pub fn median_p95(mut v: Vec<f64>) -> (f64, f64) {
    (
        median(&mut v).unwrap_or(f64::NAN),
        quantile(&mut v, 0.95).unwrap_or(f64::NAN),
    )
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_median_of_an_even_count_is_the_upper_middle_value() {
        assert_eq!(median(&mut [3.0, 1.0, 2.0]), Some(2.0));
        assert_eq!(median(&mut [4.0, 1.0, 3.0, 2.0]), Some(3.0));
        assert_eq!(median(&mut []), None);
        let (m, p) = median_p95((1..=100).map(f64::from).collect());
        assert_eq!((m, p), (51.0, 95.0));
        assert!(median_p95(Vec::new()).0.is_nan());
        assert_eq!(
            quantile(&mut [5.0, f64::NAN, 1.0], 1.0).map(f64::is_nan),
            Some(true)
        );
    }
}

//! Summary statistics of measured figures, written once for every table and comparison.

/// The mean, 0 for no values.
pub fn mean(values: impl IntoIterator<Item = f64>) -> f64 {
    let (sum, n) = values
        .into_iter()
        .fold((0.0, 0usize), |(s, n), v| (s + v, n + 1));
    if n == 0 { 0.0 } else { sum / n as f64 }
}

/// The mean and the sample standard deviation (0 for fewer than two values).
pub fn mean_std(values: &[f64]) -> (f64, f64) {
    let m = mean(values.iter().copied());
    if values.len() < 2 {
        return (m, 0.0);
    }
    let var = values.iter().map(|v| (v - m).powi(2)).sum::<f64>() / (values.len() - 1) as f64;
    (m, var.sqrt())
}

/// The `q`-quantile by nearest rank (`q` in `[0, 1]`), `None` for no values.
pub fn quantile(values: &[f64], q: f64) -> Option<f64> {
    if values.is_empty() {
        return None;
    }
    let mut sorted = values.to_vec();
    sorted.sort_by(f64::total_cmp);
    Some(sorted[((sorted.len() - 1) as f64 * q.clamp(0.0, 1.0)).round() as usize])
}

/// Two-sided 95 % quantiles of Student's t for 1 to 30 degrees of freedom (standard tables).
const STUDENT_T_95: [f64; 30] = [
    12.706, 4.303, 3.182, 2.776, 2.571, 2.447, 2.365, 2.306, 2.262, 2.228, 2.201, 2.179, 2.160,
    2.145, 2.131, 2.120, 2.110, 2.101, 2.093, 2.086, 2.080, 2.074, 2.069, 2.064, 2.060, 2.056,
    2.052, 2.048, 2.045, 2.042,
];

/// How many standard errors either side of a mean of `n` values make a 95 % interval: Student's t
/// with `n − 1` degrees of freedom, from the table up to 30 and, beyond, the normal quantile with
/// the first two terms of its Cornish–Fisher expansion in `1/df` (within 0.001 of the table at 30).
/// Infinite for fewer than two values.
pub fn t_95(n: usize) -> f64 {
    if n < 2 {
        return f64::INFINITY;
    }
    let df = (n - 1) as f64;
    if let Some(&t) = STUDENT_T_95.get(n - 2) {
        return t;
    }
    let z: f64 = 1.959_964;
    z + (z.powi(3) + z) / (4.0 * df)
        + (5.0 * z.powi(5) + 16.0 * z.powi(3) + 3.0 * z) / (96.0 * df * df)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn student_t_joins_its_expansion_and_tends_to_the_normal() {
        assert_eq!(t_95(5), 2.776);
        // Past the table, the expansion continues it (df 30 in the table is 2.042).
        assert!((t_95(32) - 2.040).abs() < 1e-3, "{}", t_95(32));
        assert!((t_95(61) - 2.000).abs() < 1e-3, "{}", t_95(61));
        assert!((t_95(101) - 1.984).abs() < 1e-3, "{}", t_95(101));
        assert!(t_95(1).is_infinite());
    }

    #[test]
    fn figures_of_small_samples() {
        assert_eq!(mean(Vec::new()), 0.0);
        assert_eq!(mean_std(&[2.0]), (2.0, 0.0));
        let (m, s) = mean_std(&[1.0, 2.0, 3.0]);
        assert!((m - 2.0).abs() < 1e-15 && (s - 1.0).abs() < 1e-15);
        assert_eq!(quantile(&[], 0.5), None);
        assert_eq!(quantile(&[3.0, 1.0, 2.0], 0.5), Some(2.0));
        assert_eq!(quantile(&[3.0, 1.0, 2.0], 1.0), Some(3.0));
    }
}

//! Small statistics of measured series: mean and standard deviation, a least-squares line.

/// Mean and (population) standard deviation.
pub fn mean_sd(x: &[f64]) -> (f64, f64) {
    let n = x.len() as f64;
    let m = x.iter().sum::<f64>() / n;
    let v = x.iter().map(|y| (y - m) * (y - m)).sum::<f64>() / n;
    (m, v.sqrt())
}

/// Least-squares slope and R² of y on x.
pub fn fit_line(x: &[f64], y: &[f64]) -> (f64, f64) {
    let (mx, _) = mean_sd(x);
    let (my, _) = mean_sd(y);
    let sxy: f64 = x.iter().zip(y).map(|(a, b)| (a - mx) * (b - my)).sum();
    let sxx: f64 = x.iter().map(|a| (a - mx) * (a - mx)).sum();
    let slope = sxy / sxx;
    let ss_res: f64 = x
        .iter()
        .zip(y)
        .map(|(a, b)| (b - my - slope * (a - mx)).powi(2))
        .sum();
    let ss_tot: f64 = y.iter().map(|b| (b - my) * (b - my)).sum();
    (slope, 1.0 - ss_res / ss_tot)
}

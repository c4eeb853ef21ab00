//! Reading a measured curve at a point between its measurements: linear
//! between the two neighbouring points, never beyond the measured range
//! (a value the sweep never reached is not measured).

/// How points of a curve at the same `x` count.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub(crate) enum Ties {
    /// Their mean `y` (repeated runs of one setting).
    Mean,
    /// Their lowest `y` (the best a curve shows there, where lower is
    /// better).
    Lowest,
}

/// The `y` a curve of `(x, y)` points, in any order, reaches at `x`:
/// linear in both between the two neighbouring points. `None` outside
/// the points' range, where there are none, or for a non-finite `x`;
/// non-finite points are left out and points at the same `x` count by
/// `ties`.
pub(crate) fn linear_at(curve: &[(f64, f64)], x: f64, ties: Ties) -> Option<f64> {
    if !x.is_finite() {
        return None;
    }
    let mut pts: Vec<(f64, f64)> = curve
        .iter()
        .copied()
        .filter(|(px, py)| px.is_finite() && py.is_finite())
        .collect();
    pts.sort_by(|a, b| a.0.total_cmp(&b.0).then(a.1.total_cmp(&b.1)));
    let mut merged: Vec<(f64, f64, u32)> = Vec::with_capacity(pts.len());
    for (px, py) in pts {
        match merged.last_mut() {
            // Sorted by `y` within one `x`: the first is the lowest.
            Some(m) if m.0 == px => {
                if ties == Ties::Mean {
                    m.1 += py;
                    m.2 += 1;
                }
            }
            _ => merged.push((px, py, 1)),
        }
    }
    let pts: Vec<(f64, f64)> = merged
        .into_iter()
        .map(|(px, sum, n)| (px, sum / f64::from(n)))
        .collect();
    if let Some(&(_, y)) = pts.iter().find(|p| p.0 == x) {
        return Some(y);
    }
    pts.windows(2).find_map(|w| {
        let ((x0, y0), (x1, y1)) = (w[0], w[1]);
        (x0 < x && x < x1).then(|| y0 + (y1 - y0) * (x - x0) / (x1 - x0))
    })
}

//! String parsing of settings given as text (command-line flags, and the
//! scene file's `statistic`): each function takes the text and returns the
//! value or a one-line reason, as clap's `value_parser` wants. A leaf
//! module (it uses only [`crate::limits`]), so the scene format, the world
//! and the commands can all parse the same way without importing each
//! other.

/// Parses a feature-size statistic name: `longest`, `mean`, `shortest` or
/// `thickness`.
pub fn parse_statistic(text: &str) -> Result<acuity_preprocess::FrequencyStatistic, String> {
    use acuity_preprocess::FrequencyStatistic as F;
    match text {
        "longest" => Ok(F::Longest),
        "mean" => Ok(F::Mean),
        "shortest" => Ok(F::Shortest),
        "thickness" => Ok(F::Thickness),
        _ => Err(format!(
            "`{text}` is not one of longest, mean, shortest, thickness"
        )),
    }
}

/// Splits `AxB` text (either case of `x`) and parses each side with
/// `parse_side`, which gets the side's trimmed text; `form` names the
/// expected shape in the error (e.g. `WIDTHxHEIGHT`).
pub fn parse_pair<T>(
    text: &str,
    form: &str,
    parse_side: impl Fn(&str) -> Result<T, String>,
) -> Result<[T; 2], String> {
    let (a, b) = text
        .split_once(['x', 'X'])
        .ok_or_else(|| format!("`{text}` is not of the form {form}"))?;
    Ok([parse_side(a.trim())?, parse_side(b.trim())?])
}

/// Parses a `WIDTHxHEIGHT` resolution in pixels (command-line flag).
pub fn parse_resolution(text: &str) -> Result<[u32; 2], String> {
    parse_pair(text, "WIDTHxHEIGHT", |s| match s.parse::<u32>() {
        Ok(v) if (1..=crate::limits::MAX_RESOLUTION_PX).contains(&v) => Ok(v),
        _ => Err(format!("`{s}` in `{text}` is not a resolution in pixels")),
    })
}

/// Parses a ΔE*uv threshold (command-line flag): finite and > 0.
pub fn parse_threshold(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(t) if t.is_finite() && t > 0.0 => Ok(t),
        _ => Err(format!("`{text}` is not a positive number")),
    }
}

/// Parses a colour difference, ΔE*uv, that may be 0 (command-line flag):
/// a finite number >= 0.
pub fn parse_min_change(text: &str) -> Result<f32, String> {
    match text.parse::<f32>() {
        Ok(t) if t.is_finite() && t >= 0.0 => Ok(t),
        _ => Err(format!("`{text}` is not a finite number >= 0")),
    }
}

/// Parses a `HORIZxVERT` pair of angles in degrees (command-line flag):
/// two finite numbers; the command checks their range.
pub fn parse_angles(text: &str) -> Result<[f32; 2], String> {
    parse_pair(text, "HORIZxVERT", |s| match s.parse::<f32>() {
        Ok(v) if v.is_finite() => Ok(v),
        _ => Err(format!(
            "`{s}` in `{text}` is not a finite angle in degrees"
        )),
    })
}

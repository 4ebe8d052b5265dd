//! A parameter's range: clamping a slider's value into it, and the error that names a
//! file's value outside it. Shared by the [`super::material`] and [`super::params`] parts,
//! which both have ranges (and so neither imports the other for them).

/// A parameter outside its documented range.
#[derive(Clone, Debug, PartialEq, thiserror::Error)]
#[error("{field} = {value} is outside {range}")]
pub struct ParamError {
    /// The field's name as files write it.
    pub field: &'static str,
    /// The value given.
    pub value: f64,
    /// The valid range, as text.
    pub range: &'static str,
}

/// `v` clamped into `lo..=hi`, or `default` where it is NaN.
pub(super) fn clamp(v: f32, lo: f32, hi: f32, default: f32) -> f32 {
    if v.is_nan() {
        default
    } else {
        v.clamp(lo, hi)
    }
}

/// One range check: the field as files name it, its value, its bounds and the range as
/// text.
pub(super) type Check = (&'static str, f32, f32, f32, &'static str);

/// The first check whose value is outside its bounds (NaN is outside every range).
pub(super) fn first_failure(checks: &[Check]) -> Result<(), ParamError> {
    for &(field, value, lo, hi, range) in checks {
        if !(lo..=hi).contains(&value) {
            // The f32 as its shortest text reads (0.9, not 0.8999999761581421).
            return Err(ParamError {
                field,
                value: value.to_string().parse().unwrap_or(f64::from(value)),
                range,
            });
        }
    }
    Ok(())
}

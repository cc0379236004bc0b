//! Values of options: points, lists of numbers, raster sizes.

use crate::error::{bad_input, CliError};
use sv_math::DVec3;

/// Three comma-separated numbers, for the option named `what`.
pub fn parse_vec3(text: &str, what: &str) -> Result<DVec3, CliError> {
    let numbers = parse_numbers(text)
        .ok_or_else(|| bad_input(format!("{what}: expected X,Y,Z, found `{text}`")))?;
    if numbers.len() != 3 || numbers.iter().any(|x| !x.is_finite()) {
        return Err(bad_input(format!(
            "{what}: expected three numbers X,Y,Z, found `{text}`"
        )));
    }
    Ok(DVec3::new(numbers[0], numbers[1], numbers[2]))
}

/// Comma-separated numbers (`None` if any is not a number).
pub fn parse_numbers(text: &str) -> Option<Vec<f64>> {
    text.split(',')
        .map(|x| x.trim().parse::<f64>().ok())
        .collect()
}

/// A raster size `WxH` given to `--size`, each side from 1 to `max`.
pub fn parse_size(text: &str, max: u32) -> Result<(u32, u32), CliError> {
    let bad = || {
        bad_input(format!(
            "--size: expected WxH such as 960x720, found `{text}`"
        ))
    };
    let (width, height) = text.split_once(['x', 'X']).ok_or_else(bad)?;
    let (width, height): (u32, u32) = (
        width.trim().parse().map_err(|_| bad())?,
        height.trim().parse().map_err(|_| bad())?,
    );
    if width == 0 || height == 0 || width > max || height > max {
        return Err(bad_input(format!(
            "--size: {width}x{height} is out of range (1 to {max} each way)"
        )));
    }
    Ok((width, height))
}

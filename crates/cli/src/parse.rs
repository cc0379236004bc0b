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

/// Comma-separated finite numbers (`None` if any is not a number, or is
/// infinite or NaN).
pub fn parse_numbers(text: &str) -> Option<Vec<f64>> {
    text.split(',')
        .map(|x| x.trim().parse::<f64>().ok().filter(|x| x.is_finite()))
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

/// Whether a raster of `width`×`height` pixels, at `bytes_per_pixel` bytes
/// of working memory each, fits in the memory the machine has free: the
/// one rule of `render`, `slice`, `film` and `bench`, checked before
/// anything is allocated.
pub fn check_memory(
    width: u32,
    height: u32,
    bytes_per_pixel: u64,
    what: &str,
) -> Result<(), CliError> {
    let needed = u64::from(width) * u64::from(height) * bytes_per_pixel;
    let available = available_memory();
    if needed > available {
        return Err(bad_input(format!(
            "{what} of {width}x{height} pixels needs about {} of memory, more than the {} free; \
             choose a smaller --size",
            bytes_text(needed),
            bytes_text(available)
        )));
    }
    Ok(())
}

/// The memory free for new work: `MemAvailable` of /proc/meminfo where
/// there is one, else 4 GiB (a cautious guess).
fn available_memory() -> u64 {
    let from_proc = std::fs::read_to_string("/proc/meminfo")
        .ok()
        .and_then(|text| {
            let line = text.lines().find(|l| l.starts_with("MemAvailable:"))?;
            let kib: u64 = line.split_whitespace().nth(1)?.parse().ok()?;
            Some(kib * 1024)
        });
    from_proc.unwrap_or(4 << 30)
}

/// A count of bytes for people: `48.0 GB`.
fn bytes_text(bytes: u64) -> String {
    let bytes = bytes as f64;
    if bytes >= 1e9 {
        format!("{:.1} GB", bytes / 1e9)
    } else {
        format!("{:.0} MB", (bytes / 1e6).ceil())
    }
}

/// `value_parser` of a number that must be finite (an angle, a seed of
/// a view).
pub fn finite(text: &str) -> Result<f64, String> {
    let value: f64 = text
        .trim()
        .parse()
        .map_err(|_| format!("expected a number, found `{text}`"))?;
    if value.is_finite() {
        Ok(value)
    } else {
        Err(format!("expected a finite number, found `{text}`"))
    }
}

/// `value_parser` of a finite number greater than zero.
pub fn positive(text: &str) -> Result<f64, String> {
    match finite(text)? {
        value if value > 0.0 => Ok(value),
        value => Err(format!("must be greater than zero, found {value}")),
    }
}

/// `value_parser` of a finite number of zero or more.
pub fn non_negative(text: &str) -> Result<f64, String> {
    match finite(text)? {
        value if value >= 0.0 => Ok(value),
        value => Err(format!("must be zero or more, found {value}")),
    }
}

/// `value_parser` of a count of worker threads: 1 to 4096.
pub fn threads(text: &str) -> Result<usize, String> {
    match text.trim().parse::<usize>() {
        Ok(count @ 1..=4096) => Ok(count),
        _ => Err(format!("expected a count from 1 to 4096, found `{text}`")),
    }
}

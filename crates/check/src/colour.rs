//! Stable region colours for section views.

use crate::rng::fnv;

/// Colour of overlapping space in pictures (magenta), display values 0…1.
pub const OVERLAP_COLOUR: [f32; 3] = [1.0, 0.0, 1.0];

/// Colour of void space in section views (yellow, drawn in stripes with
/// black), display values 0…1.
pub const VOID_COLOUR: [f32; 3] = [1.0, 0.9, 0.0];

/// The colour of a region in section views, from a hash of its name: the
/// same name gets the same colour in every run and every deck. Hues near
/// magenta are skipped (that colour marks overlaps); saturation and value
/// vary too, so neighbours rarely look alike. Display values 0…1.
pub fn region_colour(name: &str) -> [f32; 3] {
    let h = fnv(name);
    // Hues 260..345 (violet to magenta) are skipped.
    let mut hue = (h % 275) as f32;
    if hue >= 260.0 {
        hue += 85.0;
    }
    let sat = 0.35 + 0.4 * ((h >> 16) % 1000) as f32 / 1000.0;
    let val = 0.7 + 0.28 * ((h >> 32) % 1000) as f32 / 1000.0;
    hsv(hue % 360.0, sat, val)
}

fn hsv(h: f32, s: f32, v: f32) -> [f32; 3] {
    let c = v * s;
    let hp = h / 60.0;
    let x = c * (1.0 - (hp % 2.0 - 1.0).abs());
    let (r, g, b) = match hp as u32 {
        0 => (c, x, 0.0),
        1 => (x, c, 0.0),
        2 => (0.0, c, x),
        3 => (0.0, x, c),
        4 => (x, 0.0, c),
        _ => (c, 0.0, x),
    };
    let m = v - c;
    [r + m, g + m, b + m]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn colours_are_stable_distinct_and_not_magenta() {
        assert_eq!(region_colour("FUSELAGE"), region_colour("FUSELAGE"));
        assert_ne!(region_colour("A"), region_colour("B"));
        for i in 0..500 {
            let c = region_colour(&format!("r{i}"));
            assert!(c.iter().all(|v| (0.0..=1.0).contains(v)));
            // Never close to the overlap colour.
            let d: f32 = c
                .iter()
                .zip(OVERLAP_COLOUR)
                .map(|(a, b)| (a - b).abs())
                .sum();
            assert!(d > 0.4, "{c:?}");
        }
    }
}

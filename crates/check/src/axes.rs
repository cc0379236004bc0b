//! Axes round a section view: ticks along the bottom and the left in the
//! model's units, each labelled, and a scale bar, so that distances can be
//! read off the picture.

use crate::legend::Canvas;
use crate::slice::Slice;
use sv_math::DVec3;

/// Ink of the axes.
const INK: [f32; 3] = [0.0; 3];

/// The section view framed by axes: `(width, height, pixels)`, the
/// picture moved right and up by the margins that hold the tick labels,
/// with a scale bar of one tick step in `unit` under it. The slice's
/// [`Slice::rgb`] and size are unchanged; a legend strip can be added
/// under the result (`with_legend_entries`).
pub fn with_axes(section: &Slice, unit: &str) -> (u32, u32, Vec<[f32; 3]>) {
    let (width, height) = (section.width as usize, section.height as usize);
    let scale = if width >= 560 { 2 } else { 1 };
    let (per_pixel_u, per_pixel_v) = (
        section.extent.0 / width as f64,
        section.extent.1 / height as f64,
    );
    let (axis_u, start_u) = axis(section.plane.u, section.centre, -0.5 * section.extent.0);
    let (axis_v, start_v) = axis(section.plane.v, section.centre, -0.5 * section.extent.1);
    let step_u = nice_step(section.extent.0 / 6.0);
    let step_v = nice_step(section.extent.1 / 6.0);
    let ticks_v: Vec<(f64, String)> = ticks(start_v, section.extent.1, step_v);
    let label_chars = ticks_v.iter().map(|(_, l)| l.len()).max().unwrap_or(1);
    let char_width = 6 * scale;
    let tick = 4 * scale;
    let left = (label_chars + 2) * char_width + tick;
    let bottom = 3 * 11 * scale + tick;
    let top = 4 * scale;
    let right = 8 * scale + char_width * 3;
    let (full_w, full_h) = (left + width + right, top + height + bottom);
    let mut canvas = Canvas {
        w: full_w,
        h: full_h,
        px: vec![[1.0; 3]; full_w * full_h],
    };
    for row in 0..height {
        let from = row * width;
        let to = (top + row) * full_w + left;
        canvas.px[to..to + width].copy_from_slice(&section.rgb[from..from + width]);
    }
    frame(&mut canvas, left, top, width, height);
    let below = top + height;
    for (value, label) in ticks(start_u, section.extent.0, step_u) {
        let x = left + ((value - start_u) / per_pixel_u) as usize;
        for dy in 0..tick {
            canvas.set(x, below + dy, INK);
        }
        let half = label.len() * char_width / 2;
        canvas.text(
            x.saturating_sub(half),
            below + tick + 2 * scale,
            &label,
            scale,
        );
    }
    for (value, label) in &ticks_v {
        let y = top + height - ((value - start_v) / per_pixel_v) as usize;
        for dx in 0..tick {
            canvas.set(left - 1 - dx, y, INK);
        }
        let x = left - tick - (label.len() + 1) * char_width;
        canvas.text(x, y.saturating_sub(3 * scale), label, scale);
    }
    canvas.text(left + width + 4 * scale, below - 7 * scale, axis_u, scale);
    canvas.text(
        left.saturating_sub(tick + 2 * char_width),
        top,
        axis_v,
        scale,
    );
    // The scale bar: one tick step, under the tick labels.
    let bar = (step_u / per_pixel_u).round() as usize;
    let bar_y = below + tick + 14 * scale;
    for dx in 0..bar.min(width) {
        for dy in 0..2 * scale {
            canvas.set(left + dx, bar_y + dy, INK);
        }
    }
    for dy in 0..6 * scale {
        canvas.set(left, bar_y + dy - 2 * scale, INK);
        canvas.set(left + bar.min(width), bar_y + dy - 2 * scale, INK);
    }
    let bar_label = format!("{} {unit}", number(step_u));
    canvas.text(
        left + bar.min(width) + 4 * scale,
        bar_y - 2 * scale,
        &bar_label,
        scale,
    );
    (full_w as u32, full_h as u32, canvas.px)
}

/// The name of the world axis `direction` runs along (`x`, `-y`), or `u`
/// or `v` for a slanted one, and the coordinate along it at `offset`
/// from the centre.
fn axis(direction: DVec3, centre: DVec3, offset: f64) -> (&'static str, f64) {
    let names = [("x", "-x"), ("y", "-y"), ("z", "-z")];
    for (index, (plus, minus)) in names.iter().enumerate() {
        if (direction[index].abs() - 1.0).abs() < 1e-12 {
            let sign = direction[index].signum();
            let name = if sign > 0.0 { *plus } else { *minus };
            return (name, sign * centre[index] + offset);
        }
    }
    ("u", centre.dot(direction) + offset)
}

/// A step of 1, 2 or 5 times a power of ten near `rough`.
fn nice_step(rough: f64) -> f64 {
    let power = 10f64.powf(rough.abs().max(1e-300).log10().floor());
    let fraction = rough / power;
    let nice = if fraction < 1.5 {
        1.0
    } else if fraction < 3.5 {
        2.0
    } else if fraction < 7.5 {
        5.0
    } else {
        10.0
    };
    nice * power
}

/// The multiples of `step` from `start` over `length`, with their labels.
fn ticks(start: f64, length: f64, step: f64) -> Vec<(f64, String)> {
    let first = (start / step).ceil() as i64;
    let last = ((start + length) / step).floor() as i64;
    (first..=last)
        .take(64)
        .map(|k| {
            let value = k as f64 * step;
            (value, number(value))
        })
        .collect()
}

/// A tick value without float noise: `0.2`, not `0.20000000000000001`.
fn number(value: f64) -> String {
    let text = format!("{:.6}", value);
    let text = text.trim_end_matches('0').trim_end_matches('.');
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

/// A one-pixel frame round the picture at (`left`, `top`).
fn frame(canvas: &mut Canvas, left: usize, top: usize, width: usize, height: usize) {
    for x in left - 1..=left + width {
        canvas.set(x, top.saturating_sub(1), INK);
        canvas.set(x, top + height, INK);
    }
    for y in top.saturating_sub(1)..=top + height {
        canvas.set(left - 1, y, INK);
        canvas.set(left + width, y, INK);
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn steps_are_one_two_or_five_times_a_power_of_ten() {
        assert_eq!(nice_step(1.2), 1.0);
        assert_eq!(nice_step(0.3), 0.2);
        assert_eq!(nice_step(45.0), 50.0);
        assert_eq!(nice_step(800.0), 1000.0);
        assert_eq!(number(0.30000000000000004), "0.3");
        assert_eq!(number(-0.0), "0");
        let labels: Vec<String> = ticks(-1.05, 2.1, 0.5).into_iter().map(|t| t.1).collect();
        assert_eq!(labels, ["-1", "-0.5", "0", "0.5", "1"]);
    }

    #[test]
    fn axes_are_named_after_the_world_axis_they_run_along() {
        let centre = DVec3::new(1.0, 2.0, 3.0);
        assert_eq!(axis(DVec3::Y, centre, -1.0), ("y", 1.0));
        assert_eq!(axis(-DVec3::X, centre, 0.0), ("-x", -1.0));
        assert_eq!(axis(DVec3::new(0.6, 0.8, 0.0), centre, 0.0).0, "u");
    }
}

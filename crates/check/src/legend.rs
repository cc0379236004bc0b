//! The legend strip drawn under a section view: a swatch and the name of
//! every region in the picture, then the overlaps and the void, in a small
//! built-in 5×7 pixel font (capitals, digits and a little punctuation;
//! small letters are drawn as capitals).

use crate::colour::{region_colour, OVERLAP_COLOUR, VOID_COLOUR};
use crate::slice::Slice;

/// Glyph rows, 5 pixels wide, `#` set.
// Over the 120-line limit on purpose: this is the font, a table of one
// seven-row picture per character, and reads best as one match.
fn glyph(c: char) -> [&'static str; 7] {
    match c.to_ascii_uppercase() {
        ' ' => ["     "; 7],
        'A' => [
            " ### ", "#   #", "#   #", "#####", "#   #", "#   #", "#   #",
        ],
        'B' => [
            "#### ", "#   #", "#   #", "#### ", "#   #", "#   #", "#### ",
        ],
        'C' => [
            " ### ", "#   #", "#    ", "#    ", "#    ", "#   #", " ### ",
        ],
        'D' => [
            "#### ", "#   #", "#   #", "#   #", "#   #", "#   #", "#### ",
        ],
        'E' => [
            "#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#####",
        ],
        'F' => [
            "#####", "#    ", "#    ", "#### ", "#    ", "#    ", "#    ",
        ],
        'G' => [
            " ### ", "#   #", "#    ", "# ###", "#   #", "#   #", " ####",
        ],
        'H' => [
            "#   #", "#   #", "#   #", "#####", "#   #", "#   #", "#   #",
        ],
        'I' => [
            " ### ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        'J' => [
            "  ###", "   # ", "   # ", "   # ", "   # ", "#  # ", " ##  ",
        ],
        'K' => [
            "#   #", "#  # ", "# #  ", "##   ", "# #  ", "#  # ", "#   #",
        ],
        'L' => [
            "#    ", "#    ", "#    ", "#    ", "#    ", "#    ", "#####",
        ],
        'M' => [
            "#   #", "## ##", "# # #", "# # #", "#   #", "#   #", "#   #",
        ],
        'N' => [
            "#   #", "#   #", "##  #", "# # #", "#  ##", "#   #", "#   #",
        ],
        'O' => [
            " ### ", "#   #", "#   #", "#   #", "#   #", "#   #", " ### ",
        ],
        'P' => [
            "#### ", "#   #", "#   #", "#### ", "#    ", "#    ", "#    ",
        ],
        'Q' => [
            " ### ", "#   #", "#   #", "#   #", "# # #", "#  # ", " ## #",
        ],
        'R' => [
            "#### ", "#   #", "#   #", "#### ", "# #  ", "#  # ", "#   #",
        ],
        'S' => [
            " ####", "#    ", "#    ", " ### ", "    #", "    #", "#### ",
        ],
        'T' => [
            "#####", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "  #  ",
        ],
        'U' => [
            "#   #", "#   #", "#   #", "#   #", "#   #", "#   #", " ### ",
        ],
        'V' => [
            "#   #", "#   #", "#   #", "#   #", "#   #", " # # ", "  #  ",
        ],
        'W' => [
            "#   #", "#   #", "#   #", "# # #", "# # #", "# # #", " # # ",
        ],
        'X' => [
            "#   #", "#   #", " # # ", "  #  ", " # # ", "#   #", "#   #",
        ],
        'Y' => [
            "#   #", "#   #", " # # ", "  #  ", "  #  ", "  #  ", "  #  ",
        ],
        'Z' => [
            "#####", "    #", "   # ", "  #  ", " #   ", "#    ", "#####",
        ],
        '0' => [
            " ### ", "#   #", "#  ##", "# # #", "##  #", "#   #", " ### ",
        ],
        '1' => [
            "  #  ", " ##  ", "  #  ", "  #  ", "  #  ", "  #  ", " ### ",
        ],
        '2' => [
            " ### ", "#   #", "    #", "   # ", "  #  ", " #   ", "#####",
        ],
        '3' => [
            "#####", "   # ", "  #  ", "   # ", "    #", "#   #", " ### ",
        ],
        '4' => [
            "   # ", "  ## ", " # # ", "#  # ", "#####", "   # ", "   # ",
        ],
        '5' => [
            "#####", "#    ", "#### ", "    #", "    #", "#   #", " ### ",
        ],
        '6' => [
            "  ## ", " #   ", "#    ", "#### ", "#   #", "#   #", " ### ",
        ],
        '7' => [
            "#####", "    #", "   # ", "  #  ", " #   ", " #   ", " #   ",
        ],
        '8' => [
            " ### ", "#   #", "#   #", " ### ", "#   #", "#   #", " ### ",
        ],
        '9' => [
            " ### ", "#   #", "#   #", " ####", "    #", "   # ", " ##  ",
        ],
        '-' => [
            "     ", "     ", "     ", "#####", "     ", "     ", "     ",
        ],
        '_' => [
            "     ", "     ", "     ", "     ", "     ", "     ", "#####",
        ],
        '.' => [
            "     ", "     ", "     ", "     ", "     ", " ##  ", " ##  ",
        ],
        ',' => [
            "     ", "     ", "     ", "     ", " ##  ", "  #  ", " #   ",
        ],
        '(' => [
            "   # ", "  #  ", " #   ", " #   ", " #   ", "  #  ", "   # ",
        ],
        ')' => [
            " #   ", "  #  ", "   # ", "   # ", "   # ", "  #  ", " #   ",
        ],
        '[' => [
            " ### ", " #   ", " #   ", " #   ", " #   ", " #   ", " ### ",
        ],
        ']' => [
            " ### ", "   # ", "   # ", "   # ", "   # ", "   # ", " ### ",
        ],
        '×' => [
            "     ", "#   #", " # # ", "  #  ", " # # ", "#   #", "     ",
        ],
        '/' => [
            "     ", "    #", "   # ", "  #  ", " #   ", "#    ", "     ",
        ],
        ':' => [
            "     ", " ##  ", " ##  ", "     ", " ##  ", " ##  ", "     ",
        ],
        '+' => [
            "     ", "  #  ", "  #  ", "#####", "  #  ", "  #  ", "     ",
        ],
        '=' => [
            "     ", "     ", "#####", "     ", "#####", "     ", "     ",
        ],
        '#' => [
            " # # ", " # # ", "#####", " # # ", "#####", " # # ", " # # ",
        ],
        '\'' => [
            "  #  ", "  #  ", "     ", "     ", "     ", "     ", "     ",
        ],
        '*' => [
            "     ", "# # #", " ### ", "#####", " ### ", "# # #", "     ",
        ],
        '&' => [
            " ##  ", "#  # ", "# #  ", " #   ", "# # #", "#  # ", " ## #",
        ],
        '$' => [
            "  #  ", " ####", "# #  ", " ### ", "  # #", "#### ", "  #  ",
        ],
        '!' => [
            "  #  ", "  #  ", "  #  ", "  #  ", "  #  ", "     ", "  #  ",
        ],
        _ => [
            "#####", "#   #", "#   #", "#   #", "#   #", "#   #", "#####",
        ],
    }
}

/// How an entry of a legend is shown.
#[derive(Clone, Copy, Debug)]
pub enum Swatch {
    /// A square of the colour.
    Solid([f32; 3]),
    /// Stripes of the colour and black (overlaps, voids).
    Stripes([f32; 3]),
}

/// A picture to draw swatches and text on.
pub(crate) struct Canvas {
    pub(crate) w: usize,
    pub(crate) h: usize,
    pub(crate) px: Vec<[f32; 3]>,
}

impl Canvas {
    pub(crate) fn set(&mut self, x: usize, y: usize, c: [f32; 3]) {
        if x < self.w && y < self.h {
            self.px[y * self.w + x] = c;
        }
    }

    /// `s` in black from (`x0`, `y0`), 6 pixels a character at `scale` 1.
    pub(crate) fn text(&mut self, x0: usize, y0: usize, s: &str, scale: usize) {
        for (k, ch) in s.chars().enumerate() {
            for (row, bits) in glyph(ch).iter().enumerate() {
                for (col, b) in bits.bytes().enumerate() {
                    if b == b'#' {
                        for dy in 0..scale {
                            for dx in 0..scale {
                                self.set(
                                    x0 + (k * 6 + col) * scale + dx,
                                    y0 + row * scale + dy,
                                    [0.0; 3],
                                );
                            }
                        }
                    }
                }
            }
        }
    }
}

/// The section view with its legend strip underneath: `(width, height,
/// pixels)`, display colours row-major from the top left. The strip lists
/// every region in the picture (largest first; name and description),
/// then the overlapping pairs
/// and the void, each with its swatch; at most 80 entries, then a count of
/// the rest (the full list is in the legend file).
pub fn with_legend(section: &Slice) -> (u32, u32, Vec<[f32; 3]>) {
    let entries = legend_entries(section);
    with_legend_entries(section.width, section.height, &section.rgb, entries)
}

/// The entries of a section view's legend: its regions (largest first;
/// name and description), its overlapping pairs and its void.
pub fn legend_entries(section: &Slice) -> Vec<(Swatch, String)> {
    let mut entries: Vec<(Swatch, String)> = section
        .legend
        .iter()
        .map(|entry| {
            let text = if entry.description.is_empty() || entry.description == entry.label {
                entry.label.clone()
            } else {
                format!("{} {}", entry.label, entry.description)
            };
            (Swatch::Solid(region_colour(&entry.label)), text)
        })
        .collect();
    entries.extend(
        section
            .overlaps
            .iter()
            .map(|entry| (Swatch::Stripes(OVERLAP_COLOUR), entry.label.clone())),
    );
    if section.void.is_some() {
        entries.push((Swatch::Stripes(VOID_COLOUR), "void".into()));
    }
    entries
}

/// A picture (`width`×`height` display colours, row-major from the top
/// left) with a legend strip of `entries` underneath, as a section view's:
/// at most 80 entries, then a count of the rest.
pub fn with_legend_entries(
    picture_width: u32,
    picture_height: u32,
    picture: &[[f32; 3]],
    mut entries: Vec<(Swatch, String)>,
) -> (u32, u32, Vec<[f32; 3]>) {
    let width = picture_width as usize;
    let scale = if width >= 560 { 2 } else { 1 };
    const MAX: usize = 80;
    if entries.len() > MAX {
        let rest = entries.len() - (MAX - 1);
        entries.truncate(MAX - 1);
        entries.push((Swatch::Solid([1.0; 3]), format!("... {rest} more")));
    }
    let margin = 4 * scale;
    let swatch_size = 7 * scale;
    let line = 11 * scale;
    let char_width = 6 * scale;
    let max_chars =
        ((width.saturating_sub(2 * margin + swatch_size + 3 * scale)) / char_width).max(1);
    let label = |text: &str| -> String {
        if text.chars().count() <= max_chars {
            text.to_string()
        } else {
            let mut cut: String = text.chars().take(max_chars.saturating_sub(1)).collect();
            cut.push('*');
            cut
        }
    };
    let longest = entries
        .iter()
        .map(|(_, text)| label(text).chars().count())
        .max()
        .unwrap_or(0);
    let column_width = swatch_size + 3 * scale + longest * char_width + 8 * scale;
    let columns = ((width.saturating_sub(2 * margin)) / column_width.max(1)).max(1);
    let rows = entries.len().div_ceil(columns);
    let strip = if entries.is_empty() {
        0
    } else {
        2 * margin + rows * line
    };
    let height = picture_height as usize + strip;
    let mut canvas = Canvas {
        w: width,
        h: height,
        px: vec![[1.0; 3]; width * height],
    };
    canvas.px[..picture.len()].copy_from_slice(picture);
    if strip > 0 {
        for x in 0..width {
            canvas.set(x, picture_height as usize, [0.3; 3]);
        }
    }
    for (index, (swatch, text)) in entries.iter().enumerate() {
        let (column, row) = (index % columns, index / columns);
        let x0 = margin + column * column_width;
        let y0 = picture_height as usize + margin + row * line + scale;
        for dy in 0..swatch_size {
            for dx in 0..swatch_size {
                let edge = dx == 0 || dy == 0 || dx + 1 == swatch_size || dy + 1 == swatch_size;
                let colour = match *swatch {
                    _ if edge => [0.3; 3],
                    Swatch::Solid(colour) => colour,
                    Swatch::Stripes(colour) => {
                        if ((dx + dy) / (2 * scale)) % 2 == 0 {
                            colour
                        } else {
                            [0.1; 3]
                        }
                    }
                };
                canvas.set(x0 + dx, y0 + dy, colour);
            }
        }
        canvas.text(x0 + swatch_size + 3 * scale, y0, &label(text), scale);
    }
    (picture_width, height as u32, canvas.px)
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn glyphs_are_five_by_seven() {
        for ch in "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789 -_.,()[]×/:+=#'*&$!?".chars() {
            for row in glyph(ch) {
                assert_eq!(row.len(), 5, "{ch}");
            }
        }
        // Distinct glyphs for distinct letters and digits.
        let all: Vec<_> = "ABCDEFGHIJKLMNOPQRSTUVWXYZ0123456789"
            .chars()
            .map(glyph)
            .collect();
        for i in 0..all.len() {
            for j in i + 1..all.len() {
                assert_ne!(all[i], all[j]);
            }
        }
    }
}

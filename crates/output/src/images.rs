//! Still images.
//!
//! Pixel values arrive as linear intensities. By default they are written
//! linearly (value 1.0 → full scale), which is what the paper's display did
//! with its intensity levels; `Encoding::Srgb` applies the sRGB transfer
//! curve for viewing on ordinary screens. PFM always holds the linear
//! floats unchanged.

use std::io::Write;
use std::path::{Path, PathBuf};

/// File formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum ImageFormat {
    /// Portable Network Graphics.
    Png,
    /// Netpbm grey (P5) or colour (P6), 8 or 16 bit.
    Pnm,
    /// Portable float map (linear 32-bit floats).
    Pfm,
}

impl ImageFormat {
    /// From a file extension (`png`, `pgm`, `ppm`, `pnm`, `pfm`).
    pub fn from_path(p: &Path) -> Option<ImageFormat> {
        match p.extension()?.to_str()?.to_ascii_lowercase().as_str() {
            "png" => Some(ImageFormat::Png),
            "pgm" | "ppm" | "pnm" => Some(ImageFormat::Pnm),
            "pfm" => Some(ImageFormat::Pfm),
            _ => None,
        }
    }
}

/// Transfer curve for integer formats.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Default)]
pub enum Encoding {
    /// Values written as they are (the paper's intensities).
    #[default]
    Linear,
    /// sRGB-encoded.
    Srgb,
}

/// How to write.
#[derive(Clone, Debug)]
pub struct WriteOptions {
    /// 16 bits per channel instead of 8 (PNG, PNM).
    pub sixteen_bit: bool,
    /// Write one grey channel (the mean of R, G, B).
    pub grey: bool,
    /// Add an alpha channel (PNG only).
    pub alpha: bool,
    /// Quantise to this many levels first (64 reproduces the paper's CRT).
    pub levels: Option<u32>,
    /// Transfer curve.
    pub encoding: Encoding,
}

impl Default for WriteOptions {
    fn default() -> Self {
        WriteOptions {
            sixteen_bit: false,
            grey: false,
            alpha: false,
            levels: None,
            encoding: Encoding::Linear,
        }
    }
}

/// Pixels to write: linear RGB plus optional alpha, row-major.
#[derive(Clone, Copy, Debug)]
pub struct Pixels<'a> {
    /// Width.
    pub width: u32,
    /// Height.
    pub height: u32,
    /// RGB values.
    pub rgb: &'a [[f32; 3]],
    /// Alpha values (same length as `rgb`), if any.
    pub alpha: Option<&'a [f32]>,
}

/// Why an image could not be written.
#[derive(Debug, thiserror::Error)]
pub enum WriteError {
    /// File system trouble.
    #[error("cannot write {path}: {source}")]
    Io {
        /// Destination.
        path: PathBuf,
        /// Cause.
        source: std::io::Error,
    },
    /// Encoder trouble.
    #[error("cannot encode {path}: {message}")]
    Encode {
        /// Destination.
        path: PathBuf,
        /// Cause.
        message: String,
    },
    /// Unsupported request.
    #[error("{0}")]
    Unsupported(String),
}

/// Write `bytes` produced by `fill` to `path` atomically: a temporary file
/// in the same folder, flushed, then renamed over `path`. Readers see the
/// old file or the whole new one, never a part, and a failure leaves
/// nothing behind. The file gets ordinary permissions (0644 less the umask).
pub fn write_atomic(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> Result<(), WriteError> {
    write_atomic_io(path, fill).map_err(|source| WriteError::Io {
        path: path.to_owned(),
        source,
    })
}

/// [`write_atomic`] with a plain I/O error.
pub fn write_atomic_io(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<()> {
    put_in_place(write_beside(path, fill)?, path)
}

/// The first half of [`write_atomic`]: `fill` written to a temporary file
/// in `path`'s folder and flushed, neither synced nor renamed yet; the
/// temporary is deleted if dropped. [`put_in_place`] does the rest, on
/// another thread if waiting for the disk should not hold this one up.
pub fn write_beside(
    path: &Path,
    fill: impl FnOnce(&mut dyn Write) -> std::io::Result<()>,
) -> std::io::Result<tempfile::NamedTempFile> {
    let dir = match path.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let mut b = tempfile::Builder::new();
    // `film::remove_stale_temporaries` recognises the `.tmp-` prefix.
    b.prefix(".tmp-");
    #[cfg(unix)]
    {
        use std::os::unix::fs::PermissionsExt;
        b.permissions(std::fs::Permissions::from_mode(0o644));
    }
    let mut tmp = b.tempfile_in(dir)?;
    {
        let mut w = std::io::BufWriter::new(tmp.as_file_mut());
        fill(&mut w)?;
        w.flush()?;
    }
    Ok(tmp)
}

/// The second half of [`write_atomic`]: the temporary file from
/// [`write_beside`] synced to disk and renamed over `path`.
pub fn put_in_place(tmp: tempfile::NamedTempFile, path: &Path) -> std::io::Result<()> {
    tmp.as_file().sync_all()?;
    tmp.persist(path).map_err(|e| e.error)?;
    Ok(())
}

/// The sRGB transfer curve of a linear value in 0…1.
fn srgb(v: f32) -> f32 {
    if v <= 0.003_130_8 {
        12.92 * v
    } else {
        1.055 * v.powf(1.0 / 2.4) - 0.055
    }
}

/// Convert one linear value to a code of `max` (255 or 65535), quantised
/// to `levels` first when given.
fn code(v: f32, levels: Option<u32>, encoding: Encoding, max: f32) -> u16 {
    let mut v = v.clamp(0.0, 1.0);
    if let Some(levels) = levels {
        let top = levels.max(2) as f32 - 1.0;
        v = (v * top).round() / top;
    }
    if encoding == Encoding::Srgb {
        v = srgb(v);
    }
    // Round half up; the value is non-negative, so this equals round().
    (v * max + 0.5) as u16
}

/// Linear RGB values (row-major from the top left) as an 8-bit picture in
/// `encoding`, coded as [`write_image`] codes them: a film's frames are
/// the same as stills of the same view.
pub fn to_rgb8(width: u32, height: u32, rgb: &[[f32; 3]], encoding: Encoding) -> image::RgbImage {
    let mut picture = image::RgbImage::new(width, height);
    let values = rgb.as_flattened();
    match encoding {
        Encoding::Linear => linear_codes8(values, &mut picture),
        Encoding::Srgb => {
            for (code8, &v) in picture.iter_mut().zip(values) {
                *code8 = code(v, None, Encoding::Srgb, 255.0) as u8;
            }
        }
    }
    picture
}

/// [`linear_code8`] of every value, four at a time: every frame of a film
/// goes through here, and the compiler keeps the scalar cast's checks for
/// NaN and overflow one value at a time.
#[cfg(target_arch = "x86_64")]
fn linear_codes8(values: &[f32], codes: &mut [u8]) {
    // SAFETY: SSE2 is part of every x86_64 processor.
    unsafe { linear_codes8_sse2(values, codes) }
}

/// [`linear_codes8`] in SSE2's lanes.
#[cfg(target_arch = "x86_64")]
#[target_feature(enable = "sse2")]
fn linear_codes8_sse2(values: &[f32], codes: &mut [u8]) {
    use std::arch::x86_64::*;
    let mut value_quads = values.chunks_exact(4);
    let mut code_quads = codes.chunks_exact_mut(4);
    for (quad, codes) in (&mut value_quads).zip(&mut code_quads) {
        let quad = _mm_set_ps(quad[3], quad[2], quad[1], quad[0]);
        // `max` gives its second operand for a NaN, so NaN codes as 0, as
        // in `code`; the clamped value fits the truncating conversion.
        let clamped = _mm_min_ps(_mm_max_ps(quad, _mm_setzero_ps()), _mm_set1_ps(1.0));
        let scaled = _mm_add_ps(_mm_mul_ps(clamped, _mm_set1_ps(255.0)), _mm_set1_ps(0.5));
        let integers = _mm_cvttps_epi32(scaled);
        let words = _mm_packs_epi32(integers, integers);
        let bytes = _mm_packus_epi16(words, words);
        codes.copy_from_slice(&_mm_cvtsi128_si32(bytes).to_le_bytes());
    }
    let rest = value_quads.remainder().iter();
    for (code, &v) in code_quads.into_remainder().iter_mut().zip(rest) {
        *code = linear_code8(v);
    }
}

/// [`linear_code8`] of every value.
#[cfg(not(target_arch = "x86_64"))]
fn linear_codes8(values: &[f32], codes: &mut [u8]) {
    for (code, &v) in codes.iter_mut().zip(values) {
        *code = linear_code8(v);
    }
}

/// The 8-bit code of a linear value, as `code(v, None, Encoding::Linear,
/// 255.0)`.
fn linear_code8(v: f32) -> u8 {
    code(v, None, Encoding::Linear, 255.0) as u8
}

/// The channels to write for each pixel, as linear floats.
fn channels(px: &Pixels, o: &WriteOptions) -> (usize, Vec<f32>) {
    let nc = if o.grey { 1 } else { 3 } + usize::from(o.alpha);
    let mut out = Vec::with_capacity(px.rgb.len() * nc);
    for (i, c) in px.rgb.iter().enumerate() {
        if o.grey {
            out.push((c[0] + c[1] + c[2]) / 3.0);
        } else {
            out.extend_from_slice(c);
        }
        if o.alpha {
            out.push(px.alpha.map_or(1.0, |a| a[i]));
        }
    }
    (nc, out)
}

/// Write a picture in `format`.
pub fn write_image(
    path: &Path,
    format: ImageFormat,
    px: &Pixels,
    opts: &WriteOptions,
) -> Result<(), WriteError> {
    let (channel_count, values) = channels(px, opts);
    match format {
        ImageFormat::Png => {
            use image::ExtendedColorType as C;
            let colour_type = match (channel_count, opts.sixteen_bit) {
                (1, false) => C::L8,
                (2, false) => C::La8,
                (3, false) => C::Rgb8,
                (4, false) => C::Rgba8,
                (1, true) => C::L16,
                (2, true) => C::La16,
                (3, true) => C::Rgb16,
                _ => C::Rgba16,
            };
            let bytes: Vec<u8> = if opts.sixteen_bit {
                // The alpha channel is never quantised or encoded.
                values
                    .iter()
                    .enumerate()
                    .flat_map(|(index, v)| {
                        let is_alpha = opts.alpha && index % channel_count == channel_count - 1;
                        let code16 = if is_alpha {
                            (v.clamp(0.0, 1.0) * 65535.0).round() as u16
                        } else {
                            code(*v, opts.levels, opts.encoding, 65535.0)
                        };
                        code16.to_ne_bytes()
                    })
                    .collect()
            } else {
                values
                    .iter()
                    .enumerate()
                    .map(|(index, v)| {
                        let is_alpha = opts.alpha && index % channel_count == channel_count - 1;
                        if is_alpha {
                            (v.clamp(0.0, 1.0) * 255.0).round() as u8
                        } else {
                            code(*v, opts.levels, opts.encoding, 255.0) as u8
                        }
                    })
                    .collect()
            };
            write_atomic(path, |w| {
                let enc = image::codecs::png::PngEncoder::new(w);
                image::ImageEncoder::write_image(enc, &bytes, px.width, px.height, colour_type)
                    .map_err(std::io::Error::other)
            })
        }
        ImageFormat::Pnm => {
            if opts.alpha {
                return Err(WriteError::Unsupported(
                    "PGM/PPM cannot hold an alpha channel; use PNG".into(),
                ));
            }
            let max = if opts.sixteen_bit { 65535.0 } else { 255.0 };
            write_atomic(path, |w| {
                write!(
                    w,
                    "{}\n{} {}\n{}\n",
                    if channel_count == 1 { "P5" } else { "P6" },
                    px.width,
                    px.height,
                    max as u32
                )?;
                let mut buf = Vec::with_capacity(values.len() * 2);
                for v in &values {
                    let value = code(*v, opts.levels, opts.encoding, max);
                    if opts.sixteen_bit {
                        buf.extend_from_slice(&value.to_be_bytes());
                    } else {
                        buf.push(value as u8);
                    }
                }
                w.write_all(&buf)
            })
        }
        ImageFormat::Pfm => {
            if opts.alpha {
                return Err(WriteError::Unsupported(
                    "PFM cannot hold an alpha channel; use PNG".into(),
                ));
            }
            write_pfm(path, px.width, px.height, channel_count, &values)
        }
    }
}

/// Write floats as PFM (`PF` colour or `Pf` grey, little-endian, rows
/// bottom to top as the format requires).
pub fn write_pfm(
    path: &Path,
    width: u32,
    height: u32,
    channels: usize,
    vals: &[f32],
) -> Result<(), WriteError> {
    write_atomic(path, |w| {
        write!(
            w,
            "{}\n{} {}\n-1.0\n",
            if channels == 1 { "Pf" } else { "PF" },
            width,
            height
        )?;
        let row = width as usize * channels;
        let mut buf = Vec::with_capacity(vals.len() * 4);
        for y in (0..height as usize).rev() {
            for v in &vals[y * row..(y + 1) * row] {
                buf.extend_from_slice(&v.to_le_bytes());
            }
        }
        w.write_all(&buf)
    })
}

/// Write a region-id image as 16-bit grey PNG (0 = background, region
/// index + 1 otherwise): exact values, viewable in any image tool.
pub fn write_region_png(
    path: &Path,
    width: u32,
    height: u32,
    ids: &[u32],
) -> Result<(), WriteError> {
    if let Some(m) = ids.iter().max().filter(|m| **m > 65535) {
        return Err(WriteError::Unsupported(format!(
            "region id {m} does not fit a 16-bit PNG; use a .pfm region image"
        )));
    }
    let bytes: Vec<u8> = ids.iter().flat_map(|v| (*v as u16).to_ne_bytes()).collect();
    write_atomic(path, |w| {
        let enc = image::codecs::png::PngEncoder::new(w);
        image::ImageEncoder::write_image(enc, &bytes, width, height, image::ExtendedColorType::L16)
            .map_err(std::io::Error::other)
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn png_round_trips_16_bit_grey_and_quantises_to_64_levels() {
        let dir = tempfile::tempdir().unwrap();
        let p = dir.path().join("a.png");
        let rgb = [[0.5f32; 3], [1.0; 3], [0.0; 3], [0.26; 3]];
        let px = Pixels {
            width: 2,
            height: 2,
            rgb: &rgb,
            alpha: None,
        };
        write_image(
            &p,
            ImageFormat::Png,
            &px,
            &WriteOptions {
                sixteen_bit: true,
                grey: true,
                ..Default::default()
            },
        )
        .unwrap();
        let img = image::open(&p).unwrap().into_luma16();
        assert_eq!(img.get_pixel(0, 0).0[0], 32768);
        assert_eq!(img.get_pixel(1, 0).0[0], 65535);
        write_image(
            &p,
            ImageFormat::Png,
            &px,
            &WriteOptions {
                grey: true,
                levels: Some(64),
                ..Default::default()
            },
        )
        .unwrap();
        let img = image::open(&p).unwrap().into_luma8();
        // 0.26 * 63 = 16.38 → level 16 → 16/63 * 255 = 64.76 → 65.
        assert_eq!(img.get_pixel(1, 1).0[0], 65);
        // No temporary file is left behind.
        assert_eq!(std::fs::read_dir(dir.path()).unwrap().count(), 1);
    }

    #[test]
    fn linear_codes_of_frames_are_the_codes_of_stills() {
        let mut values = vec![
            f32::NAN,
            -f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            -0.0,
            0.0,
        ];
        // Either side of every rounding boundary.
        for k in 0..=256 {
            let boundary = (k as f32 + 0.5) / 255.0;
            values.extend([boundary.next_down(), boundary, boundary.next_up()]);
        }
        // Bit patterns spread over every float.
        values.extend((0..u32::MAX).step_by(997).map(f32::from_bits));
        // Any length, not only whole groups of four.
        values.truncate(values.len() / 3 * 3 - 1);
        let mut codes = vec![0u8; values.len()];
        linear_codes8(&values, &mut codes);
        for (&v, &got) in values.iter().zip(&codes) {
            assert_eq!(
                got,
                code(v, None, Encoding::Linear, 255.0) as u8,
                "{v:e} ({:#x})",
                v.to_bits()
            );
        }
    }

    #[test]
    fn film_frames_are_coded_as_stills() {
        let rgb = [[0.0f32, 0.5, 1.0], [0.002, 0.2, 7.0]];
        let linear = to_rgb8(2, 1, &rgb, Encoding::Linear);
        assert_eq!(linear.get_pixel(0, 0).0, [0, 128, 255]);
        assert_eq!(linear.get_pixel(1, 0).0, [1, 51, 255]);
        let encoded = to_rgb8(2, 1, &rgb, Encoding::Srgb);
        // sRGB: 0.5 → 0.7354 → 188; 0.002 on the straight part → 0.0258 → 7.
        assert_eq!(encoded.get_pixel(0, 0).0, [0, 188, 255]);
        assert_eq!(encoded.get_pixel(1, 0).0[0], 7);
        // The same codes as an 8-bit PPM written from the same values.
        let dir = tempfile::tempdir().unwrap();
        let path = dir.path().join("a.ppm");
        let px = Pixels {
            width: 2,
            height: 1,
            rgb: &rgb,
            alpha: None,
        };
        let opts = WriteOptions {
            encoding: Encoding::Srgb,
            ..Default::default()
        };
        write_image(&path, ImageFormat::Pnm, &px, &opts).unwrap();
        let bytes = std::fs::read(&path).unwrap();
        assert_eq!(&bytes[bytes.len() - 6..], encoded.as_raw().as_slice());
    }

    #[test]
    fn pfm_and_pnm_headers() {
        let dir = tempfile::tempdir().unwrap();
        let rgb = [[0.25f32, 0.5, 2.0]];
        let px = Pixels {
            width: 1,
            height: 1,
            rgb: &rgb,
            alpha: None,
        };
        let p = dir.path().join("a.pfm");
        write_image(&p, ImageFormat::Pfm, &px, &WriteOptions::default()).unwrap();
        let b = std::fs::read(&p).unwrap();
        assert!(b.starts_with(b"PF\n1 1\n-1.0\n"));
        assert_eq!(
            f32::from_le_bytes(b[b.len() - 4..].try_into().unwrap()),
            2.0,
            "floats are kept unclamped"
        );
        let p = dir.path().join("a.pgm");
        write_image(
            &p,
            ImageFormat::Pnm,
            &px,
            &WriteOptions {
                grey: true,
                ..Default::default()
            },
        )
        .unwrap();
        // Grey is the mean of the channels: (0.25 + 0.5 + 2.0) / 3 → 234.
        assert_eq!(std::fs::read(&p).unwrap(), b"P5\n1 1\n255\n\xea".to_vec());
    }
}

//! The GIF, the MP4 and the contact sheet of a film, assembled in frame
//! order while later frames are still being rendered.
//!
//! The worker that made a frame (or read it back from its PNG) also turns
//! it into what the three outputs need of it ([`Assembly::prepare`]): the
//! frame scaled, mapped to the film's palette and LZW-compressed for the
//! GIF, its YUV 4:2:0 planes for ffmpeg, its contact-sheet thumbnail. One
//! thread ([`Assembly::run`]) takes the prepared frames in frame order and
//! writes them out, so the outputs do not depend on the order in which
//! frames were made, and the costly work stays spread over the workers.

use super::{io_err, write_atomically, write_png, FilmError, FilmOptions, Mp4Status};
use image::{imageops, RgbImage};
use std::collections::BTreeMap;
use std::io::{self, Read, Write};
use std::path::{Path, PathBuf};
use std::process::{Child, ChildStdin, Command, Stdio};
use std::sync::mpsc::Receiver;
use std::sync::OnceLock;

/// Frames sampled to learn a film's GIF palette.
const GIF_PALETTE_FRAMES: usize = 12;

/// What one run assembles, fixed before its first frame is made.
pub(super) struct Assembly {
    dir: PathBuf,
    total: usize,
    fps: f64,
    gif: Option<GifPlan>,
    /// The ffmpeg to feed, or why there is no MP4.
    mp4: Result<PathBuf, Mp4Status>,
    contact: ContactPlan,
    /// The GIF's palette, learnt by the assembling thread from the sample
    /// frames; workers map their frames to it once it is known.
    palette: OnceLock<Palette>,
}

struct GifPlan {
    max_width: u32,
    /// The frames the palette is learnt from, spread over the film.
    samples: Vec<usize>,
    /// Each frame's delay in hundredths of a second.
    delays: Vec<u16>,
}

struct ContactPlan {
    every: usize,
    columns: u32,
    thumb_width: u32,
}

/// A frame made ready for assembly by a worker.
pub(super) struct PreparedFrame {
    number: usize,
    size: (u32, u32),
    gif: Option<GifFrame>,
    yuv: Option<Vec<u8>>,
    thumbnail: Option<RgbImage>,
}

enum GifFrame {
    /// Scaled to the GIF's size, made before the palette was known.
    Scaled(RgbImage),
    /// Mapped to the palette and LZW-compressed.
    Compressed(gif::Frame<'static>),
}

/// What an assembly made.
pub(super) struct Assembled {
    pub gif: Option<PathBuf>,
    pub contact_sheet: PathBuf,
    pub mp4: Mp4Status,
}

impl Assembly {
    /// The assembly of a film of `total` (at least one) frames as `opts`
    /// asks, into `opts.out_dir`.
    pub fn new(total: usize, opts: &FilmOptions) -> Assembly {
        let gif = opts.gif.then(|| {
            let sampled = GIF_PALETTE_FRAMES.min(total);
            GifPlan {
                max_width: opts.gif_max_width,
                samples: (0..sampled)
                    .map(|sample| sample * total / sampled)
                    .collect(),
                delays: super::gif_delays(total, opts.fps),
            }
        });
        let mp4 = if !opts.mp4 {
            Err(Mp4Status::NotMade)
        } else {
            opts.ffmpeg
                .clone()
                .or_else(|| super::find_program("ffmpeg", std::env::var_os("PATH")))
                .ok_or(Mp4Status::FfmpegNotFound)
        };
        let every = if opts.contact_every == 0 {
            total.div_ceil(48).max(1)
        } else {
            opts.contact_every
        };
        Assembly {
            dir: opts.out_dir.clone(),
            total,
            fps: opts.fps,
            gif,
            mp4,
            contact: ContactPlan {
                every,
                columns: opts.contact_columns.max(1),
                thumb_width: opts.thumb_width.max(1),
            },
            palette: OnceLock::new(),
        }
    }

    /// Frame numbers in the order to make them: the GIF's palette samples
    /// first, so that its first frame can be written early, then the rest
    /// in order, so that few frames wait for the one before them.
    pub fn order(&self) -> Vec<usize> {
        let samples = self.gif.as_ref().map_or(&[][..], |g| &g.samples[..]);
        let rest = (0..self.total).filter(|f| !samples.contains(f));
        samples.iter().copied().chain(rest).collect()
    }

    /// What the outputs need of frame `number`, made on a worker thread.
    pub fn prepare(&self, number: usize, picture: &RgbImage) -> PreparedFrame {
        let gif = self.gif.as_ref().map(|plan| {
            let scaled = gif_scaled(picture, plan.max_width);
            match self.palette.get() {
                Some(palette) => {
                    GifFrame::Compressed(palette.compress(&scaled, plan.delays[number]))
                }
                None => GifFrame::Scaled(scaled),
            }
        });
        let yuv = self.mp4.is_ok().then(|| yuv420(picture));
        let thumbnail = number.is_multiple_of(self.contact.every).then(|| {
            let (width, height) = thumbnail_size(picture.dimensions(), self.contact.thumb_width);
            resampled(picture, width, height)
        });
        PreparedFrame {
            number,
            size: picture.dimensions(),
            gif,
            yuv,
            thumbnail,
        }
    }

    /// Take every frame of the film from `frames`, in whatever order they
    /// come, and write the GIF, the MP4 and the contact sheet. Fails,
    /// leaving none of the three, when `frames` closes before every frame
    /// came (a frame failed) or a file cannot be written; a failing ffmpeg
    /// is reported in [`Assembled::mp4`] instead.
    pub fn run(&self, frames: Receiver<PreparedFrame>) -> Result<Assembled, FilmError> {
        let gif_path = self.dir.join("film.gif");
        let (sheet, mp4) = if self.gif.is_some() {
            let mut made = None;
            let written = write_atomically(&gif_path, |file| {
                let result = self.write_in_order(&frames, Some(file));
                let status = match &result {
                    Ok(_) => Ok(()),
                    Err(e) => Err(io::Error::other(e.to_string())),
                };
                made = Some(result);
                status
            });
            if let Some(Err(e)) = made {
                return Err(e);
            }
            written.map_err(io_err(&gif_path))?;
            made.and_then(Result::ok).ok_or_else(|| {
                io_err(&gif_path)(io::Error::other("the GIF's frames were not written"))
            })?
        } else {
            self.write_in_order(&frames, None)?
        };
        let contact_sheet = self.dir.join("contact.png");
        write_png(&contact_sheet, &sheet)?;
        Ok(Assembled {
            gif: self.gif.as_ref().map(|_| gif_path),
            contact_sheet,
            mp4,
        })
    }
}

impl Assembly {
    /// Write the frames from `frames` in frame order: to the GIF encoder
    /// on `gif_file` (when there is a GIF), to ffmpeg, and onto the
    /// contact sheet, which is returned with the MP4's fate.
    fn write_in_order(
        &self,
        frames: &Receiver<PreparedFrame>,
        gif_file: Option<&mut dyn Write>,
    ) -> Result<(RgbImage, Mp4Status), FilmError> {
        let gif_path = self.dir.join("film.gif");
        let gif_err = |e: gif::EncodingError| FilmError::Image {
            path: gif_path.clone(),
            message: e.to_string(),
        };
        let mut gif_file = gif_file;
        let mut gif_encoder: Option<gif::Encoder<&mut dyn Write>> = None;
        let mut mp4: Option<Result<Mp4Encoder, Mp4Status>> = None;
        let mut sheet: Option<ContactSheet> = None;
        let mut film_size = None;
        // Frames that came before their turn.
        let mut waiting: BTreeMap<usize, PreparedFrame> = BTreeMap::new();
        for number in 0..self.total {
            while !waiting.contains_key(&number) || !self.palette_known() {
                let frame = frames.recv().map_err(|_| FilmError::Render {
                    frame: number,
                    message: "the film stopped before this frame was made".into(),
                })?;
                waiting.insert(frame.number, frame);
                self.learn_palette(&waiting);
            }
            let Some(frame) = waiting.remove(&number) else {
                continue;
            };
            let size = *film_size.get_or_insert(frame.size);
            if frame.size != size {
                return Err(FilmError::Image {
                    path: super::frame_path(&self.dir, number),
                    message: format!(
                        "frame {number} is {}x{}, frame 0 is {}x{}: a film's frames are all one size",
                        frame.size.0, frame.size.1, size.0, size.1
                    ),
                });
            }
            if let (Some(plan), Some(gif_frame), Some(palette)) =
                (&self.gif, frame.gif, self.palette.get())
            {
                let compressed = match gif_frame {
                    GifFrame::Compressed(compressed) => compressed,
                    GifFrame::Scaled(scaled) => palette.compress(&scaled, plan.delays[number]),
                };
                if gif_encoder.is_none() {
                    if let Some(file) = gif_file.take() {
                        let mut encoder = gif::Encoder::new(
                            file,
                            compressed.width,
                            compressed.height,
                            &palette.rgb,
                        )
                        .map_err(gif_err)?;
                        encoder.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
                        gif_encoder = Some(encoder);
                    }
                }
                if let Some(encoder) = &mut gif_encoder {
                    encoder
                        .write_lzw_pre_encoded_frame(&compressed)
                        .map_err(gif_err)?;
                }
            }
            if let Some(yuv) = &frame.yuv {
                let encoder = mp4.get_or_insert_with(|| match &self.mp4 {
                    Ok(ffmpeg) => Mp4Encoder::start(ffmpeg, &self.dir, size, self.fps),
                    Err(status) => Err(status.clone()),
                });
                if let Ok(encoder) = encoder {
                    encoder.feed(yuv);
                }
            }
            if let Some(thumbnail) = &frame.thumbnail {
                sheet
                    .get_or_insert_with(|| self.contact_sheet(thumbnail.dimensions()))
                    .place(number / self.contact.every, thumbnail);
            }
        }
        if let Some(encoder) = gif_encoder {
            // Writes the GIF's trailer.
            encoder.into_inner().map_err(gif_err)?;
        }
        let mp4 = match mp4 {
            Some(Ok(encoder)) => encoder.finish(),
            Some(Err(status)) => status,
            None => self.mp4.clone().err().unwrap_or(Mp4Status::NotMade),
        };
        let sheet = sheet.map_or_else(|| RgbImage::new(1, 1), |sheet| sheet.image);
        Ok((sheet, mp4))
    }

    /// True once the GIF's palette is known, or when there is no GIF.
    fn palette_known(&self) -> bool {
        self.gif.is_none() || self.palette.get().is_some()
    }

    /// Learn the GIF's palette once every sample frame is among `waiting`.
    fn learn_palette(&self, waiting: &BTreeMap<usize, PreparedFrame>) {
        let Some(plan) = &self.gif else {
            return;
        };
        if self.palette.get().is_some() {
            return;
        }
        // A sample is never compressed: the palette needs it first.
        let scaled_samples: Option<Vec<&RgbImage>> = plan
            .samples
            .iter()
            .map(|sample| match waiting.get(sample)?.gif.as_ref()? {
                GifFrame::Scaled(scaled) => Some(scaled),
                GifFrame::Compressed(_) => None,
            })
            .collect();
        let Some(scaled_samples) = scaled_samples else {
            return;
        };
        // With opaque alpha, as the quantiser takes pixels.
        let pixels: Vec<u8> = scaled_samples
            .iter()
            .flat_map(|scaled| scaled.pixels().flat_map(|p| [p[0], p[1], p[2], 255]))
            .collect();
        let _ = self.palette.set(Palette::learn(&pixels));
    }

    /// An empty contact sheet for this film's thumbnails of `thumb_size`.
    fn contact_sheet(&self, thumb_size: (u32, u32)) -> ContactSheet {
        let thumbnails = self.total.div_ceil(self.contact.every).max(1) as u32;
        let columns = self.contact.columns.min(thumbnails);
        let rows = thumbnails.div_ceil(columns);
        ContactSheet {
            image: RgbImage::new(columns * thumb_size.0, rows * thumb_size.1),
            columns,
        }
    }
}

/// Thumbnails of every Nth frame, left to right and top to bottom.
struct ContactSheet {
    image: RgbImage,
    columns: u32,
}

impl ContactSheet {
    /// Put the `index`th thumbnail in its place.
    fn place(&mut self, index: usize, thumbnail: &RgbImage) {
        let (column, row) = (index as u32 % self.columns, index as u32 / self.columns);
        let (x, y) = (column * thumbnail.width(), row * thumbnail.height());
        imageops::replace(&mut self.image, thumbnail, x as i64, y as i64);
    }
}

/// A thumbnail `width` wide of a frame of `size`, keeping its aspect ratio.
fn thumbnail_size(size: (u32, u32), width: u32) -> (u32, u32) {
    let height = (width as f64 * size.1 as f64 / size.0.max(1) as f64).round() as u32;
    (width, height.max(1))
}

/// A frame as it goes in the GIF: at most `max_width` wide (0: any width).
fn gif_scaled(picture: &RgbImage, max_width: u32) -> RgbImage {
    let (width, height) = picture.dimensions();
    let scale = if max_width > 0 && width > max_width {
        max_width as f64 / width as f64
    } else {
        1.0
    };
    let scaled_width = ((width as f64 * scale).round() as u32).clamp(1, u16::MAX as u32);
    let scaled_height = ((height as f64 * scale).round() as u32).clamp(1, u16::MAX as u32);
    if (scaled_width, scaled_height) != (width, height) {
        resampled(picture, scaled_width, scaled_height)
    } else {
        picture.clone()
    }
}

/// `picture` resampled to `width` × `height` with a triangle (bilinear)
/// filter as wide as the scale asks, in fixed point.
fn resampled(picture: &RgbImage, width: u32, height: u32) -> RgbImage {
    use fast_image_resize::{images, FilterType, PixelType, ResizeAlg, ResizeOptions, Resizer};
    let source = images::ImageRef::new(
        picture.width(),
        picture.height(),
        picture.as_raw(),
        PixelType::U8x3,
    );
    let mut target = images::Image::new(width, height, PixelType::U8x3);
    let options = ResizeOptions::new().resize_alg(ResizeAlg::Convolution(FilterType::Bilinear));
    let resized = match source {
        Ok(source) => Resizer::new()
            .resize(&source, &mut target, &options)
            .is_ok(),
        Err(_) => false,
    };
    match RgbImage::from_raw(width, height, target.into_vec()) {
        Some(image) if resized => image,
        // Only a picture whose buffer does not match its size gets here,
        // which an `RgbImage` cannot be.
        _ => imageops::resize(picture, width, height, imageops::FilterType::Triangle),
    }
}

/// A 256-colour palette (NeuQuant, Dekker 1994) with a lookup table from
/// colours at 6 bits per channel to palette entries.
struct Palette {
    rgb: Vec<u8>,
    lut: Vec<u8>,
}

impl Palette {
    /// Learn the palette of RGBA `pixels`.
    fn learn(pixels: &[u8]) -> Palette {
        let quantiser = color_quant::NeuQuant::new(10, 256, pixels);
        let lut = (0..1usize << 18)
            .map(|colour| {
                // The centre of the 6-bit cell.
                let channel = |shift: usize| (((colour >> shift) & 63) * 4 + 2) as u8;
                quantiser.index_of(&[channel(12), channel(6), channel(0), 255]) as u8
            })
            .collect();
        Palette {
            rgb: quantiser.color_map_rgb(),
            lut,
        }
    }

    /// The palette entry for an RGB pixel.
    fn index(&self, p: [u8; 3]) -> u8 {
        let c = (p[0] as usize >> 2) << 12 | (p[1] as usize >> 2) << 6 | p[2] as usize >> 2;
        self.lut[c]
    }

    /// A scaled frame as a GIF frame of this palette's entries, compressed,
    /// shown for `delay` hundredths of a second.
    fn compress(&self, scaled: &RgbImage, delay: u16) -> gif::Frame<'static> {
        let indices: Vec<u8> = scaled.pixels().map(|p| self.index(p.0)).collect();
        let mut frame = gif::Frame::from_indexed_pixels(
            scaled.width() as u16,
            scaled.height() as u16,
            indices,
            None,
        );
        frame.delay = delay;
        frame.make_lzw_pre_encoded();
        frame
    }
}

/// A frame as the planes of 8-bit YUV 4:2:0 (BT.709, studio range) that
/// ffmpeg reads raw, its width and height made even (as H.264's 4:2:0
/// needs) with black on the right and at the bottom.
fn yuv420(picture: &RgbImage) -> Vec<u8> {
    let (width, height) = (picture.width() as usize, picture.height() as usize);
    let (even_width, even_height) = (width.next_multiple_of(2), height.next_multiple_of(2));
    let luma_len = even_width * even_height;
    let chroma_len = luma_len / 4;
    let mut planes = vec![0u8; luma_len + 2 * chroma_len];
    let (luma, chroma_planes) = planes.split_at_mut(luma_len);
    let (blue_difference, red_difference) = chroma_planes.split_at_mut(chroma_len);
    // The padding is black.
    luma.fill(16);
    blue_difference.fill(128);
    red_difference.fill(128);
    let raw = picture.as_raw();
    for (row, luma_row) in raw
        .chunks_exact(3 * width)
        .zip(luma.chunks_exact_mut(even_width))
    {
        for (pixel, y) in row.chunks_exact(3).zip(luma_row.iter_mut()) {
            let [r, g, b] = [pixel[0], pixel[1], pixel[2]].map(i32::from);
            *y = (16 + ((47 * r + 157 * g + 16 * b + 128) >> 8)) as u8;
        }
    }
    // Each chroma sample is the mean of a 2×2 block of pixels; a block
    // that reaches into the padding counts its pixels there as black.
    let chroma_width = even_width / 2;
    let rows = raw.chunks(6 * width);
    let chroma_rows = blue_difference
        .chunks_exact_mut(chroma_width)
        .zip(red_difference.chunks_exact_mut(chroma_width));
    for (two_rows, (blue_row, red_row)) in rows.zip(chroma_rows) {
        let (top, bottom) = two_rows.split_at((3 * width).min(two_rows.len()));
        let pixel = |row: &[u8], x: usize| -> [i32; 3] {
            row.get(3 * x..3 * x + 3)
                .map_or([0; 3], |p| [p[0], p[1], p[2]].map(i32::from))
        };
        let mut chroma_row = blue_row.iter_mut().zip(red_row.iter_mut());
        // Whole blocks first, without a test for the edge in the loop.
        let whole_blocks = if bottom.is_empty() { 0 } else { width / 2 };
        let blocks = top.chunks_exact(6).zip(bottom.chunks_exact(6));
        for ((above, below), (blue, red)) in blocks.take(whole_blocks).zip(&mut chroma_row) {
            let sum = |c: usize| {
                i32::from(above[c])
                    + i32::from(above[c + 3])
                    + i32::from(below[c])
                    + i32::from(below[c + 3])
            };
            (*blue, *red) = chroma([sum(0), sum(1), sum(2)]);
        }
        for (x, (blue, red)) in chroma_row.enumerate().map(|(i, c)| (whole_blocks + i, c)) {
            let block = [
                pixel(top, 2 * x),
                pixel(top, 2 * x + 1),
                pixel(bottom, 2 * x),
                pixel(bottom, 2 * x + 1),
            ];
            (*blue, *red) = chroma([0, 1, 2].map(|c| block.iter().map(|p| p[c]).sum()));
        }
    }
    planes
}

/// The blue and red differences (BT.709, studio range) of the mean of four
/// pixels whose red, green and blue add up to `sum`.
fn chroma(sum: [i32; 3]) -> (u8, u8) {
    let [r, g, b] = sum.map(|s| (s + 2) >> 2);
    let blue = 128 + ((-26 * r - 87 * g + 113 * b + 128) >> 8);
    let red = 128 + ((112 * r - 102 * g - 10 * b + 128) >> 8);
    (blue.clamp(16, 240) as u8, red.clamp(16, 240) as u8)
}

/// ffmpeg encoding an MP4 from raw frames written to its standard input,
/// into a temporary file renamed into place when it succeeds.
struct Mp4Encoder {
    child: Child,
    /// Closed when ffmpeg stops reading (it failed or finished early).
    input: Option<ChildStdin>,
    messages: Option<std::thread::JoinHandle<String>>,
    temporary: PathBuf,
    finished: bool,
}

impl Mp4Encoder {
    /// Start `ffmpeg` on frames of `size` at `fps` frames per second.
    fn start(
        ffmpeg: &Path,
        dir: &Path,
        size: (u32, u32),
        fps: f64,
    ) -> Result<Mp4Encoder, Mp4Status> {
        let temporary = dir.join(".tmp-film.mp4");
        let even = |n: u32| n.next_multiple_of(2);
        let mut child = Command::new(ffmpeg)
            .args([
                "-y",
                "-loglevel",
                "error",
                "-f",
                "rawvideo",
                "-pix_fmt",
                "yuv420p",
            ])
            .arg("-video_size")
            .arg(format!("{}x{}", even(size.0), even(size.1)))
            .arg("-framerate")
            .arg(format!("{fps}"))
            .args(["-i", "pipe:0"])
            // The fastest preset: frames keep both cores busy while ffmpeg
            // encodes, and a film made to look at is worth a larger file
            // more than a wait.
            .args([
                "-c:v",
                "libx264",
                "-preset",
                "ultrafast",
                "-pix_fmt",
                "yuv420p",
            ])
            .args(["-colorspace", "bt709", "-color_primaries", "bt709"])
            .args(["-color_trc", "bt709", "-color_range", "tv"])
            .args(["-movflags", "+faststart"])
            .arg(&temporary)
            .stdin(Stdio::piped())
            .stdout(Stdio::null())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| Mp4Status::Failed(e.to_string()))?;
        let input = child.stdin.take();
        let messages = child.stderr.take().map(|mut stderr| {
            std::thread::spawn(move || {
                let mut text = String::new();
                let _ = stderr.read_to_string(&mut text);
                text
            })
        });
        Ok(Mp4Encoder {
            child,
            input,
            messages,
            temporary,
            finished: false,
        })
    }

    /// Hand ffmpeg a frame's planes; once it stops reading, the rest are
    /// dropped and [`Mp4Encoder::finish`] tells why.
    fn feed(&mut self, planes: &[u8]) {
        if let Some(input) = &mut self.input {
            if input.write_all(planes).is_err() {
                self.input = None;
            }
        }
    }

    /// Close ffmpeg's input, wait for it, and move the MP4 into place.
    fn finish(mut self) -> Mp4Status {
        self.input = None;
        self.finished = true;
        let status = self.child.wait();
        let messages = self
            .messages
            .take()
            .and_then(|reader| reader.join().ok())
            .unwrap_or_default();
        let out = self.temporary.with_file_name("film.mp4");
        match status {
            Ok(status) if status.success() && self.temporary.is_file() => {
                match std::fs::rename(&self.temporary, &out) {
                    Ok(()) => Mp4Status::Written(out),
                    Err(e) => Mp4Status::Failed(e.to_string()),
                }
            }
            Ok(status) => {
                let _ = std::fs::remove_file(&self.temporary);
                let last = messages.lines().last().map(str::trim).unwrap_or_default();
                Mp4Status::Failed(if last.is_empty() {
                    format!("ffmpeg exited with {status}")
                } else {
                    last.to_string()
                })
            }
            Err(e) => Mp4Status::Failed(e.to_string()),
        }
    }
}

impl Drop for Mp4Encoder {
    /// A film that stopped part way leaves no MP4: ffmpeg is stopped and
    /// its file removed.
    fn drop(&mut self) {
        if !self.finished {
            self.input = None;
            let _ = self.child.kill();
            let _ = self.child.wait();
            let _ = std::fs::remove_file(&self.temporary);
        }
    }
}

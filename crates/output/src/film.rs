//! Films: numbered frames written atomically and resumably, then an
//! animated GIF, an MP4 (when `ffmpeg` is on the `PATH`) and a contact sheet.
//!
//! Layout of the output folder:
//!
//! ```text
//! DIR/frame_000000.png …      one PNG per frame, numbered from 0
//! DIR/hashes/frame_000000     the content hash each frame was made with
//! DIR/hashes/film.hash        the content hash the GIF, MP4 and sheet were made with
//! DIR/film.gif                the whole film (scaled to at most gif_max_width)
//! DIR/film.mp4                when ffmpeg is available
//! DIR/contact.png             thumbnails of every Nth frame
//! ```
//!
//! A frame counts as done when its PNG exists and its hash file holds the
//! hash of the current run (the caller's digest of script, scene and
//! settings). Both files are written to a temporary file in the same folder
//! and renamed into place, the PNG first: a killed run leaves no truncated
//! PNG, and a frame whose hash file is missing or stale is made again. Runs
//! over different frame ranges may share a folder (and run at the same
//! time); whichever finds every frame done assembles the film. Temporary
//! files a killed run left behind are deleted by the next run once they are
//! older than [`STALE_AFTER`].
//!
//! Frames are rendered in parallel on rayon's thread pool (the callback may
//! itself use rayon). Each frame's picture depends only on its number, and
//! the GIF, MP4 and contact sheet are built from the PNGs in frame order, so
//! the output does not depend on the order in which frames were made.
//!
//! ```
//! use sv_output::film::{content_hash, make_film, FilmOptions, Mp4Status};
//! let dir = tempfile::tempdir()?;
//! let hash = content_hash(&[b"timeline fingerprint", b"960x720 shadows"]);
//! let mut opts = FilmOptions::new(dir.path(), hash);
//! opts.ffmpeg = Some("/nonexistent/ffmpeg".into()); // skip the MP4 here
//! let render = |frame: usize| Ok(image::RgbImage::from_pixel(32, 24, image::Rgb([frame as u8 * 40, 90, 200])));
//! let report = make_film(5, &opts, render, |done, total| eprintln!("{done}/{total}"))?;
//! assert_eq!(report.rendered, vec![0, 1, 2, 3, 4]);
//! assert!(report.gif.is_some() && report.contact_sheet.is_some());
//! assert!(matches!(report.mp4, Mp4Status::Failed(_)));
//! // A second run finds every frame done.
//! let again = make_film(5, &opts, |_| unreachable!(), |_, _| {})?;
//! assert_eq!(again.reused.len(), 5);
//! # Ok::<(), Box<dyn std::error::Error>>(())
//! ```

use image::RgbImage;
use rayon::prelude::*;
use std::fmt;
use std::io::{self, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicUsize, Ordering};

/// What a render callback returns for one frame.
pub type FrameResult = Result<RgbImage, Box<dyn std::error::Error + Send + Sync>>;

/// How to make a film.
#[derive(Clone, Debug)]
pub struct FilmOptions {
    /// Output folder (created when missing).
    pub out_dir: PathBuf,
    /// Frames to render in this run (clipped to the film's length).
    pub frames: Range<usize>,
    /// Content hash of everything that decides the pictures.
    pub hash: String,
    /// Frames per second (for the GIF delays and the MP4).
    pub fps: f64,
    /// Make the GIF.
    pub gif: bool,
    /// Widest GIF frame; larger frames are scaled down.
    pub gif_max_width: u32,
    /// Make the MP4 when ffmpeg is found.
    pub mp4: bool,
    /// The ffmpeg program; `None` looks for `ffmpeg` on the `PATH`.
    pub ffmpeg: Option<PathBuf>,
    /// Contact sheet: one thumbnail every this many frames (0: about 48
    /// thumbnails in all).
    pub contact_every: usize,
    /// Contact sheet columns.
    pub contact_columns: u32,
    /// Contact sheet thumbnail width in pixels.
    pub thumb_width: u32,
}

impl FilmOptions {
    /// Every frame, 24 frames per second, GIF at most 480 pixels wide, MP4
    /// when possible, a contact sheet of 160-pixel thumbnails in 8 columns.
    pub fn new(out_dir: impl Into<PathBuf>, hash: impl Into<String>) -> FilmOptions {
        FilmOptions {
            out_dir: out_dir.into(),
            frames: 0..usize::MAX,
            hash: hash.into(),
            fps: 24.0,
            gif: true,
            gif_max_width: 480,
            mp4: true,
            ffmpeg: None,
            contact_every: 0,
            contact_columns: 8,
            thumb_width: 160,
        }
    }
}

/// What became of the MP4.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum Mp4Status {
    /// Written here.
    Written(PathBuf),
    /// No ffmpeg on the `PATH`.
    FfmpegNotFound,
    /// ffmpeg ran and failed (its last message).
    Failed(String),
    /// Not attempted: frames are missing, or MP4 was not asked for.
    NotMade,
}

impl fmt::Display for Mp4Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            Mp4Status::Written(p) => write!(f, "MP4 written to {}", p.display()),
            Mp4Status::FfmpegNotFound => f.write_str("ffmpeg not found: MP4 skipped"),
            Mp4Status::Failed(m) => write!(f, "ffmpeg failed: MP4 skipped ({m})"),
            Mp4Status::NotMade => f.write_str("MP4 not made"),
        }
    }
}

/// What a run did.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FilmReport {
    /// Frames rendered by this run, ascending.
    pub rendered: Vec<usize>,
    /// Frames of the range found already done, ascending.
    pub reused: Vec<usize>,
    /// Frames of the film (outside the range) still to be made; the film is
    /// assembled only when this is empty.
    pub missing: Vec<usize>,
    /// The GIF, when made.
    pub gif: Option<PathBuf>,
    /// The MP4's fate.
    pub mp4: Mp4Status,
    /// The contact sheet, when made.
    pub contact_sheet: Option<PathBuf>,
}

/// Why a film run stopped.
#[derive(Debug, thiserror::Error)]
pub enum FilmError {
    /// A file could not be written or read.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The cause.
        source: io::Error,
    },
    /// The render callback failed.
    #[error("frame {frame}: {message}")]
    Render {
        /// The frame.
        frame: usize,
        /// The callback's error.
        message: String,
    },
    /// An image could not be encoded or decoded.
    #[error("{}: {message}", path.display())]
    Image {
        /// The file.
        path: PathBuf,
        /// What went wrong.
        message: String,
    },
}

fn io_err(path: &Path) -> impl FnOnce(io::Error) -> FilmError + '_ {
    move |source| FilmError::Io {
        path: path.to_owned(),
        source,
    }
}

/// SHA-256 (hex) of the parts, each prefixed by its length so that
/// different splits never collide: the key of a film's frames, made from
/// for example the timeline's fingerprint, the render settings and the
/// program version.
pub fn content_hash(parts: &[&[u8]]) -> String {
    use sha2::{Digest, Sha256};
    let mut h = Sha256::new();
    for p in parts {
        h.update((p.len() as u64).to_le_bytes());
        h.update(p);
    }
    h.finalize().iter().map(|b| format!("{b:02x}")).collect()
}

/// The key of a film's frames on disk: its timeline's `fingerprint` and
/// everything else that decides the pictures (size, shadows, encoding,
/// the program's version). The CLI's `film` and the Python package key
/// frames alike, so either resumes what the other began.
pub fn frames_hash(
    fingerprint: &str,
    width: u32,
    height: u32,
    shadows: bool,
    srgb: bool,
) -> String {
    let settings = format!(
        "{width}x{height} shadows={shadows} srgb={srgb} v{}",
        env!("CARGO_PKG_VERSION")
    );
    content_hash(&[fingerprint.as_bytes(), settings.as_bytes()])
}

/// The PNG of a frame: `DIR/frame_000042.png`.
pub fn frame_path(dir: &Path, frame: usize) -> PathBuf {
    dir.join(format!("frame_{frame:06}.png"))
}

/// The hash file of a frame: `DIR/hashes/frame_000042`.
pub fn hash_path(dir: &Path, frame: usize) -> PathBuf {
    dir.join("hashes").join(format!("frame_{frame:06}"))
}

/// True when the frame's PNG exists and was made with `hash`.
pub fn frame_done(dir: &Path, frame: usize, hash: &str) -> bool {
    frame_path(dir, frame).is_file()
        && std::fs::read_to_string(hash_path(dir, frame)).is_ok_and(|h| h == hash)
}

/// Write a file through a temporary file in the same folder, renamed into
/// place only when `write` succeeds (see [`crate::images::write_atomic_io`]).
pub fn write_atomically(
    path: &Path,
    write: impl FnOnce(&mut dyn Write) -> io::Result<()>,
) -> io::Result<()> {
    crate::images::write_atomic_io(path, write)
}

fn write_png(path: &Path, img: &RgbImage) -> Result<(), FilmError> {
    let mut enc_err = None;
    let r = write_atomically(path, |w| {
        // Frames are many and short-lived: fast deflate with adaptive
        // filters costs about a third of the default's time for files a
        // few per cent larger.
        let enc = image::codecs::png::PngEncoder::new_with_quality(
            w,
            image::codecs::png::CompressionType::Fast,
            image::codecs::png::FilterType::Adaptive,
        );
        image::ImageEncoder::write_image(
            enc,
            img.as_raw(),
            img.width(),
            img.height(),
            image::ExtendedColorType::Rgb8,
        )
        .map_err(|e| {
            let msg = e.to_string();
            enc_err = Some(msg.clone());
            io::Error::other(msg)
        })
    });
    match (r, enc_err) {
        (Ok(()), _) => Ok(()),
        (Err(_), Some(message)) => Err(FilmError::Image {
            path: path.to_owned(),
            message,
        }),
        (Err(e), None) => Err(FilmError::Io {
            path: path.to_owned(),
            source: e,
        }),
    }
}

/// Age after which a temporary file left in the output folder is taken to
/// belong to a killed run (writing one frame takes well under a second).
pub const STALE_AFTER: std::time::Duration = std::time::Duration::from_secs(600);

/// Delete the temporary files (`.tmp-*`) in `dir` older than `age`: what a
/// killed run leaves behind. Younger ones may belong to a run still going
/// and are kept. Returns how many were deleted; errors are ignored.
pub fn remove_stale_temporaries(dir: &Path, age: std::time::Duration) -> usize {
    let Ok(entries) = std::fs::read_dir(dir) else {
        return 0;
    };
    let now = std::time::SystemTime::now();
    let mut n = 0;
    for e in entries.flatten() {
        let stale = e.file_name().to_string_lossy().starts_with(".tmp-")
            && e.metadata()
                .and_then(|m| m.modified())
                .is_ok_and(|t| now.duration_since(t).is_ok_and(|d| d > age));
        if stale && std::fs::remove_file(e.path()).is_ok() {
            n += 1;
        }
    }
    n
}

/// Render the frames of `opts.frames` that are not done yet, in parallel,
/// writing each PNG and then its hash file atomically. `progress(done,
/// total)` is called once at the start and after every frame (from worker
/// threads), counting frames of the range. Returns the frames rendered and
/// those found done. Stops at the first failing frame; frames finished by
/// then are kept.
pub fn render_frames<R, P>(
    total: usize,
    opts: &FilmOptions,
    render: R,
    progress: P,
) -> Result<(Vec<usize>, Vec<usize>), FilmError>
where
    R: Fn(usize) -> FrameResult + Sync,
    P: Fn(usize, usize) + Sync,
{
    let dir = &opts.out_dir;
    let hashes = dir.join("hashes");
    std::fs::create_dir_all(&hashes).map_err(io_err(&hashes))?;
    remove_stale_temporaries(dir, STALE_AFTER);
    remove_stale_temporaries(&hashes, STALE_AFTER);
    let range = opts.frames.start.min(total)..opts.frames.end.min(total);
    let (reused, todo): (Vec<usize>, Vec<usize>) =
        range.clone().partition(|&f| frame_done(dir, f, &opts.hash));
    let n = range.len();
    let done = AtomicUsize::new(reused.len());
    progress(reused.len(), n);
    todo.par_iter()
        .try_for_each(|&f| -> Result<(), FilmError> {
            let img = render(f).map_err(|e| FilmError::Render {
                frame: f,
                message: e.to_string(),
            })?;
            write_png(&frame_path(dir, f), &img)?;
            let hp = hash_path(dir, f);
            write_atomically(&hp, |w| w.write_all(opts.hash.as_bytes())).map_err(io_err(&hp))?;
            progress(done.fetch_add(1, Ordering::SeqCst) + 1, n);
            Ok(())
        })?;
    Ok((todo, reused))
}

/// Render what is missing of the range, then, when every frame of the film
/// is done, assemble the GIF, the MP4 (if ffmpeg is found) and the contact
/// sheet. A missing or failing ffmpeg is reported in
/// [`FilmReport::mp4`], never as an error.
pub fn make_film<R, P>(
    total: usize,
    opts: &FilmOptions,
    render: R,
    progress: P,
) -> Result<FilmReport, FilmError>
where
    R: Fn(usize) -> FrameResult + Sync,
    P: Fn(usize, usize) + Sync,
{
    let (rendered, reused) = render_frames(total, opts, render, progress)?;
    let dir = &opts.out_dir;
    remove_stale_assemblies(dir, &opts.hash)?;
    let missing: Vec<usize> = (0..total)
        .filter(|&f| !opts.frames.contains(&f) && !frame_done(dir, f, &opts.hash))
        .collect();
    let mut report = FilmReport {
        rendered,
        reused,
        missing,
        gif: None,
        mp4: Mp4Status::NotMade,
        contact_sheet: None,
    };
    if !report.missing.is_empty() || total == 0 {
        return Ok(report);
    }
    if opts.gif {
        let p = dir.join("film.gif");
        write_gif(dir, total, opts.fps, opts.gif_max_width, &p)?;
        report.gif = Some(p);
    }
    let p = dir.join("contact.png");
    let every = if opts.contact_every == 0 {
        total.div_ceil(48).max(1)
    } else {
        opts.contact_every
    };
    let sheet = contact_sheet(dir, total, every, opts.contact_columns, opts.thumb_width)?;
    write_png(&p, &sheet)?;
    report.contact_sheet = Some(p);
    if opts.mp4 {
        let ffmpeg = opts
            .ffmpeg
            .clone()
            .or_else(|| find_program("ffmpeg", std::env::var_os("PATH")));
        report.mp4 = match ffmpeg {
            None => Mp4Status::FfmpegNotFound,
            Some(ff) => write_mp4(&ff, dir, total, opts.fps),
        };
    }
    let hash_file = dir.join("hashes").join(ASSEMBLED);
    write_atomically(&hash_file, |w| w.write_all(opts.hash.as_bytes()))
        .map_err(io_err(&hash_file))?;
    Ok(report)
}

/// The hash file of the assembled film (GIF, MP4, contact sheet).
const ASSEMBLED: &str = "film.hash";

/// Remove the GIF, MP4 and contact sheet of `dir` unless they were made
/// from frames of `hash`: a film re-run at another size or from a changed
/// script must not leave the old film beside the new frames.
fn remove_stale_assemblies(dir: &Path, hash: &str) -> Result<(), FilmError> {
    let hash_file = dir.join("hashes").join(ASSEMBLED);
    if std::fs::read_to_string(&hash_file).is_ok_and(|made| made == hash) {
        return Ok(());
    }
    for name in ["film.gif", "film.mp4", "contact.png", "hashes/film.hash"] {
        let path = dir.join(name);
        match std::fs::remove_file(&path) {
            Err(e) if e.kind() != std::io::ErrorKind::NotFound => return Err(io_err(&path)(e)),
            _ => {}
        }
    }
    Ok(())
}

/// Read a frame range as given on a command line (`--frames`): `A..B`
/// (B excluded), `A..=B`, `A..`, `..B` or a single frame `N`, for a film of
/// `total` frames. Frame numbers start at 0; the range must hold at least
/// one frame of the film.
pub fn parse_frame_range(text: &str, total: usize) -> Result<Range<usize>, String> {
    let t = text.trim();
    let num = |s: &str| -> Result<usize, String> {
        s.trim()
            .parse::<usize>()
            .map_err(|_| format!("`{}` is not a frame number", s.trim()))
    };
    let range = match t.split_once("..") {
        None => {
            let n = num(t)?;
            n..n.saturating_add(1)
        }
        Some((a, b)) => {
            let start = if a.trim().is_empty() { 0 } else { num(a)? };
            let end = match b.strip_prefix('=') {
                Some(b) => num(b)?.saturating_add(1),
                None if b.trim().is_empty() => total,
                None => num(b)?,
            };
            start..end
        }
    };
    if range.start >= range.end.min(total) {
        return Err(format!(
            "frames {t} hold no frame of a film of {total} frames (0..{total})"
        ));
    }
    Ok(range.start..range.end.min(total))
}

/// The first executable file called `name` in the folders of a `PATH`
/// value.
pub fn find_program(name: &str, path: Option<std::ffi::OsString>) -> Option<PathBuf> {
    let path = path?;
    std::env::split_paths(&path)
        .map(|d| d.join(name))
        .find(|p| is_executable(p))
}

#[cfg(unix)]
fn is_executable(p: &Path) -> bool {
    use std::os::unix::fs::PermissionsExt;
    std::fs::metadata(p).is_ok_and(|m| m.is_file() && m.permissions().mode() & 0o111 != 0)
}

#[cfg(not(unix))]
fn is_executable(p: &Path) -> bool {
    p.is_file() || p.with_extension("exe").is_file()
}

fn read_frame(dir: &Path, f: usize) -> Result<image::RgbaImage, FilmError> {
    let p = frame_path(dir, f);
    image::open(&p)
        .map(|i| i.to_rgba8())
        .map_err(|e| FilmError::Image {
            path: p,
            message: e.to_string(),
        })
}

/// GIF delays in hundredths of a second, rounded so that the film keeps
/// its total length (24 fps alternates 4 and 5).
pub fn gif_delays(frames: usize, fps: f64) -> Vec<u16> {
    let fps = if fps.is_finite() && fps > 0.0 {
        fps
    } else {
        24.0
    };
    let at = |i: usize| (i as f64 * 100.0 / fps).round();
    (0..frames)
        .map(|i| (at(i + 1) - at(i)).clamp(1.0, u16::MAX as f64) as u16)
        .collect()
}

/// Frames sampled to learn a film's GIF palette.
const GIF_PALETTE_FRAMES: usize = 12;

/// A 256-colour palette (NeuQuant, Dekker 1994) with a lookup table from
/// colours at 6 bits per channel to palette entries.
struct Palette {
    rgb: Vec<u8>,
    lut: Vec<u8>,
}

impl Palette {
    /// Learn the palette of RGBA `pixels`.
    fn learn(pixels: &[u8]) -> Palette {
        let nq = color_quant::NeuQuant::new(10, 256, pixels);
        let lut = (0..1usize << 18)
            .map(|c| {
                // The centre of the 6-bit cell.
                let ch = |shift: usize| (((c >> shift) & 63) * 4 + 2) as u8;
                nq.index_of(&[ch(12), ch(6), ch(0), 255]) as u8
            })
            .collect();
        Palette {
            rgb: nq.color_map_rgb(),
            lut,
        }
    }

    /// The palette entry for an RGBA pixel.
    fn index(&self, p: [u8; 4]) -> u8 {
        let c = (p[0] as usize >> 2) << 12 | (p[1] as usize >> 2) << 6 | p[2] as usize >> 2;
        self.lut[c]
    }
}

fn write_gif(
    dir: &Path,
    total: usize,
    fps: f64,
    max_width: u32,
    out: &Path,
) -> Result<(), FilmError> {
    let first = read_frame(dir, 0)?;
    let (source_width, source_height) = first.dimensions();
    let scale = if max_width > 0 && source_width > max_width {
        max_width as f64 / source_width as f64
    } else {
        1.0
    };
    let width = ((source_width as f64 * scale).round() as u32).clamp(1, u16::MAX as u32);
    let height = ((source_height as f64 * scale).round() as u32).clamp(1, u16::MAX as u32);
    let delays = gif_delays(total, fps);
    let gif_err = |e: gif::EncodingError| FilmError::Image {
        path: out.to_owned(),
        message: e.to_string(),
    };
    let sized = |frame_number: usize| -> Result<image::RgbaImage, FilmError> {
        let picture = read_frame(dir, frame_number)?;
        Ok(if picture.dimensions() != (width, height) {
            image::imageops::resize(
                &picture,
                width,
                height,
                image::imageops::FilterType::Triangle,
            )
        } else {
            picture
        })
    };
    // One palette for the whole film, learnt from frames spread over it:
    // one quantisation instead of one per frame, and no colour flicker
    // from frame to frame.
    let samples: Vec<usize> = (0..GIF_PALETTE_FRAMES.min(total))
        .map(|sample| sample * total / GIF_PALETTE_FRAMES.min(total))
        .collect();
    let mut pixels = Vec::new();
    for picture in samples
        .par_iter()
        .map(|&frame_number| sized(frame_number))
        .collect::<Vec<_>>()
    {
        pixels.extend_from_slice(picture?.as_raw());
    }
    let palette = Palette::learn(&pixels);
    let mut failure: Option<FilmError> = None;
    let written = write_atomically(out, |writer| {
        let run = || -> Result<(), FilmError> {
            let mut encoder = gif::Encoder::new(writer, width as u16, height as u16, &palette.rgb)
                .map_err(gif_err)?;
            encoder.set_repeat(gif::Repeat::Infinite).map_err(gif_err)?;
            // Map a batch of frames in parallel, write them in order.
            let frames: Vec<usize> = (0..total).collect();
            for batch in frames.chunks(16) {
                let encoded: Vec<Result<gif::Frame<'static>, FilmError>> = batch
                    .par_iter()
                    .map(|&frame_number| {
                        let picture = sized(frame_number)?;
                        let indices: Vec<u8> =
                            picture.pixels().map(|p| palette.index(p.0)).collect();
                        let mut frame = gif::Frame::from_indexed_pixels(
                            width as u16,
                            height as u16,
                            indices,
                            None,
                        );
                        frame.delay = delays[frame_number];
                        Ok(frame)
                    })
                    .collect();
                for frame in encoded {
                    encoder.write_frame(&frame?).map_err(gif_err)?;
                }
            }
            Ok(())
        };
        run().map_err(|e| {
            let msg = e.to_string();
            failure = Some(e);
            io::Error::other(msg)
        })
    });
    match (written, failure) {
        (Ok(()), _) => Ok(()),
        (Err(_), Some(e)) => Err(e),
        (Err(e), None) => Err(FilmError::Io {
            path: out.to_owned(),
            source: e,
        }),
    }
}

/// A contact sheet: thumbnails `thumb_width` wide of frames 0, `every`,
/// 2·`every`…, left to right and top to bottom in `columns` columns. Its
/// size is `columns·thumb_width` by `rows·thumb_height` (fewer columns when
/// there are fewer thumbnails), where the thumbnail height keeps the first
/// frame's aspect ratio.
pub fn contact_sheet(
    dir: &Path,
    total: usize,
    every: usize,
    columns: u32,
    thumb_width: u32,
) -> Result<RgbImage, FilmError> {
    let picks: Vec<usize> = (0..total).step_by(every.max(1)).collect();
    let first = read_frame(dir, 0)?;
    let tw = thumb_width.max(1);
    let th =
        ((tw as f64 * first.height() as f64 / first.width().max(1) as f64).round() as u32).max(1);
    let cols = columns.max(1).min(picks.len().max(1) as u32);
    let rows = (picks.len() as u32).div_ceil(cols).max(1);
    let thumbs: Vec<Result<RgbImage, FilmError>> = picks
        .par_iter()
        .map(|&f| {
            let img = image::DynamicImage::ImageRgba8(read_frame(dir, f)?).to_rgb8();
            Ok(image::imageops::resize(
                &img,
                tw,
                th,
                image::imageops::FilterType::Triangle,
            ))
        })
        .collect();
    let mut sheet = RgbImage::new(cols * tw, rows * th);
    for (i, t) in thumbs.into_iter().enumerate() {
        let (c, r) = (i as u32 % cols, i as u32 / cols);
        image::imageops::replace(&mut sheet, &t?, (c * tw) as i64, (r * th) as i64);
    }
    Ok(sheet)
}

fn write_mp4(ffmpeg: &Path, dir: &Path, total: usize, fps: f64) -> Mp4Status {
    let out = dir.join("film.mp4");
    let tmp = dir.join(".tmp-film.mp4");
    let result = std::process::Command::new(ffmpeg)
        .arg("-y")
        .args(["-loglevel", "error"])
        .arg("-framerate")
        .arg(format!("{fps}"))
        .args(["-start_number", "0", "-i"])
        .arg(dir.join("frame_%06d.png"))
        .arg("-frames:v")
        .arg(total.to_string())
        .args([
            "-c:v",
            "libx264",
            "-pix_fmt",
            "yuv420p",
            "-vf",
            "pad=ceil(iw/2)*2:ceil(ih/2)*2",
        ])
        .arg(&tmp)
        .stdin(std::process::Stdio::null())
        .output();
    match result {
        Ok(o) if o.status.success() && tmp.is_file() => match std::fs::rename(&tmp, &out) {
            Ok(()) => Mp4Status::Written(out),
            Err(e) => Mp4Status::Failed(e.to_string()),
        },
        Ok(o) => {
            let _ = std::fs::remove_file(&tmp);
            let err = String::from_utf8_lossy(&o.stderr);
            Mp4Status::Failed(
                err.lines()
                    .last()
                    .unwrap_or("no message")
                    .trim()
                    .to_string(),
            )
        }
        Err(e) => Mp4Status::Failed(e.to_string()),
    }
}

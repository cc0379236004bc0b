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
//! DIR/film.mp4                H.264, BT.709 4:2:0, when ffmpeg is available
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
//! itself use rayon), each worker taking the next frame in turn. When every
//! frame the run does not render is already done, the GIF, the MP4 and the
//! contact sheet are assembled while the frames render: the workers also
//! scale, quantise and compress each frame for the GIF and convert it for
//! ffmpeg, which encodes from a pipe, and one thread writes the three in
//! frame order. Otherwise they are assembled from the PNGs once every frame
//! is done. Each frame's picture depends only on its number and the
//! assembly takes frames in frame order, so the output does not depend on
//! the order in which frames were made, nor on which runs made them.
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

mod assemble;

use assemble::{Assembled, Assembly, PreparedFrame};
use image::RgbImage;
use std::fmt;
use std::io::{self, Write};
use std::ops::Range;
use std::path::{Path, PathBuf};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{mpsc, Mutex};

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
    let png = encode_png(path, img)?;
    crate::images::put_in_place(png, path).map_err(io_err(path))
}

/// `img` encoded as a PNG into a temporary file beside `path`, to be put
/// in place with [`crate::images::put_in_place`].
fn encode_png(path: &Path, img: &RgbImage) -> Result<tempfile::NamedTempFile, FilmError> {
    let mut enc_err = None;
    let r = crate::images::write_beside(path, |w| {
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
        (Ok(png), _) => Ok(png),
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
    let run = FilmRun::begin(total, opts)?;
    run.render_only(&render, &progress)?;
    Ok((run.rendered, run.reused))
}

/// Render what is missing of the range and assemble the GIF, the MP4 (if
/// ffmpeg is found) and the contact sheet, when every frame of the film is
/// done. When every frame outside the range is done at the start, the film
/// is assembled while the frames render; otherwise (another run may be
/// making them) it is assembled from the PNGs if they are all done at the
/// end. A missing or failing ffmpeg is reported in [`FilmReport::mp4`],
/// never as an error.
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
    let run = FilmRun::begin(total, opts)?;
    let dir = &opts.out_dir;
    remove_stale_assemblies(dir, &opts.hash)?;
    let missing_elsewhere = || -> Vec<usize> {
        (0..total)
            .filter(|&f| !run.range.contains(&f) && !frame_done(dir, f, &opts.hash))
            .collect()
    };
    let mut missing = missing_elsewhere();
    let assembled = if total > 0 && missing.is_empty() {
        // Every frame this run does not render is on disk: assemble while
        // rendering, reading those from their PNGs in turn.
        let assembly = Assembly::new(total, opts);
        let jobs: Vec<Job> = assembly
            .order()
            .into_iter()
            .map(|f| {
                if run.rendered.binary_search(&f).is_ok() {
                    Job::Render(f)
                } else {
                    Job::Read(f)
                }
            })
            .collect();
        run.make(&jobs, &render, &progress, Some(&assembly))?
    } else {
        run.render_only(&render, &progress)?;
        missing = missing_elsewhere();
        if total > 0 && missing.is_empty() {
            // Another run made the rest meanwhile.
            let assembly = Assembly::new(total, opts);
            let jobs: Vec<Job> = assembly.order().into_iter().map(Job::Read).collect();
            run.make(&jobs, &render, &|_, _| {}, Some(&assembly))?
        } else {
            None
        }
    };
    let mut report = FilmReport {
        rendered: run.rendered,
        reused: run.reused,
        missing,
        gif: None,
        mp4: Mp4Status::NotMade,
        contact_sheet: None,
    };
    if let Some(assembled) = assembled {
        report.gif = assembled.gif;
        report.mp4 = assembled.mp4;
        report.contact_sheet = Some(assembled.contact_sheet);
        let hash_file = dir.join("hashes").join(ASSEMBLED);
        write_atomically(&hash_file, |w| w.write_all(opts.hash.as_bytes()))
            .map_err(io_err(&hash_file))?;
    }
    Ok(report)
}

/// One frame's work in a run.
#[derive(Clone, Copy, Debug)]
enum Job {
    /// Render the frame and write its PNG.
    Render(usize),
    /// Read the frame's PNG, made earlier, for the assembly.
    Read(usize),
}

/// A run over a range of a film's frames: which it renders and which it
/// found done.
struct FilmRun<'a> {
    opts: &'a FilmOptions,
    /// The range, clipped to the film.
    range: Range<usize>,
    /// Frames of the range to render, ascending.
    rendered: Vec<usize>,
    /// Frames of the range found done, ascending.
    reused: Vec<usize>,
}

impl FilmRun<'_> {
    /// Make the output folder, clear what killed runs left there, and sort
    /// the range into frames done and frames to render.
    fn begin(total: usize, opts: &FilmOptions) -> Result<FilmRun<'_>, FilmError> {
        let dir = &opts.out_dir;
        let hashes = dir.join("hashes");
        std::fs::create_dir_all(&hashes).map_err(io_err(&hashes))?;
        remove_stale_temporaries(dir, STALE_AFTER);
        remove_stale_temporaries(&hashes, STALE_AFTER);
        let range = opts.frames.start.min(total)..opts.frames.end.min(total);
        let (reused, rendered) = range.clone().partition(|&f| frame_done(dir, f, &opts.hash));
        Ok(FilmRun {
            opts,
            range,
            rendered,
            reused,
        })
    }

    /// Render the frames to render, with no assembly.
    fn render_only<R, P>(&self, render: &R, progress: &P) -> Result<(), FilmError>
    where
        R: Fn(usize) -> FrameResult + Sync,
        P: Fn(usize, usize) + Sync,
    {
        let jobs: Vec<Job> = self.rendered.iter().map(|&f| Job::Render(f)).collect();
        self.make(&jobs, render, progress, None).map(|_| ())
    }

    /// Do `jobs` on every thread of rayon's pool, each taking the next job
    /// in turn so that frames finish about in order; with an `assembly`,
    /// each frame is prepared for it and handed to it on its own thread.
    /// `progress` counts the frames of the range done. Stops taking jobs at
    /// the first failing frame.
    fn make<R, P>(
        &self,
        jobs: &[Job],
        render: &R,
        progress: &P,
        assembly: Option<&Assembly>,
    ) -> Result<Option<Assembled>, FilmError>
    where
        R: Fn(usize) -> FrameResult + Sync,
        P: Fn(usize, usize) + Sync + ?Sized,
    {
        let dir = &self.opts.out_dir;
        let range_len = self.range.len();
        let done = AtomicUsize::new(self.reused.len());
        progress(self.reused.len(), range_len);
        let next_job = AtomicUsize::new(0);
        let stop = AtomicBool::new(false);
        let first_failure: Mutex<Option<FilmError>> = Mutex::new(None);
        let fail = |e: FilmError| {
            stop.store(true, Ordering::SeqCst);
            first_failure
                .lock()
                .unwrap_or_else(|poisoned| poisoned.into_inner())
                .get_or_insert(e);
        };
        let workers = rayon::current_num_threads().max(1);
        // Room for a few frames per worker: workers wait rather than
        // pile frames up when the assembly falls behind.
        let (sender, receiver) = mpsc::sync_channel::<PreparedFrame>(2 * workers);
        let (to_disk, rendered_pngs) = mpsc::channel::<(usize, tempfile::NamedTempFile)>();
        let assembled = std::thread::scope(|scope| {
            let assembler = assembly.map(|assembly| scope.spawn(move || assembly.run(receiver)));
            // Syncing a file waits for the disk: a thread of its own puts
            // the PNGs in place, so that the workers' cores keep working.
            scope.spawn(|| {
                for (number, png) in rendered_pngs {
                    match put_frame_in_place(dir, &self.opts.hash, number, png) {
                        Ok(()) => progress(done.fetch_add(1, Ordering::SeqCst) + 1, range_len),
                        Err(e) => fail(e),
                    }
                }
            });
            let sender = assembly.map(|_| sender);
            // One loop on each thread of the pool: a broadcast job runs on
            // its own thread only, so no loop can start inside another's
            // frame (a thread waiting for help with its frame may run a
            // spawned job there), which would hold that frame back until
            // the nested loop ran out of frames.
            rayon::broadcast(|_| {
                let mut sender = sender.clone();
                let to_disk = to_disk.clone();
                while !stop.load(Ordering::SeqCst) {
                    let Some(&job) = jobs.get(next_job.fetch_add(1, Ordering::SeqCst)) else {
                        break;
                    };
                    let (number, made) = match job {
                        Job::Render(f) => (
                            f,
                            render_frame(dir, f, render).map(|(picture, png)| {
                                // The syncing thread outlives the workers.
                                let _ = to_disk.send((f, png));
                                picture
                            }),
                        ),
                        Job::Read(f) => (f, read_frame(dir, f)),
                    };
                    let picture = match made {
                        Ok(picture) => picture,
                        Err(e) => {
                            fail(e);
                            break;
                        }
                    };
                    if let (Some(assembly), Some(to_assembly)) = (assembly, &sender) {
                        // A closed channel: the assembly failed and says
                        // why; the frames are still worth making.
                        if to_assembly
                            .send(assembly.prepare(number, &picture))
                            .is_err()
                        {
                            sender = None;
                        }
                    }
                }
            });
            drop(to_disk);
            drop(sender);
            assembler.map(|handle| match handle.join() {
                Ok(result) => result,
                Err(panic) => std::panic::resume_unwind(panic),
            })
        });
        if let Some(failure) = first_failure
            .into_inner()
            .unwrap_or_else(|poisoned| poisoned.into_inner())
        {
            return Err(failure);
        }
        assembled.transpose()
    }
}

/// Render frame `number` and encode its PNG beside its place.
fn render_frame<R>(
    dir: &Path,
    number: usize,
    render: &R,
) -> Result<(RgbImage, tempfile::NamedTempFile), FilmError>
where
    R: Fn(usize) -> FrameResult,
{
    let picture = render(number).map_err(|e| FilmError::Render {
        frame: number,
        message: e.to_string(),
    })?;
    let png = encode_png(&frame_path(dir, number), &picture)?;
    Ok((picture, png))
}

/// Put a frame's PNG in place, then write its hash file: the frame counts
/// as done only once its picture is on disk.
fn put_frame_in_place(
    dir: &Path,
    hash: &str,
    number: usize,
    png: tempfile::NamedTempFile,
) -> Result<(), FilmError> {
    let png_path = frame_path(dir, number);
    crate::images::put_in_place(png, &png_path).map_err(io_err(&png_path))?;
    let hash_file = hash_path(dir, number);
    write_atomically(&hash_file, |w| w.write_all(hash.as_bytes())).map_err(io_err(&hash_file))
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

/// Frame `number` read back from its PNG.
fn read_frame(dir: &Path, number: usize) -> Result<RgbImage, FilmError> {
    let path = frame_path(dir, number);
    image::open(&path)
        .map(|picture| picture.into_rgb8())
        .map_err(|e| FilmError::Image {
            path,
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

//! Writing for people: reports on stdout, notes and errors on stderr.
//!
//! A closed pipe ends the program quietly, as Unix tools do
//! (`synthavision bodies | head -3`): `println!` would panic instead. A
//! closed stderr is ignored (the work still gets done and written), and
//! `--quiet` silences the notes.

use std::fmt::Arguments;
use std::io::{ErrorKind, Write};
use std::sync::atomic::{AtomicBool, Ordering};

/// Whether `--quiet` was given.
static QUIET: AtomicBool = AtomicBool::new(false);

/// Silence the notes (`--quiet`).
pub fn set_quiet(quiet: bool) {
    QUIET.store(quiet, Ordering::Relaxed);
}

/// Whether notes and progress bars are silenced.
pub fn quiet() -> bool {
    QUIET.load(Ordering::Relaxed)
}

/// Write to stdout; when the reader has gone (a closed pipe), end the
/// program quietly with exit code 0.
pub fn out(args: Arguments) {
    let mut stdout = std::io::stdout().lock();
    if let Err(error) = stdout.write_fmt(args) {
        if error.kind() == ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
    }
}

/// Write bytes to stdout (a picture for `-o -`), with the same rule for a
/// closed pipe.
pub fn out_bytes(bytes: &[u8]) {
    let mut stdout = std::io::stdout().lock();
    if let Err(error) = stdout.write_all(bytes).and_then(|()| stdout.flush()) {
        if error.kind() == ErrorKind::BrokenPipe {
            std::process::exit(0);
        }
    }
}

/// Write to stderr; a closed stderr is not worth stopping for.
pub fn err(args: Arguments) {
    let _ = std::io::stderr().lock().write_fmt(args);
}

/// A note on stderr, unless `--quiet`.
pub fn note(args: Arguments) {
    if !quiet() {
        err(args);
    }
}

/// A number for people: 4 significant figures, without trailing zeros
/// (`-2.544`, `1200`, `0.0125`).
pub fn round(value: f64) -> String {
    if value == 0.0 || !value.is_finite() {
        return format!("{value}");
    }
    let digits = (3 - value.abs().log10().floor() as i32).clamp(0, 12) as usize;
    let text = format!("{value:.digits$}");
    let text = if text.contains('.') {
        text.trim_end_matches('0').trim_end_matches('.')
    } else {
        &text
    };
    if text == "-0" {
        "0".into()
    } else {
        text.into()
    }
}

/// `print!` that ends quietly on a closed pipe.
macro_rules! out {
    ($($arg:tt)*) => { $crate::term::out(format_args!($($arg)*)) };
}

/// `println!` that ends quietly on a closed pipe.
macro_rules! outln {
    () => { $crate::term::out(format_args!("\n")) };
    ($($arg:tt)*) => { $crate::term::out(format_args!("{}\n", format_args!($($arg)*))) };
}

/// `eprint!` that ignores a closed stderr.
macro_rules! err {
    ($($arg:tt)*) => { $crate::term::err(format_args!($($arg)*)) };
}

/// `eprintln!` that ignores a closed stderr.
macro_rules! errln {
    ($($arg:tt)*) => { $crate::term::err(format_args!("{}\n", format_args!($($arg)*))) };
}

/// A line on stderr that `--quiet` silences: `note: ...`.
macro_rules! noteln {
    ($($arg:tt)*) => { $crate::term::note(format_args!("{}\n", format_args!($($arg)*))) };
}

/// A spinner with the time taken, for work without steps to count
/// (`check`, `volume`), when stderr is a terminal and `--quiet` was not
/// given; cleared when dropped.
pub struct Spinner(Option<indicatif::ProgressBar>);

impl Spinner {
    /// Start spinning with `message`.
    pub fn start(message: &str) -> Spinner {
        if quiet() || !std::io::IsTerminal::is_terminal(&std::io::stderr()) {
            return Spinner(None);
        }
        let bar = indicatif::ProgressBar::new_spinner();
        if let Ok(style) = indicatif::ProgressStyle::with_template("{spinner} {msg} {elapsed}") {
            bar.set_style(style);
        }
        bar.set_message(message.to_string());
        bar.enable_steady_tick(std::time::Duration::from_millis(120));
        Spinner(Some(bar))
    }
}

impl Drop for Spinner {
    fn drop(&mut self) {
        if let Some(bar) = &self.0 {
            bar.finish_and_clear();
        }
    }
}

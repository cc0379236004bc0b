//! The bounds on what the page may ask for: message sizes, picture sizes,
//! renders at once, sessions.

/// Largest message the page may send (bytes).
pub const MAX_MESSAGE: usize = 64 * 1024;
/// Longest side of a picture the page may ask for (pixels).
pub const MAX_SIDE: u32 = 2048;
/// Shortest side of a picture (pixels).
pub const MIN_SIDE: u32 = 16;
/// Renders running at once, over every session (the others wait).
pub const MAX_RENDERS: usize = 2;
/// Pages connected at once.
pub const MAX_SESSIONS: usize = 8;
/// Cut planes at once.
pub const MAX_CUTS: usize = 8;
/// Film frames written to files by one request.
pub const MAX_FRAMES_TO_FILE: usize = 2000;
/// Side of a section view (pixels).
pub const MAX_SLICE_SIDE: u32 = 1024;

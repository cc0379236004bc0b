//! Image writers: PNG (8/16-bit, grey/RGB, with or without alpha), PGM/PPM
//! and PFM (32-bit float), the auxiliary images, and films.
//!
//! Every file is written to a temporary file in the destination folder and
//! renamed into place, so a failed or interrupted run never leaves a
//! truncated picture.
#![warn(missing_docs)]

pub mod film;
pub mod images;

pub use images::{
    to_rgb8, write_atomic, write_image, write_pfm, write_region_png, Encoding, ImageFormat, Pixels,
    WriteError, WriteOptions,
};

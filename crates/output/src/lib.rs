//! Image writers, auxiliary images and films.
#![warn(missing_docs)]

pub mod film;

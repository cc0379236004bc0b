//! Integration tests of the renderer.
mod differential;
mod pictures;

//! Integration tests of the geometry engine.
mod bodies;
mod fills;
mod halfspace;
mod regions;
mod trees;

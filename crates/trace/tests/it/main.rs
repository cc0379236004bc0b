//! Integration tests of the geometry engine.
mod bodies;
mod fills;
mod regions;
mod trees;

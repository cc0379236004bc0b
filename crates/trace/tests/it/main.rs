//! Integration tests of the geometry engine.
mod bodies;
mod regions;
mod trees;

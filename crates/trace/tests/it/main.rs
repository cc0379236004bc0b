//! Integration tests of the geometry engine.
mod conformance;
mod regions;

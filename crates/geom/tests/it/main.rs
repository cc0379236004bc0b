//! Integration tests of the bodies.
mod conformance;
mod lanes;

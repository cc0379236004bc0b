//! Integration tests of the readers and writers: COMGEOM decks, FLUKA
//! inputs, the scene language and the POV-Ray writer.
mod comgeom;
mod fluka;
mod mcnp;
mod native;
mod pov;

//! Integration tests of the readers and writers: COMGEOM decks, FLUKA
//! inputs, MCNP inputs, OpenMC models, the scene language and the POV-Ray
//! writer.
mod comgeom;
mod fluka;
mod mcnp;
mod mutation;
mod native;
mod openmc;
mod pov;

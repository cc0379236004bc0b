//! Integration tests of the director: the example film, the script
//! language, its CAMERA and ZOOM read as scenes read them, and the timeline's transforms.
mod camera;
mod example_film;
mod script;
mod transforms;

//! Integration tests of the director: the example film, the script
//! language and the timeline's transforms.
mod example_film;
mod script;
mod transforms;

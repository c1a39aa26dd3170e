//! The second pass: camera rays, the terms, and the film.
pub mod aov;
pub mod film;

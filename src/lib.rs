//! photonmap: a two-pass photon-mapping renderer after Jensen
//! ("Realistic Image Synthesis Using Photon Mapping", 2001).

pub mod photon;

//! areo-terrain: the ground a rover plans over.
//!
//! This crate will hold TEMPEST's world model and the ground the LSR-1 physics stands
//! on: digital elevation models (`Dem`) read from GeoTIFF, ESRI ASCII and PDS3 files,
//! synthesised terrain, Horn slope and aspect, the Mars reference body and its map
//! projections, and line of sight (cast shadows, horizon maps, viewsheds).
//!
//! Conventions (shared with every areo crate, see `docs/ARCHITECTURE.md`): metres,
//! local east-north-up frame, rows stored north to south, azimuth clockwise from north.
//! Only this crate does index↔metre arithmetic.
//!
//! Architecture invariant: areo-terrain depends on no other areo crate, so a DEM loader
//! or a shadow map can be reused alone.
//!
//! Status: the crate is created by the workspace foundation; its contents land with the
//! terrain issue.

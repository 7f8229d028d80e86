//! sandlight-core: Monte Carlo light transport in sand.
//!
//! Layering (dependencies point down): `math` and `rng` → `optics` (Fresnel, layer stacks)
//! → `particle` (one grain's interaction) → `transport` (free paths, boundary, drivers).
//! No PyO3 here: bindings live in `sandlight-py`.

pub mod error;

pub use error::SandlightError;

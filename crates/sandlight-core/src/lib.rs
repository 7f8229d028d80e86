//! sandlight-core: Monte Carlo light transport in sand.
//!
//! Layering (dependencies point down): `math`, `rng` → `fresnel`, `layers` → `spheroid`,
//! `sizes` → `particle` (one grain's interaction) → `medium`, `transport` (free paths, boundary)
//! → `driver` (parallel runs and tallies). `surface_layer`: the cut-plane top layer of path memory. `packing`, `deposition` and `explicit`: the
//! explicit-geometry reference (a stored random packing, cut or with a gravity-settled surface,
//! traced with the same per-particle interaction). No PyO3 here: bindings live in `sandlight-py`.

pub mod appearance;
pub mod deposition;
pub mod driver;
pub mod error;
pub mod explicit;
pub mod fresnel;
pub mod gonio;
pub mod layers;
pub mod math;
pub mod medium;
pub mod packing;
pub mod pair_correlation;
pub mod particle;
pub mod render;
pub mod rng;
pub mod sampling;
pub mod sizes;
pub mod spheroid;
pub mod surface_layer;
pub mod transport;

pub use error::SandlightError;

//! sandlight-core: Monte Carlo light transport in sand.
//!
//! Layering: a module uses only modules to its left, so there is no cycle.
//! `error`, `math`, `rng` → `sampling` (generic samplers) → `fresnel` → `layers` → `scattering_layer` (a
//! layer stack whose coating scatters) → `spheroid`,
//! `sizes`, `pair_correlation`, `spectral` (per-wavelength path weights) → `particle` (one
//! grain's interaction, and the `PathChoices` through which every wavelength-dependent choice is
//! made) → `medium` (sand and the reference media) → `populations` (the grains as they fill the
//! volume) → `surface_layer` → `transport` (the `Medium` trait, free paths, the boundary) →
//! `memory` (sand traced with near-surface path memory) → `driver` (parallel runs and tallies) →
//! `hero` (spectral path sharing: a group of wavelengths traced together, fixed-point tallies)
//! and `gonio` (the virtual goniophotometer).
//! The explicit-geometry reference: `packing` (a stored random packing of the populations) →
//! `deposition` (a gravity-settled surface on its cut) → `explicit` (traced with the same
//! per-particle interaction and boundary as `transport`).
//! `render` (the spectral renderer) uses only `error`, `math`, `rng` and `sampling`;
//! `appearance` (the fast BRDF evaluator) only `error`. `mie` (Lorenz–Mie solution of a sphere)
//! and `phase_table` (sampling a tabulated phase function): fine-particle optics; `phase_table`
//! → `volume_scatterer` (Mie particles as volume scatterers in the pore space, an opt-in of the
//! on-the-fly tracers) → `particle`. No PyO3 here: bindings live in `sandlight-py`.

pub mod appearance;
pub mod deposition;
pub mod driver;
pub mod error;
pub mod explicit;
pub mod fresnel;
pub mod gonio;
pub mod hero;
pub mod layers;
pub mod math;
pub mod medium;
pub mod memory;
pub mod mie;
pub mod packing;
pub mod pair_correlation;
pub mod particle;
pub mod phase_table;
pub mod populations;
pub mod render;
pub mod rng;
pub mod sampling;
pub mod scattering_layer;
pub mod sizes;
pub mod spectral;
pub mod spheroid;
pub mod surface_layer;
pub mod transport;
pub mod volume_scatterer;

pub use error::SandlightError;

//! `sandlight._native.SpectralGroup`: the sand media of a group of wavelengths traced together
//! with spectral path sharing (docs/transport.md, "Spectral path sharing").

use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use sandlight_core::error::SandlightError;
use sandlight_core::hero::{spectral_directional_hemispherical, HeroGroup, FIXED_ONE};
use sandlight_core::memory::Memory;

use crate::errors::to_py;
use crate::medium::{checked_incidence, rays_and_limits, Kind, PyMedium};
use crate::pool::run_with_threads;

#[pyclass(frozen, name = "SpectralGroup", module = "sandlight._native")]
pub struct PySpectralGroup {
    group: HeroGroup,
}

/// Totals of a shared run: (launched, capped, events, escaped, transmitted, products), the
/// last three fixed-point integer sums (see `sandlight_core::hero::SpectralCounts`).
type SharedCounts = (u64, u64, u64, Vec<u128>, Vec<u128>, Vec<u128>);

#[pymethods]
impl PySpectralGroup {
    /// The group of `media` (one on-the-fly sand medium per wavelength, same geometry and path
    /// memory).
    #[new]
    fn new(py: Python<'_>, media: Vec<PyRef<'_, PyMedium>>) -> PyResult<Self> {
        let mut list = Vec::with_capacity(media.len());
        let mut memory = None;
        for (j, m) in media.iter().enumerate() {
            match &m.kind {
                Kind::Particulate(w) if *memory.get_or_insert(w.memory) == w.memory => list.push(w.medium.clone()),
                _ => {
                    return Err(to_py(
                        py,
                        SandlightError::parameter(
                            &format!("media[{j}]"),
                            "another kind of medium",
                            "an on-the-fly sand medium with the path memory of media[0]",
                        ),
                    ))
                }
            }
        }
        HeroGroup::new(list, memory.unwrap_or(Memory::None))
            .map(|group| PySpectralGroup { group })
            .map_err(|e| to_py(py, e))
    }

    /// Wavelengths in the group.
    fn __len__(&self) -> usize {
        self.group.len()
    }

    /// Fixed-point scale of the integer sums (an estimate F counts as round(F · scale)).
    #[classattr]
    fn fixed_one() -> f64 {
        FIXED_ONE
    }

    /// Fraction of the layer-stack table cells evaluated exactly rather than interpolated.
    fn exact_fraction(&self) -> f64 {
        self.group.exact_fraction()
    }

    /// Traces rays `first_ray .. first_ray + n_rays` at incidence `theta_deg` and returns
    /// (launched, capped, events, escaped, transmitted, products) with escaped and transmitted
    /// per wavelength and the products Σ q_i q_j (i ≤ j, row by row) as Python integers. The GIL
    /// is released.
    #[pyo3(signature = (theta_deg, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments)] // one argument per Python parameter
    fn dhr(
        &self,
        py: Python<'_>,
        theta_deg: f64,
        seed: u64,
        stream: u64,
        first_ray: u64,
        n_rays: u64,
        max_events: u64,
        max_internal: u32,
        threads: Option<usize>,
    ) -> PyResult<SharedCounts> {
        let dir = checked_incidence(py, theta_deg)?;
        let (rays, limits) = rays_and_limits(seed, stream, first_ray, n_rays, max_events, max_internal);
        let c = py
            .detach(|| {
                run_with_threads(threads, || spectral_directional_hemispherical(&self.group, dir, rays, &limits))
            })
            .map_err(PyRuntimeError::new_err)?;
        Ok((c.launched, c.capped, c.events, c.escaped, c.transmitted, c.products))
    }
}

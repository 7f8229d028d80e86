//! `sandlight._native.SpectralGroup`: the sand media of a group of wavelengths traced together
//! with spectral path sharing (docs/transport.md, "Spectral path sharing").

use numpy::{PyReadwriteArray1, PyReadwriteArray2, PyReadwriteArray3, PyReadwriteArray4};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use sandlight_core::error::SandlightError;
use sandlight_core::gonio::measure::{measure_brdf_shared, measure_fixed_incidence_shared};
use sandlight_core::gonio::spectral_sums::SQUARE_ONE;
use sandlight_core::gonio::{CollectorHemisphere, SpectralBrdfSums};
use sandlight_core::hero::{spectral_directional_hemispherical, HeroGroup, FIXED_ONE};
use sandlight_core::memory::Memory;

use crate::errors::to_py;
use crate::medium::{checked_incidence, checked_light, rays_and_limits, Kind, PyMedium};
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
    /// The group of `media`: one on-the-fly sand medium per wavelength, same geometry and path
    /// memory, or one explicit sand medium per wavelength, through the same packing with the
    /// same bottom.
    #[new]
    fn new(py: Python<'_>, media: Vec<PyRef<'_, PyMedium>>) -> PyResult<Self> {
        let refused = |j: usize| {
            to_py(
                py,
                SandlightError::parameter(
                    &format!("media[{j}]"),
                    "another kind of medium",
                    "a sand medium of the kind of media[0]: on the fly with its path memory, or explicit",
                ),
            )
        };
        let group = if let Some(Kind::Explicit(_)) = media.first().map(|m| &m.kind) {
            let samples = media.iter().enumerate().map(|(j, m)| match &m.kind {
                Kind::Explicit(e) => Ok(e.clone()),
                _ => Err(refused(j)),
            });
            HeroGroup::explicit(samples.collect::<PyResult<_>>()?)
        } else {
            let mut memory = None;
            let media = media.iter().enumerate().map(|(j, m)| match &m.kind {
                Kind::Particulate(w) if *memory.get_or_insert(w.memory) == w.memory => Ok(w.medium.clone()),
                _ => Err(refused(j)),
            });
            let media = media.collect::<PyResult<_>>()?;
            HeroGroup::new(media, memory.unwrap_or(Memory::None))
        };
        group.map(|group| PySpectralGroup { group }).map_err(|e| to_py(py, e))
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

    /// Scale of the goniophotometer's sums of squares: F² counts as q² = F² · scale exactly
    /// (q = round(F · fixed_one)), a u128 held as two uint64 words (high, low).
    #[classattr]
    fn square_one() -> f64 {
        SQUARE_ONE
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

    /// Goniophotometer trials `first_ray .. first_ray + n_rays` on a `stacks` × `slices`
    /// hemisphere (r patches), with shared paths, added in place to the uint64 sums `escaped`
    /// (n, r, wavelengths) and `squares` (n, r, wavelengths, 2: the high and low words of a
    /// u128), `transmitted` (n, wavelengths), `launched` and
    /// `capped` (n,) (see `sandlight_core::gonio::spectral_sums`). Uniform incidence (n = r
    /// incoming patches), or with `incidence_deg` = (zenith, azimuth) in degrees the classic
    /// instrument, every trial from that direction (n = 1). The GIL is released.
    #[pyo3(signature = (stacks, slices, seed, stream, first_ray, n_rays, max_events, max_internal,
                        escaped, squares, transmitted, launched, capped, threads = None, incidence_deg = None))]
    #[allow(clippy::too_many_arguments)] // one argument per Python parameter
    fn brdf_sums(
        &self,
        py: Python<'_>,
        stacks: usize,
        slices: usize,
        seed: u64,
        stream: u64,
        first_ray: u64,
        n_rays: u64,
        max_events: u64,
        max_internal: u32,
        mut escaped: PyReadwriteArray3<'_, u64>,
        mut squares: PyReadwriteArray4<'_, u64>,
        mut transmitted: PyReadwriteArray2<'_, u64>,
        mut launched: PyReadwriteArray1<'_, u64>,
        mut capped: PyReadwriteArray1<'_, u64>,
        threads: Option<usize>,
        incidence_deg: Option<(f64, f64)>,
    ) -> PyResult<()> {
        let toward_light = incidence_deg.map(|(theta, phi)| checked_light(py, theta, phi)).transpose()?;
        let h = CollectorHemisphere::new(stacks, slices).map_err(|e| to_py(py, e))?;
        let (rays, limits) = rays_and_limits(seed, stream, first_ray, n_rays, max_events, max_internal);
        let contiguous = |name: &str| {
            to_py(py, SandlightError::parameter(name, "a non-contiguous array", "a C-contiguous uint64 array"))
        };
        let mut sums = SpectralBrdfSums {
            escaped: escaped.as_slice_mut().map_err(|_| contiguous("escaped"))?,
            squares: squares.as_slice_mut().map_err(|_| contiguous("squares"))?,
            transmitted: transmitted.as_slice_mut().map_err(|_| contiguous("transmitted"))?,
            launched: launched.as_slice_mut().map_err(|_| contiguous("launched"))?,
            capped: capped.as_slice_mut().map_err(|_| contiguous("capped"))?,
        };
        let measure = || match toward_light {
            Some(dir) => measure_fixed_incidence_shared(&self.group, &h, dir, rays, &limits, &mut sums),
            None => measure_brdf_shared(&self.group, &h, rays, &limits, &mut sums),
        };
        py.detach(|| run_with_threads(threads, measure)).map_err(PyRuntimeError::new_err)?.map_err(|e| to_py(py, e))
    }
}

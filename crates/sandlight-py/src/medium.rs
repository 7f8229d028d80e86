//! `sandlight._native.Medium`: a medium at one wavelength, and the runs over it.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use sandlight_core::driver::{directional_hemispherical, incident_direction};
use sandlight_core::gonio::measure::{measure_brdf, measure_fixed_incidence};
use sandlight_core::gonio::{BrdfTally, CollectorHemisphere, FixedIncidenceTally};
use sandlight_core::math::Vec3;
use sandlight_core::error::SandlightError;
use sandlight_core::medium::{IsotropicScatterers, LambertianSurface, Particulate, ParticleType};
use sandlight_core::particle::{Coating, ParticleOptics, PoreOptics};
use sandlight_core::sizes::QuantileTable;
use sandlight_core::transport::Limits;

use crate::errors::to_py;
use crate::pool::run_with_threads;

pub enum Kind {
    Particulate(Particulate),
    Isotropic(IsotropicScatterers),
    Lambertian(LambertianSurface),
}

#[pyclass(frozen, name = "Medium", module = "sandlight._native")]
pub struct PyMedium {
    pub kind: Kind,
}

fn same_len(name: &str, got: usize, want: usize) -> Result<(), SandlightError> {
    if got == want { Ok(()) } else { Err(SandlightError::parameter(name, format!("length {got}"), &format!("one entry per particle type ({want})"))) }
}

#[pymethods]
impl PyMedium {
    /// A sand sample at one wavelength; see `sandlight.physics.medium` for the meaning of each
    /// array (one entry per particle type).
    #[staticmethod]
    #[pyo3(signature = (probabilities, size_quantiles_mm, aspect_ratios, core_n, core_k, core_alpha_per_mm,
                        coating_n, coating_alpha_per_mm, coating_thickness_mm, mean_free_path_mm,
                        water_n, water_alpha_per_mm, film_thickness_mm, water_filled_probability, depth_mm))]
    #[allow(clippy::too_many_arguments)]
    fn particulate(
        py: Python<'_>,
        probabilities: Vec<f64>,
        size_quantiles_mm: Vec<Vec<f64>>,
        aspect_ratios: Vec<f64>,
        core_n: Vec<f64>,
        core_k: Vec<f64>,
        core_alpha_per_mm: Vec<f64>,
        coating_n: Vec<f64>,
        coating_alpha_per_mm: Vec<f64>,
        coating_thickness_mm: Vec<f64>,
        mean_free_path_mm: f64,
        water_n: f64,
        water_alpha_per_mm: f64,
        film_thickness_mm: f64,
        water_filled_probability: f64,
        depth_mm: f64,
    ) -> PyResult<Self> {
        let build = || -> Result<Particulate, SandlightError> {
            let n = probabilities.len();
            same_len("size_quantiles_mm", size_quantiles_mm.len(), n)?;
            same_len("aspect_ratios", aspect_ratios.len(), n)?;
            same_len("core_n", core_n.len(), n)?;
            same_len("core_k", core_k.len(), n)?;
            same_len("core_alpha_per_mm", core_alpha_per_mm.len(), n)?;
            same_len("coating_n", coating_n.len(), n)?;
            same_len("coating_alpha_per_mm", coating_alpha_per_mm.len(), n)?;
            same_len("coating_thickness_mm", coating_thickness_mm.len(), n)?;
            let mut types = Vec::with_capacity(n);
            for i in 0..n {
                let coating = (coating_thickness_mm[i] > 0.0).then_some(Coating { n: coating_n[i], alpha_per_mm: coating_alpha_per_mm[i], thickness_mm: coating_thickness_mm[i] });
                types.push(ParticleType {
                    probability: probabilities[i],
                    sizes: QuantileTable::new(size_quantiles_mm[i].clone())?,
                    aspect_ratio: aspect_ratios[i],
                    optics: ParticleOptics { core_n: core_n[i], core_k: core_k[i], core_alpha_per_mm: core_alpha_per_mm[i], coating, wets: true },
                });
            }
            let pore = PoreOptics { water_n, water_alpha_per_mm, film_thickness_mm, water_filled_probability };
            Particulate::new(types, mean_free_path_mm, pore, depth_mm)
        };
        build().map(|p| PyMedium { kind: Kind::Particulate(p) }).map_err(|e| to_py(py, e))
    }

    /// Isotropic point scatterers of albedo ω, unit mean free path (Chandrasekhar's half-space).
    #[staticmethod]
    #[pyo3(signature = (albedo, depth = f64::INFINITY))]
    fn isotropic(py: Python<'_>, albedo: f64, depth: f64) -> PyResult<Self> {
        IsotropicScatterers::new(albedo, depth).map(|m| PyMedium { kind: Kind::Isotropic(m) }).map_err(|e| to_py(py, e))
    }

    /// An ideal Lambertian surface of albedo a (a test object).
    #[staticmethod]
    fn lambertian(py: Python<'_>, albedo: f64) -> PyResult<Self> {
        LambertianSurface::new(albedo).map(|m| PyMedium { kind: Kind::Lambertian(m) }).map_err(|e| to_py(py, e))
    }

    /// Traces rays `first_ray .. first_ray + n_rays` at incidence `theta_deg` and returns the
    /// counts (launched, escaped, absorbed, transmitted, capped, events). The GIL is released.
    #[pyo3(signature = (theta_deg, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments)]
    fn dhr(&self, py: Python<'_>, theta_deg: f64, seed: u64, stream: u64, first_ray: u64, n_rays: u64, max_events: u64, max_internal: u32, threads: Option<usize>) -> PyResult<(u64, u64, u64, u64, u64, u64)> {
        if !(0.0..90.0).contains(&theta_deg) {
            return Err(to_py(py, SandlightError::parameter("incidence_deg", theta_deg, "must be in [0, 90)")));
        }
        let dir = incident_direction(theta_deg.to_radians());
        let limits = Limits { max_events, max_internal };
        let run = || -> Result<_, String> {
            run_with_threads(threads, || match &self.kind {
                Kind::Particulate(m) => directional_hemispherical(m, dir, seed, stream, first_ray, n_rays, &limits),
                Kind::Isotropic(m) => directional_hemispherical(m, dir, seed, stream, first_ray, n_rays, &limits),
                Kind::Lambertian(m) => directional_hemispherical(m, dir, seed, stream, first_ray, n_rays, &limits),
            })
        };
        let c = py.detach(run).map_err(PyRuntimeError::new_err)?;
        Ok((c.launched, c.escaped, c.absorbed, c.transmitted, c.capped, c.events))
    }

    /// Uniform-incidence goniophotometer trials `first_ray .. first_ray + n_rays` on a
    /// `stacks` × `slices` hemisphere. Returns (counts (r, r), absorbed (r,), launched (r,),
    /// lost (r,)) as uint64 arrays. The GIL is released.
    #[pyo3(signature = (stacks, slices, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn brdf_counts<'py>(&self, py: Python<'py>, stacks: usize, slices: usize, seed: u64, stream: u64, first_ray: u64, n_rays: u64, max_events: u64, max_internal: u32, threads: Option<usize>)
        -> PyResult<(Bound<'py, PyArray2<u64>>, Bound<'py, PyArray1<u64>>, Bound<'py, PyArray1<u64>>, Bound<'py, PyArray1<u64>>)> {
        let h = CollectorHemisphere::new(stacks, slices).map_err(|e| to_py(py, e))?;
        let limits = Limits { max_events, max_internal };
        let run = || -> Result<BrdfTally, String> {
            run_with_threads(threads, || match &self.kind {
                Kind::Particulate(m) => measure_brdf(m, &h, seed, stream, first_ray, n_rays, &limits),
                Kind::Isotropic(m) => measure_brdf(m, &h, seed, stream, first_ray, n_rays, &limits),
                Kind::Lambertian(m) => measure_brdf(m, &h, seed, stream, first_ray, n_rays, &limits),
            })
        };
        let t = py.detach(run).map_err(PyRuntimeError::new_err)?;
        let r = t.n_patches;
        let counts = Array2::from_shape_vec((r, r), t.counts).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((counts.into_pyarray(py), t.absorbed.into_pyarray(py), t.launched.into_pyarray(py), t.lost.into_pyarray(py)))
    }

    /// Fixed-incidence goniophotometer: light from zenith `theta_deg`, azimuth `phi_deg`.
    /// Returns (counts (r,), absorbed, launched, lost).
    #[pyo3(signature = (stacks, slices, theta_deg, phi_deg, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)]
    fn fixed_counts<'py>(&self, py: Python<'py>, stacks: usize, slices: usize, theta_deg: f64, phi_deg: f64, seed: u64, stream: u64, first_ray: u64, n_rays: u64, max_events: u64, max_internal: u32, threads: Option<usize>)
        -> PyResult<(Bound<'py, PyArray1<u64>>, u64, u64, u64)> {
        if !(0.0..90.0).contains(&theta_deg) || !phi_deg.is_finite() {
            return Err(to_py(py, SandlightError::parameter("incidence_deg", theta_deg, "must be in [0, 90) with a finite azimuth")));
        }
        let h = CollectorHemisphere::new(stacks, slices).map_err(|e| to_py(py, e))?;
        let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
        let toward_light = Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos());
        let limits = Limits { max_events, max_internal };
        let run = || -> Result<FixedIncidenceTally, String> {
            run_with_threads(threads, || match &self.kind {
                Kind::Particulate(m) => measure_fixed_incidence(m, &h, toward_light, seed, stream, first_ray, n_rays, &limits),
                Kind::Isotropic(m) => measure_fixed_incidence(m, &h, toward_light, seed, stream, first_ray, n_rays, &limits),
                Kind::Lambertian(m) => measure_fixed_incidence(m, &h, toward_light, seed, stream, first_ray, n_rays, &limits),
            })
        };
        let t = py.detach(run).map_err(PyRuntimeError::new_err)?;
        Ok((t.counts.into_pyarray(py), t.absorbed, t.launched, t.lost))
    }
}

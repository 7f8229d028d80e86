//! `sandlight._native.Medium`: a medium at one wavelength, and the runs over it.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyArray2};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use sandlight_core::driver::{directional_hemispherical, incident_direction, Rays};
use sandlight_core::error::SandlightError;
use sandlight_core::gonio::measure::{measure_brdf, measure_fixed_incidence};
use sandlight_core::gonio::{BrdfTally, CollectorHemisphere, FixedIncidenceTally};
use sandlight_core::math::Vec3;
use std::sync::Arc;

use sandlight_core::deposition::deposit;
use sandlight_core::explicit::{Explicit, Scene};
use sandlight_core::medium::{IsotropicScatterers, LambertianSurface, ParticleType, Particulate};
use sandlight_core::memory::{Memory, WithMemory};
use sandlight_core::packing::{PackedParticle, Packing, PackingParams};
use sandlight_core::particle::{Coating, ParticleOptics, PoreOptics};
use sandlight_core::phase_table::PhaseTable;
use sandlight_core::sizes::QuantileTable;
use sandlight_core::transport::Limits;
use sandlight_core::volume_scatterer::{VolumeOptics, VolumeScatterer};

use crate::errors::to_py;
use crate::pool::run_with_threads;

pub enum Kind {
    Particulate(WithMemory),
    Explicit(Explicit),
    Isotropic(IsotropicScatterers),
    Lambertian(LambertianSurface),
}

#[pyclass(frozen, name = "Medium", module = "sandlight._native")]
pub struct PyMedium {
    pub kind: Kind,
}

/// `$body` with `$m` bound to the medium of `$kind` (a `&Kind`), whatever its type: the runs are
/// generic over the medium, so each variant is its own instance.
macro_rules! on_medium {
    ($kind:expr, $m:ident => $body:expr) => {
        match $kind {
            Kind::Particulate($m) => $body,
            Kind::Explicit($m) => $body,
            Kind::Isotropic($m) => $body,
            Kind::Lambertian($m) => $body,
        }
    };
}

/// The incident direction of a directional-hemispherical run from zenith `theta_deg`, refused
/// (naming the Python parameter `incidence_deg`) outside [0, 90) degrees.
pub(crate) fn checked_incidence(py: Python<'_>, theta_deg: f64) -> PyResult<Vec3> {
    if !(0.0..90.0).contains(&theta_deg) {
        return Err(to_py(py, SandlightError::parameter("incidence_deg", theta_deg, "must be in [0, 90)")));
    }
    Ok(incident_direction(theta_deg.to_radians()))
}

/// The unit direction toward a light at zenith `theta_deg` ∈ [0, 90) and azimuth `phi_deg`
/// (finite), as the fixed-incidence goniophotometer takes it.
pub(crate) fn checked_light(py: Python<'_>, theta_deg: f64, phi_deg: f64) -> PyResult<Vec3> {
    if !(0.0..90.0).contains(&theta_deg) || !phi_deg.is_finite() {
        return Err(to_py(
            py,
            SandlightError::parameter("incidence_deg", theta_deg, "must be in [0, 90) with a finite azimuth"),
        ));
    }
    let (t, p) = (theta_deg.to_radians(), phi_deg.to_radians());
    Ok(Vec3::new(t.sin() * p.cos(), t.sin() * p.sin(), t.cos()))
}

/// The rays `first_ray .. first_ray + n_rays` of stream `stream` of `seed`, and each path's limits
/// (particle events, internal reflections), as the Python run methods give them.
pub(crate) fn rays_and_limits(
    seed: u64,
    stream: u64,
    first_ray: u64,
    n_rays: u64,
    max_events: u64,
    max_internal: u32,
) -> (Rays, Limits) {
    (Rays { seed, stream, first: first_ray, n: n_rays }, Limits { max_events, max_internal })
}

/// A volume scatterer's optics in one pore medium as Python gives it: (Q̄_ext/Q_max, ω, phase
/// nodes μ, phase values).
type VolumeOpticsArgs = (f64, f64, Vec<f64>, Vec<f64>);

/// A particle type traced as a volume scatterer as Python gives it: (Q_max, optics relative to
/// air, optics relative to water or None).
type VolumeScattererArgs = (f64, VolumeOpticsArgs, Option<VolumeOpticsArgs>);

fn volume_optics((extinction, albedo, mu, p): VolumeOpticsArgs) -> Result<VolumeOptics, SandlightError> {
    VolumeOptics::new(extinction, albedo, PhaseTable::new(mu, p)?)
}

fn volume_scatterer((majorant, air, water): VolumeScattererArgs) -> Result<VolumeScatterer, SandlightError> {
    VolumeScatterer::new(majorant, volume_optics(air)?, water.map(volume_optics).transpose()?)
}

fn same_len(name: &str, got: usize, want: usize) -> Result<(), SandlightError> {
    if got == want {
        Ok(())
    } else {
        Err(SandlightError::parameter(name, format!("length {got}"), &format!("one entry per particle type ({want})")))
    }
}

#[pymethods]
impl PyMedium {
    /// A sand sample at one wavelength; see `sandlight.physics.medium` for the meaning of each
    /// array (one entry per particle type).
    #[staticmethod]
    #[pyo3(signature = (probabilities, size_quantiles_mm, aspect_ratios, core_n, core_k, core_alpha_per_mm,
                        coating_n, coating_alpha_per_mm, coating_thickness_mm, mean_free_path_mm,
                        water_n, water_alpha_per_mm, film_thickness_mm, water_filled_probability, depth_mm, memory = "none",
                        film_coverage = 1.0, coating_scattering_per_mm = None, coating_asymmetry = None,
                        coating_coverage = None, volume_scatterers = None, core_scattering_per_mm = None))]
    #[allow(clippy::too_many_arguments)] // one argument per Python parameter
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
        memory: &str,
        film_coverage: f64,
        coating_scattering_per_mm: Option<Vec<f64>>,
        coating_asymmetry: Option<Vec<f64>>,
        coating_coverage: Option<Vec<f64>>,
        volume_scatterers: Option<Vec<Option<VolumeScattererArgs>>>,
        core_scattering_per_mm: Option<Vec<f64>>,
    ) -> PyResult<Self> {
        let build = || -> Result<WithMemory, SandlightError> {
            let n = probabilities.len();
            // A uniform (non-scattering) coating unless the pigment's scattering is given.
            let coating_scattering_per_mm = coating_scattering_per_mm.unwrap_or_else(|| vec![0.0; n]);
            let coating_asymmetry = coating_asymmetry.unwrap_or_else(|| vec![0.0; n]);
            // The whole surface coated unless the coverage is given.
            let coating_coverage = coating_coverage.unwrap_or_else(|| vec![1.0; n]);
            same_len("coating_coverage", coating_coverage.len(), n)?;
            // Clear cores (no inclusions) unless their scattering is given.
            let core_scattering_per_mm = core_scattering_per_mm.unwrap_or_else(|| vec![0.0; n]);
            same_len("core_scattering_per_mm", core_scattering_per_mm.len(), n)?;
            if let Some(bad) = core_scattering_per_mm.iter().find(|s| !(s.is_finite() && **s >= 0.0)) {
                return Err(SandlightError::parameter("core_scattering_per_mm", bad, "finite values ≥ 0 (mm⁻¹)"));
            }
            same_len("coating_scattering_per_mm", coating_scattering_per_mm.len(), n)?;
            same_len("coating_asymmetry", coating_asymmetry.len(), n)?;
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
                let coating = (coating_thickness_mm[i] > 0.0).then_some(Coating {
                    n: coating_n[i],
                    alpha_per_mm: coating_alpha_per_mm[i],
                    thickness_mm: coating_thickness_mm[i],
                    scattering_per_mm: coating_scattering_per_mm[i],
                    asymmetry: coating_asymmetry[i],
                    coverage: coating_coverage[i],
                });
                types.push(ParticleType {
                    probability: probabilities[i],
                    sizes: QuantileTable::new(size_quantiles_mm[i].clone())?,
                    aspect_ratio: aspect_ratios[i],
                    optics: ParticleOptics {
                        core_n: core_n[i],
                        core_k: core_k[i],
                        core_alpha_per_mm: core_alpha_per_mm[i],
                        core_scattering_per_mm: core_scattering_per_mm[i],
                        coating,
                        wets: true,
                    },
                });
            }
            let pore =
                PoreOptics { water_n, water_alpha_per_mm, film_thickness_mm, film_coverage, water_filled_probability };
            let memory = match memory {
                "none" => Memory::None,
                "channel" => Memory::Channel,
                "cut" => Memory::Cut,
                "packed" => Memory::Packed,
                other => {
                    return Err(SandlightError::parameter("memory", other, "'none', 'channel', 'cut' or 'packed'"))
                }
            };
            let mut medium = Particulate::new(types, mean_free_path_mm, pore, depth_mm)?;
            // Volume scatterers (Mie fine particles) only when some type is one, so that every
            // other medium is built exactly as before.
            if let Some(v) = volume_scatterers.filter(|v| v.iter().any(Option::is_some)) {
                if matches!(memory, Memory::Channel | Memory::Cut) {
                    return Err(SandlightError::parameter(
                        "memory",
                        format!("{memory:?}").to_lowercase(),
                        "'none' or 'packed' with volume scatterers (particle_optics='mie')",
                    ));
                }
                let v = v.into_iter().map(|s| s.map(volume_scatterer).transpose()).collect::<Result<_, _>>()?;
                medium = medium.with_volume_scatterers(v)?;
            }
            Ok(WithMemory::new(medium, memory))
        };
        build().map(|p| PyMedium { kind: Kind::Particulate(p) }).map_err(|e| to_py(py, e))
    }

    /// This sand medium traced through the explicit packing `packing` instead of on the fly
    /// (the packing must come from a medium with the same particle types). Rays deeper than
    /// `bottom_mm` below the cut plane count as transmitted.
    #[pyo3(signature = (packing, bottom_mm = f64::INFINITY))]
    fn explicit(&self, py: Python<'_>, packing: &PyPacking, bottom_mm: f64) -> PyResult<Self> {
        let Kind::Particulate(m) = &self.kind else {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "medium",
                    "a reference medium",
                    "explicit geometry needs a sand (particulate) medium",
                ),
            ));
        };
        if m.memory != Memory::None {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "memory",
                    format!("{:?}", m.memory),
                    "'none' for explicit geometry (memory is a model of the on-the-fly engine)",
                ),
            ));
        }
        Explicit::new(m.medium.clone(), packing.scene.clone(), bottom_mm)
            .map(|e| PyMedium { kind: Kind::Explicit(e) })
            .map_err(|e| to_py(py, e))
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
    ) -> PyResult<(u64, u64, u64, u64, u64, u64)> {
        let dir = checked_incidence(py, theta_deg)?;
        let (rays, limits) = rays_and_limits(seed, stream, first_ray, n_rays, max_events, max_internal);
        let run = || -> Result<_, String> {
            run_with_threads(threads, || on_medium!(&self.kind, m => directional_hemispherical(m, dir, rays, &limits)))
        };
        let c = py.detach(run).map_err(PyRuntimeError::new_err)?;
        Ok((c.launched, c.escaped, c.absorbed, c.transmitted, c.capped, c.events))
    }

    /// Uniform-incidence goniophotometer trials `first_ray .. first_ray + n_rays` on a
    /// `stacks` × `slices` hemisphere. Returns (counts (r, r), absorbed (r,), launched (r,),
    /// lost (r,)) as uint64 arrays. The GIL is released.
    #[pyo3(signature = (stacks, slices, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)] // the Python signature and the tuple of arrays it returns
    fn brdf_counts<'py>(
        &self,
        py: Python<'py>,
        stacks: usize,
        slices: usize,
        seed: u64,
        stream: u64,
        first_ray: u64,
        n_rays: u64,
        max_events: u64,
        max_internal: u32,
        threads: Option<usize>,
    ) -> PyResult<(
        Bound<'py, PyArray2<u64>>,
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<u64>>,
        Bound<'py, PyArray1<u64>>,
    )> {
        let h = CollectorHemisphere::new(stacks, slices).map_err(|e| to_py(py, e))?;
        let (rays, limits) = rays_and_limits(seed, stream, first_ray, n_rays, max_events, max_internal);
        let run = || -> Result<BrdfTally, String> {
            run_with_threads(threads, || on_medium!(&self.kind, m => measure_brdf(m, &h, rays, &limits)))
        };
        let t = py.detach(run).map_err(PyRuntimeError::new_err)?;
        let r = t.n_patches;
        let counts = Array2::from_shape_vec((r, r), t.counts).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((counts.into_pyarray(py), t.absorbed.into_pyarray(py), t.launched.into_pyarray(py), t.lost.into_pyarray(py)))
    }

    /// Fixed-incidence goniophotometer: light from zenith `theta_deg`, azimuth `phi_deg`.
    /// Returns (counts (r,), absorbed, launched, lost).
    #[pyo3(signature = (stacks, slices, theta_deg, phi_deg, seed, stream, first_ray, n_rays, max_events, max_internal, threads = None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)] // the Python signature and the tuple of arrays it returns
    fn fixed_counts<'py>(
        &self,
        py: Python<'py>,
        stacks: usize,
        slices: usize,
        theta_deg: f64,
        phi_deg: f64,
        seed: u64,
        stream: u64,
        first_ray: u64,
        n_rays: u64,
        max_events: u64,
        max_internal: u32,
        threads: Option<usize>,
    ) -> PyResult<(Bound<'py, PyArray1<u64>>, u64, u64, u64)> {
        let toward_light = checked_light(py, theta_deg, phi_deg)?;
        let h = CollectorHemisphere::new(stacks, slices).map_err(|e| to_py(py, e))?;
        let (rays, limits) = rays_and_limits(seed, stream, first_ray, n_rays, max_events, max_internal);
        let run = || -> Result<FixedIncidenceTally, String> {
            run_with_threads(
                threads,
                || on_medium!(&self.kind, m => measure_fixed_incidence(m, &h, toward_light, rays, &limits)),
            )
        };
        let t = py.detach(run).map_err(PyRuntimeError::new_err)?;
        Ok((t.counts.into_pyarray(py), t.absorbed, t.launched, t.lost))
    }
}

/// `sandlight._native.Packing`: a periodic random dense packing of a sand medium's grains,
/// cut through a plane of centres and optionally with a gravity-settled layer on the cut, with
/// its ray-tracing grid (wavelength independent; see `sandlight_core::packing`, `deposition`).
#[pyclass(frozen, name = "Packing", module = "sandlight._native")]
pub struct PyPacking {
    pub scene: Arc<Scene>,
}

#[pymethods]
impl PyPacking {
    /// Packs the grains of the sand `medium` (any wavelength) in a box `lateral_mm` wide and
    /// about `depth_mm` high, periodic in x, y and z. `surface` 'cut' keeps the grains with
    /// centres below the top of the box; 'settled' also deposits grains on that cut under
    /// gravity, as much solid as `settled_thickness_mm` of the bulk packing. The GIL is released.
    #[staticmethod]
    #[pyo3(signature = (medium, lateral_mm, depth_mm, seed = 0, fines_below_mm = 0.05, max_particles = 400_000, overlap_tolerance = 1e-3, max_sweeps = 20_000, surface = "cut", settled_thickness_mm = None))]
    #[allow(clippy::too_many_arguments)] // one argument per Python parameter
    fn generate(
        py: Python<'_>,
        medium: &PyMedium,
        lateral_mm: f64,
        depth_mm: f64,
        seed: u64,
        fines_below_mm: f64,
        max_particles: usize,
        overlap_tolerance: f64,
        max_sweeps: usize,
        surface: &str,
        settled_thickness_mm: Option<f64>,
    ) -> PyResult<Self> {
        let Kind::Particulate(m) = &medium.kind else {
            return Err(to_py(
                py,
                SandlightError::parameter("medium", "a reference medium", "a sand (particulate) medium"),
            ));
        };
        let settled = match (surface, settled_thickness_mm) {
            ("cut", None) => None,
            ("settled", Some(t)) => Some(t),
            ("cut", Some(t)) => {
                return Err(to_py(py, SandlightError::parameter("settled_thickness_mm", t, "None for surface 'cut'")))
            }
            ("settled", None) => {
                return Err(to_py(
                    py,
                    SandlightError::parameter(
                        "settled_thickness_mm",
                        "None",
                        "a thickness > 0 (mm) for surface 'settled'",
                    ),
                ))
            }
            (other, _) => return Err(to_py(py, SandlightError::parameter("surface", other, "'cut' or 'settled'"))),
        };
        let params =
            PackingParams { lateral_mm, depth_mm, fines_below_mm, seed, max_particles, max_sweeps, overlap_tolerance };
        let m = m.medium.clone();
        let made = py.detach(move || -> Result<Arc<Scene>, SandlightError> {
            let packing = Packing::generate(&m, &params)?;
            let grains = match settled {
                Some(t) => deposit(&packing, t, seed)?,
                None => Vec::new(),
            };
            Ok(Arc::new(Scene::with_deposit(packing, grains)))
        });
        made.map(|scene| PyPacking { scene }).map_err(|e| to_py(py, e))
    }

    /// 'cut' or 'settled'.
    #[getter]
    fn surface(&self) -> &'static str {
        if self.scene.deposit.is_empty() {
            "cut"
        } else {
            "settled"
        }
    }
    /// Grains settled on the cut (0 for the cut surface).
    #[getter]
    fn n_deposited(&self) -> usize {
        self.scene.deposit.len()
    }
    /// Height (mm) of the plane where rays start and escape, above every grain.
    #[getter]
    fn top_mm(&self) -> f64 {
        self.scene.top_mm
    }
    /// Heights (mm) where `n_points` vertical lines at random (x, y) first enter a grain.
    fn surface_heights<'py>(&self, py: Python<'py>, n_points: usize, seed: u64) -> Bound<'py, PyArray1<f64>> {
        py.detach(|| self.scene.surface_heights(n_points, seed)).into_pyarray(py)
    }
    /// (porosity, overlap) at each of `heights` (mm): fractions of `n_points` random points of
    /// that plane in no grain of the sample and in two or more.
    fn porosity_profile<'py>(
        &self,
        py: Python<'py>,
        heights: Vec<f64>,
        n_points: usize,
        seed: u64,
    ) -> (Bound<'py, PyArray1<f64>>, Bound<'py, PyArray1<f64>>) {
        let (empty, multiple): (Vec<f64>, Vec<f64>) =
            py.detach(|| self.scene.porosity_profile(&heights, n_points, seed)).into_iter().unzip();
        (empty.into_pyarray(py), multiple.into_pyarray(py))
    }
    /// Centres (N, 3) in mm and volume-equivalent diameters (N,) in mm of the settled grains.
    fn deposited<'py>(&self, py: Python<'py>) -> (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>) {
        centres_and_diameters(py, &self.scene.deposit)
    }

    #[getter]
    fn n_particles(&self) -> usize {
        self.scene.packing.particles.len()
    }
    /// Σ grain volume / box volume (packed types only).
    #[getter]
    fn packing_fraction(&self) -> f64 {
        self.scene.packing.packing_fraction
    }
    /// The sample porosity implied by the medium's mean free path.
    #[getter]
    fn sample_porosity(&self) -> f64 {
        self.scene.packing.populations.porosity
    }
    /// Whether each particle type is packed (False: fines, on the fly in the pores).
    #[getter]
    fn packed_types(&self) -> Vec<bool> {
        self.scene.packing.populations.packed.clone()
    }
    /// Box periods (L, L, H) in mm.
    #[getter]
    fn period_mm(&self) -> (f64, f64, f64) {
        let p = self.scene.packing.period;
        (p.x, p.y, p.z)
    }
    /// Largest overlap along a centre line, as a fraction of the smaller diameter.
    #[getter]
    fn max_overlap(&self) -> f64 {
        self.scene.packing.max_overlap
    }
    #[getter]
    fn sweeps(&self) -> usize {
        self.scene.packing.sweeps
    }
    /// Bytes of particles, shapes and grid.
    #[getter]
    fn memory_bytes(&self) -> usize {
        self.scene.memory_bytes()
    }
    /// (fraction of points in no grain, fraction in two or more) from `n_points` random points.
    fn point_statistics(&self, py: Python<'_>, n_points: usize, seed: u64) -> (f64, f64) {
        py.detach(|| self.scene.packing.point_statistics(n_points, seed))
    }
    /// Pore chord lengths (mm) along random lines (see `Scene::pore_chords`).
    fn pore_chords<'py>(
        &self,
        py: Python<'py>,
        n_lines: usize,
        per_line: usize,
        seed: u64,
    ) -> Bound<'py, PyArray1<f64>> {
        py.detach(|| self.scene.pore_chords(n_lines, per_line, seed)).into_pyarray(py)
    }
    /// Centres (N, 3) in mm and volume-equivalent diameters (N,) in mm of the periodic packing.
    fn particles<'py>(&self, py: Python<'py>) -> (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>) {
        centres_and_diameters(py, &self.scene.packing.particles)
    }
}

fn centres_and_diameters<'py>(
    py: Python<'py>,
    ps: &[PackedParticle],
) -> (Bound<'py, PyArray2<f64>>, Bound<'py, PyArray1<f64>>) {
    let mut c = Array2::<f64>::zeros((ps.len(), 3));
    for (i, p) in ps.iter().enumerate() {
        c[[i, 0]] = p.centre.x;
        c[[i, 1]] = p.centre.y;
        c[[i, 2]] = p.centre.z;
    }
    (c.into_pyarray(py), ps.iter().map(|p| p.diameter_mm).collect::<Vec<_>>().into_pyarray(py))
}

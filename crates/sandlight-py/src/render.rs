//! Bindings of the renderer (`sandlight_core::render`). The scene description, validation with
//! user-facing messages, colour and files live in `python/sandlight/render`; this file only
//! converts arrays, releases the GIL and maps errors.

use numpy::ndarray::{Array2, Array3};
use numpy::{
    IntoPyArray, PyArray1, PyArray2, PyArray3, PyReadonlyArray2, PyReadonlyArray3, PyReadonlyArrayDyn,
    PyUntypedArrayMethods,
};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use sandlight_core::math::Vec3;
use sandlight_core::render::brdf::{BrdfSampling, BrdfStack};
use sandlight_core::render::camera::Camera;
use sandlight_core::render::environment::Environment;
use sandlight_core::render::terrain::{Heightfield, MaterialMap, Terrain};
use sandlight_core::render::{render_rows, Estimator, Heuristic, Scene, Settings};
use sandlight_core::SandlightError;

use crate::errors::to_py;
use crate::pool::run_with_threads;

fn vec3(name: &str, v: &[f64]) -> Result<[f64; 3], SandlightError> {
    if v.len() == 3 {
        Ok([v[0], v[1], v[2]])
    } else {
        Err(SandlightError::parameter(name, format!("{v:?}"), "a 3-vector"))
    }
}

fn pair(name: &str, v: &[f64]) -> Result<(f64, f64), SandlightError> {
    if v.len() == 2 {
        Ok((v[0], v[1]))
    } else {
        Err(SandlightError::parameter(name, format!("{v:?}"), "a pair (x, y)"))
    }
}

fn contiguous<'a, T: numpy::Element, D: numpy::ndarray::Dimension>(
    name: &str,
    a: &'a numpy::PyReadonlyArray<'_, T, D>,
) -> Result<&'a [T], SandlightError> {
    a.as_slice().map_err(|_| SandlightError::parameter(name, "a non-contiguous array", "a C-contiguous array"))
}

/// A scene ready to render: `RenderScene(...)` copies the arrays once; `render_rows` can then be
/// called for any row range and thread count.
#[pyclass(frozen, name = "RenderScene", module = "sandlight._native")]
pub struct PyRenderScene {
    scene: Scene,
}

#[pymethods]
impl PyRenderScene {
    /// Arguments (all arrays C-contiguous):
    /// camera_origin, camera_forward, camera_right, camera_up: 3-vectors (right/up scaled by the
    /// half-extent of the image plane at unit distance); width, height: pixels.
    /// sky_radiance: float32 (n_theta, n_phi, n_bands), W m⁻² sr⁻¹ nm⁻¹ at cell centres;
    /// sun_direction: 3-vector; sun_solid_angle_sr; sun_radiance: float64 (n_bands,).
    /// brdf: float32 (levels, n_mu_i, n_mu_o, n_dphi, n_bands) in sr⁻¹; mu_i, mu_o, dphi: axes.
    /// terrain: "plane" (plane_z) or "heightfield" (heights float32 (ny, nx), origin (x0, y0),
    /// spacing (dx, dy), wrap, outside, far_m). material: float32 (ny, nx) level coordinates or
    /// None (level 0), with material_origin, material_spacing, material_wrap.
    /// estimator: "mis" | "brdf" | "light"; sampling: "table" | "cosine"; heuristic: "power" |
    /// "balance"; max_bounces ≥ 1.
    #[new]
    #[pyo3(signature = (*, camera_origin, camera_forward, camera_right, camera_up, width, height,
                        sky_radiance, sun_direction, sun_solid_angle_sr, sun_radiance,
                        brdf, mu_i, mu_o, dphi,
                        terrain, plane_z = 0.0, heights = None, origin = None, spacing = None, wrap = false, outside = 0.0, far_m = 1000.0,
                        material = None, material_origin = None, material_spacing = None, material_wrap = false,
                        estimator = "mis", sampling = "table", heuristic = "power", max_bounces = 1))]
    #[allow(clippy::too_many_arguments)] // one argument per Python parameter
    fn new(
        py: Python<'_>,
        camera_origin: Vec<f64>,
        camera_forward: Vec<f64>,
        camera_right: Vec<f64>,
        camera_up: Vec<f64>,
        width: usize,
        height: usize,
        sky_radiance: PyReadonlyArray3<'_, f32>,
        sun_direction: Vec<f64>,
        sun_solid_angle_sr: f64,
        sun_radiance: Vec<f64>,
        brdf: PyReadonlyArrayDyn<'_, f32>,
        mu_i: Vec<f64>,
        mu_o: Vec<f64>,
        dphi: Vec<f64>,
        terrain: &str,
        plane_z: f64,
        heights: Option<PyReadonlyArray2<'_, f32>>,
        origin: Option<Vec<f64>>,
        spacing: Option<Vec<f64>>,
        wrap: bool,
        outside: f64,
        far_m: f64,
        material: Option<PyReadonlyArray2<'_, f32>>,
        material_origin: Option<Vec<f64>>,
        material_spacing: Option<Vec<f64>>,
        material_wrap: bool,
        estimator: &str,
        sampling: &str,
        heuristic: &str,
        max_bounces: u32,
    ) -> PyResult<Self> {
        let build = || -> Result<Scene, SandlightError> {
            let camera = Camera::new(
                vec3("camera_origin", &camera_origin)?,
                vec3("camera_forward", &camera_forward)?,
                vec3("camera_right", &camera_right)?,
                vec3("camera_up", &camera_up)?,
                width,
                height,
            )?;
            let sky_shape = sky_radiance.shape().to_vec();
            let environment = Environment::new(
                sky_shape[0],
                sky_shape[1],
                sky_shape[2],
                contiguous("sky_radiance", &sky_radiance)?.to_vec(),
                vec3("sun_direction", &sun_direction)?,
                sun_solid_angle_sr,
                &sun_radiance,
            )?;
            let bshape = brdf.shape().to_vec();
            if bshape.len() != 5 || bshape[1] != mu_i.len() || bshape[2] != mu_o.len() || bshape[3] != dphi.len() {
                return Err(SandlightError::parameter(
                    "brdf",
                    format!("array of shape {bshape:?}"),
                    "shape (levels, len(mu_i), len(mu_o), len(dphi), bands)",
                ));
            }
            if bshape[4] != sky_shape[2] || bshape[4] != sun_radiance.len() {
                return Err(SandlightError::parameter(
                    "brdf",
                    format!("{} bands", bshape[4]),
                    &format!("the sky's {} bands and the sun's {}", sky_shape[2], sun_radiance.len()),
                ));
            }
            let brdf = BrdfStack::new(
                bshape[0],
                mu_i.clone(),
                mu_o.clone(),
                dphi.clone(),
                bshape[4],
                contiguous("brdf", &brdf)?.to_vec(),
            )?;
            let terrain = match terrain {
                "plane" => {
                    if !plane_z.is_finite() {
                        return Err(SandlightError::parameter("plane_z", plane_z, "a finite height in metres"));
                    }
                    Terrain::Plane { z: plane_z }
                }
                "heightfield" => {
                    let h = heights.as_ref().ok_or_else(|| {
                        SandlightError::parameter("heights", "None", "an array for a heightfield terrain")
                    })?;
                    let (ny, nx) = (h.shape()[0], h.shape()[1]);
                    let (x0, y0) = pair("origin", origin.as_deref().unwrap_or(&[0.0, 0.0]))?;
                    let (dx, dy) = pair("spacing", spacing.as_deref().unwrap_or(&[1.0, 1.0]))?;
                    Terrain::Heightfield(Box::new(Heightfield::new(
                        nx,
                        ny,
                        x0,
                        y0,
                        dx,
                        dy,
                        contiguous("heights", h)?.to_vec(),
                        wrap,
                        outside,
                        far_m,
                    )?))
                }
                other => return Err(SandlightError::parameter("terrain", other, "\"plane\" or \"heightfield\"")),
            };
            let material = match material.as_ref() {
                None => MaterialMap::constant(0.0),
                Some(m) => {
                    let (ny, nx) = (m.shape()[0], m.shape()[1]);
                    let (x0, y0) = pair("material_origin", material_origin.as_deref().unwrap_or(&[0.0, 0.0]))?;
                    let (dx, dy) = pair("material_spacing", material_spacing.as_deref().unwrap_or(&[1.0, 1.0]))?;
                    MaterialMap::new(
                        nx,
                        ny,
                        x0,
                        y0,
                        dx,
                        dy,
                        contiguous("material", m)?.to_vec(),
                        material_wrap,
                        bshape[0],
                    )?
                }
            };
            let estimator = match estimator {
                "mis" => Estimator::Mis,
                "brdf" => Estimator::Brdf,
                "light" => Estimator::Light,
                other => return Err(SandlightError::parameter("estimator", other, "\"mis\", \"brdf\" or \"light\"")),
            };
            let sampling = match sampling {
                "table" => BrdfSampling::Table,
                "cosine" => BrdfSampling::Cosine,
                other => return Err(SandlightError::parameter("sampling", other, "\"table\" or \"cosine\"")),
            };
            let heuristic = match heuristic {
                "power" => Heuristic::Power,
                "balance" => Heuristic::Balance,
                other => return Err(SandlightError::parameter("heuristic", other, "\"power\" or \"balance\"")),
            };
            if max_bounces == 0 {
                return Err(SandlightError::parameter("max_bounces", max_bounces, "at least 1"));
            }
            Ok(Scene {
                camera,
                environment,
                brdf,
                terrain,
                material,
                settings: Settings { estimator, sampling, heuristic, max_bounces },
            })
        };
        build().map(|scene| PyRenderScene { scene }).map_err(|e| to_py(py, e))
    }

    #[getter]
    fn n_bands(&self) -> usize {
        self.scene.brdf.n_bands()
    }

    /// Renders rows row0 .. row0 + n_rows at `spp` samples per pixel with the GIL released.
    /// Returns (radiance float32 (n_rows, width, n_bands), coverage float32 (n_rows, width)).
    #[pyo3(signature = (row0, n_rows, spp, seed, frame = 0, threads = None))]
    #[allow(clippy::too_many_arguments, clippy::type_complexity)] // the Python signature and the tuple of arrays it returns
    fn render_rows<'py>(
        &self,
        py: Python<'py>,
        row0: usize,
        n_rows: usize,
        spp: u32,
        seed: u64,
        frame: u64,
        threads: Option<usize>,
    ) -> PyResult<(Bound<'py, PyArray3<f32>>, Bound<'py, PyArray2<f32>>)> {
        let (w, h, nb) = (self.scene.camera.width, self.scene.camera.height, self.scene.brdf.n_bands());
        if row0 + n_rows > h || spp == 0 {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "rows",
                    format!("{row0}..{} at {spp} spp", row0 + n_rows),
                    &format!("rows within 0..{h} and spp ≥ 1"),
                ),
            ));
        }
        let scene = &self.scene;
        let (rad, cov) = py
            .detach(|| run_with_threads(threads, || render_rows(scene, row0, n_rows, spp, seed, frame)))
            .map_err(PyRuntimeError::new_err)?;
        let rad = Array3::from_shape_vec((n_rows, w, nb), rad).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        let cov = Array2::from_shape_vec((n_rows, w), cov).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
        Ok((rad.into_pyarray(py), cov.into_pyarray(py)))
    }

    /// First terrain hit of rays (origins, dirs: float64 (N, 3)): returns (t (N,), inf for none;
    /// normals (N, 3), zero for none). For tests and picking.
    #[allow(clippy::type_complexity)] // the tuple of arrays Python receives
    fn intersect<'py>(
        &self,
        py: Python<'py>,
        origins: PyReadonlyArray2<'py, f64>,
        dirs: PyReadonlyArray2<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArray1<f64>>, Bound<'py, PyArray2<f64>>)> {
        if origins.shape()[1] != 3 || dirs.shape() != origins.shape() {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "origins/dirs",
                    format!("shapes {:?} and {:?}", origins.shape(), dirs.shape()),
                    "two arrays of the same shape (N, 3)",
                ),
            ));
        }
        let (o, d) = (origins.as_array(), dirs.as_array());
        let n = o.shape()[0];
        let mut t = vec![f64::INFINITY; n];
        let mut normals = Array2::<f64>::zeros((n, 3));
        for k in 0..n {
            let dir = Vec3::new(d[[k, 0]], d[[k, 1]], d[[k, 2]]).normalized();
            if let Some(hit) = self.scene.terrain.intersect(Vec3::new(o[[k, 0]], o[[k, 1]], o[[k, 2]]), dir, 0.0, false)
            {
                t[k] = hit.t;
                normals[[k, 0]] = hit.n.x;
                normals[[k, 1]] = hit.n.y;
                normals[[k, 2]] = hit.n.z;
            }
        }
        Ok((t.into_pyarray(py), normals.into_pyarray(py)))
    }
}

/// Adds the renderer to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyRenderScene>()?;
    Ok(())
}

//! Bindings of the virtual goniophotometer's geometry (`sandlight_core::gonio`). The Python
//! package `sandlight.gonio` wraps these; it holds no second implementation of the patch maths.

use numpy::ndarray::Array2;
use numpy::{IntoPyArray, PyArray1, PyReadonlyArray2, PyUntypedArrayMethods};
use pyo3::prelude::*;
use pyo3::types::PyDict;
use sandlight_core::gonio::CollectorHemisphere;
use sandlight_core::SandlightError;

use crate::errors;

fn hemisphere(py: Python<'_>, stacks: usize, slices: usize) -> PyResult<CollectorHemisphere> {
    CollectorHemisphere::new(stacks, slices).map_err(|e| errors::to_py(py, e))
}

/// Patch index of each direction.
///
/// Parameters: stacks, slices (the hemisphere); dirs, float64 array of shape (N, 3), directions
/// with z ≥ 0, not necessarily normalised. Returns int64 array of shape (N,). Directions slightly
/// below the horizon count as horizontal; zero or non-finite vectors give patch 0 (the Python
/// wrapper rejects them before calling).
#[pyfunction]
fn hemisphere_patch_index<'py>(
    py: Python<'py>,
    stacks: usize,
    slices: usize,
    dirs: PyReadonlyArray2<'py, f64>,
) -> PyResult<Bound<'py, PyArray1<i64>>> {
    let h = hemisphere(py, stacks, slices)?;
    if dirs.shape()[1] != 3 {
        return Err(errors::to_py(
            py,
            SandlightError::parameter(
                "dirs",
                format!("an array of shape {:?}", dirs.shape()),
                "must have shape (N, 3)",
            ),
        ));
    }
    let view = dirs.as_array();
    let out: Vec<i64> =
        py.detach(|| view.rows().into_iter().map(|d| h.patch_index([d[0], d[1], d[2]]) as i64).collect());
    Ok(out.into_pyarray(py))
}

/// Geometry of the collector hemisphere as numpy arrays.
///
/// Returns a dict with `centroids` (r, 3) unit vectors, `bounds` (r, 4) columns z0, z1, φ0, φ1
/// (cos θ and radians), `solid_angles` (r,) sr, `projected_solid_angles` (r,) sr, `band` (r,)
/// int64 (0 = cap, then 1..stacks−1 from the top down) and `slice` (r,) int64.
#[pyfunction]
fn hemisphere_geometry<'py>(py: Python<'py>, stacks: usize, slices: usize) -> PyResult<Bound<'py, PyDict>> {
    let h = hemisphere(py, stacks, slices)?;
    let r = h.n_patches();
    let mut centroids = Array2::<f64>::zeros((r, 3));
    let mut bounds = Array2::<f64>::zeros((r, 4));
    let mut solid = Vec::with_capacity(r);
    let mut projected = Vec::with_capacity(r);
    let mut band = Vec::with_capacity(r);
    let mut slice = Vec::with_capacity(r);
    for i in 0..r {
        let c = h.centroid(i);
        let b = h.bounds(i);
        for k in 0..3 {
            centroids[[i, k]] = c[k];
        }
        for (k, v) in [b.z0, b.z1, b.phi0, b.phi1].into_iter().enumerate() {
            bounds[[i, k]] = v;
        }
        solid.push(h.solid_angle(i));
        projected.push(h.projected_solid_angle(i));
        let (k, s) = h.band_slice(i);
        band.push(k as i64);
        slice.push(s as i64);
    }
    let d = PyDict::new(py);
    d.set_item("centroids", centroids.into_pyarray(py))?;
    d.set_item("bounds", bounds.into_pyarray(py))?;
    d.set_item("solid_angles", solid.into_pyarray(py))?;
    d.set_item("projected_solid_angles", projected.into_pyarray(py))?;
    d.set_item("band", band.into_pyarray(py))?;
    d.set_item("slice", slice.into_pyarray(py))?;
    Ok(d)
}

/// Adds the goniophotometer functions to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(hemisphere_patch_index, m)?)?;
    m.add_function(wrap_pyfunction!(hemisphere_geometry, m)?)?;
    Ok(())
}

//! Bindings of the fast BRDF evaluator (`sandlight_core::appearance`). `sandlight.appearance`
//! wraps it; the interpolant's definition is `sandlight.gonio.brdf.interpolate_band_grid`.

use numpy::ndarray::{Array2, ArrayD, IxDyn};
use numpy::{
    IntoPyArray, PyArray2, PyArrayDyn, PyReadonlyArray1, PyReadonlyArray2, PyReadonlyArrayDyn, PyUntypedArrayMethods,
};
use pyo3::exceptions::PyRuntimeError;
use pyo3::prelude::*;
use rayon::prelude::*;
use sandlight_core::appearance::{spectral_brdf, BandGrid};
use sandlight_core::SandlightError;

use crate::errors::to_py;
use crate::pool::run_with_threads;

/// Direction pairs per parallel work item (large enough to amortise scheduling).
const CHUNK: usize = 8192;

#[pyclass(frozen, name = "BandGridBrdf", module = "sandlight._native")]
pub struct PyBandGridBrdf {
    grid: BandGrid,
    /// Built from a stack of layers (4-D grid): weights and `evaluate_mu` carry a layer axis.
    stacked: bool,
}

fn check_dirs(name: &str, a: &PyReadonlyArray2<'_, f64>) -> Result<(), SandlightError> {
    if a.shape()[1] != 3 {
        return Err(SandlightError::parameter(
            name,
            format!("an array of shape {:?}", a.shape()),
            "must have shape (N, 3)",
        ));
    }
    Ok(())
}

#[pymethods]
impl PyBandGridBrdf {
    /// grid: float64 (stacks, stacks, slices) node values F[b_i, b_o, k], or (K, stacks, stacks,
    /// slices) for K layers on the same nodes; band_cos_theta: float64 (stacks,) node μ,
    /// decreasing (cap first); profile: float64 (stacks,) P at the nodes, or (K, stacks).
    #[new]
    fn new(
        py: Python<'_>,
        grid: PyReadonlyArrayDyn<'_, f64>,
        band_cos_theta: PyReadonlyArray1<'_, f64>,
        profile: PyReadonlyArrayDyn<'_, f64>,
    ) -> PyResult<Self> {
        let shape = grid.shape().to_vec();
        let stacked = shape.len() == 4;
        let (layers, cube) = if stacked { (shape[0], &shape[1..]) } else { (1, &shape[..]) };
        let profile_ok = if stacked { profile.shape() == [layers, cube[0]] } else { profile.ndim() == 1 };
        if !(shape.len() == 3 || stacked) || cube[0] != cube[1] {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "grid",
                    format!("shape {shape:?}"),
                    "must have shape (stacks, stacks, slices) or (layers, stacks, stacks, slices)",
                ),
            ));
        }
        if !profile_ok {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "profile",
                    format!("shape {:?}", profile.shape()),
                    "must have shape (stacks,), or (layers, stacks) for a stacked grid",
                ),
            ));
        }
        let values: Vec<f64> = grid.as_array().iter().copied().collect();
        let nodes: Vec<f64> = band_cos_theta.as_array().iter().copied().collect();
        let profile: Vec<f64> = profile.as_array().iter().copied().collect();
        let grid = BandGrid::new(cube[0], cube[2], &nodes, values, profile).map_err(|e| to_py(py, e))?;
        Ok(PyBandGridBrdf { grid, stacked })
    }

    /// Spectral BRDF of N direction pairs: out[p, w] = F(wi_p, wo_p)·a[w] + P(μ_i)P(μ_o)·b[w],
    /// or Σ_l F_l·a[w, l] + P_l P_l·b[w, l] for a stacked grid. wi, wo: float64 (N, 3),
    /// C-contiguous; a, b: float64 (W,), or (W, layers) C-contiguous for a stacked grid. Returns
    /// (N, W). 0 below the horizon, NaN for NaN directions; ParameterError for a zero or infinite
    /// direction. The GIL is released; `threads` > 1 splits the pairs over a rayon pool.
    #[pyo3(signature = (wi, wo, a, b, threads = None))]
    fn evaluate<'py>(
        &self,
        py: Python<'py>,
        wi: PyReadonlyArray2<'py, f64>,
        wo: PyReadonlyArray2<'py, f64>,
        a: PyReadonlyArrayDyn<'py, f64>,
        b: PyReadonlyArrayDyn<'py, f64>,
        threads: Option<usize>,
    ) -> PyResult<Bound<'py, PyArray2<f64>>> {
        let layers = self.grid.layers();
        let n_wl = a.shape().first().copied().unwrap_or(0);
        let want: &[usize] = if self.stacked { &[n_wl, layers] } else { &[n_wl] };
        for (name, x) in [("a", &a), ("b", &b)] {
            if x.shape() != want {
                return Err(to_py(
                    py,
                    SandlightError::parameter(
                        name,
                        format!("shape {:?}", x.shape()),
                        &format!(
                            "must have shape {want:?} (wavelengths{})",
                            if self.stacked { ", layers" } else { "" }
                        ),
                    ),
                ));
            }
        }
        check_dirs("wi", &wi).map_err(|e| to_py(py, e))?;
        check_dirs("wo", &wo).map_err(|e| to_py(py, e))?;
        let n = wi.shape()[0];
        if wo.shape()[0] != n {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "wo",
                    format!("{} rows", wo.shape()[0]),
                    &format!("must have as many rows as wi ({n})"),
                ),
            ));
        }
        let (x, y) = (wi.as_slice()?, wo.as_slice()?);
        let (sa, sb) = (a.as_slice()?, b.as_slice()?);
        let w = sa.len() / layers;
        let mut out = vec![0.0; n * w];
        let grid = &self.grid;
        let result = py.detach(|| -> Result<Result<(), (&'static str, usize)>, String> {
            match threads {
                Some(t) if t > 1 && w > 0 => run_with_threads(Some(t), || {
                    out.par_chunks_mut(CHUNK * w).enumerate().try_for_each(|(c, o)| {
                        let lo = c * CHUNK;
                        let hi = lo + o.len() / w;
                        spectral_brdf(grid, &x[3 * lo..3 * hi], &y[3 * lo..3 * hi], sa, sb, o)
                            .map_err(|(name, p)| (name, p + lo))
                    })
                }),
                _ => Ok(spectral_brdf(grid, x, y, sa, sb, &mut out)),
            }
        });
        match result {
            Err(msg) => Err(PyRuntimeError::new_err(msg)),
            Ok(Err((name, row))) => Err(to_py(
                py,
                SandlightError::parameter(name, format!("row {row}"), "directions must be non-zero and finite"),
            )),
            Ok(Ok(())) => {
                let arr = Array2::from_shape_vec((n, w), out).map_err(|e| PyRuntimeError::new_err(e.to_string()))?;
                Ok(arr.into_pyarray(py))
            }
        }
    }

    /// (F, P(μ_i)P(μ_o)) at (μ_i, μ_o, Δφ) for equal-length float64 arrays (no horizon test):
    /// each (P,), or (P, layers) for a stacked grid.
    #[allow(clippy::type_complexity)] // the tuple of arrays Python receives
    fn evaluate_mu<'py>(
        &self,
        py: Python<'py>,
        mu_i: PyReadonlyArray1<'py, f64>,
        mu_o: PyReadonlyArray1<'py, f64>,
        dphi: PyReadonlyArray1<'py, f64>,
    ) -> PyResult<(Bound<'py, PyArrayDyn<f64>>, Bound<'py, PyArrayDyn<f64>>)> {
        let (a, b, c) = (mu_i.as_array(), mu_o.as_array(), dphi.as_array());
        if a.len() != b.len() || a.len() != c.len() {
            return Err(to_py(
                py,
                SandlightError::parameter(
                    "mu_i, mu_o, dphi",
                    format!("lengths {}, {}, {}", a.len(), b.len(), c.len()),
                    "must have equal lengths",
                ),
            ));
        }
        let k = self.grid.layers();
        let (mut f, mut p) = (Vec::with_capacity(a.len() * k), Vec::with_capacity(a.len() * k));
        for i in 0..a.len() {
            let s = self.grid.stencil(a[i], b[i], c[i]);
            for l in 0..k {
                let (fl, pl) = self.grid.layer(&s, l);
                f.push(fl);
                p.push(pl);
            }
        }
        let dims = if self.stacked { vec![a.len(), k] } else { vec![a.len()] };
        let shaped =
            |v: Vec<f64>| ArrayD::from_shape_vec(IxDyn(&dims), v).map_err(|e| PyRuntimeError::new_err(e.to_string()));
        Ok((shaped(f)?.into_pyarray(py), shaped(p)?.into_pyarray(py)))
    }
}

/// Adds the appearance evaluator to the extension module.
pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_class::<PyBandGridBrdf>()?;
    Ok(())
}

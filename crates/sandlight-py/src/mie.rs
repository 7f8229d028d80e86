//! Bindings of the Lorenz–Mie solution (`sandlight_core::mie`). `sandlight.physics.mie` wraps
//! them (broadcasting, docstrings, checks of μ); the domains of m and x are checked here, by
//! the core.

use numpy::{Complex64, IntoPyArray, PyArray1, PyReadonlyArray1};
use pyo3::prelude::*;
use sandlight_core::mie::MieSolution;
use sandlight_core::SandlightError;

use crate::errors::to_py;

type Array<'py> = Bound<'py, PyArray1<f64>>;
type ComplexArray<'py> = Bound<'py, PyArray1<Complex64>>;

fn solve(py: Python<'_>, m_re: f64, m_im: f64, x: f64) -> PyResult<MieSolution> {
    MieSolution::new(Complex64::new(m_re, m_im), x).map_err(|e| to_py(py, e))
}

/// Efficiencies of spheres (m_re[i] + i m_im[i], x[i]), arrays of one length: (Q_ext, Q_sca,
/// Q_abs, g, albedo). The first sphere out of the domain raises ParameterError. The GIL is
/// released.
#[pyfunction]
fn mie_efficiencies<'py>(
    py: Python<'py>,
    m_re: PyReadonlyArray1<'py, f64>,
    m_im: PyReadonlyArray1<'py, f64>,
    x: PyReadonlyArray1<'py, f64>,
) -> PyResult<(Array<'py>, Array<'py>, Array<'py>, Array<'py>, Array<'py>)> {
    let (m_re, m_im, x) = (m_re.as_slice()?, m_im.as_slice()?, x.as_slice()?);
    if m_im.len() != m_re.len() || x.len() != m_re.len() {
        let got = format!("lengths {}, {}, {}", m_re.len(), m_im.len(), x.len());
        return Err(to_py(py, SandlightError::parameter("m, x", got, "arrays of one length")));
    }
    let run = || -> Result<[Vec<f64>; 5], SandlightError> {
        let mut out: [Vec<f64>; 5] = Default::default();
        for ((&n, &k), &x) in m_re.iter().zip(m_im).zip(x) {
            let e = MieSolution::new(Complex64::new(n, k), x)?.efficiencies();
            for (column, v) in out.iter_mut().zip([e.q_ext, e.q_sca, e.q_abs, e.g, e.albedo]) {
                column.push(v);
            }
        }
        Ok(out)
    };
    let [q_ext, q_sca, q_abs, g, albedo] = py.detach(run).map_err(|e| to_py(py, e))?;
    Ok((
        q_ext.into_pyarray(py),
        q_sca.into_pyarray(py),
        q_abs.into_pyarray(py),
        g.into_pyarray(py),
        albedo.into_pyarray(py),
    ))
}

/// `f(solution, μ)` for one sphere at each of the cosines `mu`, with the GIL released.
fn at_cosines<T: Send>(
    py: Python<'_>,
    (m_re, m_im, x): (f64, f64, f64),
    mu: &PyReadonlyArray1<'_, f64>,
    f: impl Fn(&MieSolution, f64) -> T + Sync,
) -> PyResult<Vec<T>> {
    let s = solve(py, m_re, m_im, x)?;
    let mu = mu.as_slice()?;
    Ok(py.detach(|| mu.iter().map(|&v| f(&s, v)).collect()))
}

/// Scattering amplitudes (S1, S2) of one sphere at the cosines `mu` (complex arrays, Bohren &
/// Huffman's convention).
#[pyfunction]
fn mie_amplitudes<'py>(
    py: Python<'py>,
    m_re: f64,
    m_im: f64,
    x: f64,
    mu: PyReadonlyArray1<'py, f64>,
) -> PyResult<(ComplexArray<'py>, ComplexArray<'py>)> {
    let (s1, s2): (Vec<Complex64>, Vec<Complex64>) =
        at_cosines(py, (m_re, m_im, x), &mu, |s, v| s.amplitudes(v))?.into_iter().unzip();
    Ok((s1.into_pyarray(py), s2.into_pyarray(py)))
}

/// Phase function p(μ) (sr⁻¹, ∫ p dΩ = 1) of one sphere at the cosines `mu`.
#[pyfunction]
fn mie_phase_function<'py>(
    py: Python<'py>,
    m_re: f64,
    m_im: f64,
    x: f64,
    mu: PyReadonlyArray1<'py, f64>,
) -> PyResult<Array<'py>> {
    Ok(at_cosines(py, (m_re, m_im, x), &mu, |s, v| s.phase_function(v))?.into_pyarray(py))
}

/// The sampling table of one sphere's phase function (`MieSolution::phase_table`): nodes μ_i,
/// normalised values p_i (sr⁻¹) and cumulative probabilities P(cos θ ≤ μ_i).
#[pyfunction]
fn mie_phase_table<'py>(
    py: Python<'py>,
    m_re: f64,
    m_im: f64,
    x: f64,
) -> PyResult<(Array<'py>, Array<'py>, Array<'py>)> {
    let s = solve(py, m_re, m_im, x)?;
    let t = py.detach(|| s.phase_table()).map_err(|e| to_py(py, e))?;
    Ok((
        t.nodes().to_vec().into_pyarray(py),
        t.values().to_vec().into_pyarray(py),
        t.cumulative().to_vec().into_pyarray(py),
    ))
}

pub fn register(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add_function(wrap_pyfunction!(mie_efficiencies, m)?)?;
    m.add_function(wrap_pyfunction!(mie_amplitudes, m)?)?;
    m.add_function(wrap_pyfunction!(mie_phase_function, m)?)?;
    m.add_function(wrap_pyfunction!(mie_phase_table, m)?)?;
    Ok(())
}

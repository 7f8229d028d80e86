//! PyO3 glue for sandlight-core. Only conversion, GIL handling and error mapping live here; the
//! user-facing API, docstrings and argument normalisation are in `python/sandlight`.

use pyo3::prelude::*;

mod appearance;
mod errors;
mod gonio;
mod medium;
mod mie;
mod pool;
mod render;
mod spectral;

#[pymodule]
fn _native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    m.add("__version__", env!("CARGO_PKG_VERSION"))?;
    m.add_class::<medium::PyMedium>()?;
    m.add_class::<medium::PyPacking>()?;
    m.add_class::<spectral::PySpectralGroup>()?;
    gonio::register(m)?;
    render::register(m)?;
    appearance::register(m)?;
    mie::register(m)?;
    Ok(())
}

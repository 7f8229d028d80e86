//! Maps `SandlightError` to the Python hierarchy in `sandlight.errors`.

use pyo3::prelude::*;
use sandlight_core::SandlightError;

pub fn to_py(py: Python<'_>, e: SandlightError) -> PyErr {
    let made = (|| -> PyResult<PyErr> {
        let errors = py.import("sandlight.errors")?;
        Ok(match e {
            SandlightError::Parameter { name, value, allowed } => {
                PyErr::from_value(errors.getattr("ParameterError")?.call1((name, value, allowed))?)
            }
            SandlightError::Cancelled => PyErr::from_value(errors.getattr("Cancelled")?.call1(("cancelled",))?),
        })
    })();
    made.unwrap_or_else(|err| err)
}

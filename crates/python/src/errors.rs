//! Python exceptions carrying the one-line messages of the Rust errors (the CLI's).

use pointillist_core::device::DeviceError;
use pointillist_plot::PlotError;
use pyo3::exceptions::{PyException, PyValueError};
use pyo3::prelude::*;

pyo3::create_exception!(
    pointillist,
    Error,
    PyException,
    "A call the device refused or a draw that failed (target size, viewport, stage index, \
     vertex buffer, backend); the message is the CLI's one line."
);

pyo3::create_exception!(
    pointillist,
    SceneError,
    Error,
    "A scene file that cannot be read or drawn; the message names file, line, column and key, \
     as `pointillist render` prints it."
);

/// A device error as [`Error`].
pub fn device_error(e: DeviceError) -> PyErr {
    Error::new_err(e.to_string())
}

/// A plot error: bad arguments as `ValueError`, a refused device call as [`Error`].
pub fn plot_error(e: PlotError) -> PyErr {
    match e {
        PlotError::Device(m) => Error::new_err(m),
        e => PyValueError::new_err(e.to_string()),
    }
}

//! `pointillist._native.Plot`: the description of a plot (the target, the blend, the data
//! ranges, the clear colour, the texture, the behaviour switches and the backend), built once
//! from the keyword arguments of `pointillist.points` and checked here, then handed to every
//! function that draws: `points` and the steps `pointillist.dask` runs on its workers, to
//! which it travels pickled (`__reduce__`).

use std::sync::Arc;

use pointillist_core::behaviour::Behaviours;
use pointillist_plot::{Blend, DataRange, Marker, Plot, SizeUnits};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::types::{PyDict, PyTuple};

use crate::arrays::{self, d3dcolor};
use crate::errors::plot_error;

/// An argument as the caller gave it (`None` included), or `Default` when it was left out:
/// `Plot(8, 8, blend=None)` is refused as `points(..., blend=None)` is, not taken as "add".
pub enum Given<'py> {
    /// Left out: the documented default.
    Default,
    /// Given, whatever it is.
    Value(Bound<'py, PyAny>),
}

impl<'a, 'py> FromPyObject<'a, 'py> for Given<'py> {
    type Error = PyErr;

    fn extract(obj: Borrowed<'a, 'py, PyAny>) -> PyResult<Self> {
        Ok(Given::Value(obj.to_owned()))
    }
}

/// The frozen description of a plot. Every field is checked when it is made; it cannot be
/// changed afterwards (a texture array is copied), so a `Plot` drawn with twice, or sent to a
/// Dask worker, draws the same.
#[pyclass(frozen, module = "pointillist._native", name = "Plot")]
pub struct PyPlot {
    /// The plot, as `pointillist-plot` draws it.
    pub plot: Plot,
    /// The backend's name: "cpu" or "gpu".
    pub backend: String,
    /// The texture as a read-only `(h, w, 4)` uint8 copy, for `texture` and `__reduce__`.
    texture: Option<Py<PyAny>>,
}

/// The `blend` argument: a preset's name.
pub fn blend_arg(obj: &Bound<'_, PyAny>) -> PyResult<Blend> {
    let expected = r#"a string ("add", "alpha", "max" or "replace")"#;
    let name: String = arrays::arg("blend", obj, expected)?;
    Blend::from_name(&name).map_err(plot_error)
}

/// A data range argument: `None` or two numbers.
fn data_range(name: &str, obj: Option<&Bound<'_, PyAny>>) -> PyResult<Option<DataRange>> {
    let Some(obj) = obj.filter(|o| !o.is_none()) else {
        return Ok(None);
    };
    let (lo, hi): (f64, f64) = obj.extract().map_err(|_| {
        PyValueError::new_err(format!("{name} must be None or two numbers (lo, hi)"))
    })?;
    Ok(Some(DataRange { lo, hi }))
}

impl PyPlot {
    /// This plot with a zero clear colour: the partial images of a commuting draw
    /// (`Plot::partial`) and the vertices of a tiled one, which the clear does not touch.
    pub fn partial(&self) -> Plot {
        self.plot.partial()
    }

    /// The range as a Python value: `None` or `(lo, hi)`.
    fn range(r: Option<DataRange>) -> Option<(f64, f64)> {
        r.map(|r| (r.lo, r.hi))
    }
}

#[pymethods]
impl PyPlot {
    /// Checks every argument and makes the plot. The parameters are the keyword arguments of
    /// `pointillist.points` that describe the plot rather than the points (the columns);
    /// every function that draws takes this one object instead of them.
    #[new]
    #[pyo3(
        signature = (width, height, blend=Given::Default, x_range=None, y_range=None, clear=Given::Default, texture=None, behaviour=None, backend=Given::Default, marker=Given::Default, size_units=Given::Default),
        text_signature = "(width, height, blend='add', x_range=None, y_range=None, clear=0xFF000000, texture=None, behaviour=None, backend='cpu', marker='square', size_units='pixels')"
    )]
    #[allow(clippy::too_many_arguments)] // the one place the plot's arguments are listed
    fn new(
        width: &Bound<'_, PyAny>,
        height: &Bound<'_, PyAny>,
        blend: Given<'_>,
        x_range: Option<&Bound<'_, PyAny>>,
        y_range: Option<&Bound<'_, PyAny>>,
        clear: Given<'_>,
        texture: Option<&Bound<'_, PyAny>>,
        behaviour: Option<&Bound<'_, PyAny>>,
        backend: Given<'_>,
        marker: Given<'_>,
        size_units: Given<'_>,
    ) -> PyResult<Self> {
        // The target's size first, before anything is allocated.
        let (width, height) = arrays::target_size(width, height)?;
        let blend = match blend {
            Given::Default => Blend::Add,
            Given::Value(b) => blend_arg(&b)?,
        };
        let clear = match clear {
            Given::Default => 0xFF00_0000,
            Given::Value(c) => d3dcolor("clear", &c)?,
        };
        let backend = match backend {
            Given::Default => "cpu".to_owned(),
            Given::Value(b) => crate::backend::name(&b)?,
        };
        // Checked here, before any array is read; drawn by name in `render`.
        crate::backend::kind(&backend)?;
        let texture = texture.filter(|t| !t.is_none());
        let (texels, texture) = match texture {
            None => (None, None),
            Some(t) => {
                let texels = Arc::new(arrays::texture("texture", t)?);
                let np = t.py().import("numpy")?;
                let copy = np.call_method1("array", (t, "uint8"))?;
                copy.getattr("flags")?.setattr("writeable", false)?;
                (Some(texels), Some(copy.unbind()))
            }
        };
        let marker = match marker {
            Given::Default => Marker::Square,
            Given::Value(m) => {
                let name: String = arrays::arg("marker", &m, r#"a string ("square" or "circle")"#)?;
                Marker::from_name(&name).map_err(plot_error)?
            }
        };
        let size_units = match size_units {
            Given::Default => SizeUnits::Pixels,
            Given::Value(u) => {
                let expected = r#"a string ("pixels" or "data")"#;
                let name: String = arrays::arg("size_units", &u, expected)?;
                SizeUnits::from_name(&name).map_err(plot_error)?
            }
        };
        let plot = Plot {
            behaviours: crate::behaviour::behaviours(behaviour)?,
            width,
            height,
            blend,
            clear,
            x_range: data_range("x_range", x_range)?,
            y_range: data_range("y_range", y_range)?,
            texture: texels,
            marker,
            size_units,
        };
        plot.axes().map_err(plot_error)?;
        plot.check_marker().map_err(plot_error)?;
        Ok(PyPlot {
            plot,
            backend,
            texture,
        })
    }

    /// The target's width in pixels.
    #[getter]
    fn width(&self) -> u32 {
        self.plot.width
    }

    /// The target's height in pixels.
    #[getter]
    fn height(&self) -> u32 {
        self.plot.height
    }

    /// The blend preset's name.
    #[getter]
    fn blend(&self) -> &'static str {
        self.plot.blend.name()
    }

    /// The data interval across the width, `(lo, hi)`, or `None` (x in pixels).
    #[getter]
    fn x_range(&self) -> Option<(f64, f64)> {
        Self::range(self.plot.x_range)
    }

    /// The data interval up the height, `(lo, hi)`, or `None` (y in pixels, downwards).
    #[getter]
    fn y_range(&self) -> Option<(f64, f64)> {
        Self::range(self.plot.y_range)
    }

    /// The D3DCOLOR the target starts as.
    #[getter]
    fn clear(&self) -> u32 {
        self.plot.clear
    }

    /// The texture, a read-only `(h, w, 4)` uint8 copy of the one given, or `None`.
    #[getter]
    fn texture<'py>(&self, py: Python<'py>) -> Option<Bound<'py, PyAny>> {
        self.texture.as_ref().map(|t| t.bind(py).clone())
    }

    /// Every behaviour switch's option, by name (a new dict each time).
    #[getter]
    fn behaviour<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyDict>> {
        crate::behaviour::as_dict(py, &self.plot.behaviours)
    }

    /// Whether the blend's result is independent of the order of the points ("add" and
    /// "max"): partial images of the parts of a draw combine into the whole.
    #[getter]
    fn commutes(&self) -> bool {
        self.plot.blend.commutes()
    }

    /// The backend's name.
    #[getter]
    fn backend(&self) -> &str {
        &self.backend
    }

    /// The marker's name: "square" or "circle".
    #[getter]
    fn marker(&self) -> &'static str {
        self.plot.marker.name()
    }

    /// What sizes are measured in: "pixels" or "data" (x's data units).
    #[getter]
    fn size_units(&self) -> &'static str {
        self.plot.size_units.name()
    }

    /// `(Plot, arguments)`: a pickled `Plot` is made again, and checked again, from the
    /// values it holds.
    fn __reduce__<'py>(
        slf: &Bound<'py, Self>,
    ) -> PyResult<(Bound<'py, PyAny>, Bound<'py, PyTuple>)> {
        let py = slf.py();
        let p = slf.get();
        let args = (
            p.plot.width,
            p.plot.height,
            p.blend(),
            p.x_range(),
            p.y_range(),
            p.plot.clear,
            p.texture(py),
            p.behaviour(py)?,
            p.backend.as_str(),
            p.marker(),
            p.size_units(),
        )
            .into_pyobject(py)?;
        Ok((slf.get_type().into_any(), args))
    }

    fn __repr__(&self) -> String {
        let range = |r: Option<(f64, f64)>| {
            r.map_or_else(|| "None".to_owned(), |(lo, hi)| format!("({lo:?}, {hi:?})"))
        };
        let texture = self.plot.texture.as_ref().map_or_else(
            || "None".to_owned(),
            |t| format!("<{}x{} texture>", t.width(), t.height()),
        );
        let defaults = Behaviours::default();
        let changed: Vec<String> = self
            .plot
            .behaviours
            .iter()
            .zip(defaults.iter())
            .filter(|((_, a), (_, b))| a != b)
            .map(|((d, o), _)| format!("'{}': '{o}'", d.name))
            .collect();
        let behaviour = if changed.is_empty() {
            "None".to_owned()
        } else {
            format!("{{{}}}", changed.join(", "))
        };
        format!(
            "Plot({}, {}, blend='{}', x_range={}, y_range={}, clear=0x{:08X}, texture={texture}, \
             behaviour={behaviour}, backend='{}', marker='{}', size_units='{}')",
            self.plot.width,
            self.plot.height,
            self.plot.blend.name(),
            range(self.x_range()),
            range(self.y_range()),
            self.plot.clear,
            self.backend,
            self.plot.marker.name(),
            self.plot.size_units.name()
        )
    }
}

//! numpy inputs as slices: read in place when they are C-contiguous float32/float64 (uint32
//! or `(n, 4)` uint8 for colours), converted once otherwise, refused with a one-line
//! `TypeError`/`ValueError` naming the argument when they cannot be.

use numpy::ndarray::Dimension;
use numpy::{
    Element, PyArray, PyArray2, PyArrayMethods, PyReadonlyArray, PyReadonlyArray1,
    PyUntypedArrayMethods,
};
use pointillist_core::device::MAX_TARGET_SIZE;
use pointillist_plot::{Colors, Column, Sizes};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyInt};

/// A 1-D column held for the length of a call.
pub enum ColumnArray<'py> {
    /// float32, read in place.
    F32(PyReadonlyArray1<'py, f32>),
    /// float64, read in place (or converted once from another dtype).
    F64(PyReadonlyArray1<'py, f64>),
}

impl ColumnArray<'_> {
    /// The values.
    pub fn column(&self) -> Column<'_> {
        match self {
            ColumnArray::F32(a) => Column::F32(slice(a)),
            ColumnArray::F64(a) => Column::F64(slice(a)),
        }
    }
}

/// The elements of an array held by [`in_place`] or [`required`], which are C-contiguous and
/// aligned: `as_slice` cannot fail on them.
pub fn slice<'a, T: Element, D: Dimension>(a: &'a PyReadonlyArray<'_, T, D>) -> &'a [T] {
    a.as_slice().unwrap_or(&[])
}

/// `obj` held as it is when it is an array of `T` and `D`, C-contiguous and aligned: read in
/// place.
pub fn in_place<'py, T: Element, D: Dimension>(
    obj: &Bound<'py, PyAny>,
) -> PyResult<Option<PyReadonlyArray<'py, T, D>>> {
    match obj.cast::<PyArray<T, D>>() {
        Ok(a) if a.is_c_contiguous() && a.is_aligned() => Ok(Some(a.try_readonly()?)),
        _ => Ok(None),
    }
}

/// `numpy.require(array, dtype, "CA")`: the array itself when it is C-contiguous and aligned
/// with that dtype, else a converted copy (made once).
pub fn required<'py, T: Element, D: Dimension>(
    array: &Bound<'py, PyAny>,
    dtype: &str,
) -> PyResult<PyReadonlyArray<'py, T, D>> {
    let np = array.py().import("numpy")?;
    Ok(np
        .call_method1("require", (array, dtype, "CA"))?
        .cast_into::<PyArray<T, D>>()?
        .try_readonly()?)
}

/// `numpy.asarray(obj)`.
fn as_ndarray<'py>(obj: &Bound<'py, PyAny>) -> PyResult<Bound<'py, PyAny>> {
    obj.py().import("numpy")?.call_method1("asarray", (obj,))
}

fn shape(array: &Bound<'_, PyAny>) -> PyResult<String> {
    Ok(array.getattr("shape")?.str()?.to_string())
}

fn dtype_kind(array: &Bound<'_, PyAny>) -> PyResult<(String, String)> {
    let dtype = array.getattr("dtype")?;
    Ok((dtype.getattr("kind")?.extract()?, dtype.str()?.to_string()))
}

/// Argument `name` as a 1-D column of numbers.
pub fn column<'py>(name: &str, obj: &Bound<'py, PyAny>) -> PyResult<ColumnArray<'py>> {
    if let Some(a) = in_place(obj)? {
        return Ok(ColumnArray::F32(a));
    }
    if let Some(a) = in_place(obj)? {
        return Ok(ColumnArray::F64(a));
    }
    let array = as_ndarray(obj)?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    if ndim != 1 {
        return Err(PyValueError::new_err(format!(
            "{name} must be a 1-D array; got shape {}",
            shape(&array)?
        )));
    }
    let (kind, dtype) = dtype_kind(&array)?;
    if !matches!(kind.as_str(), "b" | "i" | "u" | "f") {
        return Err(PyTypeError::new_err(format!(
            "{name} has dtype {dtype}; expected real numbers (float32 and float64 are read in \
             place)"
        )));
    }
    if dtype == "float32" {
        Ok(ColumnArray::F32(required(&array, "float32")?))
    } else {
        Ok(ColumnArray::F64(required(&array, "float64")?))
    }
}

/// True for a Python or numpy scalar (or a 0-d array).
fn is_scalar(obj: &Bound<'_, PyAny>) -> PyResult<bool> {
    if obj.is_instance_of::<PyFloat>() || obj.is_instance_of::<PyInt>() {
        return Ok(true);
    }
    let ndim: usize = obj
        .py()
        .import("numpy")?
        .call_method1("ndim", (obj,))?
        .extract()?;
    Ok(ndim == 0)
}

/// Sizes held for a call.
pub enum SizeArg<'py> {
    /// One size.
    Constant(f32),
    /// A size per point.
    PerPoint(ColumnArray<'py>),
}

impl SizeArg<'_> {
    /// The sizes.
    pub fn sizes(&self) -> Sizes<'_> {
        match self {
            SizeArg::Constant(s) => Sizes::Constant(*s),
            SizeArg::PerPoint(c) => Sizes::PerPoint(c.column()),
        }
    }
}

/// `size`: a number or a 1-D array of numbers.
pub fn sizes<'py>(obj: &Bound<'py, PyAny>) -> PyResult<SizeArg<'py>> {
    if is_scalar(obj)? {
        if obj.is_instance_of::<PyBool>() {
            return Err(PyTypeError::new_err(
                "size is a bool; expected a number of pixels",
            ));
        }
        let s: f64 = obj
            .extract()
            .map_err(|_| PyTypeError::new_err("size must be a number or a 1-D array"))?;
        if s.is_nan() {
            return Err(PyValueError::new_err("size is NaN"));
        }
        return Ok(SizeArg::Constant(s as f32));
    }
    Ok(SizeArg::PerPoint(column("size", obj)?))
}

/// Colours held for a call.
pub enum ColorArg<'py> {
    /// One D3DCOLOR.
    Constant(u32),
    /// uint32 D3DCOLORs.
    Argb(PyReadonlyArray1<'py, u32>),
    /// `(n, 4)` RGBA bytes.
    Rgba(numpy::PyReadonlyArray2<'py, u8>),
}

impl ColorArg<'_> {
    /// The colours.
    pub fn colors(&self) -> Colors<'_> {
        match self {
            ColorArg::Constant(c) => Colors::Constant(*c),
            ColorArg::Argb(a) => Colors::Argb(slice(a)),
            ColorArg::Rgba(a) => Colors::Rgba(bytemuck::cast_slice(slice(a))),
        }
    }
}

/// A D3DCOLOR from a Python integer.
pub fn d3dcolor(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<u32> {
    dword(
        name,
        obj,
        "a D3DCOLOR, an integer 0xAARRGGBB",
        "a D3DCOLOR 0xAARRGGBB",
    )
}

/// 32 bits from a Python integer: `expected` says what the argument is when it is not an
/// integer, `what` what its 32 bits are when it is out of range.
pub fn dword(name: &str, obj: &Bound<'_, PyAny>, expected: &str, what: &str) -> PyResult<u32> {
    if obj.is_instance_of::<PyBool>() || obj.is_instance_of::<PyFloat>() {
        return Err(PyTypeError::new_err(format!("{name} must be {expected}")));
    }
    let v: i128 = obj
        .extract()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be {expected}")))?;
    u32::try_from(v).map_err(|_| {
        let sign = if v < 0 { "-" } else { "" };
        PyValueError::new_err(format!(
            "{name} {sign}{:#x} is outside 0..=0xFFFFFFFF ({what})",
            v.unsigned_abs()
        ))
    })
}

/// `repr(obj)`, cut to a line's worth, for a message saying what an argument got.
pub fn got(obj: &Bound<'_, PyAny>) -> String {
    let text = obj.repr().map(|r| r.to_string()).unwrap_or_default();
    match text.char_indices().nth(60) {
        Some((end, _)) => format!("{}...", &text[..end]),
        None => text,
    }
}

/// Integer argument `name` (a Python or numpy integer, not a bool) within `lo..=hi`.
pub fn integer<T: TryFrom<i128>>(
    name: &str,
    obj: &Bound<'_, PyAny>,
    lo: i128,
    hi: i128,
) -> PyResult<T> {
    let v = any_integer(name, obj)?;
    v.filter(|v| (lo..=hi).contains(v))
        .and_then(|v| T::try_from(v).ok())
        .ok_or_else(|| {
            let value = v.map(|v| format!(" {v}")).unwrap_or_default();
            PyValueError::new_err(format!("{name}{value} is outside {lo}..={hi}"))
        })
}

/// An integer argument as it is (`None` beyond 128 bits); a TypeError naming `name` for
/// anything else.
pub fn any_integer(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<Option<i128>> {
    let is_bool = obj.is_instance_of::<PyBool>()
        || obj
            .getattr("dtype")
            .and_then(|d| d.getattr("kind"))
            .is_ok_and(|k| k.extract::<String>().is_ok_and(|k| k == "b"));
    if is_bool || !obj.hasattr("__index__")? {
        return Err(PyTypeError::new_err(format!(
            "{name} must be an integer; got {}",
            got(obj)
        )));
    }
    Ok(obj.extract::<i128>().ok())
}

/// The target's sides `width` and `height` (integers), refused with the device's message
/// (`pointillist.Error`) outside 1..=16384, before anything is allocated.
pub fn target_size(width: &Bound<'_, PyAny>, height: &Bound<'_, PyAny>) -> PyResult<(u32, u32)> {
    let (w, h) = (any_integer("width", width)?, any_integer("height", height)?);
    let side = |v: Option<i128>| {
        v.and_then(|v| u32::try_from(v).ok())
            .filter(|v| (1..=MAX_TARGET_SIZE).contains(v))
    };
    match (side(w), side(h)) {
        (Some(w), Some(h)) => Ok((w, h)),
        _ => {
            let show = |v: Option<i128>, obj: &Bound<'_, PyAny>| {
                v.map_or_else(|| got(obj), |v| v.to_string())
            };
            Err(crate::errors::Error::new_err(format!(
                "render target {}x{} is outside 1..={MAX_TARGET_SIZE} per side",
                show(w, width),
                show(h, height)
            )))
        }
    }
}

/// Argument `name` as `T`, or a TypeError naming it, saying it must be `expected` and what it
/// got.
pub fn arg<'py, T: FromPyObjectOwned<'py>>(
    name: &str,
    obj: &Bound<'py, PyAny>,
    expected: &str,
) -> PyResult<T> {
    obj.extract()
        .map_err(|_| PyTypeError::new_err(format!("{name} must be {expected}; got {}", got(obj))))
}

/// `color`: one D3DCOLOR, a 1-D array of D3DCOLORs (uint32, read in place; other integer
/// dtypes converted once), or an `(n, 4)` uint8 RGBA array (read in place).
pub fn colors<'py>(obj: &Bound<'py, PyAny>) -> PyResult<ColorArg<'py>> {
    if is_scalar(obj)? {
        return Ok(ColorArg::Constant(d3dcolor("color", obj)?));
    }
    if let Some(a) = in_place(obj)? {
        return Ok(ColorArg::Argb(a));
    }
    if let Ok(a) = obj.cast::<PyArray2<u8>>()
        && a.is_c_contiguous()
        && a.shape()[1] == 4
    {
        return Ok(ColorArg::Rgba(a.try_readonly()?));
    }
    let array = as_ndarray(obj)?;
    let ndim: usize = array.getattr("ndim")?.extract()?;
    let (kind, dtype) = dtype_kind(&array)?;
    let np = obj.py().import("numpy")?;
    match ndim {
        1 if matches!(kind.as_str(), "i" | "u") => {
            let below = np.call_method1("less", (&array, 0))?;
            let above = np.call_method1("greater", (&array, u32::MAX))?;
            let outside = np.call_method1("logical_or", (below, above))?;
            let bad = np.call_method1("any", (outside,))?.is_truthy()?;
            if bad {
                return Err(PyValueError::new_err(
                    "color holds values outside 0..=0xFFFFFFFF (D3DCOLORs 0xAARRGGBB)",
                ));
            }
            Ok(ColorArg::Argb(required(&array, "uint32")?))
        }
        2 if kind == "u" && dtype == "uint8" && shape(&array)?.ends_with(", 4)") => {
            Ok(ColorArg::Rgba(required(&array, "uint8")?))
        }
        1 | 2 => Err(PyTypeError::new_err(format!(
            "color has dtype {dtype} and shape {}; expected uint32 D3DCOLORs (n,) or uint8 \
             RGBA (n, 4)",
            shape(&array)?
        ))),
        _ => Err(PyValueError::new_err(format!(
            "color must be a D3DCOLOR, a 1-D array of D3DCOLORs or an (n, 4) RGBA array; got \
             shape {}",
            shape(&array)?
        ))),
    }
}

/// A texture from an `(h, w, 4)` uint8 RGBA array, as D3DCOLOR texels, top row first.
pub fn texture(name: &str, obj: &Bound<'_, PyAny>) -> PyResult<pointillist_core::texture::Texture> {
    let array = as_ndarray(obj)?;
    let (_, dtype) = dtype_kind(&array)?;
    let ok_shape =
        array.getattr("ndim")?.extract::<usize>()? == 3 && shape(&array)?.ends_with(", 4)");
    if dtype != "uint8" || !ok_shape {
        return Err(PyValueError::new_err(format!(
            "{name} must be an (height, width, 4) uint8 RGBA array; got dtype {dtype} and shape {}",
            shape(&array)?
        )));
    }
    let a: PyReadonlyArray<'_, u8, numpy::Ix3> = required(&array, "uint8")?;
    let (h, w) = (a.shape()[0], a.shape()[1]);
    let texels = slice(&a)
        .chunks_exact(4)
        .map(|p| u32::from_be_bytes([p[3], p[0], p[1], p[2]]))
        .collect();
    let size = |v: usize| u32::try_from(v).unwrap_or(u32::MAX);
    pointillist_core::texture::Texture::from_argb(size(w), size(h), texels)
        .map_err(|e| PyValueError::new_err(format!("{name}: {e}")))
}

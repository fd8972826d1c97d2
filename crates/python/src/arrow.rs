//! Arrow tables in: `pointillist.points(data, x="col", ...)` where `data` speaks the Arrow
//! PyCapsule interface (`__arrow_c_stream__`: pyarrow tables and readers, polars frames,
//! DuckDB results; or `__arrow_c_array__`: a record batch), read with arrow-rs's C data
//! interface.
//!
//! The stream is drawn chunk by chunk, in order (the order of the rows): each record batch's
//! columns are read, checked and drawn onto one target before the next batch is read, so memory
//! holds one batch at a time. float32 and float64 columns are read in place (the producer's
//! buffers), uint32 colours too; other integer columns are converted once per chunk. A null in
//! any column named by an argument is a `ValueError` naming the argument, the column and the
//! row (counted from 0 over the whole stream), as for pandas' nullable columns.

use arrow_array::cast::AsArray;
use arrow_array::ffi::{FFI_ArrowArray, FFI_ArrowSchema, from_ffi};
use arrow_array::ffi_stream::{ArrowArrayStreamReader, FFI_ArrowArrayStream};
use arrow_array::types::{
    Float16Type, Float32Type, Float64Type, Int8Type, Int16Type, Int32Type, Int64Type, UInt8Type,
    UInt16Type, UInt32Type, UInt64Type,
};
use arrow_array::{
    Array, ArrayRef, Float32Array, Float64Array, RecordBatchReader, StructArray, UInt32Array,
};
use arrow_data::ArrayData;
use arrow_schema::{ArrowError, DataType};
use numpy::{PyArray1, PyArrayMethods};
use pointillist_plot::{Colors, Column, PlotError, Points, Sizes};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyCapsule, PyString};

use crate::arrays::{self, ColorArg, SizeArg};
use crate::backend::{self, AnyDevice};
use crate::errors::plot_error;
use crate::interrupt;
use crate::plot::PyPlot;

/// The record batches of a table, as their columns, one batch at a time.
type Chunks = Box<dyn Iterator<Item = Result<Vec<ArrayRef>, ArrowError>>>;

/// An Arrow error (a producer's failure, a malformed array) as a `ValueError`.
fn arrow_error(e: ArrowError) -> PyErr {
    PyValueError::new_err(format!("data: Arrow: {e}"))
}

/// The pointer a capsule named `name` holds.
fn capsule_pointer<T>(capsule: &Bound<'_, PyAny>, name: &std::ffi::CStr) -> PyResult<*mut T> {
    let capsule = capsule.cast::<PyCapsule>()?;
    Ok(capsule.pointer_checked(Some(name))?.as_ptr().cast())
}

/// The stream an `arrow_array_stream` capsule holds, moved out of it.
#[allow(unsafe_code)] // The C stream interface: a pointer from a capsule.
fn stream_reader(capsule: &Bound<'_, PyAny>) -> PyResult<ArrowArrayStreamReader> {
    let stream = capsule_pointer::<FFI_ArrowArrayStream>(capsule, c"arrow_array_stream")?;
    // SAFETY: a capsule named "arrow_array_stream" holds a valid ArrowArrayStream (the
    // PyCapsule interface) and stays alive during the call; `from_raw` moves the stream out
    // and leaves a released one behind, so that the capsule's destructor releases nothing.
    unsafe { ArrowArrayStreamReader::from_raw(stream) }.map_err(arrow_error)
}

/// The array an `arrow_array` capsule holds (moved out of it), of the type its
/// `arrow_schema` capsule describes.
#[allow(unsafe_code)] // The C data interface: pointers from capsules.
fn array_data(schema: &Bound<'_, PyAny>, array: &Bound<'_, PyAny>) -> PyResult<ArrayData> {
    let schema = capsule_pointer::<FFI_ArrowSchema>(schema, c"arrow_schema")?;
    let array = capsule_pointer::<FFI_ArrowArray>(array, c"arrow_array")?;
    // SAFETY: capsules named "arrow_schema" and "arrow_array" hold a valid ArrowSchema and
    // ArrowArray (the PyCapsule interface) and stay alive during the call; the array is moved
    // out (its capsule then releases nothing) and the schema only borrowed.
    unsafe { from_ffi(FFI_ArrowArray::from_raw(array), &*schema) }.map_err(arrow_error)
}

/// The column names of `data` and its record batches: the stream of `__arrow_c_stream__`, or
/// the one batch of `__arrow_c_array__`.
fn source(data: &Bound<'_, PyAny>) -> PyResult<(Vec<String>, Chunks)> {
    if data.hasattr("__arrow_c_stream__")? {
        let capsule = data.call_method0("__arrow_c_stream__")?;
        let reader = stream_reader(&capsule)?;
        let names = reader
            .schema()
            .fields()
            .iter()
            .map(|f| f.name().clone())
            .collect();
        let chunks = reader.map(|batch| batch.map(|b| b.columns().to_vec()));
        return Ok((names, Box::new(chunks)));
    }
    let (schema, array): (Bound<'_, PyAny>, Bound<'_, PyAny>) =
        data.call_method0("__arrow_c_array__")?.extract()?;
    let data = array_data(&schema, &array)?;
    let DataType::Struct(fields) = data.data_type() else {
        return Err(PyTypeError::new_err(format!(
            "data is an Arrow array of type {}, not a table (a struct array: a record batch)",
            data.data_type()
        )));
    };
    let names = fields.iter().map(|f| f.name().clone()).collect();
    let batch = StructArray::from(data);
    if let Some(row) = first_null(&batch) {
        return Err(PyValueError::new_err(format!(
            "data: the record batch's row {row} is null"
        )));
    }
    let columns = batch.columns().to_vec();
    Ok((names, Box::new(std::iter::once(Ok(columns)))))
}

/// The first null row of `a`, if any.
fn first_null(a: &dyn Array) -> Option<usize> {
    let nulls = a.logical_nulls()?;
    (nulls.null_count() > 0)
        .then(|| (0..nulls.len()).find(|&i| nulls.is_null(i)))
        .flatten()
}

/// A column an argument names: the argument, the column's name (quoted as Python quotes it)
/// and its index in the table.
struct Named {
    arg: &'static str,
    quoted: String,
    index: usize,
}

impl Named {
    /// Argument `arg`'s column `name` among `names`; a `ValueError` listing the columns when
    /// there is none.
    fn find(arg: &'static str, name: &Bound<'_, PyString>, names: &[String]) -> PyResult<Named> {
        let text: String = name.extract()?;
        let quoted = name.repr()?.to_string();
        match names.iter().position(|n| *n == text) {
            Some(index) => Ok(Named { arg, quoted, index }),
            None => Err(PyValueError::new_err(format!(
                "{arg}: column {quoted} is not in data (its columns: {})",
                names.join(", ")
            ))),
        }
    }

    /// This column of a chunk whose first row is row `offset` of the table, refused when it
    /// holds a null.
    fn of<'c>(&self, columns: &'c [ArrayRef], offset: usize) -> PyResult<&'c ArrayRef> {
        let a = &columns[self.index];
        match first_null(a) {
            Some(row) => Err(PyValueError::new_err(format!(
                "{}: column {} is null at row {}",
                self.arg,
                self.quoted,
                offset + row
            ))),
            None => Ok(a),
        }
    }

    /// This column of a chunk as numbers: float32 and float64 in place, other numbers
    /// converted.
    fn numbers(&self, columns: &[ArrayRef], offset: usize) -> PyResult<Numbers> {
        let a = self.of(columns, offset)?;
        macro_rules! convert {
            ($t:ty) => {
                Numbers::Owned(
                    a.as_primitive::<$t>()
                        .values()
                        .iter()
                        .map(|&v| v as f64)
                        .collect(),
                )
            };
        }
        Ok(match a.data_type() {
            DataType::Float32 => Numbers::F32(a.as_primitive::<Float32Type>().clone()),
            DataType::Float64 => Numbers::F64(a.as_primitive::<Float64Type>().clone()),
            DataType::Float16 => Numbers::Owned(
                a.as_primitive::<Float16Type>()
                    .values()
                    .iter()
                    .map(|v| f64::from(v.to_f32()))
                    .collect(),
            ),
            DataType::Int8 => convert!(Int8Type),
            DataType::Int16 => convert!(Int16Type),
            DataType::Int32 => convert!(Int32Type),
            DataType::Int64 => convert!(Int64Type),
            DataType::UInt8 => convert!(UInt8Type),
            DataType::UInt16 => convert!(UInt16Type),
            DataType::UInt32 => convert!(UInt32Type),
            DataType::UInt64 => convert!(UInt64Type),
            DataType::Boolean => {
                Numbers::Owned(a.as_boolean().values().iter().map(f64::from).collect())
            }
            t => {
                return Err(PyTypeError::new_err(format!(
                    "{}: column {} has Arrow type {t}; expected numbers (float32 and float64 \
                     are read in place)",
                    self.arg, self.quoted
                )));
            }
        })
    }

    /// This column of a chunk as D3DCOLORs: uint32 in place, other integers converted when
    /// every value is within 0..=0xFFFFFFFF.
    fn colors(&self, columns: &[ArrayRef], offset: usize) -> PyResult<Argb> {
        let a = self.of(columns, offset)?;
        let outside = || {
            PyValueError::new_err(format!(
                "color: column {} holds values outside 0..=0xFFFFFFFF (D3DCOLORs 0xAARRGGBB)",
                self.quoted
            ))
        };
        macro_rules! convert {
            ($t:ty) => {
                Argb::Owned(
                    a.as_primitive::<$t>()
                        .values()
                        .iter()
                        .map(|&v| u32::try_from(v).map_err(|_| outside()))
                        .collect::<PyResult<_>>()?,
                )
            };
        }
        Ok(match a.data_type() {
            DataType::UInt32 => Argb::Borrowed(a.as_primitive::<UInt32Type>().clone()),
            DataType::Int8 => convert!(Int8Type),
            DataType::Int16 => convert!(Int16Type),
            DataType::Int32 => convert!(Int32Type),
            DataType::Int64 => convert!(Int64Type),
            DataType::UInt8 => convert!(UInt8Type),
            DataType::UInt16 => convert!(UInt16Type),
            DataType::UInt64 => convert!(UInt64Type),
            t => {
                return Err(PyTypeError::new_err(format!(
                    "color: column {} has Arrow type {t}; expected uint32 D3DCOLORs \
                     0xAARRGGBB (other integers are converted)",
                    self.quoted
                )));
            }
        })
    }
}

/// A numeric column of one chunk.
enum Numbers {
    /// float32, the producer's buffer.
    F32(Float32Array),
    /// float64, the producer's buffer.
    F64(Float64Array),
    /// Converted from another type.
    Owned(Vec<f64>),
}

impl Numbers {
    fn column(&self) -> Column<'_> {
        match self {
            Numbers::F32(a) => Column::F32(a.values()),
            Numbers::F64(a) => Column::F64(a.values()),
            Numbers::Owned(v) => Column::F64(v),
        }
    }
}

/// A colour column of one chunk.
enum Argb {
    /// uint32, the producer's buffer.
    Borrowed(UInt32Array),
    /// Converted from another integer type.
    Owned(Vec<u32>),
}

impl Argb {
    fn colors(&self) -> Colors<'_> {
        match self {
            Argb::Borrowed(a) => Colors::Argb(a.values()),
            Argb::Owned(v) => Colors::Argb(v),
        }
    }
}

/// `size`: a column or a constant.
enum Either<T> {
    Named(Named),
    Constant(T),
}

/// `color`: a column, a constant, or an array of one colour a row of the table (colours
/// computed from a column's values: `cmap`, `color_key`).
enum ColorSpec<'py> {
    Named(Named),
    Constant(u32),
    Array(ColorArg<'py>),
}

/// What each argument of a draw is: the columns it names, or its constant.
struct Spec<'py> {
    x: Named,
    y: Named,
    z: Option<Named>,
    size: Either<f32>,
    color: ColorSpec<'py>,
}

/// The columns of one chunk, held while it is drawn.
struct Chunk {
    x: Numbers,
    y: Numbers,
    z: Option<Numbers>,
    size: Option<Numbers>,
    color: Option<Argb>,
}

impl<'py> Spec<'py> {
    /// The arguments of `points` against the table's column `names`: `x`, `y` (and `z` when
    /// given) name columns; `size` names a column or is a constant; `color` names a column or
    /// is a constant or an array of a colour a row.
    fn new(
        names: &[String],
        x: &Bound<'py, PyString>,
        y: &Bound<'py, PyString>,
        z: Option<&Bound<'py, PyString>>,
        size: &Bound<'py, PyAny>,
        color: &Bound<'py, PyAny>,
    ) -> PyResult<Spec<'py>> {
        let size = match size.cast::<PyString>() {
            Ok(name) => Either::Named(Named::find("size", name, names)?),
            Err(_) => match arrays::sizes(size)? {
                SizeArg::Constant(s) => Either::Constant(s),
                SizeArg::PerPoint(_) => return Err(not_an_array("size")),
            },
        };
        let color = match color.cast::<PyString>() {
            Ok(name) => ColorSpec::Named(Named::find("color", name, names)?),
            Err(_) => match arrays::colors(color)? {
                ColorArg::Constant(c) => ColorSpec::Constant(c),
                array => ColorSpec::Array(array),
            },
        };
        Ok(Spec {
            x: Named::find("x", x, names)?,
            y: Named::find("y", y, names)?,
            z: z.map(|z| Named::find("z", z, names)).transpose()?,
            size,
            color,
        })
    }

    /// The columns of a chunk whose first row is row `offset` of the table.
    fn read(&self, columns: &[ArrayRef], offset: usize) -> PyResult<Chunk> {
        Ok(Chunk {
            x: self.x.numbers(columns, offset)?,
            y: self.y.numbers(columns, offset)?,
            z: self
                .z
                .as_ref()
                .map(|z| z.numbers(columns, offset))
                .transpose()?,
            size: match &self.size {
                Either::Named(n) => Some(n.numbers(columns, offset)?),
                Either::Constant(_) => None,
            },
            color: match &self.color {
                ColorSpec::Named(n) => Some(n.colors(columns, offset)?),
                _ => None,
            },
        })
    }

    /// The points of `chunk` (read by [`Spec::read`]), whose first row is row `offset` of
    /// the table: a colour array's rows `offset..` with them.
    fn points<'a>(&'a self, chunk: &'a Chunk, offset: usize) -> PyResult<Points<'a>> {
        let rows = chunk.x.column().len();
        let color = match (&self.color, &chunk.color) {
            (_, Some(c)) => c.colors(),
            (ColorSpec::Constant(c), None) => Colors::Constant(*c),
            (ColorSpec::Array(a), None) => {
                let colors = a.colors();
                let len = colors_len(&colors);
                if offset + rows > len {
                    return Err(PyValueError::new_err(format!(
                        "color has {len} rows but data has more ({} at least)",
                        offset + rows
                    )));
                }
                let range = offset..offset + rows;
                match colors {
                    Colors::Argb(c) => Colors::Argb(&c[range]),
                    Colors::Rgba(c) => Colors::Rgba(&c[range]),
                    c => c,
                }
            }
            (ColorSpec::Named(_), None) => Colors::Argb(&[]),
        };
        Ok(Points {
            x: chunk.x.column(),
            y: chunk.y.column(),
            z: chunk.z.as_ref().map(Numbers::column),
            size: match (&self.size, &chunk.size) {
                (_, Some(s)) => Sizes::PerPoint(s.column()),
                (Either::Constant(s), None) => Sizes::Constant(*s),
                (Either::Named(_), None) => Sizes::PerPoint(Column::F32(&[])),
            },
            color,
        })
    }

    /// Refuses a colour array of more rows than the table's `rows`.
    fn check_rows(&self, rows: usize) -> PyResult<()> {
        if let ColorSpec::Array(a) = &self.color {
            let len = colors_len(&a.colors());
            if len != rows {
                return Err(PyValueError::new_err(format!(
                    "color has {len} rows but data has {rows}"
                )));
            }
        }
        Ok(())
    }

    /// No points, laid out as this draw's: its layout and constants without rows.
    fn empty(&self) -> Points<'static> {
        Points {
            x: Column::F32(&[]),
            y: Column::F32(&[]),
            z: self.z.as_ref().map(|_| Column::F32(&[])),
            size: match self.size {
                Either::Constant(s) => Sizes::Constant(s),
                Either::Named(_) => Sizes::PerPoint(Column::F32(&[])),
            },
            color: match self.color {
                ColorSpec::Constant(c) => Colors::Constant(c),
                _ => Colors::Argb(&[]),
            },
        }
    }
}

/// The rows of an array of colours.
fn colors_len(colors: &Colors<'_>) -> usize {
    match colors {
        Colors::Argb(c) => c.len(),
        Colors::Rgba(c) => c.len(),
        Colors::Constant(_) => 0,
    }
}

/// With an Arrow table, an argument is a column's name or a constant.
fn not_an_array(arg: &str) -> PyErr {
    PyTypeError::new_err(format!(
        "with an Arrow table as data, {arg} must be a column name or a constant, not an array \
         (add the array to the table as a column)"
    ))
}

/// A plot error of a chunk whose first row is row `offset` of the table: a NaN's row counted
/// over the table.
fn chunk_error(offset: usize) -> impl Fn(PlotError) -> PyErr {
    move |e| match e {
        PlotError::Nan { name, row } => plot_error(PlotError::Nan {
            name,
            row: row + offset,
        }),
        e => plot_error(e),
    }
}

/// The counts of a draw whose pixels are not its counts.
fn not_counted() -> PyErr {
    PyValueError::new_err(
        "only a draw of one colour is shaded from its counts: a constant color, blend \"add\", \
         \"max\" or \"replace\", no z, no texture",
    )
}

/// The image being drawn, chunk by chunk.
enum Target {
    /// No chunk yet.
    None,
    /// A counted draw (one colour: `Plot::add_counts_of`): the counts so far.
    Counts(Vec<u8>),
    /// Any other draw: the device, its target holding the chunks drawn so far.
    Device(Box<AnyDevice>),
}

impl Target {
    /// Draws the points of one chunk after those before it.
    fn draw(
        &mut self,
        py: Python<'_>,
        spec: &PyPlot,
        points: &Points<'_>,
        (offset, counts): (usize, bool),
    ) -> PyResult<()> {
        let plot = &spec.plot;
        let error = chunk_error(offset);
        if let Target::None = self {
            if spec.backend == "cpu" || counts {
                let mut sum = vec![0u8; plot.width as usize * plot.height as usize];
                if py
                    .detach(|| plot.add_counts_of(points, &mut sum))
                    .map_err(&error)?
                {
                    *self = Target::Counts(sum);
                    return Ok(());
                }
            }
            if counts {
                return Err(not_counted());
            }
            let backend = backend::backend(&spec.backend)?;
            let size = (plot.width, plot.height);
            let device = plot
                .device(backend, &points.layout(), size, None)
                .map_err(plot_error)?;
            *self = Target::Device(Box::new(device));
        }
        match self {
            Target::Counts(sum) => {
                py.detach(|| plot.add_counts_of(points, sum))
                    .map_err(&error)?;
            }
            Target::Device(device) => {
                interrupt::detach(py, || plot.draw(device, points))?.map_err(&error)?;
            }
            Target::None => {}
        }
        Ok(())
    }

    /// The counts of every chunk drawn, a `(height, width)` uint8 array (saturating at 255):
    /// the draw must be counted.
    fn counts<'py>(
        self,
        py: Python<'py>,
        spec: &PyPlot,
        layout: &Points<'_>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let plot = &spec.plot;
        let shape = (plot.height as usize, plot.width as usize);
        let sum = match self {
            Target::Counts(sum) => sum,
            Target::None => {
                let mut sum = vec![0u8; shape.0 * shape.1];
                if !plot.add_counts_of(layout, &mut sum).map_err(plot_error)? {
                    return Err(not_counted());
                }
                sum
            }
            Target::Device(_) => return Err(not_counted()),
        };
        Ok(PyArray1::from_vec(py, sum).reshape(shape)?.into_any())
    }

    /// The image of every chunk drawn.
    fn finish<'py>(
        self,
        py: Python<'py>,
        spec: &PyPlot,
        layout: &Points<'_>,
    ) -> PyResult<Bound<'py, PyAny>> {
        let plot = &spec.plot;
        let (width, height) = (plot.width, plot.height);
        match self {
            Target::None => {
                let rgba = py.detach(|| plot.render(layout)).map_err(plot_error)?;
                crate::image(py, rgba, width, height)
            }
            Target::Counts(sum) => {
                let rgba = plot.from_counts(layout, &sum).map_err(plot_error)?;
                crate::image(py, rgba, width, height)
            }
            Target::Device(device) => {
                let rgba = interrupt::detach(py, || -> Result<_, PlotError> {
                    Ok(device.into_target()?.into_rgba8())
                })?
                .map_err(plot_error)?;
                crate::image_words(py, rgba.into_words(), width, height)
            }
        }
    }
}

/// Draws the rows of an Arrow table (`__arrow_c_stream__` or `__arrow_c_array__`) with
/// `plot`: `x`, `y` and `z` name its columns, `size` names a column or is a constant, `color`
/// names a column or is a constant or an array of a colour a row. The record batches are
/// drawn one after another, in order: the pixels of one draw of all the rows, as `points`
/// draws the same columns from numpy. With `counts`, the `(height, width)` uint8 counts of a
/// draw of one colour instead (as `_counts`).
#[pyfunction]
#[pyo3(signature = (plot, data, x, y, *, size, color, z=None, counts=false))]
#[allow(clippy::too_many_arguments)] // the columns of `points`, and what to return
pub fn points_arrow<'py>(
    plot: &Bound<'py, PyPlot>,
    data: &Bound<'py, PyAny>,
    x: &Bound<'py, PyString>,
    y: &Bound<'py, PyString>,
    size: &Bound<'py, PyAny>,
    color: &Bound<'py, PyAny>,
    z: Option<&Bound<'py, PyString>>,
    counts: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let py = plot.py();
    let plot = plot.get();
    let (names, chunks) = source(data)?;
    let spec = Spec::new(&names, x, y, z, size, color)?;
    let mut target = Target::None;
    let mut offset = 0;
    for columns in chunks {
        py.check_signals()?;
        let chunk = spec.read(&columns.map_err(arrow_error)?, offset)?;
        let points = spec.points(&chunk, offset)?;
        let rows = points.count().map_err(plot_error)?;
        target.draw(py, plot, &points, (offset, counts))?;
        offset += rows;
    }
    spec.check_rows(offset)?;
    if counts {
        return target.counts(py, plot, &spec.empty());
    }
    target.finish(py, plot, &spec.empty())
}

//! `pointillist._native`: the native module of the `pointillist` Python package.
//!
//! The public API is `pointillist.points`, `pointillist.Device`, `pointillist.render_scene`,
//! `pointillist.animate`, `pointillist.behaviours` and `pointillist.dask.points`; the functions
//! whose names start with an underscore are the steps `pointillist.dask` runs on the workers.
//! Everything is drawn by `pointillist-plot` and `pointillist-core`'s device; this crate only
//! turns Python arguments into their types and their errors into exceptions.

mod arrays;
mod arrow;
mod backend;
mod behaviour;
mod device;
mod errors;
mod interrupt;
mod plot;
mod scene;

use std::sync::{Arc, Mutex};

use numpy::{Element, PyArray1, PyArrayMethods, PyUntypedArrayMethods};
use pointillist_plot::tiles::Tiles;
use pointillist_plot::{Layout, Plot, Points};
use pyo3::exceptions::PyValueError;
use pyo3::prelude::*;
use pyo3::sync::PyOnceLock;
use pyo3::types::PyType;

use arrays::{ColorArg, SizeArg, colors, column, sizes};
use errors::plot_error;
use plot::PyPlot;

/// `pointillist._image.Image`, looked up when the module is imported: a lookup during a call
/// could run Python code, which a pending Ctrl-C would break.
static IMAGE: PyOnceLock<Py<PyType>> = PyOnceLock::new();

/// `rgba` (`height * width * 4` bytes, rows top to bottom) as a `pointillist.Image`, the
/// `(height, width, 4)` uint8 ndarray that shows itself in Jupyter; the bytes are not copied.
pub(crate) fn image<'py>(
    py: Python<'py>,
    rgba: Vec<u8>,
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyAny>> {
    as_image(py, PyArray1::from_vec(py, rgba).into_any(), width, height)
}

/// [`image`] of RGBA bytes held four a word, each pixel's in memory order (`Rgba8`); the
/// words are not copied.
pub(crate) fn image_words<'py>(
    py: Python<'py>,
    words: Vec<u32>,
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let bytes = PyArray1::from_vec(py, words).call_method1("view", (u8::get_dtype(py),))?;
    as_image(py, bytes, width, height)
}

/// A 1-D uint8 array of `height * width * 4` bytes as an `Image`.
fn as_image<'py>(
    py: Python<'py>,
    bytes: Bound<'py, PyAny>,
    width: u32,
    height: u32,
) -> PyResult<Bound<'py, PyAny>> {
    let shape = (height as usize, width as usize, 4);
    let class = IMAGE.import(py, "pointillist._image", "Image")?;
    bytes
        .call_method1("reshape", (shape,))?
        .call_method1("view", (class,))
}

/// The columns of a call, held (borrowed in place or converted once) for its length.
struct Held<'py> {
    x: arrays::ColumnArray<'py>,
    y: arrays::ColumnArray<'py>,
    z: Option<arrays::ColumnArray<'py>>,
    size: SizeArg<'py>,
    color: ColorArg<'py>,
}

/// The columns the steps of `pointillist.dask` pass, as one tuple `(x, y, z, size, color)`
/// (`z` may be `None`; `size` and `color` may be constants).
#[derive(FromPyObject)]
struct Columns<'py>(
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
    Option<Bound<'py, PyAny>>,
    Bound<'py, PyAny>,
    Bound<'py, PyAny>,
);

impl<'py> Held<'py> {
    fn new(
        x: &Bound<'py, PyAny>,
        y: &Bound<'py, PyAny>,
        z: Option<&Bound<'py, PyAny>>,
        size: &Bound<'py, PyAny>,
        color: &Bound<'py, PyAny>,
    ) -> PyResult<Self> {
        Ok(Held {
            x: column("x", x)?,
            y: column("y", y)?,
            z: z.map(|z| column("z", z)).transpose()?,
            size: sizes(size)?,
            color: colors(color)?,
        })
    }

    fn of(c: &Columns<'py>) -> PyResult<Self> {
        Held::new(&c.0, &c.1, c.2.as_ref(), &c.3, &c.4)
    }

    fn points(&self) -> Points<'_> {
        Points {
            x: self.x.column(),
            y: self.y.column(),
            z: self.z.as_ref().map(|z| z.column()),
            size: self.size.sizes(),
            color: self.color.colors(),
        }
    }
}

/// Draws points from numpy arrays with `plot`; see `pointillist.points` for the full
/// description.
#[pyfunction]
#[pyo3(signature = (plot, x, y, *, size, color, z=None))]
fn points<'py>(
    plot: &Bound<'py, PyPlot>,
    x: &Bound<'py, PyAny>,
    y: &Bound<'py, PyAny>,
    size: &Bound<'py, PyAny>,
    color: &Bound<'py, PyAny>,
    z: Option<&Bound<'py, PyAny>>,
) -> PyResult<Bound<'py, PyAny>> {
    let py = plot.py();
    let spec = plot.get();
    let plot = &spec.plot;
    let held = Held::new(x, y, z, size, color)?;
    let points = held.points();
    if spec.backend == "cpu" {
        let rgba = py.detach(|| plot.render(&points)).map_err(plot_error)?;
        return image(py, rgba, plot.width, plot.height);
    }
    let backend = backend::backend(&spec.backend)?;
    let rgba = interrupt::detach(py, || -> Result<_, pointillist_plot::PlotError> {
        plot.check(&points)?;
        let size = (plot.width, plot.height);
        let mut device = plot.device(backend, &points.layout(), size, None)?;
        plot.draw(&mut device, &points)?;
        Ok(device.into_target()?.into_rgba8())
    })?
    .map_err(plot_error)?;
    image_words(py, rgba.into_words(), plot.width, plot.height)
}

/// Checks `columns` against `plot` (dtypes, shapes, lengths, NaNs, constants) without
/// drawing: `pointillist.dask` checks its constant size and colour before any task.
#[pyfunction]
fn _check(plot: &Bound<'_, PyPlot>, columns: Columns<'_>) -> PyResult<()> {
    let held = Held::of(&columns)?;
    plot.get().plot.check(&held.points()).map_err(plot_error)?;
    Ok(())
}

/// The partial image of one part of a draw whose blend commutes: the points drawn onto a
/// zero target (`Plot::partial`).
#[pyfunction]
#[pyo3(signature = (plot, columns, threads=None))]
fn _partial<'py>(
    plot: &Bound<'py, PyPlot>,
    columns: Columns<'py>,
    threads: Option<usize>,
) -> PyResult<Bound<'py, PyAny>> {
    let py = plot.py();
    let pool = pool(threads)?;
    let plot = plot.get().partial();
    if !plot.blend.commutes() {
        return Err(PyValueError::new_err(format!(
            "blend \"{}\" depends on the order of the points; draw it by tiles",
            plot.blend.name()
        )));
    }
    if columns.2.is_some() {
        return Err(PyValueError::new_err(
            "a draw with z depends on the order of the points; draw it by tiles",
        ));
    }
    let held = Held::of(&columns)?;
    let points = held.points();
    let rgba = py
        .detach(|| on(&pool, || plot.render(&points)))
        .map_err(plot_error)?;
    image(py, rgba, plot.width, plot.height)
}

/// Rayon pools of a given number of threads, made on first use and kept for the process.
static POOLS: Mutex<Vec<(usize, Arc<rayon::ThreadPool>)>> = Mutex::new(Vec::new());

/// The pool of `threads` threads (`None`: rayon's global pool, as every other call uses).
fn pool(threads: Option<usize>) -> PyResult<Option<Arc<rayon::ThreadPool>>> {
    let Some(threads) = threads else {
        return Ok(None);
    };
    if threads == 0 {
        return Err(PyValueError::new_err("threads must be at least 1"));
    }
    let mut pools = POOLS.lock().unwrap_or_else(|e| e.into_inner());
    if let Some((_, pool)) = pools.iter().find(|(n, _)| *n == threads) {
        return Ok(Some(pool.clone()));
    }
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(threads)
        .thread_name(move |i| format!("pointillist-{threads}-{i}"))
        .build()
        .map(Arc::new)
        .map_err(|e| PyValueError::new_err(format!("cannot start {threads} threads: {e}")))?;
    pools.push((threads, pool.clone()));
    Ok(Some(pool))
}

/// `f` on `pool`, or on the calling thread (rayon's global pool) without one.
fn on<T: Send>(pool: &Option<Arc<rayon::ThreadPool>>, f: impl FnOnce() -> T + Send) -> T {
    match pool {
        Some(pool) => pool.install(f),
        None => f(),
    }
}

/// The `(height, width)` uint8 counts of the points covering each pixel (`Plot::counts`), or
/// `None` when the draw is not one of one colour that is counted. With `out` (a C-contiguous
/// `(height, width)` uint8 array) the counts are added to it, saturating, without an array of
/// their own (`Plot::add_counts_of`), and `out` is returned. With `threads`, the counting runs
/// on a pool of that many threads (a Dask worker's own number of threads) instead of rayon's
/// global pool of one thread a core.
#[pyfunction]
#[pyo3(signature = (plot, columns, out=None, threads=None))]
fn _counts<'py>(
    plot: &Bound<'py, PyPlot>,
    columns: Columns<'py>,
    out: Option<&Bound<'py, PyAny>>,
    threads: Option<usize>,
) -> PyResult<Option<Bound<'py, PyAny>>> {
    let py = plot.py();
    let pool = pool(threads)?;
    let plot = &plot.get().plot;
    let (width, height) = (plot.width, plot.height);
    let held = Held::of(&columns)?;
    let points = held.points();
    if let Some(out) = out {
        let array = count_array("out", out)?;
        if array.shape() != [height as usize, width as usize] {
            let shape = array.shape();
            return Err(PyValueError::new_err(format!(
                "out has shape ({}, {}), not ({height}, {width})",
                shape[0], shape[1]
            )));
        }
        let counted = {
            let mut sum = array.try_readwrite()?;
            let sum = contiguous(sum.as_slice_mut())?;
            py.detach(|| on(&pool, || plot.add_counts_of(&points, sum)))
                .map_err(plot_error)?
        };
        return Ok(counted.then(|| array.into_any()));
    }
    let Some(counts) = py
        .detach(|| on(&pool, || plot.counts(&points)))
        .map_err(plot_error)?
    else {
        return Ok(None);
    };
    let array = PyArray1::from_vec(py, counts).reshape([height as usize, width as usize])?;
    Ok(Some(array.into_any()))
}

/// A C-contiguous 2-D uint8 array argument.
fn count_array<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray2<u8>>> {
    let a = obj
        .cast::<numpy::PyArray2<u8>>()
        .map_err(|_| PyValueError::new_err(format!("{name} must be an (h, w) uint8 array")))?;
    if !a.is_c_contiguous() {
        return Err(PyValueError::new_err(format!(
            "{name} must be C-contiguous"
        )));
    }
    Ok(a.clone())
}

/// Adds counts `src` into `dst` (in place), saturating at 255 (`Plot::add_counts`).
#[pyfunction]
fn _add_counts(dst: &Bound<'_, PyAny>, src: &Bound<'_, PyAny>) -> PyResult<()> {
    let dst = count_array("dst", dst)?;
    let src = count_array("src", src)?;
    let src = src.try_readonly()?;
    let mut dst = dst.try_readwrite()?;
    Plot::add_counts(contiguous(dst.as_slice_mut())?, contiguous(src.as_slice())?)
        .map_err(plot_error)
}

/// The image of a counted draw from its counts (`Plot::from_counts`); `x`, `y` and a size
/// column may be empty: they give the layout.
#[pyfunction]
fn _from_counts<'py>(
    plot: &Bound<'py, PyPlot>,
    counts: &Bound<'py, PyAny>,
    columns: Columns<'py>,
) -> PyResult<Bound<'py, PyAny>> {
    let py = plot.py();
    let plot = &plot.get().plot;
    let (width, height) = (plot.width, plot.height);
    let held = Held::of(&columns)?;
    let counts = count_array("counts", counts)?;
    let counts = counts.try_readonly()?;
    let rgba = plot
        .from_counts(&held.points(), contiguous(counts.as_slice())?)
        .map_err(plot_error)?;
    image(py, rgba, width, height)
}

/// A slice of an array checked to be C-contiguous, or the error saying it is not.
pub(crate) fn contiguous<T>(r: Result<T, numpy::AsSliceError>) -> PyResult<T> {
    r.map_err(|_| PyValueError::new_err("the array must be C-contiguous and aligned"))
}

/// An RGBA8 image argument as a mutable or shared byte slice of `len` bytes.
fn rgba_bytes<'py>(
    name: &str,
    obj: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, numpy::PyArray3<u8>>> {
    let a = obj
        .cast::<numpy::PyArray3<u8>>()
        .map_err(|_| PyValueError::new_err(format!("{name} must be an (h, w, 4) uint8 array")))?;
    if !a.is_c_contiguous() || a.shape()[2] != 4 {
        return Err(PyValueError::new_err(format!(
            "{name} must be a C-contiguous (h, w, 4) uint8 array"
        )));
    }
    Ok(a.clone())
}

/// Combines partial image `src` into `dst` (in place) with the exact operator of `plot`'s
/// blend (`Blend::combine`: 8-bit saturating addition for "add", maximum for "max").
#[pyfunction]
fn _combine(
    dst: &Bound<'_, PyAny>,
    src: &Bound<'_, PyAny>,
    plot: &Bound<'_, PyPlot>,
) -> PyResult<()> {
    let blend = plot.get().plot.blend;
    let dst = rgba_bytes("dst", dst)?;
    let src = rgba_bytes("src", src)?;
    let src = src.try_readonly()?;
    let mut dst = dst.try_readwrite()?;
    blend
        .combine(contiguous(dst.as_slice_mut())?, contiguous(src.as_slice())?)
        .map_err(plot_error)
}

/// Combines `plot`'s clear colour into the combined partial images `rgba` (in place)
/// (`Plot::finish`).
#[pyfunction]
fn _finish(rgba: &Bound<'_, PyAny>, plot: &Bound<'_, PyPlot>) -> PyResult<()> {
    let plot = &plot.get().plot;
    let a = rgba_bytes("rgba", rgba)?;
    let mut a = a.try_readwrite()?;
    plot.finish(contiguous(a.as_slice_mut())?)
        .map_err(plot_error)
}

/// The tiles of `plot`'s target: a list of `(x0, y0, x1, y1)`, row by row.
#[pyfunction]
fn _tiles(
    plot: &Bound<'_, PyPlot>,
    tile_width: &Bound<'_, PyAny>,
    tile_height: &Bound<'_, PyAny>,
) -> PyResult<Vec<(i32, i32, i32, i32)>> {
    let (width, height) = (plot.get().plot.width, plot.get().plot.height);
    let side = i128::from(u32::MAX);
    let tile_width = arrays::integer("tile_size", tile_width, 1, side)?;
    let tile_height = arrays::integer("tile_size", tile_height, 1, side)?;
    let tiles = Tiles::new(width, height, tile_width, tile_height).map_err(plot_error)?;
    Ok((0..tiles.len())
        .map(|i| {
            let r = tiles.rect(i);
            (r.x0, r.y0, r.x1, r.y1)
        })
        .collect())
}

/// One tile's vertices and indices as arrays.
type TileArrays<'py> = (Bound<'py, PyAny>, Bound<'py, PyArray1<u64>>);

/// Sends one part of the points (global indices from `first_index`) to the tiles their
/// squares overlap (`Plot::bin`): a list with one `(vertices, index)` pair of arrays per
/// tile, `vertices` `(k, words)` uint32 (one row a vertex), `index` `(k,)` uint64.
#[pyfunction]
fn _bin<'py>(
    plot: &Bound<'py, PyPlot>,
    columns: Columns<'py>,
    first_index: u64,
    tile_width: u32,
    tile_height: u32,
) -> PyResult<Vec<TileArrays<'py>>> {
    let py = plot.py();
    // The clear and the texture touch no vertex.
    let plot = Plot {
        texture: None,
        ..plot.get().partial()
    };
    let (width, height) = (plot.width, plot.height);
    let tiles = Tiles::new(width, height, tile_width, tile_height).map_err(plot_error)?;
    let held = Held::of(&columns)?;
    let points = held.points();
    let bins = py
        .detach(|| plot.bin(&points, first_index, &tiles))
        .map_err(plot_error)?;
    let stride = points.layout().stride();
    bins.into_iter()
        .map(|b| {
            let rows = b.index.len();
            let vertices = PyArray1::from_vec(py, b.vertices).reshape([rows, stride])?;
            Ok((vertices.into_any(), PyArray1::from_vec(py, b.index)))
        })
        .collect()
}

/// Draws one tile (`Plot::render_tile`): `vertices` (a C-contiguous uint32 array of the
/// words of the layout that `depth` and `size` give, in index order) on a target cleared to
/// `clear` whose viewport is `rect`; returns the tile's `(h, w, 4)` RGBA.
#[pyfunction]
#[pyo3(signature = (plot, vertices, rect, *, size, depth))]
fn _render_tile<'py>(
    plot: &Bound<'py, PyPlot>,
    vertices: &Bound<'py, PyAny>,
    rect: (i32, i32, i32, i32),
    size: Option<f32>,
    depth: bool,
) -> PyResult<Bound<'py, PyAny>> {
    let py = plot.py();
    let plot = &plot.get().plot;
    let layout = Layout { depth, size };
    let words: numpy::PyReadonlyArrayDyn<'_, u32> = match arrays::in_place(vertices)? {
        Some(a) => a,
        None => arrays::required(vertices, "uint32")?,
    };
    let words = arrays::slice(&words);
    if !words.len().is_multiple_of(layout.stride()) {
        return Err(PyValueError::new_err(format!(
            "{} vertex words are not whole vertices of {} words",
            words.len(),
            layout.stride()
        )));
    }
    let (x0, y0, x1, y1) = rect;
    let r = pointillist_core::point::PixelRect { x0, y0, x1, y1 };
    let rgba = py
        .detach(|| plot.render_tile(&layout, words, r))
        .map_err(plot_error)?;
    image(py, rgba, (x1 - x0).max(0) as u32, (y1 - y0).max(0) as u32)
}

/// Encodes an `(h, w, 4)` uint8 RGBA array as PNG bytes.
#[pyfunction]
fn _encode_png<'py>(
    py: Python<'py>,
    rgba: &Bound<'py, PyAny>,
) -> PyResult<Bound<'py, pyo3::types::PyBytes>> {
    let a = rgba_bytes("image", rgba)?;
    let (h, w) = (a.shape()[0] as u32, a.shape()[1] as u32);
    let a = a.try_readonly()?;
    let png = pointillist_image::png::encode_png_rgba8(w, h, contiguous(a.as_slice())?)
        .map_err(|e| errors::Error::new_err(e.to_string()))?;
    Ok(pyo3::types::PyBytes::new(py, &png))
}

/// Writes an `(h, w, 4)` uint8 RGBA array as a PNG file, atomically (as `pointillist render`
/// writes its output: an existing file is replaced only by a complete one).
#[pyfunction]
fn _save_png(py: Python<'_>, path: std::path::PathBuf, rgba: &Bound<'_, PyAny>) -> PyResult<()> {
    let a = rgba_bytes("image", rgba)?;
    let (h, w) = (a.shape()[0] as u32, a.shape()[1] as u32);
    let a = a.try_readonly()?;
    let bytes = contiguous(a.as_slice())?;
    py.detach(|| pointillist_image::write_png_atomic(&path, w, h, bytes))
        .map_err(|e| errors::Error::new_err(e.to_string()))
}

/// The vector level the CPU backend's wide spans run on ("avx512", "avx2", "sse2" or "portable").
#[pyfunction]
fn lanes() -> &'static str {
    pointillist_cpu::lanes()
}

#[pymodule]
#[pyo3(name = "_native")]
fn native(m: &Bound<'_, PyModule>) -> PyResult<()> {
    let py = m.py();
    // numpy's C API and the Image class, loaded now: loaded by the first call that makes an
    // array, they run Python code that a Ctrl-C pending from the draw would break (a panic).
    PyArray1::<u8>::zeros(py, 0, false);
    IMAGE.import(py, "pointillist._image", "Image")?;
    m.add("Error", py.get_type::<errors::Error>())?;
    m.add("SceneError", py.get_type::<errors::SceneError>())?;
    m.add_class::<device::PyDevice>()?;
    m.add_class::<PyPlot>()?;
    m.add_function(wrap_pyfunction!(points, m)?)?;
    m.add_function(wrap_pyfunction!(arrow::points_arrow, m)?)?;
    m.add_function(wrap_pyfunction!(scene::render_scene, m)?)?;
    m.add_function(wrap_pyfunction!(scene::animate, m)?)?;
    m.add_function(wrap_pyfunction!(lanes, m)?)?;
    m.add_function(wrap_pyfunction!(behaviour::behaviours_table, m)?)?;
    m.add_function(wrap_pyfunction!(behaviour::behaviour_profiles, m)?)?;
    m.add_function(wrap_pyfunction!(_check, m)?)?;
    m.add_function(wrap_pyfunction!(_partial, m)?)?;
    m.add_function(wrap_pyfunction!(_combine, m)?)?;
    m.add_function(wrap_pyfunction!(_counts, m)?)?;
    m.add_function(wrap_pyfunction!(_add_counts, m)?)?;
    m.add_function(wrap_pyfunction!(_from_counts, m)?)?;
    m.add_function(wrap_pyfunction!(_finish, m)?)?;
    m.add_function(wrap_pyfunction!(_tiles, m)?)?;
    m.add_function(wrap_pyfunction!(_bin, m)?)?;
    m.add_function(wrap_pyfunction!(_render_tile, m)?)?;
    m.add_function(wrap_pyfunction!(_encode_png, m)?)?;
    m.add_function(wrap_pyfunction!(_save_png, m)?)?;
    Ok(())
}

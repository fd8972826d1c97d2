//! `pointillist.Device`: the D3D9-shaped device of `pointillist-core` from Python.

use std::sync::{Arc, Mutex, MutexGuard, TryLockError};
use std::time::Duration;

use numpy::{PyArray1, PyArrayMethods};
use pointillist_core::caps::Caps;
use pointillist_core::device::{DeviceDesc, TransformType, Viewport};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::states::{
    Api, EnumType, RenderState, SamplerState, TextureStageState, ValueKind, texture_arg_from_name,
};
use pyo3::exceptions::{PyTypeError, PyValueError};
use pyo3::prelude::*;
use pyo3::types::{PyBool, PyFloat, PyString};

use crate::arrays::{any_integer, arg, d3dcolor, dword, got, integer, texture};
use crate::backend::AnyDevice;
use crate::errors::{Error, device_error};

/// A Direct3D 9 device drawing point lists, with the calls of IDirect3DDevice9 that shape
/// points: ``set_render_state``, ``set_texture_stage_state``, ``set_sampler_state``,
/// ``set_texture``, ``set_transform``, ``set_viewport``, ``set_clip_plane``, ``clear``,
/// ``draw_points`` (DrawPrimitiveUP with D3DPT_POINTLIST) and ``read_target``.
///
/// The target is ``width`` x ``height`` A8R8G8B8 with a depth buffer, cleared to ``clear``
/// and depth 1.0. ``api`` picks the default states ("d3d9" or "d3d8"), ``caps`` the device
/// profile ("reference", "no_per_vertex_size", "single_pixel", "vertex_position_clip",
/// "software"). State names are the D3D names with or without their prefix, in any case
/// ("POINTSIZE" or "D3DRS_POINTSIZE"); values are numbers for float states, ``True``/``False``
/// for BOOLs, names for enums ("SRCALPHA") and integers for masks and colours, as in a scene
/// file (docs/spec/SCENE.md). ``behaviour`` sets device behaviour switches, a dict such as
/// ``{"minimum_size": "one_pixel"}`` (``pointillist.behaviours()`` lists them; the defaults
/// otherwise). The GIL is released while drawing.
///
/// Example::
///
///     dev = pointillist.Device(64, 64)
///     dev.set_render_state("POINTSIZE", 9.0)
///     v = numpy.array([(32.0, 32.0, 0.5, 1.0, 0xFFFF0000)],
///                     dtype=[("xyzrhw", "<f4", 4), ("diffuse", "<u4")])
///     dev.draw_points("XYZRHW | DIFFUSE", v)
///     img = dev.read_target()   # (64, 64, 4) uint8 RGBA
#[pyclass(name = "Device", module = "pointillist")]
pub struct PyDevice {
    device: Mutex<AnyDevice>,
}

impl PyDevice {
    /// The device, once no other thread uses it: waited for with the GIL released (the thread
    /// drawing on it needs the GIL to finish), answering Ctrl-C while it waits.
    fn lock(&self, py: Python<'_>) -> PyResult<MutexGuard<'_, AnyDevice>> {
        loop {
            match self.device.try_lock() {
                Ok(guard) => return Ok(guard),
                Err(TryLockError::Poisoned(e)) => return Ok(e.into_inner()),
                Err(TryLockError::WouldBlock) => {
                    py.check_signals()?;
                    py.detach(|| std::thread::sleep(Duration::from_millis(1)));
                }
            }
        }
    }
}

/// A state's name argument.
fn state_name(obj: &Bound<'_, PyAny>) -> PyResult<String> {
    arg("name", obj, "a state's name (a string)")
}

/// An index argument (a stage, a sampler, a clip plane): one no call could take is refused
/// as the device refuses one past `max`.
fn index(name: &str, obj: &Bound<'_, PyAny>, max: usize) -> PyResult<usize> {
    let v = any_integer(name, obj)?;
    v.and_then(|v| usize::try_from(v).ok()).ok_or_else(|| {
        let shown = v.map_or_else(|| got(obj), |v| v.to_string());
        Error::new_err(format!("{name} {shown} is outside 0..={max}"))
    })
}

/// A state's 32 bits from a Python value, by the state's kind (SPEC 2.7).
fn state_bits(name: &str, kind: ValueKind, value: &Bound<'_, PyAny>) -> PyResult<u32> {
    let is_bool = value.is_instance_of::<PyBool>();
    let type_error = |expected: &str| {
        PyTypeError::new_err(format!(
            "{name} takes {expected}; got {}",
            value.repr().map(|r| r.to_string()).unwrap_or_default()
        ))
    };
    match kind {
        ValueKind::Float if !is_bool && !value.is_instance_of::<PyString>() => value
            .extract::<f64>()
            .map(|v| (v as f32).to_bits())
            .map_err(|_| type_error("a number")),
        ValueKind::Float => Err(type_error("a number")),
        ValueKind::Bool if is_bool => Ok(u32::from(value.extract::<bool>()?)),
        ValueKind::Bool => Err(type_error("True or False")),
        ValueKind::Color => d3dcolor(name, value),
        ValueKind::Int => dword(name, value, "an integer", "a 32-bit value"),
        ValueKind::Enum(e) => {
            if let Ok(s) = value.extract::<String>() {
                return e.value_from_name(&s).ok_or_else(|| {
                    let names: Vec<&str> = e.names().iter().map(|(n, _)| *n).collect();
                    PyValueError::new_err(format!(
                        "unknown {name} value `{s}` (expected one of: {})",
                        names.join(", ")
                    ))
                });
            }
            if is_bool && e == EnumType::ZBufferType {
                return Ok(u32::from(value.extract::<bool>()?));
            }
            if is_bool || value.is_instance_of::<PyFloat>() {
                return Err(type_error("a name (a string) or an integer"));
            }
            let expected = "a name (a string) or an integer";
            dword(name, value, expected, "a 32-bit enum value")
        }
        ValueKind::TextureArg => match value.extract::<String>() {
            Ok(s) => texture_arg_from_name(&s).ok_or_else(|| {
                PyValueError::new_err(format!(
                    "unknown texture argument `{s}` (expected DIFFUSE, CURRENT, TEXTURE, \
                     TFACTOR, SPECULAR, TEMP or CONSTANT, optionally with | COMPLEMENT and | \
                     ALPHAREPLICATE)"
                ))
            }),
            Err(_) if is_bool || value.is_instance_of::<PyFloat>() => {
                Err(type_error("a name (a string) or an integer"))
            }
            Err(_) => dword(
                name,
                value,
                "a name (a string) or an integer",
                "a 32-bit texture argument",
            ),
        },
    }
}

fn unknown(what: &str, name: &str) -> PyErr {
    PyValueError::new_err(format!("unknown {what} `{name}`"))
}

#[pymethods]
impl PyDevice {
    #[new]
    #[pyo3(
        signature = (width, height, backend=None, *, api=None, caps=None, clear=None, behaviour=None),
        text_signature = "(width, height, backend='cpu', *, api='d3d9', caps='reference', clear=0xFF000000, behaviour=None)"
    )]
    #[allow(clippy::too_many_arguments)]
    fn new(
        width: &Bound<'_, PyAny>,
        height: &Bound<'_, PyAny>,
        backend: Option<&Bound<'_, PyAny>>,
        api: Option<&Bound<'_, PyAny>>,
        caps: Option<&Bound<'_, PyAny>>,
        clear: Option<&Bound<'_, PyAny>>,
        behaviour: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let (width, height) = crate::arrays::target_size(width, height)?;
        let api: String = api.map_or(Ok("d3d9".into()), |a| arg("api", a, "a string"))?;
        let api = match api.to_ascii_lowercase().as_str() {
            "d3d9" => Api::D3d9,
            "d3d8" => Api::D3d8,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown api `{api}` (expected \"d3d9\" or \"d3d8\")"
                )));
            }
        };
        let caps: String = caps.map_or(Ok("reference".into()), |c| arg("caps", c, "a string"))?;
        let caps = Caps::profile(&caps).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown caps profile `{caps}` (expected one of: {})",
                Caps::PROFILES.join(", ")
            ))
        })?;
        let desc = DeviceDesc {
            api,
            caps,
            clear_color: clear.map_or(Ok(0xFF00_0000), |c| d3dcolor("clear", c))?,
            behaviours: crate::behaviour::behaviours(behaviour)?,
            ..DeviceDesc::new(width, height)
        };
        let backend = backend.map_or(Ok("cpu".into()), crate::backend::name)?;
        let device =
            AnyDevice::new(crate::backend::backend(&backend)?, desc).map_err(device_error)?;
        Ok(PyDevice {
            device: Mutex::new(device),
        })
    }

    /// The target's ``(width, height)``.
    #[getter]
    fn size(&self, py: Python<'_>) -> PyResult<(u32, u32)> {
        let d = self.lock(py)?;
        let s = d.state();
        Ok((s.target_width, s.target_height))
    }

    /// The device behaviour switches it was created with: every switch's option, by name.
    #[getter]
    fn behaviour<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, pyo3::types::PyDict>> {
        let behaviours = self.lock(py)?.state().behaviours;
        crate::behaviour::as_dict(py, &behaviours)
    }

    /// SetRenderState: ``name`` a D3DRS_* name, ``value`` as its kind says (see the class).
    fn set_render_state(
        &self,
        py: Python<'_>,
        name: &Bound<'_, PyAny>,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let name = state_name(name)?;
        let s = RenderState::from_name(&name).ok_or_else(|| unknown("render state", &name))?;
        let bits = state_bits(s.name().unwrap_or(&name), s.kind(), value)?;
        self.lock(py)?.set_render_state(s, bits);
        Ok(())
    }

    /// GetRenderState: the state's raw 32 bits.
    fn render_state(&self, py: Python<'_>, name: &Bound<'_, PyAny>) -> PyResult<u32> {
        let name = state_name(name)?;
        let s = RenderState::from_name(&name).ok_or_else(|| unknown("render state", &name))?;
        Ok(self.lock(py)?.render_state(s))
    }

    /// SetTextureStageState: a D3DTSS_* state of stage 0..7.
    fn set_texture_stage_state(
        &self,
        py: Python<'_>,
        stage: &Bound<'_, PyAny>,
        name: &Bound<'_, PyAny>,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let stage = index("stage", stage, 7)?;
        let name = state_name(name)?;
        let s = TextureStageState::from_name(&name)
            .ok_or_else(|| unknown("texture stage state", &name))?;
        let bits = state_bits(s.name().unwrap_or(&name), s.kind(), value)?;
        self.lock(py)?
            .set_texture_stage_state(stage, s, bits)
            .map_err(device_error)
    }

    /// SetSamplerState: a D3DSAMP_* state of sampler 0..7.
    fn set_sampler_state(
        &self,
        py: Python<'_>,
        sampler: &Bound<'_, PyAny>,
        name: &Bound<'_, PyAny>,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let sampler = index("sampler", sampler, 7)?;
        let name = state_name(name)?;
        let s = SamplerState::from_name(&name).ok_or_else(|| unknown("sampler state", &name))?;
        let bits = state_bits(s.name().unwrap_or(&name), s.kind(), value)?;
        self.lock(py)?
            .set_sampler_state(sampler, s, bits)
            .map_err(device_error)
    }

    /// SetTexture: binds an ``(height, width, 4)`` uint8 RGBA array (top row first, its mip
    /// chain built by a 2x2 box filter) to ``stage``; ``None`` unbinds.
    #[pyo3(signature = (stage, array))]
    fn set_texture(
        &self,
        py: Python<'_>,
        stage: &Bound<'_, PyAny>,
        array: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let stage = index("stage", stage, 7)?;
        let tex = array.map(|a| texture("texture", a)).transpose()?;
        self.lock(py)?
            .set_texture(stage, tex.map(Arc::new))
            .map_err(device_error)
    }

    /// SetTransform: ``name`` "world", "view" or "projection" (D3DTS_*), ``matrix`` 4x4 rows
    /// (D3D row vectors, ``v' = v * M``).
    fn set_transform(
        &self,
        py: Python<'_>,
        name: &Bound<'_, PyAny>,
        matrix: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let name: String = arg(
            "name",
            name,
            r#"a string ("world", "view" or "projection")"#,
        )?;
        let key = name.trim().to_ascii_lowercase();
        let t = match key.strip_prefix("d3dts_").unwrap_or(&key) {
            "world" => TransformType::World,
            "view" => TransformType::View,
            "projection" => TransformType::Projection,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown transform `{name}` (expected \"world\", \"view\" or \"projection\")"
                )));
            }
        };
        let np = py.import("numpy")?;
        let m = np
            .call_method1("asarray", (matrix, "float32"))
            .map_err(|_| {
                PyTypeError::new_err(format!(
                    "{name} matrix must be 4x4 numbers; got {}",
                    got(matrix)
                ))
            })?;
        if m.getattr("shape")?.extract::<Vec<usize>>()? != [4, 4] {
            return Err(PyValueError::new_err(format!(
                "{name} matrix must be 4x4; got shape {}",
                m.getattr("shape")?.str()?
            )));
        }
        let rows: [[f32; 4]; 4] = m.call_method0("tolist")?.extract()?;
        self.lock(py)?.set_transform(t, Mat4(rows));
        Ok(())
    }

    /// SetViewport (D3DVIEWPORT9): must lie inside the target, depths within 0..1.
    #[pyo3(signature = (x, y, width, height, min_z=None, max_z=None), text_signature = "(self, x, y, width, height, min_z=0.0, max_z=1.0)")]
    #[allow(clippy::too_many_arguments)]
    fn set_viewport(
        &self,
        py: Python<'_>,
        x: &Bound<'_, PyAny>,
        y: &Bound<'_, PyAny>,
        width: &Bound<'_, PyAny>,
        height: &Bound<'_, PyAny>,
        min_z: Option<&Bound<'_, PyAny>>,
        max_z: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let int = |name, obj| integer(name, obj, 0, u32::MAX.into());
        let depth = |name, obj: Option<&Bound<'_, PyAny>>, default| {
            obj.map_or(Ok(default), |o| arg::<f32>(name, o, "a number"))
        };
        let viewport = Viewport {
            x: int("x", x)?,
            y: int("y", y)?,
            width: int("width", width)?,
            height: int("height", height)?,
            min_z: depth("min_z", min_z, 0.0)?,
            max_z: depth("max_z", max_z, 1.0)?,
        };
        self.lock(py)?.set_viewport(viewport).map_err(device_error)
    }

    /// SetClipPlane: plane ``(a, b, c, d)`` in world space, ``index`` 0..5.
    fn set_clip_plane(
        &self,
        py: Python<'_>,
        index: &Bound<'_, PyAny>,
        plane: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let index = self::index("clip plane", index, 5)?;
        let plane: [f32; 4] = arg("plane", plane, "four numbers (a, b, c, d)")?;
        self.lock(py)?
            .set_clip_plane(index, plane)
            .map_err(device_error)
    }

    /// Clear of the whole target to D3DCOLOR ``color`` and the depth buffer to ``depth``.
    #[pyo3(signature = (color=None, depth=None), text_signature = "(self, color=0xFF000000, depth=1.0)")]
    fn clear(
        &self,
        py: Python<'_>,
        color: Option<&Bound<'_, PyAny>>,
        depth: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<()> {
        let c = color.map_or(Ok(0xFF00_0000), |c| d3dcolor("color", c))?;
        let depth = depth.map_or(Ok(1.0), |d| arg::<f32>("depth", d, "a number"))?;
        self.lock(py)?.clear(c, depth).map_err(device_error)
    }

    /// DrawPrimitiveUP(D3DPT_POINTLIST): ``fvf`` a D3DFVF code (int) or names
    /// ("XYZRHW | PSIZE | DIFFUSE"); ``vertices`` bytes or a C-contiguous numpy array (a
    /// structured array whose rows are vertices, or raw bytes) laid out as the FVF says:
    /// little-endian fields in FVF order (position, RHW, PSIZE, DIFFUSE, SPECULAR, texture
    /// coordinates). The vertices are read in place, with the GIL released; Ctrl-C ends a long
    /// draw within about a second (the points drawn so far stay drawn).
    fn draw_points(
        &self,
        py: Python<'_>,
        fvf: &Bound<'_, PyAny>,
        vertices: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let fvf = match fvf.extract::<String>() {
            Ok(s) => Fvf::parse(&s).map_err(|e| PyValueError::new_err(e.to_string()))?,
            Err(_) => Fvf(dword(
                "fvf",
                fvf,
                "a D3DFVF code (an integer) or names (\"XYZRHW | DIFFUSE\")",
                "a D3DFVF code",
            )?),
        };
        let np = py.import("numpy")?;
        if let Ok(itemsize) = vertices
            .getattr("dtype")
            .and_then(|d| d.getattr("itemsize"))
            .and_then(|i| i.extract::<usize>())
        {
            let stride = fvf.stride();
            let names = vertices.getattr("dtype")?.getattr("names")?;
            if !names.is_none() && itemsize != stride {
                return Err(PyValueError::new_err(format!(
                    "vertices have {itemsize}-byte rows but the FVF's vertices are {stride} bytes"
                )));
            }
        }
        let bytes = np
            .call_method1("frombuffer", (vertices, "uint8"))
            .map_err(|e| {
                PyTypeError::new_err(format!(
                    "vertices must be bytes or a C-contiguous numpy array ({e})"
                ))
            })?
            .cast_into::<PyArray1<u8>>()?;
        let bytes = bytes.try_readonly()?;
        let slice = crate::contiguous(bytes.as_slice())?;
        let mut guard = self.lock(py)?;
        let device: &mut AnyDevice = &mut guard;
        crate::interrupt::detach(py, || device.draw_point_list(fvf, slice))?.map_err(device_error)
    }

    /// The render target as an ``(height, width, 4)`` uint8 RGBA array (alpha included), as
    /// `pointillist render` writes it to a PNG.
    fn read_target<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let mut guard = self.lock(py)?;
        let device: &mut AnyDevice = &mut guard;
        let (width, height) = (device.state().target_width, device.state().target_height);
        // Converted where the target lies (no copy of colour and depth first).
        let mut rgba = Vec::with_capacity(width as usize * height as usize * 4);
        py.detach(|| device.read_rgba8(&mut rgba))
            .map_err(device_error)?;
        crate::image(py, rgba, width, height)
    }

    /// The notes gathered since the last call: states set that have no effect on points,
    /// once each (the CLI prints them as warnings).
    fn take_notices(&self, py: Python<'_>) -> PyResult<Vec<String>> {
        Ok(self.lock(py)?.take_notices())
    }
}

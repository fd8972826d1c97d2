//! `pointillist.Device`: the D3D9-shaped device of `pointillist-core` from Python.

use std::sync::{Arc, Mutex, MutexGuard};

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

use crate::arrays::{d3dcolor, texture};
use crate::backend::AnyDevice;
use crate::errors::device_error;

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
/// file (docs/spec/SCENE.md). The GIL is released while drawing.
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
    fn lock(&self) -> MutexGuard<'_, AnyDevice> {
        self.device.lock().unwrap_or_else(|e| e.into_inner())
    }
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
        ValueKind::Color | ValueKind::Int => d3dcolor(name, value),
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
            d3dcolor(name, value)
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
            Err(_) => d3dcolor(name, value),
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
        signature = (width, height, backend="cpu", *, api="d3d9", caps="reference", clear=None),
        text_signature = "(width, height, backend='cpu', *, api='d3d9', caps='reference', clear=0xFF000000)"
    )]
    fn new(
        width: u32,
        height: u32,
        backend: &str,
        api: &str,
        caps: &str,
        clear: Option<&Bound<'_, PyAny>>,
    ) -> PyResult<Self> {
        let api = match api.to_ascii_lowercase().as_str() {
            "d3d9" => Api::D3d9,
            "d3d8" => Api::D3d8,
            _ => {
                return Err(PyValueError::new_err(format!(
                    "unknown api `{api}` (expected \"d3d9\" or \"d3d8\")"
                )));
            }
        };
        let caps = Caps::profile(caps).ok_or_else(|| {
            PyValueError::new_err(format!(
                "unknown caps profile `{caps}` (expected one of: {})",
                Caps::PROFILES.join(", ")
            ))
        })?;
        let desc = DeviceDesc {
            api,
            caps,
            clear_color: clear.map_or(Ok(0xFF00_0000), |c| d3dcolor("clear", c))?,
            ..DeviceDesc::new(width, height)
        };
        let device =
            AnyDevice::new(crate::backend::backend(backend)?, desc).map_err(device_error)?;
        Ok(PyDevice {
            device: Mutex::new(device),
        })
    }

    /// The target's ``(width, height)``.
    #[getter]
    fn size(&self) -> (u32, u32) {
        let d = self.lock();
        let s = d.state();
        (s.target_width, s.target_height)
    }

    /// SetRenderState: ``name`` a D3DRS_* name, ``value`` as its kind says (see the class).
    fn set_render_state(&self, name: &str, value: &Bound<'_, PyAny>) -> PyResult<()> {
        let s = RenderState::from_name(name).ok_or_else(|| unknown("render state", name))?;
        let bits = state_bits(s.name().unwrap_or(name), s.kind(), value)?;
        self.lock().set_render_state(s, bits);
        Ok(())
    }

    /// GetRenderState: the state's raw 32 bits.
    fn render_state(&self, name: &str) -> PyResult<u32> {
        let s = RenderState::from_name(name).ok_or_else(|| unknown("render state", name))?;
        Ok(self.lock().render_state(s))
    }

    /// SetTextureStageState: a D3DTSS_* state of stage 0..7.
    fn set_texture_stage_state(
        &self,
        stage: usize,
        name: &str,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let s = TextureStageState::from_name(name)
            .ok_or_else(|| unknown("texture stage state", name))?;
        let bits = state_bits(s.name().unwrap_or(name), s.kind(), value)?;
        self.lock()
            .set_texture_stage_state(stage, s, bits)
            .map_err(device_error)
    }

    /// SetSamplerState: a D3DSAMP_* state of sampler 0..7.
    fn set_sampler_state(
        &self,
        sampler: usize,
        name: &str,
        value: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let s = SamplerState::from_name(name).ok_or_else(|| unknown("sampler state", name))?;
        let bits = state_bits(s.name().unwrap_or(name), s.kind(), value)?;
        self.lock()
            .set_sampler_state(sampler, s, bits)
            .map_err(device_error)
    }

    /// SetTexture: binds an ``(height, width, 4)`` uint8 RGBA array (top row first, its mip
    /// chain built by a 2x2 box filter) to ``stage``; ``None`` unbinds.
    #[pyo3(signature = (stage, array))]
    fn set_texture(&self, stage: usize, array: Option<&Bound<'_, PyAny>>) -> PyResult<()> {
        let tex = array.map(|a| texture("texture", a)).transpose()?;
        self.lock()
            .set_texture(stage, tex.map(Arc::new))
            .map_err(device_error)
    }

    /// SetTransform: ``name`` "world", "view" or "projection" (D3DTS_*), ``matrix`` 4x4 rows
    /// (D3D row vectors, ``v' = v * M``).
    fn set_transform(&self, name: &str, matrix: &Bound<'_, PyAny>) -> PyResult<()> {
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
        let np = matrix.py().import("numpy")?;
        let m = np.call_method1("asarray", (matrix, "float32"))?;
        if m.getattr("shape")?.extract::<Vec<usize>>()? != [4, 4] {
            return Err(PyValueError::new_err(format!(
                "{name} matrix must be 4x4; got shape {}",
                m.getattr("shape")?.str()?
            )));
        }
        let rows: [[f32; 4]; 4] = m.call_method0("tolist")?.extract()?;
        self.lock().set_transform(t, Mat4(rows));
        Ok(())
    }

    /// SetViewport (D3DVIEWPORT9): must lie inside the target, depths within 0..1.
    #[pyo3(signature = (x, y, width, height, min_z=0.0, max_z=1.0))]
    fn set_viewport(
        &self,
        x: u32,
        y: u32,
        width: u32,
        height: u32,
        min_z: f32,
        max_z: f32,
    ) -> PyResult<()> {
        self.lock()
            .set_viewport(Viewport {
                x,
                y,
                width,
                height,
                min_z,
                max_z,
            })
            .map_err(device_error)
    }

    /// SetClipPlane: plane ``(a, b, c, d)`` in world space, ``index`` 0..5.
    fn set_clip_plane(&self, index: usize, plane: [f32; 4]) -> PyResult<()> {
        self.lock()
            .set_clip_plane(index, plane)
            .map_err(device_error)
    }

    /// Clear of the whole target to D3DCOLOR ``color`` and the depth buffer to ``depth``.
    #[pyo3(signature = (color=None, depth=1.0), text_signature = "(self, color=0xFF000000, depth=1.0)")]
    fn clear(&self, color: Option<&Bound<'_, PyAny>>, depth: f32) -> PyResult<()> {
        let c = color.map_or(Ok(0xFF00_0000), |c| d3dcolor("color", c))?;
        self.lock().clear(c, depth).map_err(device_error)
    }

    /// DrawPrimitiveUP(D3DPT_POINTLIST): ``fvf`` a D3DFVF code (int) or names
    /// ("XYZRHW | PSIZE | DIFFUSE"); ``vertices`` bytes or a C-contiguous numpy array (a
    /// structured array whose rows are vertices, or raw bytes) laid out as the FVF says:
    /// little-endian fields in FVF order (position, RHW, PSIZE, DIFFUSE, SPECULAR, texture
    /// coordinates). The vertices are read in place, with the GIL released.
    fn draw_points(
        &self,
        py: Python<'_>,
        fvf: &Bound<'_, PyAny>,
        vertices: &Bound<'_, PyAny>,
    ) -> PyResult<()> {
        let fvf = match fvf.extract::<String>() {
            Ok(s) => Fvf::parse(&s).map_err(|e| PyValueError::new_err(e.to_string()))?,
            Err(_) => Fvf(d3dcolor("fvf", fvf)?),
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
        let mut guard = self.lock();
        let device: &mut AnyDevice = &mut guard;
        py.detach(|| device.draw_point_list(fvf, slice))
            .map_err(device_error)
    }

    /// The render target as an ``(height, width, 4)`` uint8 RGBA array (alpha included), as
    /// `pointillist render` writes it to a PNG.
    fn read_target<'py>(&self, py: Python<'py>) -> PyResult<Bound<'py, PyAny>> {
        let mut guard = self.lock();
        let device: &mut AnyDevice = &mut guard;
        let target = py.detach(|| device.read_target()).map_err(device_error)?;
        let rgba = target.to_rgba8();
        crate::image(py, rgba, target.width, target.height)
    }

    /// The notes gathered since the last call: states set that have no effect on points,
    /// once each (the CLI prints them as warnings).
    fn take_notices(&self) -> Vec<String> {
        self.lock().take_notices()
    }
}

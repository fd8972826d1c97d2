//! The peer: the same workloads drawn with Mesa llvmpipe's OpenGL point sprites.
//!
//! A surfaceless EGL context (`EGL_PLATFORM_SURFACELESS_MESA`, libEGL loaded at run time), an
//! offscreen framebuffer (RGBA8 + 32-bit float depth), `GL_PROGRAM_POINT_SIZE` with
//! `gl_PointSize` computed as SPEC 2 says, the same blending and depth test, and `glFinish`
//! before each frame's clock stops. Vertices are uploaded once, in their FVF layout.
#![allow(unsafe_code)] // OpenGL and EGL are C APIs

use std::convert::Infallible;

use glow::HasContext;
use khronos_egl as egl;

use crate::workloads::{Kind, Workload};
use crate::{Timing, time_frames};

/// EGL_PLATFORM_SURFACELESS_MESA.
const PLATFORM_SURFACELESS_MESA: egl::Enum = 0x31DD;

/// A current OpenGL context on llvmpipe (or whatever Mesa driver EGL picks).
pub struct Peer {
    gl: glow::Context,
    renderer: String,
    // Keeps libEGL loaded and the context alive for the life of `gl`.
    _egl: egl::DynamicInstance<egl::EGL1_5>,
    _context: egl::Context,
}

impl Peer {
    /// Opens a surfaceless OpenGL 3.3 core context; the error says what is missing
    /// (`apt-get install libegl1 libegl-mesa0 libgl1-mesa-dri` provides llvmpipe on Debian).
    pub fn new() -> Result<Peer, String> {
        let hint = "(install libegl1 libegl-mesa0 libgl1-mesa-dri)";
        // SAFETY: loads the system's libEGL; its initialisers run no Rust code and the
        // instance it returns is kept alive in `Peer` as long as anything calls through it.
        let egl = unsafe { egl::DynamicInstance::<egl::EGL1_5>::load_required() }
            .map_err(|e| format!("cannot load libEGL with EGL 1.5 {hint}: {e}"))?;
        // SAFETY: the default native display of the surfaceless platform is a valid argument,
        // and the attribute list ends with ATTRIB_NONE.
        let display = unsafe {
            egl.get_platform_display(
                PLATFORM_SURFACELESS_MESA,
                egl::DEFAULT_DISPLAY,
                &[egl::ATTRIB_NONE],
            )
        }
        .map_err(|e| format!("no surfaceless EGL display {hint}: {e}"))?;
        egl.initialize(display)
            .map_err(|e| format!("eglInitialize failed: {e}"))?;
        egl.bind_api(egl::OPENGL_API)
            .map_err(|e| format!("eglBindAPI(OpenGL) failed: {e}"))?;
        let config = egl
            .choose_first_config(
                display,
                &[
                    egl::RENDERABLE_TYPE,
                    egl::OPENGL_BIT,
                    egl::SURFACE_TYPE,
                    egl::PBUFFER_BIT,
                    egl::NONE,
                ],
            )
            .map_err(|e| format!("eglChooseConfig failed: {e}"))?
            .ok_or("no OpenGL-capable EGL config")?;
        let attribs = [
            egl::CONTEXT_MAJOR_VERSION,
            3,
            egl::CONTEXT_MINOR_VERSION,
            3,
            egl::CONTEXT_OPENGL_PROFILE_MASK,
            egl::CONTEXT_OPENGL_CORE_PROFILE_BIT,
            egl::NONE,
        ];
        let context = egl
            .create_context(display, config, None, &attribs)
            .map_err(|e| format!("cannot create an OpenGL 3.3 core context: {e}"))?;
        egl.make_current(display, None, None, Some(context))
            .map_err(|e| format!("eglMakeCurrent (surfaceless) failed: {e}"))?;
        // SAFETY: the OpenGL context is current on this thread (made so just above), and the
        // loader returns libEGL's entry points for it, or null for a missing one.
        let gl = unsafe {
            glow::Context::from_loader_function(|name| {
                egl.get_proc_address(name)
                    .map_or(std::ptr::null(), |f| f as *const _)
            })
        };
        // SAFETY: the context is current; GL_RENDERER is a valid string query.
        let renderer = unsafe { gl.get_parameter_string(glow::RENDERER) };
        Ok(Peer {
            gl,
            renderer,
            _egl: egl,
            _context: context,
        })
    }

    /// GL_RENDERER, e.g. "llvmpipe (LLVM 15.0.6, 256 bits)".
    pub fn renderer(&self) -> &str {
        &self.renderer
    }

    /// Times `frames` frames of `w` (clear, draw, glFinish) after one warm-up frame.
    pub fn time(&self, w: &Workload, frames: usize) -> Result<Timing, String> {
        let gl = &self.gl;
        // SAFETY: the context was made current on this thread in `Peer::new` (the bench uses a
        // `Peer` on the thread that created it); every object used is created in it; the
        // attribute pointers lie inside one vertex of `w.fvf`'s layout and the draw reads
        // `w.points` whole vertices, all of them in the buffer uploaded from `w.vertices`.
        unsafe {
            let fbo = gl.create_framebuffer()?;
            gl.bind_framebuffer(glow::FRAMEBUFFER, Some(fbo));
            // A renderbuffer of `format` the size of the target, attached at `attachment`.
            let attach = |format: u32, attachment: u32| -> Result<glow::Renderbuffer, String> {
                let buffer = gl.create_renderbuffer()?;
                gl.bind_renderbuffer(glow::RENDERBUFFER, Some(buffer));
                gl.renderbuffer_storage(
                    glow::RENDERBUFFER,
                    format,
                    w.width as i32,
                    w.height as i32,
                );
                gl.framebuffer_renderbuffer(
                    glow::FRAMEBUFFER,
                    attachment,
                    glow::RENDERBUFFER,
                    Some(buffer),
                );
                Ok(buffer)
            };
            let color = attach(glow::RGBA8, glow::COLOR_ATTACHMENT0)?;
            let depth = attach(glow::DEPTH_COMPONENT32F, glow::DEPTH_ATTACHMENT)?;
            if gl.check_framebuffer_status(glow::FRAMEBUFFER) != glow::FRAMEBUFFER_COMPLETE {
                return Err("incomplete offscreen framebuffer".into());
            }
            gl.viewport(0, 0, w.width as i32, w.height as i32);

            let program = self.program(w)?;
            gl.use_program(Some(program));
            let loc = |n: &str| gl.get_uniform_location(program, n);
            gl.uniform_2_f32(loc("target").as_ref(), w.width as f32, w.height as f32);
            gl.uniform_1_f32(loc("point_size").as_ref(), w.point_size);
            // D3D row-vector matrices uploaded untransposed act as `M * v` in GLSL.
            let proj: Vec<f32> = w.projection().0.iter().flatten().copied().collect();
            gl.uniform_matrix_4_f32_slice(loc("projection").as_ref(), false, &proj);
            gl.uniform_1_i32(loc("tex").as_ref(), 0);

            let vao = gl.create_vertex_array()?;
            gl.bind_vertex_array(Some(vao));
            let vbo = gl.create_buffer()?;
            gl.bind_buffer(glow::ARRAY_BUFFER, Some(vbo));
            gl.buffer_data_u8_slice(glow::ARRAY_BUFFER, &w.vertices, glow::STATIC_DRAW);
            let layout = w.fvf.layout();
            let stride = layout.stride as i32;
            gl.vertex_attrib_pointer_f32(
                0,
                layout.position_len as i32,
                glow::FLOAT,
                false,
                stride,
                0,
            );
            gl.enable_vertex_attrib_array(0);
            match layout.psize {
                Some(o) => {
                    gl.vertex_attrib_pointer_f32(1, 1, glow::FLOAT, false, stride, o as i32);
                    gl.enable_vertex_attrib_array(1);
                }
                None => gl.vertex_attrib_1_f32(1, w.point_size),
            }
            let diffuse = layout.diffuse.ok_or("workloads carry DIFFUSE")?;
            gl.vertex_attrib_pointer_f32(2, 4, glow::UNSIGNED_BYTE, true, stride, diffuse as i32);
            gl.enable_vertex_attrib_array(2);

            if let Some(t) = &w.texture {
                let level = &t.levels()[0];
                let rgba: Vec<u8> = level
                    .texels
                    .iter()
                    .flat_map(|&c| pointillist_core::color::argb_to_rgba8(c))
                    .collect();
                let tex = gl.create_texture()?;
                gl.active_texture(glow::TEXTURE0);
                gl.bind_texture(glow::TEXTURE_2D, Some(tex));
                gl.tex_image_2d(
                    glow::TEXTURE_2D,
                    0,
                    glow::RGBA8 as i32,
                    level.width as i32,
                    level.height as i32,
                    0,
                    glow::RGBA,
                    glow::UNSIGNED_BYTE,
                    glow::PixelUnpackData::Slice(Some(&rgba)),
                );
                let filter = if w.kind == Kind::W2 {
                    glow::NEAREST
                } else {
                    glow::LINEAR
                };
                gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MIN_FILTER, filter as i32);
                gl.tex_parameter_i32(glow::TEXTURE_2D, glow::TEXTURE_MAG_FILTER, filter as i32);
            }
            gl.enable(glow::PROGRAM_POINT_SIZE);
            gl.enable(glow::BLEND);
            match w.kind {
                Kind::W1 | Kind::W2 => gl.blend_func(glow::ONE, glow::ONE),
                Kind::W3 | Kind::W4 => gl.blend_func(glow::SRC_ALPHA, glow::ONE_MINUS_SRC_ALPHA),
            }
            if w.kind == Kind::W4 {
                gl.enable(glow::DEPTH_TEST);
                gl.depth_func(glow::LEQUAL);
            } else {
                gl.disable(glow::DEPTH_TEST);
            }
            let [r, g, b, a] = pointillist_core::color::unpack(w.clear_color);
            gl.clear_color(r, g, b, a);
            gl.clear_depth_f32(1.0);

            let Ok(times) = time_frames(frames, || -> Result<(), Infallible> {
                gl.clear(glow::COLOR_BUFFER_BIT | glow::DEPTH_BUFFER_BIT);
                gl.draw_arrays(glow::POINTS, 0, w.points as i32);
                gl.finish();
                Ok(())
            });
            let error = gl.get_error();
            gl.delete_vertex_array(vao);
            gl.delete_buffer(vbo);
            gl.delete_program(program);
            gl.delete_framebuffer(fbo);
            gl.delete_renderbuffer(color);
            gl.delete_renderbuffer(depth);
            if error != glow::NO_ERROR {
                return Err(format!("OpenGL error {error:#x} while drawing"));
            }
            Ok(Timing {
                renderer: format!("llvmpipe ({})", self.renderer),
                frames: times,
            })
        }
    }

    fn program(&self, w: &Workload) -> Result<glow::Program, String> {
        let gl = &self.gl;
        let defines = format!(
            "#version 330 core\n#define PRETRANSFORMED {}\n#define TEXTURED {}\n",
            i32::from(w.fvf.is_pretransformed()),
            i32::from(w.texture.is_some())
        );
        // SAFETY: the context is current on this thread (see `Peer::time`); the shaders and the
        // program are objects of it.
        unsafe {
            let program = gl.create_program()?;
            let mut shaders = Vec::new();
            for (kind, body) in [
                (glow::VERTEX_SHADER, VERTEX),
                (glow::FRAGMENT_SHADER, FRAGMENT),
            ] {
                let s = gl.create_shader(kind)?;
                gl.shader_source(s, &format!("{defines}{body}"));
                gl.compile_shader(s);
                if !gl.get_shader_compile_status(s) {
                    return Err(format!("GLSL compile error: {}", gl.get_shader_info_log(s)));
                }
                gl.attach_shader(program, s);
                shaders.push(s);
            }
            gl.link_program(program);
            if !gl.get_program_link_status(program) {
                return Err(format!(
                    "GLSL link error: {}",
                    gl.get_program_info_log(program)
                ));
            }
            for s in shaders {
                gl.delete_shader(s);
            }
            Ok(program)
        }
    }
}

/// D3D9 pixel centres are integers: pre-transformed points shift by half a pixel, transformed
/// ones by half a pixel in clip space; D3D's clip z in 0..w becomes GL's -w..w. W4's scaling
/// uses A = 0, B = 0, C = 1 (SPEC 2.2 with Vh = target height).
const VERTEX: &str = r"
layout(location = 0) in vec4 position;
layout(location = 1) in float psize;
layout(location = 2) in vec4 bgra;
uniform vec2 target;
uniform mat4 projection;
flat out vec4 color;
void main() {
    color = bgra.zyxw;
#if PRETRANSFORMED
    gl_Position = vec4((position.x + 0.5) / target.x * 2.0 - 1.0,
                       1.0 - (position.y + 0.5) / target.y * 2.0, position.z * 2.0 - 1.0, 1.0);
    gl_PointSize = psize;
#else
    vec4 eye = vec4(position.xyz, 1.0);
    vec4 clip = projection * eye;
    float de = length(eye.xyz);
    gl_PointSize = clamp(target.y * psize * inversesqrt(de * de), 1.0, 8192.0);
    clip.x += clip.w / target.x;
    clip.y -= clip.w / target.y;
    clip.z = 2.0 * clip.z - clip.w;
    gl_Position = clip;
#endif
}
";

const FRAGMENT: &str = r"
flat in vec4 color;
uniform sampler2D tex;
uniform float point_size;
out vec4 frag;
void main() {
#if TEXTURED
    frag = color * texture(tex, gl_PointCoord);
#else
    frag = color;
#endif
}
";

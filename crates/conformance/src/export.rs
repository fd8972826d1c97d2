//! A scene's calls as a call stream ([`crate::calls`]): what `pointillist export-calls` writes
//! and what the kit hands to a replayer.
//!
//! The scene's own calls are written literally, in order, with their raw values: the clear,
//! the top-level state, each draw's changes and the draw. The stream is for a D3D9 device, so a
//! D3D8 scene starts with the render states whose D3D8 default differs (SPEC 2.6). A particle
//! scene at frame N is written as [`Scene::render_frame`] draws it: the camera's VIEW first,
//! the scene's calls, then each emitter's draw preceded by the state changes it makes, as a
//! device sees them at the draw.

use std::io::Write;
use std::path::{Path, PathBuf};
use std::sync::Arc;

use pointillist_core::DrawSetup;
use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_core::light::{Light, Material};
use pointillist_core::math::Mat4;
use pointillist_core::states::{Api, RenderState};
use pointillist_core::texture::Texture;
use pointillist_core::tolerance::{Tolerance, device_tolerance, sprite_texel_edges};
use pointillist_core::{
    Backend, Device, DeviceDesc, DeviceError, DeviceState, RenderTarget, TransformType, Viewport,
};
use pointillist_image::output::{Destination, PendingFile, commit_all};
use pointillist_particles::DrawBuffers;
use pointillist_scene::{Command, Scene};

use crate::calls::{
    self, Call, CallWriter, D3DTS_PROJECTION, D3DTS_VIEW, D3DTS_WORLD,
    FLAG_SOFTWARE_VERTEX_PROCESSING, Header, NO_TEXTURE,
};

/// What a scene exported for one device tells.
#[derive(Clone, Debug)]
pub struct Exported {
    /// The bytes of the call stream written.
    pub bytes: u64,
    /// How close the device's image must come to pointillist's (SPEC 7): the largest tolerance
    /// of the draws after the last clear.
    pub tolerance: Tolerance,
    /// Whether a draw after the last clear samples sprites by points, so that a device may take
    /// a neighbouring texel (SPEC 7, [`sprite_texel_edges`]).
    pub texel_edges: bool,
    /// The draws that reach the device (empty draws are not written).
    pub draws: usize,
}

/// The frame of `scene` a command draws: `frame` (default 0) for a scene that moves or when a
/// frame is asked for, `None` for a still scene; an error when the frame is past the last.
pub fn frame_of(scene: &Scene, frame: Option<u32>) -> Result<Option<u32>, String> {
    scene
        .frame_to_draw(frame, "--frame")
        .map_err(|e| format!("{}: {e}", scene.file.display()))
}

/// The D3DTRANSFORMSTATETYPE of a transform.
fn transform_id(t: TransformType) -> u32 {
    match t {
        TransformType::World => D3DTS_WORLD,
        TransformType::View => D3DTS_VIEW,
        TransformType::Projection => D3DTS_PROJECTION,
    }
}

fn transform(which: TransformType, m: &Mat4) -> Call {
    Call::Transform {
        which: transform_id(which),
        matrix: m.0,
    }
}

fn viewport(vp: &Viewport) -> Call {
    Call::Viewport {
        rect: [vp.x, vp.y, vp.width, vp.height],
        depth: [vp.min_z, vp.max_z],
    }
}

/// The backend the export draws on: it writes the stream's particle part from the states a
/// draw sees, and tracks the tolerance of every draw.
struct Recorder<'a> {
    writer: CallWriter<&'a mut dyn Write>,
    /// Textures given an id, kept alive so that their addresses stay unique.
    textures: Vec<Arc<Texture>>,
    /// While the particle part is written: the state the stream has set so far.
    written: Option<DeviceState>,
    tolerance: Tolerance,
    texel_edges: bool,
    draws: usize,
}

impl Recorder<'_> {
    /// Ends the stream; what the draws tell, or the error that stopped the writes.
    fn finish(&mut self, out_name: &Path) -> Result<Exported, String> {
        let bytes = self
            .writer
            .end()
            .map_err(|e| format!("{}: cannot write the call stream: {e}", out_name.display()))?;
        Ok(Exported {
            bytes,
            tolerance: self.tolerance,
            texel_edges: self.texel_edges,
            draws: self.draws,
        })
    }

    /// The id of `texture`, writing its CreateTexture record the first time.
    fn texture_id(&mut self, texture: &Option<Arc<Texture>>) -> u32 {
        let Some(t) = texture else {
            return NO_TEXTURE;
        };
        if let Some(i) = self.textures.iter().position(|k| Arc::ptr_eq(k, t)) {
            return i as u32;
        }
        let id = self.textures.len() as u32;
        self.writer.create_texture(id, t.levels());
        self.textures.push(t.clone());
        id
    }

    /// Writes the calls that take the stream's state from `old` to `new`.
    fn write_changes(&mut self, old: &DeviceState, new: &DeviceState) {
        // Every field is named, so that a new kind of device state cannot be missed here.
        let DeviceState {
            api: _,
            caps: _,
            // A device's behaviour is its own: no call sets it.
            behaviours: _,
            target_width: _,
            target_height: _,
            render_states,
            stage_states,
            sampler_states,
            textures,
            world,
            view,
            projection,
            viewport: vp,
            clip_planes,
            material,
            lights,
        } = new;
        let w = &mut self.writer;
        for (i, (&a, &b)) in old.render_states.iter().zip(render_states).enumerate() {
            if a != b {
                w.call(&Call::RenderState {
                    state: i as u32,
                    value: b,
                });
            }
        }
        for (stage, (olds, news)) in old.stage_states.iter().zip(stage_states).enumerate() {
            for (i, (&a, &b)) in olds.iter().zip(news).enumerate() {
                if a != b {
                    w.call(&Call::TextureStageState {
                        stage: stage as u32,
                        state: i as u32,
                        value: b,
                    });
                }
            }
        }
        for (s, (olds, news)) in old.sampler_states.iter().zip(sampler_states).enumerate() {
            for (i, (&a, &b)) in olds.iter().zip(news).enumerate() {
                if a != b {
                    w.call(&Call::SamplerState {
                        sampler: s as u32,
                        state: i as u32,
                        value: b,
                    });
                }
            }
        }
        let bits = |m: &Mat4| m.0.map(|r| r.map(f32::to_bits));
        for (which, a, b) in [
            (TransformType::World, &old.world, world),
            (TransformType::View, &old.view, view),
            (TransformType::Projection, &old.projection, projection),
        ] {
            if bits(a) != bits(b) {
                w.call(&transform(which, b));
            }
        }
        if old.viewport != *vp {
            w.call(&viewport(vp));
        }
        for (i, (a, b)) in old.clip_planes.iter().zip(clip_planes).enumerate() {
            if a.map(f32::to_bits) != b.map(f32::to_bits) {
                w.call(&Call::ClipPlane {
                    index: i as u32,
                    plane: *b,
                });
            }
        }
        if old.material != *material {
            w.call(&material_call(material));
        }
        for (index, slot) in lights.iter() {
            let before = old.lights.get(index);
            if before.map(|b| b.light) != Some(slot.light) {
                w.call(&light_call(index, &slot.light));
            }
            if before.is_some_and(|b| b.enabled) != slot.enabled {
                w.call(&Call::LightEnable {
                    index,
                    enable: slot.enabled,
                });
            }
        }
        for (index, slot) in old.lights.iter() {
            if slot.enabled && lights.get(index).is_none() {
                w.call(&Call::LightEnable {
                    index,
                    enable: false,
                });
            }
        }
        for (stage, (a, b)) in old.textures.iter().zip(textures).enumerate() {
            let same = match (a, b) {
                (Some(a), Some(b)) => Arc::ptr_eq(a, b),
                (None, None) => true,
                _ => false,
            };
            if !same {
                let id = self.texture_id(b);
                self.writer.call(&Call::SetTexture {
                    stage: stage as u32,
                    id,
                });
            }
        }
    }
}

impl Backend for Recorder<'_> {
    fn create_target(&mut self, _: u32, _: u32, _: u32, _: f32) -> Result<(), DeviceError> {
        Ok(())
    }

    fn clear(&mut self, _: u32, _: f32) -> Result<(), DeviceError> {
        self.tolerance = Tolerance::Exact;
        self.texel_edges = false;
        Ok(())
    }

    fn draw_points(&mut self, draw: &DrawSetup<'_>, vertices: &[u8]) -> Result<(), DeviceError> {
        let (state, fvf) = (draw.state, draw.fvf);
        self.tolerance = self.tolerance.max(device_tolerance(draw));
        self.texel_edges |= sprite_texel_edges(draw);
        self.draws += 1;
        if let Some(old) = self.written.take() {
            self.write_changes(&old, state);
            self.writer
                .draw_points(fvf.0, fvf.stride() as u32, vertices);
            self.written = Some(state.clone());
        }
        Ok(())
    }

    fn read_target(&mut self) -> Result<RenderTarget, DeviceError> {
        Ok(RenderTarget::default())
    }
}

/// SetMaterial of core's D3DMATERIAL9.
fn material_call(m: &Material) -> Call {
    Call::Material(calls::Material {
        diffuse: m.diffuse,
        ambient: m.ambient,
        specular: m.specular,
        emissive: m.emissive,
        power: m.power,
    })
}

/// SetLight of core's D3DLIGHT9.
fn light_call(index: u32, l: &Light) -> Call {
    Call::Light {
        index,
        light: calls::Light {
            kind: l.light_type as u32,
            diffuse: l.diffuse,
            specular: l.specular,
            ambient: l.ambient,
            position: l.position,
            direction: l.direction,
            range: l.range,
            falloff: l.falloff,
            attenuation: [l.attenuation0, l.attenuation1, l.attenuation2],
            theta: l.theta,
            phi: l.phi,
        },
    }
}

/// Writes the scene's own calls literally; `view` replaces every VIEW the scene sets. The error:
/// a vertex file that changed size since the scene was read ([`pointillist_scene::VertexBytes`]).
fn write_steps(rec: &mut Recorder, scene: &Scene, view: Option<Mat4>) -> Result<(), String> {
    if scene.api != Api::D3d9 {
        // Only the API's defaults are written: a behaviour's default (POINTSIZE_MAX) is the
        // device's own, what the kit classifies.
        let (b, max) = (&scene.behaviours, scene.caps.max_point_size);
        for &s in RenderState::all() {
            let (ours, d3d9) = (
                s.default_value(scene.api, b, max),
                s.default_value(Api::D3d9, b, max),
            );
            if ours != d3d9 {
                rec.writer.call(&Call::RenderState {
                    state: s.0,
                    value: ours,
                });
            }
        }
    }
    if let Some(m) = &view {
        rec.writer.call(&transform(TransformType::View, m));
    }
    for step in &scene.steps {
        let call = match &step.command {
            Command::Clear { color, depth } => Call::Clear {
                color: *color,
                depth: *depth,
            },
            Command::RenderState(s, v) => Call::RenderState {
                state: s.0,
                value: *v,
            },
            Command::TextureStageState {
                stage,
                state,
                value,
            } => Call::TextureStageState {
                stage: *stage as u32,
                state: state.0,
                value: *value,
            },
            Command::SamplerState {
                sampler,
                state,
                value,
            } => Call::SamplerState {
                sampler: *sampler as u32,
                state: state.0,
                value: *value,
            },
            Command::Texture { stage, texture } => Call::SetTexture {
                stage: *stage as u32,
                id: rec.texture_id(texture),
            },
            Command::Transform(TransformType::View, _) if view.is_some() => continue,
            Command::Transform(which, m) => transform(*which, m),
            Command::Viewport(vp) => viewport(vp),
            Command::ClipPlane { index, plane } => Call::ClipPlane {
                index: *index as u32,
                plane: *plane,
            },
            Command::Material(m) => material_call(m),
            Command::Light { index, light } => light_call(*index, light),
            Command::LightEnable { index, enable } => Call::LightEnable {
                index: *index,
                enable: *enable,
            },
            Command::Draw { fvf, vertices } => {
                // A mapped vertex file shortened since the parse is an error, not a SIGBUS.
                vertices
                    .check_unchanged()
                    .map_err(|e| step.origin.error(&scene.file, e).to_string())?;
                if !vertices.is_empty() {
                    rec.writer.draw_points(fvf.0, fvf.stride() as u32, vertices);
                }
                continue;
            }
        };
        rec.writer.call(&call);
    }
    Ok(())
}

/// Exports `scene` for a device with `caps` (the vertex processing flag of the header comes
/// from them) to `out`, written as it goes (no copy of the scene's texels and vertices is held);
/// `frame` as [`frame_of`] reads it. Errors are one line naming the scene, or `out_name` when
/// `out` fails.
pub fn export(
    scene: &Scene,
    caps: Caps,
    frame: Option<u32>,
    out: &mut dyn Write,
    out_name: &Path,
) -> Result<Exported, String> {
    let frame = frame_of(scene, frame)?;
    let flags = match caps.vertex_processing {
        VertexProcessing::Hardware => 0,
        VertexProcessing::Software => FLAG_SOFTWARE_VERTEX_PROCESSING,
    };
    let recorder = Recorder {
        writer: CallWriter::to(
            out,
            Header {
                width: scene.target.width,
                height: scene.target.height,
                flags,
            },
        ),
        textures: Vec::new(),
        written: None,
        tolerance: Tolerance::Exact,
        texel_edges: false,
        draws: 0,
    };
    let desc = DeviceDesc {
        caps,
        ..scene.device_desc()
    };
    let name = scene.file.display();
    let mut device = Device::new(recorder, desc)
        .map_err(|e| format!("{name}: cannot create the device: {e}"))?;
    match frame {
        None => {
            write_steps(device.backend_mut(), scene, None)?;
            scene.replay(&mut device).map_err(|e| e.to_string())?;
        }
        Some(frame) => {
            // Scene::render_frame, with the stream written as it goes.
            let mut system = scene.particle_system().map_err(|e| e.to_string())?;
            system.advance_to(scene.animation.sim_time(frame));
            let view = scene
                .animation
                .view_at(f64::from(frame) / f64::from(scene.animation.fps))
                .map_err(|e| format!("{name}: {e}"))?;
            write_steps(device.backend_mut(), scene, view)?;
            scene
                .replay_with_view(&mut device, view)
                .map_err(|e| e.to_string())?;
            let state = device.state().clone();
            device.backend_mut().written = Some(state);
            system
                .draw(&mut device, &mut DrawBuffers::new())
                .map_err(|e| format!("{name}: cannot draw the particles: {e}"))?;
        }
    }
    device.backend_mut().finish(out_name)
}

/// Exports `scene` with its own caps into a temporary file for `path`, which must not be one of
/// the files the scene reads; the file is closed and put in place by [`commit_outside`].
pub fn export_pending(
    scene: &Scene,
    frame: Option<u32>,
    path: &Path,
) -> Result<(Exported, PendingFile), String> {
    let mut file = Destination::check(path, &scene.inputs)
        .and_then(|d| d.create())
        .map_err(|e| e.to_string())?;
    let exported = export(scene, scene.caps, frame, &mut file, path)?;
    // Closed until it is put in place, so that many streams hold no file descriptors.
    file.close().map_err(|e| e.to_string())?;
    Ok((exported, file))
}

/// Exports `cases` with their own caps into the folder `out` (created when missing): `NAME.calls`
/// each and `list.txt`, the replayer's argument file (`replayer OUTDIR @list.txt`), one stream
/// name a line. The streams are written under temporary names as they are made and put in place
/// only when all are whole and none of them is a file a scene reads; the first error stops it.
pub fn export_cases(cases: &[crate::Case], frame: Option<u32>, out: &Path) -> Result<(), String> {
    std::fs::create_dir_all(out).map_err(|e| format!("cannot create {}: {e}", out.display()))?;
    let (mut files, mut inputs, mut list) = (Vec::new(), Vec::new(), String::new());
    for case in cases {
        let scene = pointillist_scene::load(&case.scene).map_err(|e| e.to_string())?;
        inputs.extend_from_slice(&scene.inputs);
        let path = out.join(format!("{}.calls", case.name));
        files.push(export_pending(&scene, frame, &path)?.1);
        list.push_str(&format!("{}.calls\n", case.name));
    }
    let list_path = out.join("list.txt");
    let mut list_file = Destination::check(&list_path, &inputs)
        .and_then(|d| d.create())
        .map_err(|e| e.to_string())?;
    list_file
        .write_all(list.as_bytes())
        .map_err(|e| format!("{}: {e}", list_path.display()))?;
    files.push(list_file);
    commit_outside(files, &inputs)
}

/// Puts `files` in place, all or none, once none of them is one of `inputs` (the files of every
/// scene exported with them): a stream never replaces a file another scene reads.
pub fn commit_outside(files: Vec<PendingFile>, inputs: &[PathBuf]) -> Result<(), String> {
    for f in &files {
        Destination::check(f.destination().path(), inputs).map_err(|e| e.to_string())?;
    }
    commit_all(files).map_err(|e| e.to_string())
}

//! One frame of a scene file (docs/spec/SCENE.md) drawn on a backend: what `pointillist render`
//! writes and Python's `pointillist.render_scene` returns, drawn by the same lines.
//!
//! The scene's `[behaviour]` is merged with the caller's settings over it (as `--behaviour`
//! does); a scene with particles or an `[animation]`, or any scene when a frame is asked for,
//! renders that frame (0 by default): the particles simulated to `warmup + frame / fps`
//! seconds, the camera at `frame / fps`. Other scenes are replayed once.

use pointillist_core::behaviour::BehaviourSetting;
use pointillist_core::{Backend, Device, DeviceDesc, RenderTarget};
use pointillist_particles::DrawBuffers;
use pointillist_scene::Scene;

/// What to draw of a scene besides the scene itself.
#[derive(Clone, Debug, Default)]
pub struct FrameRequest<'a> {
    /// Device behaviour switches set over the scene's `[behaviour]`.
    pub behaviours: &'a [BehaviourSetting],
    /// The frame of an animated scene (`None`: frame 0; a scene without animation is then
    /// replayed once).
    pub frame: Option<u32>,
    /// How the caller's messages name the frame argument (`--frame`, `frame`): the error for a
    /// frame outside the animation says `SCENE: {frame_arg} N is outside ...`. Empty: `frame`.
    pub frame_arg: &'a str,
}

/// A drawn frame.
#[derive(Debug)]
pub struct Frame {
    /// The render target as the draws left it.
    pub target: RenderTarget,
    /// The device's notices (states that have no effect on points), for the caller to show.
    pub notices: Vec<String>,
    /// For a scene drawn as an animation frame: the frame and the number of live particles.
    pub particles: Option<(u32, usize)>,
}

/// Draws `request`'s frame of `scene` on `backend` and reads the target back.
///
/// `check` is called between the particle simulation's fixed steps (a long warm-up): an error
/// it returns (a signal, in Python) ends the frame with that message before anything is drawn.
/// The error is the one-line message the command line prints: the scene file, then what went
/// wrong (the device refused the scene's target, a frame outside the animation, a draw, the
/// read-back).
pub fn render<B: Backend>(
    scene: &Scene,
    backend: B,
    request: &FrameRequest<'_>,
    check: impl FnMut() -> Result<(), String>,
) -> Result<Frame, String> {
    let name = scene.file.display();
    let desc = DeviceDesc {
        behaviours: scene.behaviours.with(request.behaviours),
        ..scene.device_desc()
    };
    let mut device =
        Device::new(backend, desc).map_err(|e| format!("{name}: cannot create the device: {e}"))?;
    let mut particles = None;
    let arg = match request.frame_arg {
        "" => "frame",
        arg => arg,
    };
    let frame = scene
        .frame_to_draw(request.frame, arg)
        .map_err(|e| format!("{name}: {e}"))?;
    if let Some(frame) = frame {
        let mut system = scene.particle_system().map_err(|e| e.to_string())?;
        let mut buffers = DrawBuffers::new();
        scene
            .render_frame_checked(&mut device, &mut system, &mut buffers, frame, check)
            .map_err(|e| e.to_string())?;
        particles = Some((frame, system.len()));
    } else {
        scene.replay(&mut device).map_err(|e| e.to_string())?;
    }
    let notices = device.take_notices();
    // Taken where it lies: no copy of colour and depth.
    let target = device
        .into_target()
        .map_err(|e| format!("{name}: cannot read the render target: {e}"))?;
    Ok(Frame {
        target,
        notices,
        particles,
    })
}

//! `pointillist view SCENE`: a window showing the scene live, with an orbit camera.
//!
//! Contract: without `--backend` the scene is drawn on the GPU backend when wgpu finds a
//! hardware adapter and on the CPU backend otherwise (no adapter, or a software rasterizer such
//! as lavapipe: `backend::automatic`), and one line on standard error says which; the target is read back and blitted into the window with softbuffer, scaled to
//! fit. The simulation runs in real time (steps of the
//! scene's fixed time step); Space pauses, Right or `.` steps one frame while paused, R
//! restarts, the left mouse button or the arrow keys orbit, the wheel or +/- zoom, Esc or Q
//! quits. The window title shows the frame time and the particle count. `--frames N` renders N
//! frames of 1/fps each and exits by itself (what the CI smoke test runs under Xvfb).

use std::num::NonZeroU32;
use std::rc::Rc;
use std::time::{Duration, Instant};

use pointillist_core::math::Mat4;
use pointillist_core::{Backend, Device};
use pointillist_particles::{DrawBuffers, ParticleSystem};
use pointillist_scene::Scene;
use pointillist_scene::work::Limited;
use winit::application::ApplicationHandler;
use winit::dpi::PhysicalSize;
use winit::event::{ElementState, MouseButton, MouseScrollDelta, WindowEvent};
use winit::event_loop::{ActiveEventLoop, ControlFlow, EventLoop};
use winit::keyboard::{Key, NamedKey};
use winit::window::{Window, WindowId};

use crate::{BackendKind, ViewArgs, backend};

/// An orbit camera: yaw and pitch around a centre, at a distance.
#[derive(Copy, Clone, Debug)]
struct Orbit {
    at: [f32; 3],
    distance: f32,
    yaw: f32,
    pitch: f32,
}

impl Orbit {
    /// The camera that sees what the scene's VIEW matrix sees, looking at the point of its view
    /// axis nearest the origin (at least 1 unit ahead).
    fn from_view(view: &Mat4) -> Orbit {
        let inv = view.inverse().unwrap_or(Mat4::IDENTITY);
        let eye = [inv.0[3][0], inv.0[3][1], inv.0[3][2]];
        let f = inv.0[2];
        let len = (f[0] * f[0] + f[1] * f[1] + f[2] * f[2]).sqrt().max(1e-6);
        let fwd = [f[0] / len, f[1] / len, f[2] / len];
        let along = -(eye[0] * fwd[0] + eye[1] * fwd[1] + eye[2] * fwd[2]);
        let distance = along.max(1.0);
        let at = [
            eye[0] + fwd[0] * distance,
            eye[1] + fwd[1] * distance,
            eye[2] + fwd[2] * distance,
        ];
        Orbit {
            at,
            distance,
            yaw: (-fwd[0]).atan2(-fwd[2]),
            pitch: (-fwd[1]).clamp(-1.0, 1.0).asin(),
        }
    }

    fn eye(&self) -> [f32; 3] {
        let (sy, cy) = self.yaw.sin_cos();
        let (sp, cp) = self.pitch.sin_cos();
        [
            self.at[0] + self.distance * cp * sy,
            self.at[1] + self.distance * sp,
            self.at[2] + self.distance * cp * cy,
        ]
    }

    fn view(&self) -> Mat4 {
        Mat4::look_at_lh(self.eye(), self.at, [0.0, 1.0, 0.0])
    }

    fn rotate(&mut self, dyaw: f32, dpitch: f32) {
        self.yaw += dyaw;
        self.pitch = (self.pitch + dpitch).clamp(-1.5, 1.5);
    }
}

/// Everything the window needs between events.
struct App<B: Backend> {
    scene: Scene,
    title: String,
    device: Device<B>,
    backend_name: &'static str,
    system: ParticleSystem,
    buffers: DrawBuffers,
    orbit: Orbit,
    paused: bool,
    step_once: bool,
    /// Frames to render before exiting (`--frames`), with a fixed 1/fps per frame.
    frame_limit: Option<u32>,
    frames: u32,
    last: Instant,
    title_at: Instant,
    frame_ms: f64,
    drag: Option<(f64, f64)>,
    cursor: (f64, f64),
    pixels: Vec<u32>,
    window: Option<Rc<Window>>,
    surface: Option<softbuffer::Surface<Rc<Window>, Rc<Window>>>,
    error: Option<String>,
}

impl<B: Backend> App<B> {
    fn fail(&mut self, event_loop: &ActiveEventLoop, message: String) {
        self.error = Some(message);
        event_loop.exit();
    }

    /// Advances the simulation and draws one frame into `self.pixels`.
    fn render(&mut self) -> Result<(), String> {
        let fps = f64::from(self.scene.animation.fps);
        let now = Instant::now();
        let dt = if self.frame_limit.is_some() {
            1.0 / fps
        } else {
            (now - self.last).as_secs_f64().min(0.1)
        };
        self.last = now;
        if !self.paused {
            self.system.advance(dt);
        } else if self.step_once {
            self.system.advance(1.0 / fps);
        }
        self.step_once = false;
        let start = Instant::now();
        self.scene
            .replay_with_view(&mut self.device, Some(self.orbit.view()))
            .map_err(|e| e.to_string())?;
        self.system
            .draw(&mut self.device, &mut self.buffers)
            .map_err(|e| e.to_string())?;
        let target = self.device.read_target().map_err(|e| e.to_string())?;
        self.pixels.clear();
        self.pixels
            .extend(target.color.iter().map(|c| c & 0x00FF_FFFF));
        let ms = start.elapsed().as_secs_f64() * 1000.0;
        self.frame_ms = if self.frames == 0 {
            ms
        } else {
            self.frame_ms * 0.9 + ms * 0.1
        };
        self.frames += 1;
        Ok(())
    }

    /// Copies the target into the window, scaled to fit (nearest texel), letterboxed.
    fn present(&mut self) -> Result<(), String> {
        let (Some(window), Some(surface)) = (&self.window, &mut self.surface) else {
            return Ok(());
        };
        let size = window.inner_size();
        let (Some(w), Some(h)) = (NonZeroU32::new(size.width), NonZeroU32::new(size.height)) else {
            return Ok(());
        };
        surface
            .resize(w, h)
            .map_err(|e| format!("cannot resize the window surface: {e}"))?;
        let mut buffer = surface
            .buffer_mut()
            .map_err(|e| format!("cannot draw into the window: {e}"))?;
        let (tw, th) = (
            self.scene.target.width as usize,
            self.scene.target.height as usize,
        );
        let (ww, wh) = (w.get() as usize, h.get() as usize);
        let scale = (ww as f64 / tw as f64).min(wh as f64 / th as f64);
        let (sw, sh) = (
            ((tw as f64 * scale) as usize).max(1),
            ((th as f64 * scale) as usize).max(1),
        );
        let (ox, oy) = ((ww - sw.min(ww)) / 2, (wh - sh.min(wh)) / 2);
        buffer.fill(0);
        for y in 0..sh.min(wh) {
            let ty = (y * th / sh).min(th - 1);
            let row = &self.pixels[ty * tw..(ty + 1) * tw];
            let out = &mut buffer[(oy + y) * ww + ox..(oy + y) * ww + ox + sw.min(ww)];
            for (x, px) in out.iter_mut().enumerate() {
                *px = row[(x * tw / sw).min(tw - 1)];
            }
        }
        buffer
            .present()
            .map_err(|e| format!("cannot present the frame: {e}"))?;
        if self.title_at.elapsed() > Duration::from_millis(250) {
            self.title_at = Instant::now();
            window.set_title(&format!(
                "{} - {} particles - {:.1} ms/frame ({}){}",
                self.title,
                self.system.len(),
                self.frame_ms,
                self.backend_name,
                if self.paused { " - paused" } else { "" }
            ));
        }
        Ok(())
    }

    fn key(&mut self, event_loop: &ActiveEventLoop, key: &Key) {
        match key {
            Key::Named(NamedKey::Escape) => event_loop.exit(),
            Key::Named(NamedKey::Space) => self.paused = !self.paused,
            Key::Named(NamedKey::ArrowRight) if self.paused => self.step_once = true,
            Key::Named(NamedKey::ArrowLeft) => self.orbit.rotate(-0.1, 0.0),
            Key::Named(NamedKey::ArrowRight) => self.orbit.rotate(0.1, 0.0),
            Key::Named(NamedKey::ArrowUp) => self.orbit.rotate(0.0, 0.1),
            Key::Named(NamedKey::ArrowDown) => self.orbit.rotate(0.0, -0.1),
            Key::Character(c) => match c.as_str() {
                "q" | "Q" => event_loop.exit(),
                "." | "n" | "N" => self.step_once = true,
                "r" | "R" => {
                    self.system.reset();
                    self.system.advance_to(self.scene.animation.sim_time(0));
                }
                "+" | "=" => self.orbit.distance = (self.orbit.distance * 0.9).max(0.1),
                "-" => self.orbit.distance *= 1.1,
                _ => {}
            },
            _ => {}
        }
    }
}

impl<B: Backend> ApplicationHandler for App<B> {
    fn resumed(&mut self, event_loop: &ActiveEventLoop) {
        if self.window.is_some() {
            return;
        }
        let (w, h) = (self.scene.target.width, self.scene.target.height);
        let attrs = Window::default_attributes()
            .with_title(self.title.clone())
            .with_inner_size(PhysicalSize::new(w.min(1920), h.min(1080)));
        let window = match event_loop.create_window(attrs) {
            Ok(w) => Rc::new(w),
            Err(e) => return self.fail(event_loop, format!("cannot open a window: {e}")),
        };
        let context = match softbuffer::Context::new(Rc::clone(&window)) {
            Ok(c) => c,
            Err(e) => return self.fail(event_loop, format!("cannot draw into a window here: {e}")),
        };
        match softbuffer::Surface::new(&context, Rc::clone(&window)) {
            Ok(s) => self.surface = Some(s),
            Err(e) => return self.fail(event_loop, format!("cannot draw into the window: {e}")),
        }
        window.request_redraw();
        self.window = Some(window);
        self.last = Instant::now();
    }

    fn window_event(&mut self, event_loop: &ActiveEventLoop, _id: WindowId, event: WindowEvent) {
        match event {
            WindowEvent::CloseRequested => event_loop.exit(),
            WindowEvent::RedrawRequested => {
                if let Err(e) = self.render().and_then(|()| self.present()) {
                    return self.fail(event_loop, e);
                }
                if self.frame_limit.is_some_and(|n| self.frames >= n) {
                    event_loop.exit();
                }
            }
            WindowEvent::KeyboardInput { event, .. } if event.state == ElementState::Pressed => {
                self.key(event_loop, &event.logical_key);
            }
            WindowEvent::MouseInput {
                state,
                button: MouseButton::Left,
                ..
            } => {
                self.drag = (state == ElementState::Pressed).then_some(self.cursor);
            }
            WindowEvent::CursorMoved { position, .. } => {
                self.cursor = (position.x, position.y);
                if let Some((x, y)) = self.drag {
                    self.orbit.rotate(
                        ((position.x - x) * 0.01) as f32,
                        ((position.y - y) * 0.01) as f32,
                    );
                    self.drag = Some(self.cursor);
                }
            }
            WindowEvent::MouseWheel { delta, .. } => {
                let lines = match delta {
                    MouseScrollDelta::LineDelta(_, y) => y,
                    MouseScrollDelta::PixelDelta(p) => (p.y / 40.0) as f32,
                };
                self.orbit.distance = (self.orbit.distance * 0.9f32.powf(lines)).max(0.1);
            }
            _ => {}
        }
    }

    fn about_to_wait(&mut self, _event_loop: &ActiveEventLoop) {
        if let Some(w) = &self.window {
            w.request_redraw();
        }
    }
}

fn run_on<B: Backend>(
    scene: Scene,
    title: String,
    device: Device<B>,
    backend_name: &'static str,
    frame_limit: Option<u32>,
) -> Result<(), String> {
    let mut system = scene.particle_system().map_err(|e| e.to_string())?;
    // Start where the animation's frame 0 is: after the warm-up.
    system.advance_to(scene.animation.sim_time(0));
    let view = scene.initial_view();
    let event_loop = EventLoop::new().map_err(|e| format!("cannot open a window: {e}"))?;
    event_loop.set_control_flow(ControlFlow::Poll);
    let mut app = App {
        scene,
        title,
        device,
        backend_name,
        system,
        buffers: DrawBuffers::new(),
        orbit: Orbit::from_view(&view),
        paused: false,
        step_once: false,
        frame_limit,
        frames: 0,
        last: Instant::now(),
        title_at: Instant::now(),
        frame_ms: 0.0,
        drag: None,
        cursor: (0.0, 0.0),
        pixels: Vec::new(),
        window: None,
        surface: None,
        error: None,
    };
    event_loop
        .run_app(&mut app)
        .map_err(|e| format!("the window closed with an error: {e}"))?;
    if let Some(e) = app.error {
        return Err(e);
    }
    crate::report::outln!(
        "{} frames, {:.1} ms per frame on the {} backend, {} particles",
        app.frames,
        app.frame_ms,
        app.backend_name,
        app.system.len()
    );
    Ok(())
}

/// Runs `pointillist view` on the backend `--backend` names, or else on the one
/// `backend::automatic` chooses, saying which on standard error. Without `--backend`, a GPU that
/// cannot hold the scene's target (out of memory, a target beyond its limits) is a one-line
/// warning and the CPU backend draws instead.
pub fn run(args: &ViewArgs) -> Result<(), String> {
    let scene = pointillist_scene::load(&args.scene).map_err(|e| e.to_string())?;
    let title = format!("pointillist - {}", args.scene.display());
    let cannot = |e: pointillist_core::DeviceError| {
        format!("{}: cannot create the device: {e}", args.scene.display())
    };
    // Every frame's draws are limited as `render`'s are (`--max-pixels`): one beyond the
    // limit ends the view with the error instead of freezing the window for hours.
    let limited = |b| Limited::new(b, args.max_pixels);
    let cpu = || {
        Device::new(
            limited(backend::create(BackendKind::Cpu)?),
            scene.device_desc(),
        )
        .map_err(cannot)
    };
    let (device, name) = match args.backend {
        Some(BackendKind::Cpu) => (cpu()?, "cpu"),
        Some(BackendKind::Gpu) => (
            Device::new(
                limited(backend::create(BackendKind::Gpu)?),
                scene.device_desc(),
            )
            .map_err(cannot)?,
            "gpu",
        ),
        None => {
            let (kind, line) = backend::automatic();
            crate::report::errln!("view: {}", crate::report::printable(&line));
            match kind {
                BackendKind::Cpu => (cpu()?, "cpu"),
                BackendKind::Gpu => match backend::create(BackendKind::Gpu)
                    .and_then(|b| Device::new(limited(b), scene.device_desc()).map_err(cannot))
                {
                    Ok(d) => (d, "gpu"),
                    Err(e) => {
                        crate::report::warning(&format!("{e}; drawing on the CPU backend"));
                        (cpu()?, "cpu")
                    }
                },
            }
        }
    };
    run_on(scene, title, device, name, args.frames)
}

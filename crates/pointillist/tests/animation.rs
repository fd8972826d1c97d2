//! The pipelined frame loop (drawing frame k + 1 while frame k is encoded) writes the bytes of
//! drawing and encoding the frames one after another, in order.

use std::path::{Path, PathBuf};

use pointillist::animation::{Compression, Observer, Request, animate};
use pointillist::cpu::CpuBackend;
use pointillist::image::png::write_png_rgba8;
use pointillist::particles::DrawBuffers;

struct Quiet {
    done: Vec<u32>,
    stop_at: Option<u32>,
}

impl Observer for Quiet {
    fn warning(&mut self, text: &str) {
        panic!("unexpected warning: {text}");
    }
    fn frame_done(&mut self, k: u32) -> Result<(), String> {
        self.done.push(k);
        match self.stop_at {
            Some(s) if s == k => Err("stopped".into()),
            _ => Ok(()),
        }
    }
}

fn scene() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../../scenes/fountain.toml")
}

/// Frame k of the scene drawn alone, as RGBA8.
fn sequential_frames(frames: u32) -> Vec<Vec<u8>> {
    let scene = pointillist::scene::load(&scene()).unwrap();
    let mut device = pointillist::Device::new(CpuBackend::new(), scene.device_desc()).unwrap();
    let mut system = scene.particle_system().unwrap();
    let mut buffers = DrawBuffers::new();
    (0..frames)
        .map(|k| {
            scene
                .render_frame(&mut device, &mut system, &mut buffers, k)
                .unwrap();
            device.read_target().unwrap().to_rgba8()
        })
        .collect()
}

fn run(out: &Path, frames: u32, stop_at: Option<u32>) -> (Result<(), String>, Vec<u32>) {
    let request = Request {
        scene: scene(),
        output: out.to_path_buf(),
        format: None,
        frames: Some(frames),
        compression: Compression::Fast,
        behaviours: Vec::new(),
    };
    let mut observer = Quiet {
        done: Vec::new(),
        stop_at,
    };
    let r = animate(&request, || Ok(CpuBackend::new()), &mut observer).map(|_| ());
    (r, observer.done)
}

#[test]
fn pipelined_frames_are_the_sequential_frames_byte_for_byte() {
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let frames = 6;
    let expected = sequential_frames(frames);
    assert!(
        expected.windows(2).all(|w| w[0] != w[1]),
        "the particles move"
    );

    // A PNG sequence: each file is the sequential frame encoded alone.
    let (r, done) = run(&dir.join("f_%02d.png"), frames, None);
    r.unwrap();
    assert_eq!(done, (0..frames).collect::<Vec<_>>());
    let scene = pointillist::scene::load(&scene()).unwrap();
    let (w, h) = (scene.target.width, scene.target.height);
    for (k, rgba) in expected.iter().enumerate() {
        let mut png = Vec::new();
        write_png_rgba8(&mut png, w, h, rgba, Compression::Fast).unwrap();
        let written = std::fs::read(dir.join(format!("f_{k:02}.png"))).unwrap();
        assert!(
            written == png,
            "frame {k} differs from the frame drawn alone"
        );
    }

    // An APNG: its frames, decoded, in order.
    let apng = dir.join("a.png");
    run(&apng, frames, None).0.unwrap();
    let decoded = pointillist_fixtures::png_frames(&apng, expected.len()).unwrap();
    for (k, (frame, rgba)) in decoded.iter().zip(&expected).enumerate() {
        assert!(&frame.rgba == rgba, "APNG frame {k}");
    }

    // Stopped after frame 2: nothing written, no later frame reported.
    let stopped = dir.join("stopped.png");
    let (r, done) = run(&stopped, frames, Some(2));
    assert_eq!(r.unwrap_err(), "stopped");
    assert_eq!(done, [0, 1, 2]);
    assert!(!stopped.exists());
}

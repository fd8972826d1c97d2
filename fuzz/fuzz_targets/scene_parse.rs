//! The scene parser (SCENE.md) on arbitrary text: every input is a scene or a one-line
//! `SceneError`, never a panic. Files the scene names are looked up beside a folder that does not
//! exist, so the fuzzer exercises the error paths without reading the disk. A parsed scene with a
//! small target and few vertices is also replayed on the CPU backend.
#![no_main]

use std::path::Path;

use libfuzzer_sys::fuzz_target;
use pointillist_core::device::Device;
use pointillist_cpu::CpuBackend;
use pointillist_scene::Command;

fuzz_target!(|data: &[u8]| {
    let Ok(text) = std::str::from_utf8(data) else {
        return;
    };
    match pointillist_scene::parse(text, Path::new("/nonexistent-fuzz-dir/fuzz.toml")) {
        Ok(scene) => {
            let pixels = u64::from(scene.target.width) * u64::from(scene.target.height);
            let bytes: usize = scene
                .steps
                .iter()
                .map(|s| match &s.command {
                    Command::Draw { vertices, .. } => vertices.len(),
                    _ => 0,
                })
                .sum();
            if pixels <= 64 * 64 && bytes <= 64 * 1024 {
                let mut device = Device::new(CpuBackend::new(), scene.device_desc())
                    .expect("a parsed target size is valid");
                let _ = scene.replay(&mut device);
                let target = device.read_target().expect("the CPU target reads back");
                assert_eq!(target.color.len() as u64, pixels);
            }
        }
        Err(e) => {
            let line = e.to_string();
            assert!(!line.contains('\n'), "multi-line error: {line}");
        }
    }
});

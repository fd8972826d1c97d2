//! The front door: a backend chosen by name draws what the backend crate draws, and a scene's
//! frame drawn through [`pointillist::frame::render`] is the bytes of drawing it by hand.

use std::path::{Path, PathBuf};

use pointillist::backend::{self, BackendKind};
use pointillist::behaviour::BehaviourSetting;
use pointillist::frame::{self, FrameRequest};
use pointillist::particles::DrawBuffers;
use pointillist::states::RenderState;
use pointillist::{BackendError, Device, DeviceDesc, RenderTarget, XyzRhwDiffuse};

fn scene(name: &str) -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR"))
        .join("../../scenes")
        .join(name)
}

/// The README's point (SPEC 4.1: size 15 at centre 64 covers pixels 57..=71) on `device`.
fn draw_readme_point<B: pointillist::Backend>(device: &mut Device<B>) -> RenderTarget {
    device.set_render_state(RenderState::POINTSIZE, 15.0f32);
    device
        .draw_vertices(&[XyzRhwDiffuse {
            position: [64.0, 64.0, 0.5, 1.0],
            diffuse: 0xFFFF_0000,
        }])
        .unwrap();
    device.read_target().unwrap()
}

#[test]
fn the_backend_called_cpu_draws_the_cpu_backends_pixels() {
    let mut device =
        Device::new(backend::by_name("cpu").unwrap(), DeviceDesc::new(128, 128)).unwrap();
    let target = draw_readme_point(&mut device);
    assert_eq!(target.pixel(57, 64), 0xFFFF_0000);
    assert_eq!(target.pixel(71, 71), 0xFFFF_0000);
    assert_eq!(target.pixel(56, 64), 0xFF00_0000);
    assert_eq!(target.pixel(72, 64), 0xFF00_0000);
    let mut direct = pointillist::cpu::device(DeviceDesc::new(128, 128)).unwrap();
    assert_eq!(
        &target.into_rgba8()[..],
        &draw_readme_point(&mut direct).into_rgba8()[..]
    );
}

#[test]
fn backend_names_round_trip_and_an_unknown_name_is_named_with_the_choices() {
    for kind in BackendKind::ALL {
        assert_eq!(BackendKind::from_name(kind.name()).unwrap(), kind);
        assert_eq!(kind.name().parse::<BackendKind>().unwrap(), kind);
        assert_eq!(kind.to_string(), kind.name());
    }
    for name in ["tpu", "CPU", "", "cpu "] {
        let e = BackendKind::from_name(name).unwrap_err();
        assert!(matches!(&e, BackendError::Unknown(n) if n == name), "{e:?}");
        assert_eq!(
            e.to_string(),
            format!("unknown backend `{name}` (expected \"cpu\" or \"gpu\")")
        );
        let e = backend::by_name(name).err().expect("no backend");
        assert!(matches!(e, BackendError::Unknown(_)), "{e:?}");
    }
}

/// Without the `gpu` feature the name is known and the reason is the build.
#[cfg(not(feature = "gpu"))]
#[test]
fn a_build_without_the_gpu_feature_says_so_for_the_gpu_backend() {
    let e = backend::create(BackendKind::Gpu).err().expect("no GPU");
    assert!(matches!(e, BackendError::NoGpuBuild), "{e:?}");
    assert_eq!(
        e.to_string(),
        "this build of pointillist has no GPU backend (build it with the `gpu` feature)"
    );
}

/// With the `gpu` feature: the GPU backend where an adapter is, else the driver hint.
#[cfg(feature = "gpu")]
#[test]
fn the_gpu_backend_opens_or_names_why_not() {
    match backend::create(BackendKind::Gpu) {
        Ok(b) => {
            let mut device = Device::new(b, DeviceDesc::new(128, 128)).unwrap();
            let target = draw_readme_point(&mut device);
            assert_eq!(target.pixel(57, 64), 0xFFFF_0000);
            assert_eq!(target.pixel(56, 64), 0xFF00_0000);
        }
        Err(e) => {
            assert!(
                std::env::var_os("POINTILLIST_REQUIRE_GPU").is_none(),
                "POINTILLIST_REQUIRE_GPU is set and there is no GPU backend: {e}"
            );
            assert!(matches!(e, BackendError::Gpu(_)), "{e:?}");
        }
    }
}

/// A still scene, drawn through the front door and by hand (load, device, replay, target).
#[test]
fn a_still_scene_through_the_front_door_is_the_bytes_of_a_replay() {
    let s = pointillist::scene::load(&scene("blending.toml")).unwrap();
    assert!(!s.is_animated());
    let drawn = frame::render(
        &s,
        backend::create(BackendKind::Cpu).unwrap(),
        &FrameRequest::default(),
        || Ok(()),
    )
    .unwrap();
    assert_eq!(drawn.particles, None);
    let mut device = pointillist::cpu::device(s.device_desc()).unwrap();
    s.replay(&mut device).unwrap();
    let by_hand = device.into_target().unwrap();
    assert_eq!(
        (drawn.target.width, drawn.target.height),
        (by_hand.width, by_hand.height)
    );
    assert_eq!(&drawn.target.into_rgba8()[..], &by_hand.into_rgba8()[..]);
}

/// A frame of an animated scene: the particles simulated to the frame, and the behaviour
/// settings over the scene's.
#[test]
fn an_animation_frame_through_the_front_door_is_the_bytes_of_render_frame() {
    let s = pointillist::scene::load(&scene("fountain.toml")).unwrap();
    let settings: Vec<BehaviourSetting> = vec!["minimum_size=one_pixel".parse().unwrap()];
    let request = FrameRequest {
        behaviours: &settings,
        frame: Some(7),
        frame_arg: "--frame",
    };
    let drawn =
        frame::render(&s, pointillist::cpu::CpuBackend::new(), &request, || Ok(())).unwrap();
    let (frame, particles) = drawn.particles.expect("an animation frame");
    assert_eq!(frame, 7);
    assert!(particles > 0);

    let desc = DeviceDesc {
        behaviours: s.behaviours.with(&settings),
        ..s.device_desc()
    };
    let mut device = pointillist::cpu::device(desc).unwrap();
    let mut system = s.particle_system().unwrap();
    s.render_frame(&mut device, &mut system, &mut DrawBuffers::new(), 7)
        .unwrap();
    assert_eq!(system.len(), particles);
    assert_eq!(
        &drawn.target.into_rgba8()[..],
        &device.into_target().unwrap().into_rgba8()[..]
    );
}

#[test]
fn a_frame_outside_the_animation_is_named_as_the_caller_names_it() {
    let path = scene("fountain.toml");
    let s = pointillist::scene::load(&path).unwrap();
    let frames = s.animation.frames;
    for (arg, said) in [("--frame", "--frame"), ("frame", "frame"), ("", "frame")] {
        let request = FrameRequest {
            frame: Some(frames),
            frame_arg: arg,
            ..FrameRequest::default()
        };
        let e = frame::render(&s, pointillist::cpu::CpuBackend::new(), &request, || Ok(()))
            .unwrap_err();
        assert_eq!(
            e,
            format!(
                "{}: {said} {frames} is outside 0..={} ([animation] frames = {frames})",
                path.display(),
                frames - 1
            )
        );
    }
}

/// `check` is called during the warm-up; its error ends the frame with that message.
#[test]
fn a_check_that_fails_ends_the_frame_with_its_message() {
    let s = pointillist::scene::load(&scene("fountain.toml")).unwrap();
    let request = FrameRequest {
        frame: Some(40),
        ..FrameRequest::default()
    };
    let mut calls = 0;
    let e = frame::render(&s, pointillist::cpu::CpuBackend::new(), &request, || {
        calls += 1;
        Err("interrupted".into())
    })
    .unwrap_err();
    assert!(calls >= 1);
    assert!(e.contains("interrupted"), "{e}");
}

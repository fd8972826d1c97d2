//! The CPU backend defers a clear to the next draw, which writes it band by band; the result
//! must be the pixels of a clear written at once, for binned and sequential draws, through a
//! depth test that reads the cleared depth.

mod common;

use common::Rng;

use pointillist_core::device::{Backend, Device, DeviceDesc, RenderTarget};
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{Blend, Cmp, RenderState};
use pointillist_cpu::CpuBackend;

const CLEAR_COLOR: u32 = 0xFF20_4060;
const CLEAR_DEPTH: f32 = 0.6;

/// Pre-transformed points with a size and a colour, a few outside the 200x150 target.
const RHW: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);

/// `n` points of [`RHW`] at random places, depths in 0..1, sizes 1 to 7 and colours.
fn random_points(rng: &mut Rng, n: usize) -> Vec<u8> {
    let mut v = Vec::new();
    for _ in 0..n {
        let words = [
            (rng.unit() * 220.0 - 10.0).to_bits(),
            (rng.unit() * 170.0 - 10.0).to_bits(),
            rng.unit().to_bits(),
            1.0f32.to_bits(),
            (1.0 + rng.unit() * 6.0).to_bits(),
            rng.next_u64() as u32,
        ];
        v.extend(words.iter().flat_map(|w| w.to_le_bytes()));
    }
    v
}

/// Points with depths in 0..1 under a LESS depth test (so the cleared depth 0.6 rejects some),
/// additive, after an earlier draw that wrote colour and depth; `read_after_clear` reads the
/// target right after the clear, which writes the clear at once.
fn render(points: usize, read_after_clear: bool) -> RenderTarget {
    let mut d = pointillist_cpu::device(DeviceDesc::new(200, 150)).expect("device");
    let mut rng = Rng(0x00C1_EA25_0000_0003);
    d.set_render_state(RenderState::ZENABLE, true);
    d.set_render_state(RenderState::ZWRITEENABLE, true);
    d.set_render_state(RenderState::ZFUNC, Cmp::Less);
    let before = random_points(&mut rng, 3000);
    d.draw_point_list(RHW, &before).expect("first draw");
    d.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    if read_after_clear {
        let cleared = d.read_target().expect("read back");
        assert!(cleared.color.iter().all(|&c| c == CLEAR_COLOR));
        assert!(cleared.depth.iter().all(|&z| z == CLEAR_DEPTH));
    }
    d.set_render_state(RenderState::ALPHABLENDENABLE, true);
    d.set_render_state(RenderState::SRCBLEND, Blend::One);
    d.set_render_state(RenderState::DESTBLEND, Blend::One);
    let after = random_points(&mut rng, points);
    d.draw_point_list(RHW, &after).expect("second draw");
    d.read_target().expect("read back")
}

#[test]
fn a_deferred_clear_gives_the_pixels_of_an_immediate_one() {
    // 5,000 points are binned, 100 are drawn one after another.
    for points in [5000, 100] {
        let deferred = render(points, false);
        let immediate = render(points, true);
        let cleared = deferred.color.iter().filter(|&&c| c == CLEAR_COLOR).count();
        let kept = deferred.depth.iter().filter(|&&z| z == CLEAR_DEPTH).count();
        assert!(
            cleared > 0 && kept > 0 && kept < deferred.depth.len(),
            "{points} points: {cleared} pixels keep the clear colour, {kept} its depth"
        );
        common::assert_same_target(&deferred, &immediate, &format!("{points} points"));
    }
}

#[test]
fn a_clear_without_a_draw_is_read_back() {
    let mut d = pointillist_cpu::device(DeviceDesc::new(64, 48)).expect("device");
    d.clear(0xFF00_FF00, 0.25).expect("clear");
    d.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    let t = d.read_target().expect("read back");
    assert!(t.color.iter().all(|&c| c == CLEAR_COLOR));
    assert!(t.depth.iter().all(|&z| z == CLEAR_DEPTH));
    assert_eq!(d.backend_mut().target().pixel(5, 5), CLEAR_COLOR);
}

#[test]
fn a_new_target_drops_a_pending_clear() {
    let mut d = pointillist_cpu::device(DeviceDesc::new(64, 48)).expect("device");
    d.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    let backend = d.backend_mut();
    backend
        .create_target(32, 16, 0xFF00_00FF, 0.5)
        .expect("new target");
    let t = backend.read_target().expect("read back");
    assert_eq!((t.width, t.height), (32, 16));
    assert!(t.color.iter().all(|&c| c == 0xFF00_00FF));
    assert!(t.depth.iter().all(|&z| z == 0.5));
}

/// `read_rgba8` reads the target where it lies, a pending clear written first, into a buffer
/// that serves frame after frame: the bytes of `read_target`'s colours, whatever the buffer
/// held, directly and through a boxed backend.
#[test]
fn read_rgba8_gives_the_colours_of_read_target() {
    let mut d = pointillist_cpu::device(DeviceDesc::new(200, 150)).expect("device");
    d.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    let mut rgba = vec![7u8; 200_000];
    d.read_rgba8(&mut rgba).expect("read back");
    assert_eq!(rgba.len(), 200 * 150 * 4);
    assert!(rgba.chunks(4).all(|p| p == [0x20, 0x40, 0x60, 0xFF]));

    let vertices = random_points(&mut Rng(0x00C1_EA25_0000_0004), 500);
    d.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    d.draw_point_list(RHW, &vertices).expect("draw");
    d.read_rgba8(&mut rgba).expect("read back");
    let target = d.read_target().expect("read back");
    assert_ne!(
        target.color.iter().filter(|&&c| c != CLEAR_COLOR).count(),
        0
    );
    assert_eq!(rgba, target.to_rgba8());

    let backend: Box<dyn Backend> = Box::new(CpuBackend::new());
    let mut boxed = Device::new(backend, DeviceDesc::new(200, 150)).expect("device");
    boxed.clear(CLEAR_COLOR, CLEAR_DEPTH).expect("clear");
    boxed.draw_point_list(RHW, &vertices).expect("draw");
    let mut again = Vec::new();
    boxed.read_rgba8(&mut again).expect("read back");
    assert_eq!(again, rgba);
}

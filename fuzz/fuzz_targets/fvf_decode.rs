//! The FVF code checks and the raw vertex-buffer decoder (`PointSetup::process`, the per-point
//! stage of SPEC 2 and 3) on arbitrary bytes: a 32-bit FVF code, up to 16 render states that
//! shape points (any 32 bits, SPEC 2.7), then the vertex bytes. An FVF is valid or an
//! `FvfError`; every whole vertex of a valid one is dropped or becomes a point whose pixel
//! rectangle lies inside the viewport.
#![no_main]

use libfuzzer_sys::fuzz_target;
use pointillist_core::caps::Caps;
use pointillist_core::device::{DeviceState, Viewport};
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::point::PointSetup;
use pointillist_core::states::{Api, RenderState};

fn u32_at(data: &[u8], at: usize) -> Option<u32> {
    Some(u32::from_le_bytes(data.get(at..at + 4)?.try_into().ok()?))
}

fuzz_target!(|data: &[u8]| {
    let Some(code) = u32_at(data, 0) else {
        return;
    };
    let fvf = match Fvf(code).validate() {
        Ok(f) => f,
        Err(e) => {
            assert!(!e.to_string().contains('\n'), "{e}");
            return;
        }
    };
    let count = usize::from(*data.get(4).unwrap_or(&0) % 17);
    let mut at = 5;
    let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 64, 48);
    state.viewport = Viewport {
        x: 3,
        y: 5,
        width: 50,
        height: 40,
        min_z: 0.0,
        max_z: 1.0,
    };
    state.view = Mat4::look_at_lh([0.0, 0.0, -5.0], [0.0; 3], [0.0, 1.0, 0.0]);
    state.projection = Mat4::perspective_fov_lh(0.8, 1.25, 0.5, 50.0);
    let states = RenderState::all();
    for _ in 0..count {
        let (Some(&which), Some(value)) = (data.get(at), u32_at(data, at + 1)) else {
            return;
        };
        let s = states[usize::from(which) % states.len()];
        state.render_states[s.0 as usize] = value;
        at += 5;
    }
    let vertices = &data[at.min(data.len())..];
    let stride = fvf.stride();
    let whole = vertices.len() / stride * stride;
    let vertices = &vertices[..whole];
    let setup = PointSetup::new(&state, fvf);
    let vp = setup.viewport_rect();
    for i in 0..(whole / stride) as u32 {
        if let Some(p) = setup.process(vertices, i) {
            let r = p.rect;
            assert!(
                !r.is_empty() && r.intersect(&vp) == r,
                "{r:?} outside {vp:?}"
            );
        }
        for set in 0..fvf.tex_count() {
            let _ = setup.tex_coords(vertices, i, set);
        }
    }
});

//! Property tests of the point pipeline on both backends (`pointillist_testkit`):
//! (a) coverage of pre-transformed points equals the SPEC 4.1 count, computed independently;
//! (b) the size formula agrees with an f64 evaluation, alone and end to end;
//! (c) no state or vertex value makes a draw fail, panic, or write a non-finite depth;
//! (d) random combinations of blends, filters, mip levels and extreme floats draw the same
//! pixels on both backends (SPEC 7's tolerances).

use std::collections::BTreeSet;
use std::sync::Arc;

use crate::common::*;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::point::{PointScale, clamp_size, scaled_size};
use pointillist_core::states::{RenderState, SamplerState};
use pointillist_core::{DeviceDesc, TransformType, Viewport};
use proptest::prelude::*;

type Rs = RenderState;

/// The integers k in `0..n` with `lo <= k < hi`, found by walking k in f64 over a range around
/// the edges (no ceil arithmetic shared with the implementation).
fn covered(lo: f64, hi: f64, n: u32) -> Vec<u32> {
    let start = (lo.floor() as i64 - 2).max(0);
    let end = (hi.floor() as i64 + 2).min(i64::from(n) - 1);
    (start..=end)
        .filter(|&k| lo <= k as f64 && (k as f64) < hi)
        .map(|k| k as u32)
        .collect()
}

/// Centres: anywhere, or on a quarter-pixel grid where edges hit pixel centres exactly.
fn centre(n: u32) -> impl Strategy<Value = f32> {
    prop_oneof![
        0.0f32..n as f32,
        (0..(4 * n)).prop_map(|k| k as f32 / 4.0),
        (0..n).prop_map(|k| k as f32 + 0.5),
    ]
}

/// Sizes: anywhere in (0, 40], or multiples of 1/4 (exact half-sizes on the quarter grid).
fn size() -> impl Strategy<Value = f32> {
    prop_oneof![
        (0.0f32..40.0).prop_filter("positive", |s| *s > 0.0),
        (1..160u32).prop_map(|k| k as f32 / 4.0),
        (1..41u32).prop_map(|k| k as f32),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// (a) SPEC 4.1: a pre-transformed point covers exactly the pixels (i, j) of the target with
    /// X - S/2 <= i < X + S/2 and Y - S/2 <= j < Y + S/2; their number is the product of the
    /// per-axis counts.
    #[test]
    fn coverage_matches_the_top_left_rule(x in centre(48), y in centre(40), s in size()) {
        let (w, h) = (48u32, 40u32);
        let mut d = dev(w, h);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        d.set_render_state(Rs::POINTSIZE, s);
        rhw_point(&mut d, x, y, 0.5, WHITE);
        let t = target(&mut d);
        let got = drawn(&t, BLACK);
        let half = s / 2.0;
        let xs = covered(f64::from(x - half), f64::from(x + half), w);
        let ys = covered(f64::from(y - half), f64::from(y + half), h);
        prop_assert_eq!(got.len(), xs.len() * ys.len());
        let want: BTreeSet<(u32, u32)> =
            ys.iter().flat_map(|&j| xs.iter().map(move |&i| (i, j))).collect();
        prop_assert_eq!(got, want);
    }

    /// (b) SPEC 2.2: `scaled_size` agrees with an f64 evaluation of
    /// `Vh * Si * sqrt(1 / (A + B*De + C*De^2))` within 1e-5 relative.
    #[test]
    fn scaled_size_matches_f64(
        si in 1e-3f32..1e3,
        a in 0.0f32..100.0,
        b in 0.0f32..100.0,
        c in 0.0f32..100.0,
        de in 0.0f32..1e3,
        vh in 1u32..16384,
    ) {
        let den = f64::from(a) + f64::from(b) * f64::from(de)
            + f64::from(c) * f64::from(de) * f64::from(de);
        prop_assume!(den > 1e-3);
        let want = f64::from(vh) * f64::from(si) * (1.0 / den).sqrt();
        let scale = PointScale { a, b, c, viewport_height: vh as f32 };
        let got = f64::from(scaled_size(si, &scale, de));
        prop_assert!(((got - want) / want).abs() < 1e-5, "got {got}, want {want}");
    }

    /// (b) SPEC 2.3: `clamp_size` is `min(max(Ss', MIN), min(caps, MAX))` with NaN and negative
    /// sizes taken as 0 and +inf clamped to the upper bound.
    #[test]
    fn clamp_size_matches_f64(
        ss in prop_oneof![
            -1e3f32..1e4,
            Just(f32::NAN),
            Just(f32::INFINITY),
            Just(f32::NEG_INFINITY),
            Just(-0.0f32),
        ],
        lo in prop_oneof![0.0f32..100.0, Just(f32::NEG_INFINITY), -10.0f32..0.0],
        max in prop_oneof![0.0f32..1e4, Just(f32::INFINITY)],
        caps in prop_oneof![Just(1.0f32), Just(64.0), Just(8192.0), 1.0f32..1e4],
    ) {
        let ssf = f64::from(ss);
        let ss0 = if ssf.is_nan() || ssf < 0.0 { 0.0 } else { ssf };
        let hi = f64::from(caps).min(f64::from(max));
        let want = ss0.max(f64::from(lo)).min(hi);
        let got = f64::from(clamp_size(ss, lo, max, caps));
        prop_assert_eq!(got, want);
    }

    /// (b) SPEC 2.2 end to end: a transformed point with random A, B, C, eye position and
    /// viewport height covers the square of the f64 size (cases whose edges fall within 1e-3
    /// of a pixel centre are skipped: there f32 rounding may decide).
    #[test]
    fn scaled_points_cover_the_f64_square(
        a in 0.0f32..4.0,
        b in 0.0f32..1.0,
        c in 0.0f32..0.5,
        si in 0.01f32..0.5,
        ex in -6.0f32..6.0,
        ey in -6.0f32..6.0,
        ez in 0.0f32..8.0,
        vh in 24u32..64,
    ) {
        let (ef, ff, gf) = (f64::from(ex), f64::from(ey), f64::from(ez));
        let de = (ef * ef + ff * ff + gf * gf).sqrt();
        let den = f64::from(a) + f64::from(b) * de + f64::from(c) * de * de;
        prop_assume!(den > 1e-2);
        let s = (f64::from(vh) * f64::from(si) / den.sqrt()).max(0.0);
        // Projection x/8, y/8, z/16, w = 1 on a 64 x vh viewport.
        let x = 32.0 + ef / 8.0 * 32.0;
        let y = f64::from(vh) / 2.0 - ff / 8.0 * f64::from(vh) / 2.0;
        let edges = [x - s / 2.0, x + s / 2.0, y - s / 2.0, y + s / 2.0];
        prop_assume!(edges.iter().all(|e| (e - e.round()).abs() > 1e-3));
        let mut d = dev(64, 64);
        d.set_viewport(Viewport { height: vh, ..Viewport::full(64, 64) }).unwrap();
        d.set_transform(
            TransformType::Projection,
            Mat4([
                [0.125, 0.0, 0.0, 0.0],
                [0.0, 0.125, 0.0, 0.0],
                [0.0, 0.0, 0.0625, 0.0],
                [0.0, 0.0, 0.0, 1.0],
            ]),
        );
        d.set_render_state(Rs::POINTSCALEENABLE, true);
        d.set_render_state(Rs::POINTSCALE_A, a);
        d.set_render_state(Rs::POINTSCALE_B, b);
        d.set_render_state(Rs::POINTSCALE_C, c);
        d.set_render_state(Rs::POINTSIZE_MIN, 0.0f32);
        d.set_render_state(Rs::POINTSIZE, si);
        draw(&mut d, XYZ, &[f(ex), f(ey), f(ez)]);
        let got = drawn(&target(&mut d), BLACK);
        let xs = covered(edges[0], edges[1], 64);
        let ys = covered(edges[2], edges[3], vh);
        let want: BTreeSet<(u32, u32)> =
            ys.iter().flat_map(|&j| xs.iter().map(move |&i| (i, j))).collect();
        prop_assert_eq!(got, want, "S = {}", s);
    }
}

/// Any f32: arbitrary bits, the special values, or ordinary small values that draw something.
fn any_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        any::<u32>().prop_map(f32::from_bits),
        prop::sample::select(vec![
            f32::NAN,
            -f32::NAN,
            f32::from_bits(0x7F80_0001),
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.0,
            -0.0,
            f32::from_bits(1),
            f32::MIN_POSITIVE,
            f32::MAX,
            f32::MIN,
            1e-30,
            -1e30,
            8192.0,
            1e6,
        ]),
        -2.0f32..2.0,
        0.0f32..40.0,
    ]
}

/// The size states (SPEC 2), in the order of the generated `states` arrays.
const SIZE_STATES: [Rs; 6] = [
    Rs::POINTSIZE,
    Rs::POINTSIZE_MIN,
    Rs::POINTSIZE_MAX,
    Rs::POINTSCALE_A,
    Rs::POINTSCALE_B,
    Rs::POINTSCALE_C,
];

const FVFS: [Fvf; 7] = [
    Fvf::XYZ,
    Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0),
    Fvf::XYZRHW,
    Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
    Fvf(Fvf::XYZW.0 | Fvf::PSIZE.0 | Fvf::SPECULAR.0),
    Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0 | Fvf::TEX2.0),
    Fvf(Fvf::XYZRHW.0 | Fvf::TEX1.0 | Fvf::texcoord_size(4, 0).0),
];

#[derive(Debug, Clone)]
struct Chaos {
    states: [f32; 6],
    scale: bool,
    sprite: bool,
    clipping: bool,
    planes: u32,
    plane: [f32; 4],
    world: [f32; 4],
    lod_bias: f32,
    profile: usize,
    fvf: usize,
    textured: bool,
    floats: Vec<f32>,
}

fn chaos() -> impl Strategy<Value = Chaos> {
    (
        prop::array::uniform6(any_f32()),
        any::<(bool, bool, bool)>(),
        0u32..64,
        prop::array::uniform4(any_f32()),
        prop::array::uniform4(any_f32()),
        any_f32(),
        0..Caps::PROFILES.len(),
        0..FVFS.len(),
        any::<bool>(),
        prop::collection::vec(any_f32(), 1..=64),
    )
        .prop_map(
            |(states, flags, planes, plane, world, lod_bias, profile, fvf, textured, floats)| {
                Chaos {
                    states,
                    scale: flags.0,
                    sprite: flags.1,
                    clipping: flags.2,
                    planes,
                    plane,
                    world,
                    lod_bias,
                    profile,
                    fvf,
                    textured,
                    floats,
                }
            },
        )
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(256))]

    /// (c) SPEC 2.3, 2.7, 3.1: any raw bits for the size states, any vertex floats, any of a few
    /// formats, caps profiles, clip planes and transforms: the draw returns Ok, nothing panics,
    /// and every depth is finite (written depths are finite, the rest is the clear value).
    #[test]
    fn any_values_draw_without_failing(c in chaos()) {
        let caps = Caps::profile(Caps::PROFILES[c.profile]).unwrap();
        let mut d = pointillist_testkit::device(DeviceDesc { caps, ..DeviceDesc::new(32, 24) })
            .unwrap();
        for (s, v) in SIZE_STATES.iter().zip(c.states) {
            d.set_render_state(*s, v);
            prop_assert_eq!(d.render_state(*s), v.to_bits());
        }
        d.set_render_state(Rs::POINTSCALEENABLE, c.scale);
        d.set_render_state(Rs::POINTSPRITEENABLE, c.sprite);
        d.set_render_state(Rs::CLIPPING, c.clipping);
        d.set_render_state(Rs::ZFUNC, 8u32); // ALWAYS: every surviving pixel writes its depth
        d.set_clip_plane(0, c.plane).unwrap();
        d.set_render_state(Rs::CLIPPLANEENABLE, c.planes);
        let mut m = Mat4::IDENTITY;
        m.0[3] = c.world;
        d.set_transform(TransformType::World, m);
        d.set_viewport(Viewport { x: 3, y: 2, width: 20, height: 17, min_z: 0.25, max_z: 0.75 })
            .unwrap();
        if c.textured {
            let texels = (0..64u32).map(|k| k.wrapping_mul(0x0103_0507)).collect();
            d.set_texture(0, Some(Arc::new(
                pointillist_core::texture::Texture::from_argb(8, 8, texels).unwrap(),
            )))
            .unwrap();
            d.set_sampler_state(0, SamplerState::MIPFILTER, 2u32).unwrap();
            d.set_sampler_state(0, SamplerState::MINFILTER, 2u32).unwrap();
            d.set_sampler_state(0, SamplerState::MIPMAPLODBIAS, c.lod_bias).unwrap();
        }
        let fvf = FVFS[c.fvf];
        let row = fvf.row_len();
        let mut words: Vec<u32> = c.floats.iter().map(|v| v.to_bits()).collect();
        words.truncate(words.len() / row * row);
        if words.is_empty() {
            words = c.floats.iter().cycle().take(row).map(|v| v.to_bits()).collect();
        }
        prop_assert!(d.draw_point_list(fvf, &bytes(&words)).is_ok());
        let t = target(&mut d);
        prop_assert!(t.depth.iter().all(|z| z.is_finite()), "non-finite depth");
        // Nothing outside the viewport is touched.
        for y in 0..24u32 {
            for x in 0..32u32 {
                let inside = (3..23).contains(&x) && (2..19).contains(&y);
                if !inside {
                    prop_assert_eq!(t.pixel(x, y), BLACK);
                    prop_assert_eq!(t.depth[(y * 32 + x) as usize], 1.0);
                }
            }
        }
    }
}

/// Extreme floats for sizes and attenuation: the special values, huge sizes, or small ones.
fn extreme_f32() -> impl Strategy<Value = f32> {
    prop_oneof![
        prop::sample::select(vec![
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            0.0,
            -0.0,
            f32::from_bits(1),
            f32::from_bits(0x007F_FFFF),
            f32::MIN_POSITIVE,
            f32::MAX,
            1e30,
            3.0e37,
            8192.0,
            1e6,
        ]),
        0.0f32..40.0,
        0.0f32..2.0,
    ]
}

#[derive(Debug, Clone)]
struct Mix {
    /// SRCBLEND, DESTBLEND (D3DBLEND 1..=17), BLENDOP (1..=5).
    blend: Option<(u32, u32, u32)>,
    /// MINFILTER, MAGFILTER (POINT or LINEAR), MIPFILTER (NONE, POINT, LINEAR), MAXMIPLEVEL.
    filters: (u32, u32, u32, u32),
    lod_bias: f32,
    /// ADDRESSU, ADDRESSV (D3DTADDRESS 1..=5).
    address: (u32, u32),
    /// ALPHAREF when the alpha test is on.
    alpha_ref: Option<u32>,
    /// POINTSIZE, POINTSIZE_MIN, POINTSIZE_MAX, POINTSCALE_A, POINTSCALE_B, POINTSCALE_C.
    states: [f32; 6],
    scale: bool,
    /// Pre-transformed (XYZRHW) or transformed by identity matrices (XYZ).
    rhw: bool,
    /// Per point: x, y (fractions of the target), z, PSIZE, DIFFUSE.
    points: Vec<(f32, f32, f32, f32, u32)>,
}

fn mix() -> impl Strategy<Value = Mix> {
    (
        prop::option::weighted(0.9, (1u32..=17, 1u32..=17, 1u32..=5)),
        (1u32..=2, 1u32..=2, 0u32..=2, 0u32..=5),
        prop_oneof![extreme_f32(), -4.0f32..4.0],
        (1u32..=5, 1u32..=5),
        prop::option::weighted(0.3, 0u32..=255),
        prop::array::uniform6(extreme_f32()),
        any::<(bool, bool)>(),
        prop::collection::vec(
            (
                -0.2f32..1.2,
                -0.2f32..1.2,
                0.0f32..1.0,
                extreme_f32(),
                any::<u32>(),
            ),
            1..=24,
        ),
    )
        .prop_map(
            |(blend, filters, lod_bias, address, alpha_ref, states, flags, points)| Mix {
                blend,
                filters,
                lod_bias,
                address,
                alpha_ref,
                states,
                scale: flags.0,
                rhw: flags.1,
                points,
            },
        )
}

/// A 16x16 texture whose five levels differ in colour and alpha, level 0 varying per texel.
fn mip_texture() -> Arc<pointillist_core::texture::Texture> {
    let levels = [0u32, 0x80_00FF00, 0xC0_0000FF, 0x40_FFFF00, 0xFF_FF00FF]
        .iter()
        .enumerate()
        .map(|(k, &c)| {
            let side = 16u32 >> k;
            let texels = (0..side * side)
                .map(|t| {
                    if k == 0 {
                        t.wrapping_mul(0x0B03_0507)
                    } else {
                        c
                    }
                })
                .collect();
            pointillist_core::texture::Level {
                width: side,
                height: side,
                texels,
            }
        })
        .collect();
    Arc::new(pointillist_core::texture::Texture::from_levels(levels).unwrap())
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(48))]

    /// (d) SPEC 2, 5.2, 5.3, 5.5, 7: sprites with any blend factors and operation, min, mag
    /// and mip filters, MAXMIPLEVEL, LOD bias, addressing, alpha test, and extreme sizes and
    /// attenuation (infinite, NaN, subnormal, huge), drawn twice over each other: the GPU
    /// matches the CPU within the draw's tolerance (`pointillist_testkit` compares on read).
    #[test]
    fn blends_filters_and_mip_levels_match_on_both_backends(m in mix()) {
        let (w, h) = (48u32, 40u32);
        let mut d = pointillist_testkit::device(DeviceDesc::new(w, h)).unwrap();
        let texture = mip_texture();
        d.set_texture(0, Some(texture)).unwrap();
        let (min, mag, mip, max_mip) = m.filters;
        let samplers = [
            (SamplerState::MINFILTER, min),
            (SamplerState::MAGFILTER, mag),
            (SamplerState::MIPFILTER, mip),
            (SamplerState::MAXMIPLEVEL, max_mip),
            (SamplerState::ADDRESSU, m.address.0),
            (SamplerState::ADDRESSV, m.address.1),
            (SamplerState::BORDERCOLOR, 0x80A0_4020),
        ];
        for (s, v) in samplers {
            d.set_sampler_state(0, s, v).unwrap();
        }
        d.set_sampler_state(0, SamplerState::MIPMAPLODBIAS, m.lod_bias).unwrap();
        if let Some((src, dest, op)) = m.blend {
            d.set_render_state(Rs::ALPHABLENDENABLE, true);
            d.set_render_state(Rs::SRCBLEND, src);
            d.set_render_state(Rs::DESTBLEND, dest);
            d.set_render_state(Rs::BLENDOP, op);
            d.set_render_state(Rs::BLENDFACTOR, 0x6090_30C0u32);
        }
        if let Some(r) = m.alpha_ref {
            d.set_render_state(Rs::ALPHATESTENABLE, true);
            d.set_render_state(Rs::ALPHAREF, r);
            d.set_render_state(Rs::ALPHAFUNC, 7u32); // GREATEREQUAL
        }
        for (s, v) in SIZE_STATES.iter().zip(m.states) {
            d.set_render_state(*s, v);
        }
        d.set_render_state(Rs::POINTSCALEENABLE, m.scale);
        d.set_render_state(Rs::POINTSPRITEENABLE, true);
        d.set_render_state(Rs::LIGHTING, false);
        let fvf = if m.rhw {
            Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0)
        } else {
            Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0)
        };
        let mut words = Vec::new();
        for &(x, y, z, size, diffuse) in &m.points {
            if m.rhw {
                words.extend([f(x * w as f32), f(y * h as f32), f(z), f(1.0)]);
            } else {
                // Identity transforms: clip space, eye distance up to about 1.7.
                words.extend([f(x * 2.0 - 1.0), f(1.0 - y * 2.0), f(z)]);
            }
            words.extend([f(size), diffuse]);
        }
        let vertices = bytes(&words);
        // Twice: the second draw blends over the first one's pixels.
        prop_assert!(d.draw_point_list(fvf, &vertices).is_ok());
        prop_assert!(d.draw_point_list(fvf, &vertices).is_ok());
        if let Err(e) = d.read_target() {
            prop_assert!(false, "{}", e);
        }
    }
}

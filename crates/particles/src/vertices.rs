//! The vertices a pool's particles write (the rules are in [`crate::system`]'s contract):
//! sixty-four at a time, each step over all of them so that it vectorises (compiled with AVX2
//! too, eight a lane, where [`NoiseField::accelerate`](crate::NoiseField) uses it), with the
//! scalar arithmetic in each lane, so the bytes do not depend on the CPU.

use crate::emitter::Emitter;
use crate::layout::{BLOCK, BLOCK_LEN, VERTEX_STRIDE};

/// Particles whose vertices are computed together.
const RUN: usize = 64;

/// Float to 8-bit unorm: saturate (NaN to 0), then round half up, `trunc(v 255 + 0.5)`, with
/// operations that vectorise on every level: the comparisons are those of `maxps` and
/// `minps`, and the truncation of `y` in 0.5..=255.5 adds 2^23 (rounding `y` to an integer,
/// exactly), steps down where that rounded up, and reads the integer from the mantissa.
#[inline(always)]
fn unorm8(v: f32) -> u32 {
    const TWO_23: f32 = 8_388_608.0;
    let v = if v > 0.0 { v } else { 0.0 };
    let v = if v < 1.0 { v } else { 1.0 };
    let y = v * 255.0 + 0.5;
    let z = y + TWO_23;
    let z = if z - TWO_23 > y { z - 1.0 } else { z };
    z.to_bits() - TWO_23.to_bits()
}

/// Writes the vertices of the `n` live particles of one block into `out` (`n` vertices long).
fn write_block(block: &[f32], n: usize, e: &Emitter, out: &mut [u8]) {
    #[cfg(target_arch = "x86_64")]
    if let Some(avx2) = pointillist_lanes::SimdLevel::detect().avx2() {
        return write_at::avx2(avx2, block, n, e, out);
    }
    write_block_inline(block, n, e, out);
}

/// [`write_block`]'s work, inlined into each level's function.
#[inline(always)]
fn write_block_inline(block: &[f32], n: usize, e: &Emitter, out: &mut [u8]) {
    let col = |k: usize| &block[k * BLOCK..k * BLOCK + n];
    let (px, py, pz) = (col(0), col(1), col(2));
    let (age, life, size, shade) = (col(6), col(7), col(8), col(10));
    let mut t = [0.0f32; RUN];
    let mut scale = [0.0f32; RUN];
    let [mut r, mut g, mut b, mut a] = [[0.0f32; RUN]; 4];
    let mut psize = [0.0f32; RUN];
    let mut argb = [0u32; RUN];
    for first in (0..n).step_by(RUN) {
        let range = first..n.min(first + RUN);
        let len = range.len();
        life_fractions(&age[range.clone()], &life[range.clone()], &mut t[..len]);
        let t = &t[..len];
        e.size_over_life.eval_into(t, |v| [v], [&mut scale[..len]]);
        let rgba = [&mut r[..len], &mut g[..len], &mut b[..len], &mut a[..len]];
        e.color_over_life.eval_into(t, |v| v, rgba);
        sizes_and_colours(
            (&size[range.clone()], &scale[..len]),
            [&r[..len], &g[..len], &b[..len], &a[..len]],
            &shade[range.clone()],
            &mut psize[..len],
            &mut argb[..len],
        );
        let out = &mut out[first * VERTEX_STRIDE..range.end * VERTEX_STRIDE];
        for (k, v) in out.chunks_exact_mut(VERTEX_STRIDE).enumerate() {
            let i = first + k;
            let words = [
                px[i].to_bits(),
                py[i].to_bits(),
                pz[i].to_bits(),
                psize[k].to_bits(),
                argb[k],
            ];
            for (dst, w) in v.chunks_exact_mut(4).zip(words) {
                dst.copy_from_slice(&w.to_le_bytes());
            }
        }
    }
}

/// `t = age / life` of each particle.
#[inline(always)]
fn life_fractions(age: &[f32], life: &[f32], t: &mut [f32]) {
    let n = t.len();
    let (age, life) = (&age[..n], &life[..n]);
    for i in 0..n {
        t[i] = age[i] / life[i];
    }
}

/// Each vertex's size (the particle's times its multiplier) and colour (red, green and blue
/// times the particle's brightness) as D3DCOLOR.
#[inline(always)]
fn sizes_and_colours(
    (size, scale): (&[f32], &[f32]),
    [r, g, b, a]: [&[f32]; 4],
    shade: &[f32],
    psize: &mut [f32],
    argb: &mut [u32],
) {
    let n = argb.len();
    let (size, scale, psize, shade) = (&size[..n], &scale[..n], &mut psize[..n], &shade[..n]);
    let (r, g, b, a) = (&r[..n], &g[..n], &b[..n], &a[..n]);
    for i in 0..n {
        psize[i] = size[i] * scale[i];
        let k = shade[i];
        argb[i] =
            unorm8(a[i]) << 24 | unorm8(r[i] * k) << 16 | unorm8(g[i] * k) << 8 | unorm8(b[i] * k);
    }
}

/// Writes the blocks' vertices into `out`, which holds exactly their live particles; splits
/// the work in halves with `rayon::join` when `parallel`.
pub(crate) fn write_blocks(
    data: &[f32],
    counts: &[u32],
    e: &Emitter,
    out: &mut [u8],
    parallel: bool,
) {
    if !parallel || counts.len() <= 2 {
        let mut offset = 0;
        for (block, &n) in data.chunks_exact(BLOCK_LEN).zip(counts) {
            let len = n as usize * VERTEX_STRIDE;
            write_block(block, n as usize, e, &mut out[offset..offset + len]);
            offset += len;
        }
        return;
    }
    let mid = counts.len() / 2;
    let left: usize = counts[..mid].iter().map(|&n| n as usize).sum();
    let (out_l, out_r) = out.split_at_mut(left * VERTEX_STRIDE);
    let (data_l, data_r) = data.split_at(mid * BLOCK_LEN);
    rayon::join(
        || write_blocks(data_l, &counts[..mid], e, out_l, parallel),
        || write_blocks(data_r, &counts[mid..], e, out_r, parallel),
    );
}

pointillist_lanes::entry_points! {
    /// [`write_block_inline`], [`write_block`]'s work, compiled with AVX2.
    mod write_at for avx2;
    fn [] [] (
        _avx2,
        block: &[f32],
        n: usize,
        e: &Emitter,
        out: &mut [u8],
    ) {
        write_block_inline(block, n, e, out);
    }
}

#[cfg(test)]
mod tests {
    use pointillist_core::{Vertex, XyzPsizeDiffuse};

    use super::*;
    use crate::Curve;
    use crate::layout::VERTEX_FVF;
    use crate::rng::Rng;

    #[test]
    fn the_vertex_layout_is_the_seeds() {
        assert_eq!(VERTEX_FVF.stride(), VERTEX_STRIDE);
        let mut bytes = Vec::new();
        XyzPsizeDiffuse {
            position: [1.0, 2.0, 3.0],
            psize: 0.5,
            diffuse: 0xFF10_2030,
        }
        .write(&mut bytes);
        let mut block = vec![0.0; BLOCK_LEN];
        for (k, v) in [1.0, 2.0, 3.0, 0.0, 0.0, 0.0, 0.0, 1.0, 0.5, 0.0, 1.0]
            .into_iter()
            .enumerate()
        {
            block[k * BLOCK] = v;
        }
        let e = Emitter {
            color_over_life: Curve::constant(pointillist_core::color::unpack(0xFF10_2030)),
            ..Emitter::default()
        };
        let mut out = vec![0u8; VERTEX_STRIDE];
        write_block(&block, 1, &e, &mut out);
        assert_eq!(out, bytes);
    }

    /// `unorm8` is `trunc(clamp(v, 0, 1) 255 + 0.5)` on a fine sweep of 0..=1, around every
    /// level's midpoint and outside the range.
    #[test]
    fn unorm8_is_the_clamped_rounding() {
        let want = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
        let sweep = (0..=1u32 << 20).map(|k| k as f32 / (1 << 20) as f32);
        let levels = (0..=255u32).flat_map(|k| {
            let v = (k as f32 + 0.5) / 255.0;
            [v.next_down(), v, v.next_up(), k as f32 / 255.0]
        });
        let odd = [
            -0.0,
            -1.0,
            1.5,
            f32::NAN,
            f32::INFINITY,
            f32::NEG_INFINITY,
            1e-45,
        ];
        for v in sweep.chain(levels).chain(odd) {
            assert_eq!(unorm8(v), want(v), "{v:e}");
        }
    }

    /// The vectorised vertices are the ones of one particle at a time with [`Curve::eval`],
    /// byte for byte, on every level, for curves of one to five keys (steps included), colours
    /// outside 0..=1, and ages outside the lifetime or NaN.
    #[test]
    fn vertices_are_the_scalar_ones() {
        let mut rng = Rng::from_key(3);
        let n = 1000;
        let mut block = vec![0.0; BLOCK_LEN];
        for (k, col) in block.chunks_exact_mut(BLOCK).enumerate() {
            for v in &mut col[..n] {
                *v = match k {
                    6 => rng.next_f32() * 3.0 - 0.5,
                    7 => rng.next_f32() * 2.0,
                    10 => rng.next_f32() * 1.5,
                    _ => rng.signed() * 30.0,
                };
            }
        }
        block[6 * BLOCK + 5] = f32::NAN;
        block[7 * BLOCK + 9] = 0.0;
        let colours = [
            Curve::constant([0.2, 0.4, 0.6, 0.8]),
            Curve::new(vec![
                (0.3, [1.0, -0.5, 0.5, 1.0]),
                (0.7, [0.0, 1.2, 0.5, -0.0]),
            ])
            .unwrap(),
            Curve::new(vec![
                (0.0, [0.0; 4]),
                (0.05, [0.85, 0.87, 0.9, 1.0]),
                (0.5, [0.1, 0.2, 0.3, 0.4]),
                (0.5, [0.9, 0.2, 0.3, 0.6]),
                (1.0, [0.0; 4]),
            ])
            .unwrap(),
        ];
        let sizes = [
            Curve::constant(1.0),
            Curve::new(vec![(0.0, 0.5), (0.25, 2.0), (0.25, 1.0), (1.0, 0.1)]).unwrap(),
        ];
        for color_over_life in &colours {
            for size_over_life in &sizes {
                let e = Emitter {
                    color_over_life: color_over_life.clone(),
                    size_over_life: size_over_life.clone(),
                    ..Emitter::default()
                };
                // Vertices as the writer did one at a time, with `f32::clamp`.
                let unorm8 = |v: f32| (v.clamp(0.0, 1.0) * 255.0 + 0.5) as u32;
                let mut want = Vec::new();
                for i in 0..n {
                    let col = |k: usize| block[k * BLOCK + i];
                    let t = col(6) / col(7);
                    let rgba = e.color_over_life.eval(t);
                    let b = col(10);
                    XyzPsizeDiffuse {
                        position: [col(0), col(1), col(2)],
                        psize: col(8) * e.size_over_life.eval(t),
                        diffuse: unorm8(rgba[3]) << 24
                            | unorm8(rgba[0] * b) << 16
                            | unorm8(rgba[1] * b) << 8
                            | unorm8(rgba[2] * b),
                    }
                    .write(&mut want);
                }
                let mut got = vec![0u8; n * VERTEX_STRIDE];
                write_block_inline(&block, n, &e, &mut got);
                assert!(got == want, "portable");
                #[cfg(target_arch = "x86_64")]
                if let Some(avx2) = pointillist_lanes::Avx2::new() {
                    got.fill(0);
                    write_at::avx2(avx2, &block, n, &e, &mut got);
                    assert!(got == want, "AVX2");
                }
            }
        }
    }
}

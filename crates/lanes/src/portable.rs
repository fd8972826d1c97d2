//! [`Portable`]: N lanes of plain scalar code: eight are the reference the other levels are
//! tested against and the level of CPUs without vectors this crate knows; four are the
//! baseline of targets other than x86-64 (see [`crate::BASELINE`]).

use pointillist_core::color::{f32_to_unorm8, unorm8_to_f32};
use pointillist_core::states::Cmp;

use crate::{Lanes, Quad, modulate_pixel, source_alpha_pixel};

/// The portable twin: `W` lanes of the scalar reference, lane by lane.
#[derive(Copy, Clone, Debug, Default)]
pub struct Portable<const W: usize>;

impl<const W: usize> Lanes for Portable<W> {
    const N: usize = W;
    type F = [f32; W];
    type U = [u32; W];
    type M = [bool; W];

    #[inline(always)]
    fn splat(self, x: f32) -> [f32; W] {
        [x; W]
    }
    #[inline(always)]
    fn splat_u(self, x: u32) -> [u32; W] {
        [x; W]
    }
    #[inline(always)]
    fn load(self, s: &[f32]) -> [f32; W] {
        s[..W].try_into().expect("W lanes")
    }
    #[inline(always)]
    fn load_u(self, s: &[u32]) -> [u32; W] {
        s[..W].try_into().expect("W lanes")
    }
    #[inline(always)]
    fn store(self, s: &mut [f32], v: [f32; W]) {
        s[..W].copy_from_slice(&v);
    }
    #[inline(always)]
    fn store_u(self, s: &mut [u32], v: [u32; W]) {
        s[..W].copy_from_slice(&v);
    }
    #[inline(always)]
    fn load_part(self, s: &[f32]) -> [f32; W] {
        std::array::from_fn(|i| s.get(i).copied().unwrap_or(0.0))
    }
    #[inline(always)]
    fn load_u_part(self, s: &[u32]) -> [u32; W] {
        std::array::from_fn(|i| s.get(i).copied().unwrap_or(0))
    }
    #[inline(always)]
    fn store_part(self, s: &mut [f32], v: [f32; W]) {
        let n = s.len().min(W);
        s[..n].copy_from_slice(&v[..n]);
    }
    #[inline(always)]
    fn store_u_part(self, s: &mut [u32], v: [u32; W]) {
        let n = s.len().min(W);
        s[..n].copy_from_slice(&v[..n]);
    }
    const REGISTER_GATHER: usize = usize::MAX;
    #[inline(always)]
    fn gather(self, row: &[f32], idx: [u32; W]) -> [f32; W] {
        let last = row.len() - 1;
        idx.map(|i| row[(i as usize).min(last)])
    }
    #[inline(always)]
    fn gather_u(self, row: &[u32], idx: [u32; W]) -> [u32; W] {
        let last = row.len() - 1;
        idx.map(|i| row[(i as usize).min(last)])
    }
    #[inline(always)]
    fn add(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| a[i] + b[i])
    }
    #[inline(always)]
    fn sub(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| a[i] - b[i])
    }
    #[inline(always)]
    fn mul(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| a[i] * b[i])
    }
    #[inline(always)]
    fn div(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| a[i] / b[i])
    }
    #[inline(always)]
    fn min(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| if a[i] < b[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn max(self, a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| if a[i] > b[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn sqrt(self, a: [f32; W]) -> [f32; W] {
        a.map(f32::sqrt)
    }
    #[inline(always)]
    fn floor(self, a: [f32; W]) -> [f32; W] {
        a.map(f32::floor)
    }
    #[inline(always)]
    fn ceil(self, a: [f32; W]) -> [f32; W] {
        a.map(f32::ceil)
    }
    #[inline(always)]
    fn bits_as_float(self, u: [u32; W]) -> [f32; W] {
        u.map(f32::from_bits)
    }
    #[inline(always)]
    fn gather_bytes(self, bytes: &[u8], offsets: [u32; W]) -> [u32; W] {
        let last = bytes.len() - 4;
        offsets.map(|o| {
            let o = (o as usize).min(last);
            u32::from_le_bytes(bytes[o..o + 4].try_into().expect("four bytes"))
        })
    }
    #[inline(always)]
    fn int_to_float(self, i: [u32; W]) -> [f32; W] {
        i.map(|x| x as i32 as f32)
    }
    #[inline(always)]
    fn float_to_int(self, x: [f32; W]) -> [u32; W] {
        x.map(|v| v as i32 as u32)
    }
    #[inline(always)]
    fn add_u(self, a: [u32; W], b: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| a[i].wrapping_add(b[i]))
    }
    #[inline(always)]
    fn bits(self, m: [bool; W]) -> u32 {
        m.iter().rev().fold(0, |acc, &b| acc << 1 | u32::from(b))
    }
    #[inline(always)]
    fn channel<const SHIFT: u32>(self, px: [u32; W]) -> [f32; W] {
        px.map(|p| unorm8_to_f32((p >> SHIFT) as u8))
    }
    #[inline(always)]
    fn round_unit(self, v: [f32; W]) -> [u32; W] {
        v.map(|x| u32::from(f32_to_unorm8(x)))
    }
    #[inline(always)]
    fn pack(self, [b, g, r, a]: [[u32; W]; 4]) -> [u32; W] {
        std::array::from_fn(|i| b[i] | g[i] << 8 | r[i] << 16 | a[i] << 24)
    }
    #[inline(always)]
    fn alpha_bytes(self, px: [u32; W]) -> [u32; W] {
        px.map(|x| x >> 24)
    }
    #[inline(always)]
    fn adds_u8(self, a: [u32; W], b: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| {
            let (x, y) = (a[i].to_le_bytes(), b[i].to_le_bytes());
            u32::from_le_bytes(std::array::from_fn(|k| x[k].saturating_add(y[k])))
        })
    }
    #[inline(always)]
    fn source_alpha(self, src: [u32; W], dst: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| source_alpha_pixel(src[i], dst[i]))
    }
    #[inline(always)]
    fn modulate(self, a: [u32; W], b: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| modulate_pixel(a[i], b[i]))
    }
    #[inline(always)]
    fn write_masked(self, mask: u32, new: [u32; W], old: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| (new[i] & mask) | (old[i] & !mask))
    }
    #[inline(always)]
    fn cmp(self, func: Cmp, a: [f32; W], b: [f32; W]) -> [bool; W] {
        std::array::from_fn(|i| pointillist_core::pixel::compare(func, a[i], b[i]))
    }
    #[inline(always)]
    fn cmp_u(self, func: Cmp, a: [u32; W], b: [u32; W]) -> [bool; W] {
        std::array::from_fn(|i| pointillist_core::pixel::compare(func, a[i], b[i]))
    }
    #[inline(always)]
    fn and(self, a: [bool; W], b: [bool; W]) -> [bool; W] {
        std::array::from_fn(|i| a[i] && b[i])
    }
    #[inline(always)]
    fn all(self) -> [bool; W] {
        [true; W]
    }
    #[inline(always)]
    fn select(self, m: [bool; W], a: [u32; W], b: [u32; W]) -> [u32; W] {
        std::array::from_fn(|i| if m[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn select_f(self, m: [bool; W], a: [f32; W], b: [f32; W]) -> [f32; W] {
        std::array::from_fn(|i| if m[i] { a[i] } else { b[i] })
    }
}

impl Quad for Portable<4> {
    #[inline(always)]
    fn color(self, c: u32) -> [f32; 4] {
        c.to_le_bytes().map(unorm8_to_f32)
    }
    #[inline(always)]
    fn pack_color(self, v: [f32; 4]) -> u32 {
        u32::from_le_bytes(v.map(f32_to_unorm8))
    }
    #[inline(always)]
    fn with_alpha_of(self, rgb: [f32; 4], alpha: [f32; 4]) -> [f32; 4] {
        [rgb[0], rgb[1], rgb[2], alpha[3]]
    }
}

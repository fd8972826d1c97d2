//! The machine's vectors, one foundation for the workspace: [`Lanes`] is N lanes of f32 and of
//! u32 with the operations the CPU backend's wide sprite spans and point stage's batches need
//! (SPEC 1's unpack and round-to-nearest pack, the sampler's lerp, the blend arithmetic, the
//! alpha and depth comparisons, the stage's tests and ceilings), one file per level: AVX-512
//! (sixteen lanes, `avx512.rs`), AVX2 (eight, `avx2.rs`), SSE2 (four, `sse2.rs`: the x86-64
//! baseline) and a portable twin (eight lanes of plain scalar code, `portable.rs`: the
//! reference the tests compare the others with). [`SimdLevel`] chooses one per process, the one
//! place that reads [`LANES_VAR`] and detects the CPU's features; the particles and the plot
//! take their levels from it too. [`entry_points!`] writes a generic kernel's per-level
//! `#[target_feature]` functions. The scalar helpers the levels share are here.
//!
//! Contract: every operation is, lane by lane, the exact IEEE f32 operation (or the integer
//! operation) the scalar reference performs, never fused, so a span gives the bits of its
//! pixels drawn one at a time whichever implementation runs.
//!
//! A value of [`Avx2`] or [`Avx512`] exists only once the CPU has been seen to have the
//! features ([`SimdLevel::detect`]); their operations call the intrinsics, which is sound because
//! holding the value proves the features. Code generic over `L: Lanes` must be inlined into a
//! function compiled with the features ([`entry_points!`] writes them), so every operation is
//! `#[inline(always)]`; SSE2's need no such function.

#![allow(unsafe_code)]

use pointillist_core::states::Cmp;

/// `[e(0), e(1), e(2), e(3)]` for the four channels, written out: closures (`array::map`,
/// `array::from_fn`) are functions of their own, compiled without the features of the
/// function they would otherwise inline into, and would call every intrinsic out of line.
#[macro_export]
macro_rules! channels {
    (|$c:ident| $e:expr) => {
        [
            {
                let $c = 0;
                $e
            },
            {
                let $c = 1;
                $e
            },
            {
                let $c = 2;
                $e
            },
            {
                let $c = 3;
                $e
            },
        ]
    };
}

/// Lane numbers: `load_u(&LANE_INDEX)` is `0, 1, 2, ...` in the lanes.
pub const LANE_INDEX: [u32; MAX_LANES] = [0, 1, 2, 3, 4, 5, 6, 7, 8, 9, 10, 11, 12, 13, 14, 15];

/// The most lanes any implementation has: scratch rows are padded to a multiple of it.
pub const MAX_LANES: usize = 16;

/// N lanes of f32 ([`Lanes::F`]), of u32 ([`Lanes::U`]) and a lane mask ([`Lanes::M`]).
pub trait Lanes: Copy + Send + Sync {
    /// The number of lanes.
    const N: usize;
    /// N f32.
    type F: Copy;
    /// N u32.
    type U: Copy;
    /// One bit of truth per lane.
    type M: Copy;

    /// `x` in every lane.
    fn splat(self, x: f32) -> Self::F;
    /// `x` in every lane.
    fn splat_u(self, x: u32) -> Self::U;
    /// The first N values of `s` (panics when it is shorter).
    fn load(self, s: &[f32]) -> Self::F;
    /// The first N values of `s` (panics when it is shorter).
    fn load_u(self, s: &[u32]) -> Self::U;
    /// Stores the lanes into the first N values of `s` (panics when it is shorter).
    fn store(self, s: &mut [f32], v: Self::F);
    /// Stores the lanes into the first N values of `s` (panics when it is shorter).
    fn store_u(self, s: &mut [u32], v: Self::U);
    /// The values of `s`, at most N, in the first lanes; the other lanes are 0.
    fn load_part(self, s: &[f32]) -> Self::F;
    /// The values of `s`, at most N, in the first lanes; the other lanes are 0.
    fn load_u_part(self, s: &[u32]) -> Self::U;
    /// Stores the first lanes into `s`, at most N values.
    fn store_part(self, s: &mut [f32], v: Self::F);
    /// Stores the first lanes into `s`, at most N values.
    fn store_u_part(self, s: &mut [u32], v: Self::U);
    /// Rows of at most this many values [`Lanes::gather`] reads from registers, at about the
    /// cost of a load; longer rows take the CPU's gather, a load per lane.
    const REGISTER_GATHER: usize;
    /// `row[idx]` lane by lane; an index past the end reads the last value.
    fn gather(self, row: &[f32], idx: Self::U) -> Self::F;
    /// `row[idx]` lane by lane; an index past the end reads the last value.
    fn gather_u(self, row: &[u32], idx: Self::U) -> Self::U;

    /// `a + b`.
    fn add(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a - b`.
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a * b`.
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;

    /// `a / b`.
    fn div(self, a: Self::F, b: Self::F) -> Self::F;
    /// `if a < b { a } else { b }` (`b` when either is NaN).
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    /// `if a > b { a } else { b }` (`b` when either is NaN).
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a.sqrt()`.
    fn sqrt(self, a: Self::F) -> Self::F;
    /// `a.floor()`.
    fn floor(self, a: Self::F) -> Self::F;
    /// `a.ceil()`.
    fn ceil(self, a: Self::F) -> Self::F;
    /// The f32 whose bits each lane holds.
    fn bits_as_float(self, u: Self::U) -> Self::F;
    /// The little-endian u32 at each byte offset of `bytes` (an offset past `bytes.len() - 4`
    /// reads the last four bytes); `bytes` holds at least four and at most `i32::MAX`.
    fn gather_bytes(self, bytes: &[u8], offsets: Self::U) -> Self::U;
    /// Signed integers as f32 (`i as f32`).
    fn int_to_float(self, i: Self::U) -> Self::F;
    /// Integral f32 in the i32 range as signed integers (`x as i32`).
    fn float_to_int(self, x: Self::F) -> Self::U;
    /// Wrapping `a + b` of 32-bit integers.
    fn add_u(self, a: Self::U, b: Self::U) -> Self::U;
    /// One bit per lane, lane 0 the lowest.
    fn bits(self, m: Self::M) -> u32;

    /// The sampler's `a + (b - a) * t` (SPEC 5.2), three roundings.
    #[inline(always)]
    fn lerp(self, a: Self::F, b: Self::F, t: Self::F) -> Self::F {
        self.add(a, self.mul(self.sub(b, a), t))
    }

    /// SPEC 1's unpack of the byte at bit `SHIFT` of each D3DCOLOR: `byte * (1 / 255)`.
    fn channel<const SHIFT: u32>(self, px: Self::U) -> Self::F;
    /// SPEC 1's unpack of the four channels (blue, green, red, alpha) of each D3DCOLOR.
    #[inline(always)]
    fn unpack(self, px: Self::U) -> [Self::F; 4] {
        [
            self.channel::<0>(px),
            self.channel::<8>(px),
            self.channel::<16>(px),
            self.channel::<24>(px),
        ]
    }
    /// SPEC 1's float to unorm8 (`color::f32_to_unorm8`: saturate, scale by 255, round half
    /// up) of values within 1/512 of the unit interval, where the saturation cannot change the
    /// result (`v * 255` is within 255/512 of `0..=255`, under the half step): the products
    /// and lerps of unpacked bytes the span fills quantize.
    fn round_unit(self, v: Self::F) -> Self::U;
    /// D3DCOLORs from byte lanes (blue, green, red, alpha).
    fn pack(self, c: [Self::U; 4]) -> Self::U;
    /// SPEC 1's packing of shaded channels (blue, green, red, alpha) within
    /// [`Lanes::round_unit`]'s domain into D3DCOLORs.
    #[inline(always)]
    fn quantize(self, shaded: [Self::F; 4]) -> Self::U {
        self.pack(channels!(|c| self.round_unit(shaded[c])))
    }
    /// The alpha bytes of D3DCOLORs.
    fn alpha_bytes(self, px: Self::U) -> Self::U;
    /// The per-byte saturating sum (SPEC 5.5's ONE, ONE, ADD).
    fn adds_u8(self, a: Self::U, b: Self::U) -> Self::U;
    /// SPEC 5.5's SRCALPHA, INVSRCALPHA, ADD of the D3DCOLORs `src` onto `dst`, on every
    /// channel: [`source_alpha_pixel`] lane by lane.
    fn source_alpha(self, src: Self::U, dst: Self::U) -> Self::U;
    /// SPEC 5.1's MODULATE of the D3DCOLORs `a` and `b`, quantized (SPEC 1), on every
    /// channel: [`modulate_pixel`] lane by lane.
    fn modulate(self, a: Self::U, b: Self::U) -> Self::U;
    /// SPEC 5.6: `(new & mask) | (old & !mask)`.
    fn write_masked(self, mask: u32, new: Self::U, old: Self::U) -> Self::U;

    /// `compare(func, a, b)` of core (SPEC 5.4) lane by lane.
    fn cmp(self, func: Cmp, a: Self::F, b: Self::F) -> Self::M;
    /// `compare(func, a, b)` of core (SPEC 5.3) lane by lane, for bytes.
    fn cmp_u(self, func: Cmp, a: Self::U, b: Self::U) -> Self::M;
    /// Lanes true in both.
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    /// Every lane true.
    fn all(self) -> Self::M;
    /// `if m { a } else { b }` lane by lane.
    fn select(self, m: Self::M, a: Self::U, b: Self::U) -> Self::U;
    /// `if m { a } else { b }` lane by lane.
    fn select_f(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F;
}

/// SPEC 5.5's SRCALPHA, INVSRCALPHA, ADD of the D3DCOLOR `src` onto `dst`, channel by channel
/// in integers: `round((s * a + d * (255 - a)) / 255)` of the bytes, `a` the source alpha.
///
/// The reference's float arithmetic rounds to the same byte for every one of the 2^24 inputs
/// of a channel (the exact quotient is never a half, and the float error stays far below
/// the distance to one; a test checks all of them), and the integers take a third of the
/// vector operations.
#[inline(always)]
pub fn source_alpha_pixel(src: u32, dst: u32) -> u32 {
    let a = src >> 24;
    let channel = |shift: u32| {
        let (s, d) = ((src >> shift) & 0xFF, (dst >> shift) & 0xFF);
        div_255(s * a + d * (255 - a)) << shift
    };
    channel(0) | channel(8) | channel(16) | channel(24)
}

/// SPEC 5.1's MODULATE of the D3DCOLORs `a` and `b`, quantized (SPEC 1), channel by channel
/// in integers: `round(a * b / 255)` of the bytes.
///
/// The reference's float arithmetic (the product of the unpacked bytes, then SPEC 1's
/// rounding) gives the same byte for every one of the 2^16 inputs of a channel (the exact
/// quotient is never a half; a test checks all of them).
#[inline(always)]
pub fn modulate_pixel(a: u32, b: u32) -> u32 {
    let channel = |shift: u32| div_255(((a >> shift) & 0xFF) * ((b >> shift) & 0xFF)) << shift;
    channel(0) | channel(8) | channel(16) | channel(24)
}

/// `round(x / 255)` of `x <= 255 * 255`, a product of bytes or a sum of two whose factors add
/// up to 255 (never a half): `t = x + 128`, then `(t + t / 256) / 256`, at most 65,407 on the
/// way. The vector levels' `source_alpha` and `modulate` write the same steps on 16-bit lanes,
/// with their constants shared between the two halves of a register (a helper of their own
/// measured 2 % more instructions on W3).
#[inline(always)]
fn div_255(x: u32) -> u32 {
    let t = x + 128;
    (t + (t >> 8)) >> 8
}

/// Four lanes as the four channels of one colour in D3DCOLOR byte order (blue, green, red,
/// alpha; lane `c` holds channel `c`), for the fills that shade one pixel at a time.
pub trait Quad: Lanes {
    /// SPEC 1's unpack of the D3DCOLOR `c` (`color::unpack`, reordered into lanes).
    fn color(self, c: u32) -> Self::F;
    /// SPEC 1's pack of the lanes (`color::pack`: saturate, scale by 255, round half up; NaN
    /// packs as 0).
    fn pack_color(self, v: Self::F) -> u32;
    /// The blue, green and red lanes of `rgb` with the alpha lane of `alpha`.
    fn with_alpha_of(self, rgb: Self::F, alpha: Self::F) -> Self::F;
    /// An RGBA colour of the reference arithmetic, reordered into lanes.
    #[inline(always)]
    fn rgba(self, [r, g, b, a]: pointillist_core::color::Rgba) -> Self::F {
        self.load(&[b, g, r, a])
    }
}

/// The four lanes every CPU of the target has: SSE2 on x86-64, the portable twin elsewhere.
#[cfg(target_arch = "x86_64")]
pub type Baseline = Sse2;
/// The four lanes every CPU of the target has: SSE2 on x86-64, the portable twin elsewhere.
#[cfg(not(target_arch = "x86_64"))]
pub type Baseline = Portable<4>;

// A colour's four channels are one vector of [`Baseline`]'s lanes, and rectangles of one
// colour blend four pixels at a time in them.
const _: () = assert!(<Baseline as Lanes>::N == 4);

/// One colour's four channels in [`Baseline`]'s lanes, named by its type (a projection through
/// [`Lanes`] would not be known apart from other types in the impls of other crates).
#[cfg(target_arch = "x86_64")]
pub type Channels = std::arch::x86_64::__m128;
/// One colour's four channels in [`Baseline`]'s lanes, named by its type (a projection through
/// [`Lanes`] would not be known apart from other types in the impls of other crates).
#[cfg(not(target_arch = "x86_64"))]
pub type Channels = [f32; 4];
const _: fn(Channels) -> <Baseline as Lanes>::F = |c| c;

/// [`Baseline`]'s lanes, for the code that runs outside any [`SimdLevel`]'s functions: the
/// single pixels of the fills, the rectangles of one colour, the wide spans on the portable
/// level, and the vertices the stage's batches leave over.
#[cfg(target_arch = "x86_64")]
pub const BASELINE: Baseline = Sse2::new();
/// [`Baseline`]'s lanes, for the code that runs outside any [`SimdLevel`]'s functions: the
/// single pixels of the fills, the rectangles of one colour, the wide spans on the portable
/// level, and the vertices the stage's batches leave over.
#[cfg(not(target_arch = "x86_64"))]
pub const BASELINE: Baseline = Portable;

mod entry;
mod level;
pub use level::{LANES_VAR, SimdLevel};

mod portable;
pub use portable::Portable;

#[cfg(target_arch = "x86_64")]
mod avx2;
#[cfg(target_arch = "x86_64")]
mod avx512;
#[cfg(target_arch = "x86_64")]
mod sse2;
#[cfg(target_arch = "x86_64")]
pub use {avx2::Avx2, avx512::Avx512, sse2::Sse2};

/// `unsafe { ... }` in the operations of [`Sse2`], [`Avx2`] and [`Avx512`].
#[cfg(target_arch = "x86_64")]
macro_rules! with_features {
    ($($body:tt)*) => {
        // SAFETY: a value of `Avx2` or `Avx512` exists only after
        // `is_x86_feature_detected!` saw its features (its field is private to this module
        // and `new` checks), and SSE2 is enabled for the whole build (`sse2.rs` checks), so
        // the CPU runs the instructions; loads and stores go through slices whose length was
        // checked first, and gathers clamp their indices into the slice.
        unsafe { $($body)* }
    };
}
#[cfg(target_arch = "x86_64")]
use with_features;

#[cfg(test)]
mod tests {
    use super::*;
    use pointillist_core::color::{f32_to_unorm8, unorm8_to_f32};
    use pointillist_fixtures::Rng;

    /// How far outside `0..=1` [`Lanes::round_unit`] may be given a value.
    const UNIT_SLACK: f32 = 1.0 / 512.0;

    const CMPS: [Cmp; 8] = [
        Cmp::Never,
        Cmp::Less,
        Cmp::Equal,
        Cmp::LessEqual,
        Cmp::Greater,
        Cmp::NotEqual,
        Cmp::GreaterEqual,
        Cmp::Always,
    ];

    /// Floats a span meets and hostile ones: NaN, infinities, signed zeros, values next to
    /// the rounding boundaries of SPEC 1's pack.
    fn float(rng: &mut Rng) -> f32 {
        match rng.next_u32() % 8 {
            0 => f32::from_bits(rng.next_u32()),
            1 => rng.pick(&[f32::NAN, f32::INFINITY, f32::NEG_INFINITY, -0.0, 0.0, 1.0]),
            2 => {
                // Just below, at and just above a half step of 1/255.
                let half = ((rng.next_u32() % 256) as f32 + 0.5) / 255.0;
                f32::from_bits(half.to_bits() + rng.next_u32() % 3 - 1)
            }
            3 => rng.pick(&[0.499_999_97 / 255.0, 0.5 / 255.0, 254.5 / 255.0]),
            _ => rng.range(-0.1, 1.1),
        }
    }

    /// Lane `i` of `v`, through a store.
    fn f<L: Lanes>(l: L, v: L::F) -> [f32; MAX_LANES] {
        let mut out = [0.0; MAX_LANES];
        l.store(&mut out, v);
        out
    }

    fn u<L: Lanes>(l: L, v: L::U) -> [u32; MAX_LANES] {
        let mut out = [0; MAX_LANES];
        l.store_u(&mut out, v);
        out
    }

    fn m<L: Lanes>(l: L, v: L::M) -> [bool; MAX_LANES] {
        let ones = u(l, l.select(v, l.splat_u(1), l.splat_u(0)));
        ones.map(|x| x == 1)
    }

    /// Every operation of `l` against the portable twin, lane by lane, on the same inputs.
    fn matches_the_portable_twin<L: Lanes>(l: L) {
        let p = Portable::<8>;
        let mut rng = Rng(0x1A4E_5000_0000_0001 ^ L::N as u64);
        for round in 0..4000 {
            let a: [f32; MAX_LANES] = std::array::from_fn(|_| float(&mut rng));
            let b: [f32; MAX_LANES] = std::array::from_fn(|_| float(&mut rng));
            let t: [f32; MAX_LANES] = std::array::from_fn(|_| float(&mut rng));
            let px: [u32; MAX_LANES] = std::array::from_fn(|_| rng.next_u32());
            let qx: [u32; MAX_LANES] = std::array::from_fn(|_| rng.next_u32());
            let bytes: [u32; 2 * MAX_LANES] = std::array::from_fn(|_| rng.next_u32() % 256);
            let idx: [u32; MAX_LANES] = std::array::from_fn(|_| rng.next_u32() % 56);
            let row: Vec<f32> = (0..1 + rng.next_u32() % 48)
                .map(|_| float(&mut rng))
                .collect();
            let row_u: Vec<u32> = (0..1 + rng.next_u32() % 48)
                .map(|_| rng.next_u32())
                .collect();
            let mask = rng.next_u32();
            // Values over the whole domain of `round_unit`, its ends included.
            let rng_unit: [f32; MAX_LANES] = std::array::from_fn(|_| match rng.next_u32() % 4 {
                0 => rng.pick(&[-UNIT_SLACK, 1.0 + UNIT_SLACK, -0.0, 1.0]),
                _ => rng.range(-UNIT_SLACK, 1.0 + UNIT_SLACK),
            });
            let func = rng.pick(&CMPS);
            // Partial loads fill the lanes past the slice with zeros; partial stores write
            // only the slice.
            let part = rng.next_u32() as usize % (L::N + 1);
            let got = f(l, l.load_part(&a[..part]));
            assert!(
                (0..L::N).all(|i| got[i].to_bits() == if i < part { a[i] } else { 0.0 }.to_bits())
            );
            let got = u(l, l.load_u_part(&px[..part]));
            assert!((0..L::N).all(|i| got[i] == if i < part { px[i] } else { 0 }));
            let (mut out, mut out_u) = ([7.0f32; MAX_LANES + 1], [7u32; MAX_LANES + 1]);
            l.store_part(&mut out[..part], l.load(&a));
            l.store_u_part(&mut out_u[..part], l.load_u(&px));
            for i in 0..=MAX_LANES {
                let (want, want_u) = if i < part { (a[i], px[i]) } else { (7.0, 7) };
                assert_eq!(
                    (out[i].to_bits(), out_u[i]),
                    (want.to_bits(), want_u),
                    "part {part}"
                );
            }
            for first in (0..MAX_LANES).step_by(Portable::<8>::N) {
                if first >= L::N {
                    break;
                }
                // The lanes of `l` this round compares: eight, or all of a narrower level's.
                let w = Portable::<8>::N.min(L::N);
                let r = first..first + Portable::<8>::N;
                let rw = first..first + w;
                let (fa, fb, ft) = (
                    p.load(&a[r.clone()]),
                    p.load(&b[r.clone()]),
                    p.load(&t[r.clone()]),
                );
                let (la, lb, lt) = (l.load(&a), l.load(&b), l.load(&t));
                let (pu, qu, bu) = (l.load_u(&px), l.load_u(&qx), l.load_u(&bytes));
                let (ppu, pqu, pbu) = (
                    p.load_u(&px[r.clone()]),
                    p.load_u(&qx[r.clone()]),
                    p.load_u(&bytes[r.clone()]),
                );
                let same_f = |name: &str, got: [f32; MAX_LANES], want: [f32; 8]| {
                    // Bits, any NaN as one (payloads are not part of the contract).
                    let bits = |v: &[f32]| {
                        v.iter()
                            .map(|x| if x.is_nan() { u32::MAX } else { x.to_bits() })
                            .collect::<Vec<_>>()
                    };
                    assert_eq!(
                        bits(&got[rw.clone()]),
                        bits(&want[..w]),
                        "{name}, round {round}"
                    );
                };
                let same_u = |name: &str, got: [u32; MAX_LANES], want: [u32; 8]| {
                    assert_eq!(got[rw.clone()], want[..w], "{name}, round {round}");
                };
                same_f("add", f(l, l.add(la, lb)), p.add(fa, fb));
                same_f("sub", f(l, l.sub(la, lb)), p.sub(fa, fb));
                same_f("mul", f(l, l.mul(la, lb)), p.mul(fa, fb));
                same_f("lerp", f(l, l.lerp(la, lb, lt)), p.lerp(fa, fb, ft));
                same_f("div", f(l, l.div(la, lb)), p.div(fa, fb));
                same_f("min", f(l, l.min(la, lb)), p.min(fa, fb));
                same_f("max", f(l, l.max(la, lb)), p.max(fa, fb));
                same_f("floor", f(l, l.floor(la)), p.floor(fa));
                same_f("sqrt", f(l, l.sqrt(la)), p.sqrt(fa));
                same_f("ceil", f(l, l.ceil(la)), p.ceil(fa));
                same_f(
                    "bits_as_float",
                    f(l, l.bits_as_float(pu)),
                    p.bits_as_float(ppu),
                );
                let raw: Vec<u8> = row_u.iter().flat_map(|w| w.to_le_bytes()).collect();
                let spots: [u32; MAX_LANES] = std::array::from_fn(|i| idx[i] * 3);
                same_u(
                    "gather_bytes",
                    u(l, l.gather_bytes(&raw, l.load_u(&spots))),
                    p.gather_bytes(&raw, p.load_u(&spots[r.clone()])),
                );
                same_f(
                    "int_to_float",
                    f(l, l.int_to_float(pu)),
                    p.int_to_float(ppu),
                );
                let small: [f32; MAX_LANES] = std::array::from_fn(|i| (a[i] * 1000.0).floor());
                let small = small.map(|x| if x.abs() < 1e9 { x } else { 0.0 });
                same_u(
                    "float_to_int",
                    u(l, l.float_to_int(l.load(&small))),
                    p.float_to_int(p.load(&small[r.clone()])),
                );
                same_u("add_u", u(l, l.add_u(pu, qu)), p.add_u(ppu, pqu));
                same_f(
                    "gather",
                    f(l, l.gather(&row, l.load_u(&idx))),
                    p.gather(&row, p.load_u(&idx[r.clone()])),
                );
                same_u(
                    "gather_u",
                    u(l, l.gather_u(&row_u, l.load_u(&idx))),
                    p.gather_u(&row_u, p.load_u(&idx[r.clone()])),
                );
                same_f("channel 0", f(l, l.channel::<0>(pu)), p.channel::<0>(ppu));
                same_f("channel 8", f(l, l.channel::<8>(pu)), p.channel::<8>(ppu));
                same_f(
                    "channel 16",
                    f(l, l.channel::<16>(pu)),
                    p.channel::<16>(ppu),
                );
                same_f(
                    "channel 24",
                    f(l, l.channel::<24>(pu)),
                    p.channel::<24>(ppu),
                );
                let near: [f32; MAX_LANES] = std::array::from_fn(|i| {
                    if a[i].abs() <= 1.0 + UNIT_SLACK {
                        a[i].abs()
                    } else {
                        rng_unit[i]
                    }
                });
                same_u(
                    "round_unit",
                    u(l, l.round_unit(l.load(&near))),
                    p.round_unit(p.load(&near[r.clone()])),
                );
                let q = [bu, l.load_u(&bytes[1..]), l.load_u(&bytes[..]), bu];
                let pq = [
                    pbu,
                    p.load_u(&bytes[first + 1..]),
                    p.load_u(&bytes[r.clone()]),
                    pbu,
                ];
                same_u("pack", u(l, l.pack(q)), p.pack(pq));
                // Four channels over the whole domain of `round_unit`.
                let unit: [[f32; MAX_LANES]; 4] = [0, 1, 2, 3]
                    .map(|c| std::array::from_fn(|i| rng_unit[(i + 5 * c) % MAX_LANES]));
                same_u(
                    "quantize",
                    u(l, l.quantize(unit.map(|v| l.load(&v)))),
                    p.quantize(unit.map(|v| p.load(&v[r.clone()]))),
                );
                same_u("adds_u8", u(l, l.adds_u8(pu, qu)), p.adds_u8(ppu, pqu));
                same_u("modulate", u(l, l.modulate(pu, qu)), p.modulate(ppu, pqu));
                same_u("alpha_bytes", u(l, l.alpha_bytes(pu)), p.alpha_bytes(ppu));
                same_u(
                    "source_alpha",
                    u(l, l.source_alpha(pu, qu)),
                    p.source_alpha(ppu, pqu),
                );
                same_u(
                    "write_masked",
                    u(l, l.write_masked(mask, pu, qu)),
                    p.write_masked(mask, ppu, pqu),
                );
                let (cm, pcm) = (l.cmp(func, la, lb), p.cmp(func, fa, fb));
                assert_eq!(
                    m(l, cm)[rw.clone()],
                    pcm[..w],
                    "cmp {func:?}, round {round}"
                );
                let (cu, pcu) = (
                    l.cmp_u(func, bu, l.load_u(&bytes[1..])),
                    p.cmp_u(func, pbu, p.load_u(&bytes[first + 1..])),
                );
                assert_eq!(
                    m(l, cu)[rw.clone()],
                    pcu[..w],
                    "cmp_u {func:?}, round {round}"
                );
                let want = pcm[..w]
                    .iter()
                    .enumerate()
                    .filter(|x| *x.1)
                    .map(|(i, _)| 1 << i)
                    .sum::<u32>();
                let lanes = (1 << w) - 1;
                assert_eq!(l.bits(cm) >> first & lanes, want, "bits, round {round}");
                let both = l.and(cm, cu);
                assert_eq!(
                    m(l, both)[rw.clone()],
                    p.and(pcm, pcu)[..w],
                    "and, round {round}"
                );
                same_u(
                    "select",
                    u(l, l.select(cm, pu, qu)),
                    p.select(pcm, ppu, pqu),
                );
                same_f(
                    "select_f",
                    f(l, l.select_f(cm, la, lb)),
                    p.select_f(pcm, fa, fb),
                );
                assert!(m(l, l.all())[..L::N].iter().all(|&x| x));
            }
        }
    }

    /// The portable twin is the scalar reference lane by lane (its definition), and round-trips
    /// SPEC 1's pack of every byte.
    #[test]
    fn spec_1_portable_lanes_pack_every_byte_like_the_reference() {
        let p = Portable::<8>;
        for byte in 0..=255u32 {
            let v = p.channel::<16>([byte << 16; 8]);
            assert_eq!(v, [unorm8_to_f32(byte as u8); 8]);
            assert_eq!(p.round_unit(v), [byte; 8]);
        }
    }

    /// The integer source-alpha blend is core's float reference (SPEC 5.5) for every source
    /// byte, source alpha and target byte: the colour channels carry `(s, a, d)`, the alpha
    /// channel `(a, a, d)`.
    #[test]
    fn spec_5_5_source_alpha_in_integers_is_the_reference_for_every_input() {
        use pointillist_core::pixel::{BlendSetup, blend};
        use pointillist_core::states::{Blend, BlendOp};
        let setup = BlendSetup {
            src: Blend::SrcAlpha,
            dst: Blend::InvSrcAlpha,
            op: BlendOp::Add,
            src_alpha: Blend::SrcAlpha,
            dst_alpha: Blend::InvSrcAlpha,
            op_alpha: BlendOp::Add,
            factor: [0.0; 4],
        };
        for a in 0..=255u32 {
            for s in 0..=255u32 {
                let src = a << 24 | s << 16 | (255 - s) << 8 | s;
                for d in 0..=255u32 {
                    let dst = d << 24 | d << 16 | (d ^ 0x5A) << 8 | d;
                    assert_eq!(source_alpha_pixel(src, dst), blend(&setup, src, dst));
                }
            }
        }
    }

    /// Each level's [`Lanes::quantize`] of the floats around every half step and every step of
    /// 1/255, and the ends of `round_unit`'s domain, against the reference's rounding.
    fn quantize_rounds_like_the_reference<L: Lanes>(l: L) {
        let mut values = vec![-UNIT_SLACK, -0.0, 0.0, 1.0 + UNIT_SLACK];
        for k in 0..=510u32 {
            let v = k as f32 / 510.0;
            for ulps in -4..=4i32 {
                values.push(f32::from_bits(v.to_bits().wrapping_add_signed(ulps)));
            }
        }
        values.retain(|v| (-UNIT_SLACK..=1.0 + UNIT_SLACK).contains(v));
        for chunk in values.chunks(L::N) {
            let mut lanes = [0.0; MAX_LANES];
            lanes[..chunk.len()].copy_from_slice(chunk);
            let v = l.load(&lanes);
            let got = u(l, l.quantize([v, l.splat(0.0), v, l.splat(1.0)]));
            for (i, &x) in chunk.iter().enumerate() {
                let byte = u32::from(f32_to_unorm8(x));
                assert_eq!(got[i], 0xFF00_0000 | byte << 16 | byte, "{x:e}");
            }
        }
    }

    #[test]
    fn spec_1_every_level_quantizes_half_steps_like_the_reference() {
        for level in SimdLevel::available() {
            match level {
                SimdLevel::Portable => quantize_rounds_like_the_reference(Portable::<8>),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Sse2(l) => quantize_rounds_like_the_reference(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx2(l) => quantize_rounds_like_the_reference(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx512(l) => quantize_rounds_like_the_reference(l),
            }
        }
    }

    /// The integer MODULATE is core's float reference (SPEC 5.1, then SPEC 1's rounding) for
    /// every pair of bytes.
    #[test]
    fn spec_5_1_modulate_in_integers_is_the_reference_for_every_input() {
        for a in 0..=255u8 {
            for b in 0..=255u8 {
                let want = f32_to_unorm8(unorm8_to_f32(a) * unorm8_to_f32(b));
                let (a, b) = (u32::from(a), u32::from(b));
                let got = modulate_pixel(a << 24 | a << 8, b << 24 | b << 8);
                assert_eq!(got, u32::from(want) * 0x0100_0100, "{a} * {b}");
            }
        }
    }

    /// Each four-lane level's [`Quad`] operations against the scalar reference (SPEC 1's
    /// `unpack` and `pack`) and the plain definitions, on ordinary and hostile values.
    fn quad_matches_the_reference<L: Quad>(l: L) {
        use pointillist_core::color::{pack, unpack};
        let bits = |v: [f32; 4]| v.map(f32::to_bits);
        let lanes = |v| {
            let out = f(l, v);
            [out[0], out[1], out[2], out[3]]
        };
        let mut rng = Rng(0x1234_5678_9ABC_DEF1);
        for _ in 0..100_000 {
            let c = rng.next_u32();
            let [r, g, b, a] = unpack(c);
            assert_eq!(bits(lanes(l.color(c))), bits([b, g, r, a]), "{c:08x}");
            assert_eq!(l.pack_color(l.color(c)), c);
            let v = [
                float(&mut rng),
                float(&mut rng),
                float(&mut rng),
                float(&mut rng),
            ];
            assert_eq!(l.pack_color(l.rgba(v)), pack(v), "{v:?}");
            let o = [
                float(&mut rng),
                float(&mut rng),
                float(&mut rng),
                float(&mut rng),
            ];
            let [vb, vg, vr, _] = lanes(l.rgba(v));
            let got = lanes(l.with_alpha_of(l.rgba(v), l.rgba(o)));
            assert_eq!(bits(got), bits([vb, vg, vr, o[3]]), "{v:?} {o:?}");
        }
    }

    #[test]
    fn spec_1_four_lane_colours_match_the_reference() {
        quad_matches_the_reference(Portable::<4>);
        quad_matches_the_reference(BASELINE);
    }

    #[test]
    fn every_level_matches_the_portable_twin() {
        for level in SimdLevel::available() {
            match level {
                SimdLevel::Portable => {
                    matches_the_portable_twin(Portable::<8>);
                    matches_the_portable_twin(Portable::<4>);
                }
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Sse2(l) => matches_the_portable_twin(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx2(l) => matches_the_portable_twin(l),
                #[cfg(target_arch = "x86_64")]
                SimdLevel::Avx512(l) => matches_the_portable_twin(l),
            }
        }
    }
}

//! [`entry_points!`](crate::entry_points): the per-level functions a generic kernel runs in.

/// Writes the entry points of a kernel on each listed level, in a module of its own (x86-64
/// only): a safe function per level, named after it, that takes the level's token first (its
/// argument named as the kernel names it) and runs the kernel's body compiled with the level's
/// features, so that the `#[inline(always)]` operations of [`Lanes`](crate::Lanes) inline
/// into it.
///
/// - `sse2` takes [`Sse2`](crate::Sse2): no features (SSE2 is the x86-64 baseline), out of
///   line like the others.
/// - `avx2` takes [`Avx2`](crate::Avx2) and is compiled with AVX2.
/// - `avx512` takes [`Avx512`](crate::Avx512) and is compiled with AVX-512 F, BW, DQ and VL.
///
/// The kernel is written as a function without a name: its generic parameters in brackets,
/// then their names in brackets (for the call, which names them), then the token and the
/// arguments:
///
/// ```
/// use pointillist_lanes::{Lanes, SimdLevel, Portable};
///
/// /// The doubled values.
/// fn double<L: Lanes>(l: L, v: &mut [f32]) {
///     for chunk in v.chunks_exact_mut(L::N) {
///         let x = l.load(chunk);
///         l.store(chunk, l.add(x, x));
///     }
/// }
///
/// pointillist_lanes::entry_points! {
///     /// [`double`] on each level.
///     mod doubled for sse2, avx2;
///     fn [] [] (l, v: &mut [f32]) { double(l, v) }
/// }
///
/// # fn main() {
/// let mut v = [1.0; 16];
/// match SimdLevel::detect() {
///     SimdLevel::Portable => double(Portable::<8>, &mut v),
///     #[cfg(target_arch = "x86_64")]
///     SimdLevel::Sse2(l) => doubled::sse2(l, &mut v),
///     #[cfg(target_arch = "x86_64")]
///     SimdLevel::Avx2(l) => doubled::avx2(l, &mut v),
///     #[cfg(target_arch = "x86_64")]
///     SimdLevel::Avx512(l) => doubled::avx2(l.narrow(), &mut v),
/// }
/// assert_eq!(v, [2.0; 16]);
/// # }
/// ```
#[macro_export]
macro_rules! entry_points {
    (
        $(#[$doc:meta])*
        $vis:vis mod $name:ident for $($level:ident),+ ;
        $($kernel:tt)*
    ) => {
        $(#[$doc])*
        #[cfg(target_arch = "x86_64")]
        $vis mod $name {
            #[allow(unused_imports)]
            use super::*;
            $crate::entry_points!(@levels [$($level)+] $($kernel)*);
        }
    };
    (@levels [] $($kernel:tt)*) => {};
    (@levels [$first:ident $($rest:ident)*] $($kernel:tt)*) => {
        $crate::entry_points!(@entry $first $($kernel)*);
        $crate::entry_points!(@levels [$($rest)*] $($kernel)*);
    };
    (
        @entry sse2 fn [$($generics:tt)*] [$($names:tt)*]
        ($l:ident $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        /// The kernel on SSE2, the x86-64 baseline.
        #[inline(never)]
        pub(crate) fn sse2<$($generics)*>($l: $crate::Sse2 $(, $arg: $ty)*) $(-> $ret)? $body
    };
    (@entry avx2 $($kernel:tt)*) => {
        $crate::entry_points!(@featured avx2, $crate::Avx2, "avx2", $($kernel)*);
    };
    (@entry avx512 $($kernel:tt)*) => {
        $crate::entry_points!(
            @featured avx512, $crate::Avx512, "avx512f,avx512bw,avx512dq,avx512vl", $($kernel)*
        );
    };
    (
        @featured $level:ident, $token:ty, $features:literal,
        fn [$($generics:tt)*] [$($names:tt)*]
        ($l:ident $(, $arg:ident: $ty:ty)* $(,)?) $(-> $ret:ty)? $body:block
    ) => {
        /// The kernel compiled with the level's features, which its token proves the CPU has.
        #[inline(always)]
        #[allow(unsafe_code)] // The call of a `target_feature` function.
        pub(crate) fn $level<$($generics)*>(token: $token $(, $arg: $ty)*) $(-> $ret)? {
            #[target_feature(enable = $features)]
            fn kernel<$($generics)*>($l: $token $(, $arg: $ty)*) $(-> $ret)? $body
            // SAFETY: a value of the token exists only once `SimdLevel::detect` (or the token's
            // `new`) saw the CPU has the features `kernel` is compiled with.
            unsafe { kernel::<$($names)*>(token $(, $arg)*) }
        }
    };
}

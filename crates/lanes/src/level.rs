//! [`SimdLevel`]: which [`Lanes`](crate::Lanes) this process runs, chosen once from the CPU's
//! features and [`LANES_VAR`].

#[cfg(target_arch = "x86_64")]
use crate::{Avx2, Avx512, BASELINE, Sse2};
#[cfg(doc)]
use crate::{Lanes, Portable};

/// The environment variable that chooses a narrower [`SimdLevel`] than the widest the CPU has
/// (`portable`, `sse2`, `avx2`, `avx512`), to compare them.
pub const LANES_VAR: &str = "POINTILLIST_LANES";

/// Which [`Lanes`] this machine runs, detected once: the CPU backend's spans and batches, the
/// particles' kernels and the plot's counting pass all run on it.
#[derive(Copy, Clone, Debug)]
pub enum SimdLevel {
    /// [`Portable`] with eight lanes.
    Portable,
    /// [`Avx2`].
    #[cfg(target_arch = "x86_64")]
    Avx2(Avx2),
    /// [`Avx512`].
    #[cfg(target_arch = "x86_64")]
    Avx512(Avx512),
    /// [`Sse2`] (last: the wide spans' dispatch on the other levels then compiles as before
    /// it came, a comparison less a sprite).
    #[cfg(target_arch = "x86_64")]
    Sse2(Sse2),
}

impl SimdLevel {
    /// The level the process runs on, chosen once: the one [`LANES_VAR`] names when
    /// the CPU supports it, else the widest the CPU supports.
    pub fn detect() -> SimdLevel {
        static LEVEL: std::sync::OnceLock<SimdLevel> = std::sync::OnceLock::new();
        *LEVEL.get_or_init(|| {
            let wanted = std::env::var(LANES_VAR).ok();
            let available = SimdLevel::available();
            let named = available
                .iter()
                .find(|l| wanted.as_deref() == Some(l.name()));
            *named.or(available.last()).unwrap_or(&SimdLevel::Portable)
        })
    }

    /// The level's name: `portable`, `sse2`, `avx2` or `avx512`.
    pub fn name(self) -> &'static str {
        match self {
            SimdLevel::Portable => "portable",
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Sse2(_) => "sse2",
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx2(_) => "avx2",
            #[cfg(target_arch = "x86_64")]
            SimdLevel::Avx512(_) => "avx512",
        }
    }

    /// Every level the CPU supports, narrowest first (for the tests, which run each).
    pub fn available() -> Vec<SimdLevel> {
        #[cfg(target_arch = "x86_64")]
        let wide = [
            Some(SimdLevel::Sse2(BASELINE)),
            Avx2::new().map(SimdLevel::Avx2),
            Avx512::new().map(SimdLevel::Avx512),
        ];
        #[cfg(not(target_arch = "x86_64"))]
        let wide: [Option<SimdLevel>; 0] = [];
        std::iter::once(SimdLevel::Portable)
            .chain(wide.into_iter().flatten())
            .collect()
    }

    /// The eight lanes of AVX2 where the level has them (AVX-512's narrowed), for the kernels
    /// that have no wider entry (the particles').
    #[cfg(target_arch = "x86_64")]
    pub fn avx2(self) -> Option<Avx2> {
        match self {
            SimdLevel::Avx2(l) => Some(l),
            SimdLevel::Avx512(l) => Some(l.narrow()),
            SimdLevel::Portable | SimdLevel::Sse2(_) => None,
        }
    }
}

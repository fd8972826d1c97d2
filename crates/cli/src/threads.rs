//! The worker threads: rayon's global pool, started before any work with the size
//! `RAYON_NUM_THREADS` asks for (docs/RELIABILITY.md), so that a size the system cannot give is
//! a one-line error instead of a panic at the first parallel draw.

/// The most worker threads `RAYON_NUM_THREADS` may ask for.
pub const MAX_THREADS: usize = 256;

/// Starts rayon's global pool: `RAYON_NUM_THREADS` threads when set to 1..=[`MAX_THREADS`]
/// (0 or unset: one a CPU, rayon's default).
pub fn start() -> Result<(), String> {
    let mut builder = rayon::ThreadPoolBuilder::new();
    if let Some(value) = std::env::var_os("RAYON_NUM_THREADS") {
        let text = value.to_string_lossy();
        let n: usize = text.trim().parse().map_err(|_| {
            format!("RAYON_NUM_THREADS={text:?} is not a number of threads (0 to {MAX_THREADS})")
        })?;
        if n > MAX_THREADS {
            return Err(format!(
                "RAYON_NUM_THREADS={n} is above the limit of {MAX_THREADS} worker threads"
            ));
        }
        builder = builder.num_threads(n);
    }
    builder
        .build_global()
        .map_err(|e| format!("cannot start the worker threads: {e}"))
}

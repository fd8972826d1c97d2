//! The scene crate's unit tests, by topic: the sections of a scene file with inline TOML, exact
//! error messages and a replay on the CPU backend (`sections`), the `[case]` table, hostile
//! input, lighting, limits, particles and raw vertex files. Files named by the scenes live in
//! `tests/data/` (paths relative to the crate root, where `cargo test` runs).

mod case;
mod hostile;
mod lighting;
mod limits;
mod particles;
mod sections;
mod vertex_file;

use std::path::Path;

use crate::{Scene, parse};

/// The scene file name the tests parse under: relative files are found in `tests/data/`.
pub(crate) const FILE: &str = "tests/data/test.toml";

/// Four lines: the required keys, a 64x32 target.
pub(crate) const HEAD: &str = "format = 1\n[target]\nwidth = 64\nheight = 32\n";

/// `HEAD` + `body`, parsed.
pub(crate) fn ok(body: &str) -> Scene {
    let src = format!("{HEAD}{body}");
    parse(&src, Path::new(FILE)).unwrap_or_else(|e| panic!("{e}"))
}

/// The one-line error of `HEAD` + `body`.
pub(crate) fn err(body: &str) -> String {
    let src = format!("{HEAD}{body}");
    match parse(&src, Path::new(FILE)) {
        Ok(_) => panic!("parsed:\n{src}"),
        Err(e) => e.to_string(),
    }
}

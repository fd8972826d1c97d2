//! Conformance cases: a scene file whose `[case]` table says what it checks (a title, the SPEC
//! rules) and what a D3D9 device must draw (`docs/spec/SCENE.md`, "Conformance cases").
//!
//! # Contract
//! - [`Case`] is metadata: replaying a scene ignores it, so a case draws what the same scene
//!   without `[case]` draws.
//! - [`Case::check`] compares a read-back target with the expectations: each [`Expect`] names a
//!   rectangle of pixels and the colour (any of a list, under a channel mask, within a
//!   per-channel tolerance) or depth every one of them must have; with [`Others::Clear`] every
//!   pixel no expectation names must hold the clear colour.
//! - [`list_cases`] finds the scene files of a folder tree, in a stable order.

use std::path::{Path, PathBuf};

use pointillist_core::RenderTarget;
use pointillist_core::tolerance::channel_difference;

use crate::error::{Origin, SceneError};

/// The `[case]` table of a scene.
#[derive(Clone, Debug, PartialEq)]
pub struct Case {
    /// What the case checks, in a sentence.
    pub title: String,
    /// The SPEC items it checks, each `"n"` or `"n.m"` (section n, item m of
    /// `docs/spec/SPEC.md`).
    pub rules: Vec<String>,
    /// Where the case comes from when it restates a public test (a file and function).
    pub source: Option<String>,
    /// What the pixels no expectation names must hold (by default [`Others::Clear`], or
    /// [`Others::Any`] when the case has an image, which states every pixel).
    pub others: Others,
    /// The expectations, in file order.
    pub expect: Vec<Expect>,
    /// The image the whole target must equal, every byte of its RGBA8 form (a golden image of
    /// the scene, not a D3D9 fact), resolved from the scene file's folder.
    pub image: Option<PathBuf>,
}

/// What the pixels that no [`Expect`] names must hold.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Others {
    /// The target's clear colour, exactly (the default).
    Clear,
    /// Anything: the expectations are probes.
    Any,
}

/// One `[[case.expect]]` table: every pixel of a rectangle must pass its tests.
#[derive(Clone, Debug, PartialEq)]
pub struct Expect {
    /// First column, first row, last column, last row, all inclusive (`pixel = [x, y]` is the
    /// rectangle `[x, y, x, y]`).
    pub rect: [u32; 4],
    /// The D3DCOLORs a pixel may have (one of them); empty when the colour is not checked.
    pub colors: Vec<u32>,
    /// The bits of a colour that are compared (default 0xFFFFFFFF).
    pub mask: u32,
    /// The largest difference allowed per 8-bit channel (default 0).
    pub tolerance: u8,
    /// The depth every pixel must hold, exactly.
    pub depth: Option<f32>,
    /// Where the table is in the scene file, for failure messages.
    pub origin: Origin,
}

/// True for `"n"` and `"n.m"`, n and m decimal numbers.
pub(crate) fn is_rule(s: &str) -> bool {
    let digits = |p: &str| !p.is_empty() && p.bytes().all(|b| b.is_ascii_digit());
    match s.split_once('.') {
        None => digits(s),
        Some((n, m)) => digits(n) && digits(m),
    }
}

impl Expect {
    /// True when the colour `c` passes.
    fn color_passes(&self, c: u32) -> bool {
        self.colors.is_empty()
            || self
                .colors
                .iter()
                .any(|&want| channel_difference(c & self.mask, want & self.mask) <= self.tolerance)
    }

    /// True when `(x, y)` lies in the rectangle.
    fn contains(&self, x: u32, y: u32) -> bool {
        let [x0, y0, x1, y1] = self.rect;
        (x0..=x1).contains(&x) && (y0..=y1).contains(&y)
    }

    /// What the pixels must hold, for messages.
    fn wanted(&self) -> String {
        let mut parts = Vec::new();
        if !self.colors.is_empty() {
            let list: Vec<String> = self.colors.iter().map(|c| format!("{c:#010X}")).collect();
            let mut s = format!("colour {}", list.join(" or "));
            if self.mask != u32::MAX {
                s += &format!(" under mask {:#010X}", self.mask);
            }
            if self.tolerance > 0 {
                s += &format!(" within {}", self.tolerance);
            }
            parts.push(s);
        }
        if let Some(d) = self.depth {
            parts.push(format!("depth {d:?}"));
        }
        parts.join(" and ").replace("0X", "0x")
    }
}

impl Case {
    /// Checks `target` against the expectations, with `clear` the target's clear colour. The
    /// error names, one line each, every expectation that fails (its file line, how many of its
    /// pixels fail and the first) and the pixels outside every expectation that are not `clear`.
    pub fn check(&self, target: &RenderTarget, clear: u32, file: &Path) -> Result<(), String> {
        let mut lines = Vec::new();
        for e in &self.expect {
            let [x0, y0, x1, y1] = e.rect;
            if x1 >= target.width || y1 >= target.height {
                lines.push(format!(
                    "{}:{}: {}: the rectangle leaves the {}x{} target",
                    file.display(),
                    e.origin.line,
                    e.origin.key,
                    target.width,
                    target.height
                ));
                continue;
            }
            let mut failing = 0usize;
            let mut first = None;
            for y in y0..=y1 {
                for x in x0..=x1 {
                    let k = (y * target.width + x) as usize;
                    let (c, z) = (target.color[k], target.depth[k]);
                    let depth_ok = e.depth.is_none_or(|d| d == z);
                    if !(e.color_passes(c) && depth_ok) {
                        failing += 1;
                        first.get_or_insert((x, y, c, z));
                    }
                }
            }
            if let Some((x, y, c, z)) = first {
                let total = u64::from(x1 - x0 + 1) * u64::from(y1 - y0 + 1);
                lines.push(format!(
                    "{}:{}: {}: {failing} of {total} pixel(s) fail; ({x}, {y}) holds colour \
                     {c:#010X} depth {z:?}, expected {}",
                    file.display(),
                    e.origin.line,
                    e.origin.key,
                    e.wanted()
                ));
            }
        }
        if self.others == Others::Clear {
            let mut stray = 0usize;
            let mut first = None;
            let mut bbox = [u32::MAX, u32::MAX, 0, 0];
            for y in 0..target.height {
                for x in 0..target.width {
                    let c = target.pixel(x, y);
                    if c != clear && !self.expect.iter().any(|e| e.contains(x, y)) {
                        stray += 1;
                        first.get_or_insert((x, y, c));
                        bbox = [
                            bbox[0].min(x),
                            bbox[1].min(y),
                            bbox[2].max(x),
                            bbox[3].max(y),
                        ];
                    }
                }
            }
            if let Some((x, y, c)) = first {
                lines.push(format!(
                    "{}: {stray} pixel(s) outside every expectation are not the clear colour \
                     {clear:#010X}, within {}..={} x {}..={}; first ({x}, {y}) holds {c:#010X}",
                    file.display(),
                    bbox[0],
                    bbox[2],
                    bbox[1],
                    bbox[3]
                ));
            }
        }
        if lines.is_empty() {
            Ok(())
        } else {
            Err(lines.join("\n").replace("0X", "0x"))
        }
    }
}

/// Every scene file (`*.toml`) under `dir` and its subfolders (following links), sorted by
/// path: the cases of a suite folder.
pub fn list_cases(dir: &Path) -> Result<Vec<PathBuf>, SceneError> {
    let mut out = Vec::new();
    let mut pending = vec![dir.to_path_buf()];
    while let Some(d) = pending.pop() {
        let entries = std::fs::read_dir(&d)
            .map_err(|e| SceneError::unplaced(&d, format!("cannot read the folder: {e}")))?;
        for entry in entries {
            let path = entry
                .map_err(|e| SceneError::unplaced(&d, format!("cannot read the folder: {e}")))?
                .path();
            if path.is_dir() {
                pending.push(path);
            } else if path.extension().is_some_and(|x| x == "toml") {
                out.push(path);
            }
        }
    }
    out.sort();
    Ok(out)
}

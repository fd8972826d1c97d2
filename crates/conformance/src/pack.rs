//! The capture pack (`pointillist capture-pack`): one folder to copy to a Windows PC, where a
//! double-click on `run.bat` replays the cases on the PC's Direct3D 9 and keeps what it drew in
//! a folder named after the adapter, its driver version and the Windows version, ready to send
//! back and compare with `conform --captures` (docs/CONFORMANCE.md, "Check a Windows machine's
//! hardware").
//!
//! The pack holds:
//! - `streams/`: `NAME.calls` per case and `list.txt`, as `export-calls` writes a folder;
//! - `replayer.exe`, built with [`runner::MINGW_CC`] (unless asked not
//!   to);
//! - `source/`: `replayer.c` and `BUILD.txt`, its one-line MSVC and MinGW builds;
//! - `run.bat`: plain `cmd.exe` (nothing Wine's `cmd` lacks), which runs the replayer from
//!   `streams\` into `captures\running` and then renames that folder;
//! - `README.txt`: for whoever runs it, not a developer.
//!
//! The pack is made in a temporary folder beside `out` and renamed to `out` only when whole, so a
//! failure leaves no folder that looks like a pack. `out` must not exist or be an empty folder:
//! nothing the user has is ever replaced or removed.

use std::fs;
use std::path::{Path, PathBuf};

use crate::{export, find_cases, runner};

/// `run.bat`, with LF line ends (written with CRLF).
const RUN_BAT: &str = include_str!("../pack/run.bat");
/// `README.txt`'s template: `{CASES}`, `{VERSION}`, `{PATHS}` and `{BUILT}` are filled in.
const README: &str = include_str!("../pack/README.txt");
/// `source/BUILD.txt`.
const BUILD: &str = include_str!("../pack/BUILD.txt");

/// What [`write_pack`] wrote.
#[derive(Clone, Debug)]
pub struct Pack {
    /// The cases whose streams are in the pack.
    pub cases: usize,
    /// Whether `replayer.exe` was built into it.
    pub built: bool,
}

/// Text for Windows tools: CRLF line ends (cmd.exe misreads labels in a batch file with LF
/// line ends; old Notepad shows one line).
fn crlf(text: &str) -> String {
    text.replace("\r\n", "\n").replace('\n', "\r\n")
}

/// `paths` as a command line shows them: a path with a space or a quote in quotes.
fn shown_paths(paths: &[PathBuf]) -> String {
    paths
        .iter()
        .map(|p| {
            let s = p.display().to_string();
            if s.is_empty() || s.contains([' ', '"', '\'']) {
                format!("\"{}\"", s.replace('"', "\\\""))
            } else {
                s
            }
        })
        .collect::<Vec<_>>()
        .join(" ")
}

/// Refuses an `out` that exists and is not an empty folder (a file, a link, a folder holding
/// anything): the pack never replaces what the user has.
fn check_out(out: &Path) -> Result<(), String> {
    let meta = match fs::symlink_metadata(out) {
        Err(e) if e.kind() == std::io::ErrorKind::NotFound => return Ok(()),
        Err(e) => return Err(format!("{}: {e}", out.display())),
        Ok(m) => m,
    };
    let empty_dir = meta.is_dir()
        && fs::read_dir(out)
            .map_err(|e| format!("{}: {e}", out.display()))?
            .next()
            .is_none();
    if empty_dir {
        Ok(())
    } else {
        Err(format!(
            "{} already exists and is not an empty folder; give a new folder for the pack \
             (nothing is written over)",
            out.display()
        ))
    }
}

/// Writes the capture pack of the cases of `paths` (scene files and folders of them, named as
/// `conform` names them) into the folder `out`, with `replayer.exe` built when `build`.
/// Errors are one line.
pub fn write_pack(paths: &[PathBuf], out: &Path, build: bool) -> Result<Pack, String> {
    let cases = find_cases(paths)?;
    check_out(out)?;
    let name = out
        .file_name()
        .ok_or_else(|| format!("{}: not a folder name for the pack", out.display()))?;
    let parent = match out.parent() {
        Some(p) if !p.as_os_str().is_empty() => p,
        _ => Path::new("."),
    };
    fs::create_dir_all(parent).map_err(|e| format!("cannot create {}: {e}", parent.display()))?;
    let mut temp_name = std::ffi::OsString::from(".");
    temp_name.push(name);
    temp_name.push(format!(".partial-{}", std::process::id()));
    let temp = parent.join(temp_name);
    // A fresh folder of this process's own, so that removing it on failure removes nothing else.
    fs::create_dir(&temp).map_err(|e| format!("cannot create {}: {e}", temp.display()))?;
    let result = fill(&temp, paths, &cases, build).and_then(|pack| {
        put_in_place(&temp, out)?;
        Ok(pack)
    });
    if result.is_err() {
        let _ = fs::remove_dir_all(&temp);
    }
    result
}

/// Renames the whole pack `temp` to `out`, which is missing or an empty folder.
fn put_in_place(temp: &Path, out: &Path) -> Result<(), String> {
    // rename(2) replaces an empty folder and fails on one that is not; elsewhere the empty
    // folder is removed first (remove_dir removes only an empty one).
    if cfg!(not(unix)) && out.is_dir() {
        fs::remove_dir(out).map_err(|e| format!("cannot replace {}: {e}", out.display()))?;
    }
    fs::rename(temp, out).map_err(|e| format!("cannot create {}: {e}", out.display()))
}

/// Writes a file of the pack.
fn write(path: &Path, text: &str) -> Result<(), String> {
    fs::write(path, text).map_err(|e| format!("cannot write {}: {e}", path.display()))
}

/// Writes the pack's files into the fresh folder `dir`.
fn fill(dir: &Path, paths: &[PathBuf], cases: &[crate::Case], build: bool) -> Result<Pack, String> {
    export::export_cases(cases, None, &dir.join("streams"))?;
    let source = dir.join("source");
    fs::create_dir(&source).map_err(|e| format!("cannot create {}: {e}", source.display()))?;
    if build {
        // build_replayer writes replayer.c beside the program it builds.
        let exe = source.join("replayer.exe");
        runner::build_replayer(&exe).map_err(|e| {
            format!("{e}; or give --no-build and build replayer.exe on Windows (source/BUILD.txt)")
        })?;
        fs::rename(&exe, dir.join("replayer.exe"))
            .map_err(|e| format!("cannot move {}: {e}", exe.display()))?;
    } else {
        write(&source.join("replayer.c"), runner::REPLAYER_SOURCE)?;
    }
    write(&source.join("BUILD.txt"), &crlf(BUILD))?;
    write(&dir.join("run.bat"), &crlf(RUN_BAT))?;
    let built = if build {
        "source\\replayer.c built by capture-pack with MinGW-w64."
    } else {
        "NOT IN THIS PACK (made with --no-build): build it as source\\BUILD.txt says and\n  \
         put it beside run.bat before sending the pack."
    };
    let readme = README
        .replace("{CASES}", &cases.len().to_string())
        .replace("{VERSION}", env!("CARGO_PKG_VERSION"))
        .replace("{PATHS}", &shown_paths(paths))
        .replace("{BUILT}", built);
    write(&dir.join("README.txt"), &crlf(&readme))?;
    Ok(Pack {
        cases: cases.len(),
        built: build,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn pack_text_has_crlf_line_ends_only() {
        let text = crlf("a\nb\r\nc\n");
        assert_eq!(text, "a\r\nb\r\nc\r\n");
        for t in [RUN_BAT, README, BUILD] {
            assert!(!crlf(t).replace("\r\n", "").contains('\n'));
        }
    }

    #[test]
    fn paths_with_spaces_are_quoted_in_the_readme() {
        let paths = [PathBuf::from("cases"), PathBuf::from("my scenes/a.toml")];
        assert_eq!(shown_paths(&paths), "cases \"my scenes/a.toml\"");
    }

    #[test]
    fn run_bat_uses_nothing_wine_cmd_lacks() {
        // Wine's cmd reads !VAR! but not !VAR:~N,M! or !VAR:A=B!: the script stays in plain
        // percent expansion.
        assert!(RUN_BAT.contains("DisableDelayedExpansion"));
        assert!(!RUN_BAT.contains("EnableDelayedExpansion"));
        assert!(!RUN_BAT.to_ascii_lowercase().contains("powershell"));
    }
}

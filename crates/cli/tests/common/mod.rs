//! Helpers shared by the CLI's integration tests: a scratch folder and the `pointillist` binary.

#![allow(dead_code)] // each test binary uses its own subset

use std::fs;
use std::path::{Path, PathBuf};
use std::process::{Command, Output};

/// A fresh scratch folder (tempfile's), removed when dropped.
pub struct TempDir(tempfile::TempDir);

impl TempDir {
    /// A fresh folder whose name starts with the test binary's name and `name`.
    pub fn new(name: &str) -> TempDir {
        let prefix = format!("pointillist-{}-{name}-", env!("CARGO_CRATE_NAME"));
        TempDir(tempfile::Builder::new().prefix(&prefix).tempdir().unwrap())
    }

    /// Writes `contents` to the file `name` in the folder and returns its path.
    pub fn write(&self, name: &str, contents: &str) -> PathBuf {
        let path = self.path(name);
        fs::write(&path, contents).unwrap();
        path
    }

    /// The folder itself.
    pub fn dir(&self) -> &Path {
        self.0.path()
    }

    /// The path of `name` in the folder.
    pub fn path(&self, name: &str) -> PathBuf {
        self.0.path().join(name)
    }

    /// Names of the files in the folder, sorted.
    pub fn listing(&self) -> Vec<String> {
        let mut names: Vec<String> = fs::read_dir(self.dir())
            .unwrap()
            .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
            .collect();
        names.sort();
        names
    }
}

/// The repository's root folder: two levels above this crate.
pub fn repo_root() -> PathBuf {
    Path::new(env!("CARGO_MANIFEST_DIR")).join("../..")
}

/// The `pointillist` binary of this build.
pub fn command() -> Command {
    Command::new(env!("CARGO_BIN_EXE_pointillist"))
}

/// Runs `pointillist args...` to completion.
pub fn pointillist(args: &[&str]) -> Output {
    command()
        .args(args)
        .output()
        .expect("the pointillist binary runs")
}

/// A path as a command-line argument.
pub fn path_arg(p: &Path) -> &str {
    p.to_str().expect("temp paths are UTF-8")
}

/// Standard output as text.
pub fn stdout(out: &Output) -> String {
    String::from_utf8(out.stdout.clone()).expect("stdout is UTF-8")
}

/// Standard error as text.
pub fn stderr(out: &Output) -> String {
    String::from_utf8(out.stderr.clone()).expect("stderr is UTF-8")
}

/// The one error line of a `conform` run that could not happen (exit status 2).
pub fn kit_error(o: &Output) -> String {
    let err = stderr(o);
    assert_eq!(o.status.code(), Some(2), "{err}");
    assert_eq!(err.lines().count(), 1, "one line: {err}");
    assert!(err.starts_with("error: "), "{err}");
    err
}

//! [`SceneError`]: one error, located by file, line, column and key path.

use std::fmt;
use std::path::{Path, PathBuf};

/// `text` with every control character (a line break, a carriage return, an escape sequence's
/// ESC) written as its Rust escape (`\n`, `\r`, `\u{1b}`): what a message quotes from a scene
/// or a path can then neither break the line nor rewrite a terminal.
pub fn printable(text: &str) -> std::borrow::Cow<'_, str> {
    if !text.chars().any(char::is_control) {
        return text.into();
    }
    let mut out = String::with_capacity(text.len() + 8);
    for c in text.chars() {
        if c.is_control() {
            out.extend(c.escape_debug());
        } else {
            out.push(c);
        }
    }
    out.into()
}

/// Why a scene could not be read or replayed: where (file, line, column, key path) and what.
///
/// Displays on one line as `FILE:LINE:COLUMN: KEY: MESSAGE`, for instance
/// `scenes/ring.toml:12:5: draw[2].states.POINTSIZE: expected a number, found a string`, with
/// control characters escaped ([`printable`]).
/// The position is left out when there is none (`line == 0`: the scene file itself could not be
/// read), and the key path when the error is not about one key (a TOML syntax error).
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct SceneError {
    /// The scene file, as given to [`crate::load`] or [`crate::parse`].
    pub file: PathBuf,
    /// One-based line of the offending text; 0 when the error has no position.
    pub line: usize,
    /// One-based column (in characters) of the offending text; 0 when the error has no position.
    pub column: usize,
    /// Key path of the offending value, like `draw[2].states.POINTSIZE` (draws counted from 0);
    /// empty when the error concerns no key.
    pub key: String,
    /// What is wrong, without position or key.
    pub message: String,
}

impl SceneError {
    /// An error with no position in the file (the file could not be read).
    pub(crate) fn unplaced(file: &Path, message: String) -> SceneError {
        SceneError {
            file: file.to_path_buf(),
            line: 0,
            column: 0,
            key: String::new(),
            message,
        }
    }
}

impl SceneError {
    /// The same error about `key`.
    pub(crate) fn with_key(mut self, key: &str) -> SceneError {
        self.key = key.to_owned();
        self
    }
}

impl fmt::Display for SceneError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "{}:", printable(&self.file.display().to_string()))?;
        if self.line > 0 {
            write!(f, "{}:{}:", self.line, self.column)?;
        }
        if !self.key.is_empty() {
            write!(f, " {}:", printable(&self.key))?;
        }
        write!(f, " {}", printable(&self.message))
    }
}

impl std::error::Error for SceneError {}

/// Where a command came from in the scene file, so that errors met while replaying it (a device
/// refusing a value) can name the file position and key like parse errors do.
#[derive(Clone, Debug, PartialEq, Eq, Default)]
pub struct Origin {
    /// One-based line.
    pub line: usize,
    /// One-based column, in characters.
    pub column: usize,
    /// Key path, like `draw[2].states.POINTSIZE`.
    pub key: String,
}

impl Origin {
    /// The error `message` at this origin of `file`.
    pub fn error(&self, file: &Path, message: impl Into<String>) -> SceneError {
        SceneError {
            file: file.to_path_buf(),
            line: self.line,
            column: self.column,
            key: self.key.clone(),
            message: message.into(),
        }
    }
}

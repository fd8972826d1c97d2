//! What the command line says on its standard streams: one line each, with control characters
//! (carriage returns, escape sequences, ...) that a scene, a path or a library put in a
//! message written as escapes, so that no input can rewrite the terminal
//! (docs/RELIABILITY.md).

use std::fmt;
use std::io::{self, Write};

/// Prints a line on standard output with [`out`], as `println!` does, without its panic.
macro_rules! outln {
    ($($arg:tt)*) => { $crate::report::out(format_args!($($arg)*)) };
}

/// Prints a line on standard error with [`err`], as `eprintln!` does, without its panic.
macro_rules! errln {
    ($($arg:tt)*) => { $crate::report::err(format_args!($($arg)*)) };
}

pub(crate) use {errln, outln};

/// Writes `line` and a line feed on standard output. When it cannot be written the process
/// ends as [`crate::interrupt::end`] says: a closed pipe (`pointillist bench | head -3`) ends
/// it quietly with status 141, as SIGPIPE ends other tools; any other failure says so on
/// standard error and ends it with status 1.
pub fn out(line: fmt::Arguments) {
    if let Err(e) = write_line(&mut io::stdout().lock(), line) {
        if e.kind() != io::ErrorKind::BrokenPipe {
            let _ = write_line(
                &mut io::stderr().lock(),
                format_args!("error: cannot write to standard output: {e}"),
            );
        }
        crate::interrupt::end(exit_status(&e));
    }
}

/// Writes `line` and a line feed on standard error; when it cannot be written the process
/// ends as for [`out`], silently.
pub fn err(line: fmt::Arguments) {
    if let Err(e) = write_line(&mut io::stderr().lock(), line) {
        crate::interrupt::end(exit_status(&e));
    }
}

fn write_line(w: &mut impl Write, line: fmt::Arguments) -> io::Result<()> {
    w.write_fmt(line)?;
    w.write_all(b"\n")?;
    w.flush()
}

/// 141 (128 + SIGPIPE) for a closed pipe, as shells report a tool that SIGPIPE ended; 1 else.
fn exit_status(e: &io::Error) -> i32 {
    if e.kind() == io::ErrorKind::BrokenPipe {
        141
    } else {
        1
    }
}

/// `text` with every control character written as its Rust escape (`\r`, `\u{1b}`): the
/// scene crate's rule ([`pointillist_scene::printable`]).
pub fn printable(text: &str) -> String {
    pointillist_scene::printable(text).into_owned()
}

/// Prints `warning: TEXT` on standard error.
pub fn warning(text: &str) {
    errln!("warning: {}", printable(text));
}

/// Prints `error: TEXT` on standard error, a message of several lines joined with "; ".
pub fn error(text: &str) {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    errln!("error: {}", printable(&lines.join("; ")));
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn control_characters_are_escaped_and_the_rest_kept() {
        assert_eq!(
            printable("a\r\u{1b}[2Jb\tc\u{7f}é ✓"),
            "a\\r\\u{1b}[2Jb\\tc\\u{7f}é ✓"
        );
    }
}

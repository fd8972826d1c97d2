//! What the command line says on its standard streams: one line each, with control characters
//! (carriage returns, escape sequences, ...) that a scene, a path or a library put in a
//! message written as escapes, so that no input can rewrite the terminal
//! (docs/RELIABILITY.md).

/// `text` with every control character written as its Rust escape (`\r`, `\u{1b}`): the
/// scene crate's rule ([`pointillist_scene::printable`]).
pub fn printable(text: &str) -> String {
    pointillist_scene::printable(text).into_owned()
}

/// Prints `warning: TEXT` on standard error.
pub fn warning(text: &str) {
    eprintln!("warning: {}", printable(text));
}

/// Prints `error: TEXT` on standard error, a message of several lines joined with "; ".
pub fn error(text: &str) {
    let lines: Vec<&str> = text
        .lines()
        .map(str::trim)
        .filter(|l| !l.is_empty())
        .collect();
    eprintln!("error: {}", printable(&lines.join("; ")));
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

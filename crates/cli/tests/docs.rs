//! The repository carries every document it cites: each relative link of every Markdown file
//! resolves to a file or folder inside the repository, each `docs/...` path named in the code
//! exists, and each "SPEC n.m" citation names a section and item of docs/spec/SPEC.md.

mod common;

use std::fs;
use std::path::{Component, Path, PathBuf};

use common::repo_root;

/// Files of the repository with one of `extensions`, skipping build output, git's folder and the
/// fuzzers' corpora (binary inputs).
fn files(root: &Path, extensions: &[&str]) -> Vec<PathBuf> {
    let mut found = Vec::new();
    let mut stack = vec![root.to_path_buf()];
    while let Some(dir) = stack.pop() {
        for entry in fs::read_dir(&dir).unwrap() {
            let path = entry.unwrap().path();
            let name = path.file_name().unwrap().to_string_lossy().into_owned();
            if path.is_dir() {
                if !matches!(name.as_str(), "target" | ".git" | "corpus" | "artifacts") {
                    stack.push(path);
                }
            } else if extensions.iter().any(|e| name.ends_with(e)) {
                found.push(path);
            }
        }
    }
    found.sort();
    found
}

/// The targets of the inline links `[text](target)` of a Markdown text, outside code blocks.
fn link_targets(text: &str) -> Vec<String> {
    let mut targets = Vec::new();
    let mut in_code = false;
    for line in text.lines() {
        if line.trim_start().starts_with("```") {
            in_code = !in_code;
            continue;
        }
        if in_code {
            continue;
        }
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let end = after.find(')').unwrap_or(after.len());
            targets.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    targets
}

/// `path` with `.` and `..` folded away, without touching the file system.
fn normalize(path: &Path) -> PathBuf {
    let mut out = PathBuf::new();
    for part in path.components() {
        match part {
            Component::ParentDir => {
                if !out.pop() {
                    out.push("..");
                }
            }
            Component::CurDir => {}
            other => out.push(other),
        }
    }
    out
}

#[test]
fn every_relative_markdown_link_resolves_inside_the_repository() {
    let root = repo_root().canonicalize().unwrap();
    let mut broken = Vec::new();
    let mut checked = 0;
    for file in files(&root, &[".md"]) {
        let text = fs::read_to_string(&file).unwrap();
        for target in link_targets(&text) {
            let target = target.split_whitespace().next().unwrap_or("");
            let path = target.split('#').next().unwrap();
            if path.is_empty() || path.contains("://") || path.starts_with("mailto:") {
                continue;
            }
            checked += 1;
            let resolved = normalize(&file.parent().unwrap().join(path));
            if !resolved.starts_with(&root) || !resolved.exists() {
                broken.push(format!(
                    "{}: {target}",
                    file.strip_prefix(&root).unwrap().display()
                ));
            }
        }
    }
    assert!(
        checked > 20,
        "only {checked} links found: is the scan broken?"
    );
    assert!(
        broken.is_empty(),
        "links that leave the repository or name nothing:\n{}",
        broken.join("\n")
    );
}

#[test]
fn every_document_the_code_names_exists() {
    let root = repo_root().canonicalize().unwrap();
    let mut missing = Vec::new();
    let mut checked = 0;
    for file in files(&root, &[".rs", ".toml", ".wgsl", ".md"]) {
        let text = fs::read_to_string(&file).unwrap();
        for (at, _) in text.match_indices("docs/") {
            let name: String = text[at..]
                .chars()
                .take_while(|c| c.is_ascii_alphanumeric() || matches!(c, '/' | '_' | '-' | '.'))
                .collect();
            let Some(name) = name.strip_suffix('.').or(Some(&name)) else {
                continue;
            };
            if !name.ends_with(".md") {
                continue;
            }
            // A path is named from the repository root (`docs/spec/SPEC.md`), or from a crate's
            // folder or the file's own folder in relative links.
            checked += 1;
            let candidates = [root.join(name), file.parent().unwrap().join(name)];
            if !candidates.iter().any(|p| p.exists()) {
                missing.push(format!(
                    "{}: {name}",
                    file.strip_prefix(&root).unwrap().display()
                ));
            }
        }
    }
    assert!(
        checked > 10,
        "only {checked} document names found: is the scan broken?"
    );
    assert!(
        missing.is_empty(),
        "documents named but not in the repository:\n{}",
        missing.join("\n")
    );
}

/// The sections (`## n. Title`) of SPEC.md, each with the item numbers (`m. ...` at the start of
/// a line) it holds.
fn spec_sections(spec: &str) -> Vec<(u32, Vec<u32>)> {
    let mut sections: Vec<(u32, Vec<u32>)> = Vec::new();
    for line in spec.lines() {
        if let Some(title) = line.strip_prefix("## ")
            && let Some((n, _)) = title.split_once('.')
            && let Ok(n) = n.parse()
        {
            sections.push((n, Vec::new()));
        } else if let (Some(last), Some((m, _))) = (sections.last_mut(), line.split_once(". "))
            && let Ok(m) = m.parse()
        {
            last.1.push(m);
        }
    }
    sections
}

#[test]
fn every_spec_citation_names_a_rule_of_the_spec() {
    let root = repo_root().canonicalize().unwrap();
    let sections = spec_sections(&fs::read_to_string(root.join("docs/spec/SPEC.md")).unwrap());
    assert!(sections.len() >= 7, "{sections:?}");
    let mut dangling = Vec::new();
    let mut checked = 0;
    for file in files(&root, &[".rs", ".toml", ".wgsl", ".md"]) {
        let text = fs::read_to_string(&file).unwrap();
        for (at, _) in text.match_indices("SPEC ") {
            let cited: String = text[at + 5..]
                .chars()
                .take_while(|c| c.is_ascii_digit() || *c == '.')
                .collect();
            let cited = cited.trim_end_matches('.');
            if cited.is_empty() {
                continue;
            }
            checked += 1;
            let mut parts = cited.split('.').map(|p| p.parse::<u32>().ok());
            let section = parts.next().flatten();
            let item = parts.next().flatten();
            let found = sections.iter().find(|(n, _)| Some(*n) == section);
            let ok = match (found, item) {
                (Some(_), None) => true,
                (Some((_, items)), Some(m)) => items.contains(&m),
                (None, _) => false,
            };
            if !ok {
                dangling.push(format!(
                    "{}: SPEC {cited}",
                    file.strip_prefix(&root).unwrap().display()
                ));
            }
        }
    }
    assert!(
        checked > 200,
        "only {checked} citations found: is the scan broken?"
    );
    assert!(
        dangling.is_empty(),
        "citations of rules SPEC.md does not have:\n{}",
        dangling.join("\n")
    );
}

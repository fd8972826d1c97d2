//! The suite as a whole: its folders, and the SPEC items its cases cite.

use std::collections::BTreeSet;
use std::path::PathBuf;

use crate::run::cases_dir;

/// The folders of `cases/`, each with its list of cases in a chapter module.
const FOLDERS: [&str; 7] = [
    "2-size",
    "3-clipping",
    "4-rasterization",
    "5-pixels",
    "6-caps",
    "golden",
    "wine",
];

#[test]
fn the_suite_has_exactly_the_known_folders() {
    let mut found: Vec<String> = std::fs::read_dir(cases_dir())
        .expect("cases/")
        .map(|e| e.expect("entry").path())
        .filter(|p| p.is_dir())
        .map(|p| p.file_name().expect("name").to_string_lossy().into_owned())
        .collect();
    found.sort();
    assert_eq!(
        found, FOLDERS,
        "add a new folder to FOLDERS and give it a cases! list"
    );
}

/// The items of docs/spec/SPEC.md: "n" for each section `## n.` and "n.m" for each numbered
/// item `m.` in it.
fn spec_items() -> BTreeSet<String> {
    let spec = PathBuf::from(env!("CARGO_MANIFEST_DIR")).join("../../docs/spec/SPEC.md");
    let text = std::fs::read_to_string(&spec).expect("SPEC.md");
    let mut items = BTreeSet::new();
    let mut section = None;
    for line in text.lines() {
        if let Some(rest) = line.strip_prefix("## ") {
            section = rest.split_once('.').map(|(n, _)| n.to_owned());
            items.extend(section.clone());
        } else if let (Some(s), Some((m, _))) = (&section, line.split_once(". "))
            && !m.is_empty()
            && m.bytes().all(|b| b.is_ascii_digit())
        {
            items.insert(format!("{s}.{m}"));
        }
    }
    items
}

#[test]
fn every_case_cites_spec_items_that_exist() {
    let items = spec_items();
    assert!(items.contains("2.3") && items.contains("7"), "{items:?}");
    let files = pointillist_scene::list_cases(&cases_dir()).expect("cases/");
    assert!(files.len() > 20, "only {} case files found", files.len());
    for file in files {
        let scene = pointillist_scene::load(&file).unwrap_or_else(|e| panic!("{e}"));
        let case = scene
            .case
            .unwrap_or_else(|| panic!("{}: no [case] table", file.display()));
        for rule in &case.rules {
            assert!(
                items.contains(rule),
                "{}: rule {rule} is not an item of docs/spec/SPEC.md",
                file.display()
            );
        }
    }
}

/// Every numbered item of a chapter with a case folder (`N-name/`) is checked by at least one
/// case of that folder, so the suite covers each rule of the chapter it is named for.
#[test]
fn every_item_of_a_chapter_has_a_case() {
    let items = spec_items();
    for folder in FOLDERS {
        let Some((chapter, _)) = folder.split_once('-') else {
            continue;
        };
        let files = pointillist_scene::list_cases(&cases_dir().join(folder)).expect(folder);
        let mut cited = BTreeSet::new();
        for file in files {
            let scene = pointillist_scene::load(&file).unwrap_or_else(|e| panic!("{e}"));
            cited.extend(scene.case.map(|c| c.rules).unwrap_or_default());
        }
        let prefix = format!("{chapter}.");
        let missing: Vec<&String> = items
            .iter()
            .filter(|i| i.starts_with(&prefix) && !cited.contains(*i))
            .collect();
        assert!(
            missing.is_empty(),
            "cases/{folder}: no case cites SPEC {missing:?}"
        );
    }
}

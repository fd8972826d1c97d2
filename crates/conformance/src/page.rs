//! One page for several devices (`pointillist conform-page`, docs/CONFORMANCE.md "Several
//! devices on one page"): the reports of several `conform` runs (Wine, DXVK, a Windows PC's
//! captures through `--captures`) read back from their `report.json` and shown side by side. A
//! row per case with the SPEC rules it covers and each rule's evidence grade, pointillist's
//! image, a cell per device (its status; the device's image and the magnified difference on
//! demand), and per behaviour switch the option each device showed beside pointillist's default.

use std::collections::{BTreeMap, BTreeSet};
use std::fmt::Write as _;
use std::fs;
use std::path::{Path, PathBuf};

use pointillist_core::behaviour::BEHAVIOURS;
use pointillist_image::output::Destination;
use serde::Deserialize;

use crate::report::{STYLE, esc, rule_key, spec_evidence};

#[derive(Deserialize)]
struct JsonReport {
    #[serde(default)]
    implementation: Option<String>,
    device: JsonDevice,
    behaviours: BTreeMap<String, Option<String>>,
    cases: Vec<JsonCase>,
}

#[derive(Deserialize)]
struct JsonDevice {
    description: String,
    #[serde(default)]
    d3d9_dll: Option<String>,
    #[serde(default)]
    vulkan_device: Option<String>,
}

#[derive(Deserialize)]
struct JsonCase {
    name: String,
    #[serde(default)]
    title: Option<String>,
    rules: Vec<String>,
    status: String,
    pixels_differing: u64,
    message: String,
    #[serde(default)]
    images: Option<JsonImages>,
    #[serde(default)]
    unexpected: Option<String>,
    #[serde(default)]
    explanation: Option<JsonExplanation>,
}

#[derive(Deserialize)]
struct JsonExplanation {
    d3d9: String,
    implementation: String,
}

#[derive(Deserialize)]
struct JsonImages {
    pointillist: String,
    device: String,
    diff: String,
}

/// One device's column: a `conform` report folder read back.
pub struct Column {
    label: String,
    folder: PathBuf,
    report: JsonReport,
}

impl Column {
    /// Reads `folder/report.json` (written by `pointillist conform`); `label` heads the column
    /// (default: the expectations' implementation line, else the adapter's description).
    pub fn load(folder: &Path, label: Option<String>) -> Result<Column, String> {
        let path = folder.join("report.json");
        let text = fs::read_to_string(&path).map_err(|e| {
            format!(
                "{}: cannot read a conform report: {e} (give the folder `conform --report` wrote)",
                path.display()
            )
        })?;
        let report: JsonReport = serde_json::from_str(&text).map_err(|e| {
            format!(
                "{}:{}:{}: not a conform report: {e}",
                path.display(),
                e.line(),
                e.column()
            )
        })?;
        let label = label
            .or_else(|| report.implementation.clone())
            .unwrap_or_else(|| report.device.description.clone());
        Ok(Column {
            label,
            folder: folder.to_path_buf(),
            report,
        })
    }
}

/// What the page counted: cases, those every device matched (`match` or `option`), those the
/// devices split on, and those every device differs on or failed.
#[derive(Debug, Default, PartialEq, Eq)]
pub struct PageSummary {
    /// Cases on the page (every case of every report).
    pub cases: usize,
    /// Cases every device that ran them matched (`match` or `option`).
    pub all_match: usize,
    /// Cases some devices matched and others did not.
    pub split: usize,
    /// Cases no device matched.
    pub none_match: usize,
}

fn matched(status: &str) -> bool {
    status == "match" || status == "option"
}

/// Writes `out/index.html` and the images it shows (copied under `out/img/`, so the page
/// travels as one folder) from `columns`. `out` must not be one of the report folders.
pub fn write(columns: &[Column], out: &Path) -> Result<PageSummary, String> {
    if columns.is_empty() {
        return Err("give at least one report folder".into());
    }
    let inputs: Vec<PathBuf> = columns
        .iter()
        .map(|c| c.folder.join("report.json"))
        .collect();
    for c in columns {
        if same_folder(&c.folder, out) {
            return Err(format!(
                "{}: the page's folder is a report folder; give another --out",
                out.display()
            ));
        }
    }
    // Every case in the order the first report that has it lists it.
    let mut names: Vec<&str> = Vec::new();
    let mut seen = BTreeSet::new();
    for c in columns {
        for case in &c.report.cases {
            if seen.insert(case.name.as_str()) {
                names.push(&case.name);
            }
        }
    }
    let lookup: Vec<BTreeMap<&str, &JsonCase>> = columns
        .iter()
        .map(|c| {
            c.report
                .cases
                .iter()
                .map(|k| (k.name.as_str(), k))
                .collect()
        })
        .collect();
    let copy = |from: &Path, to: &str| -> Result<String, String> {
        let bytes = fs::read(from).map_err(|e| format!("{}: {e}", from.display()))?;
        let path = out.join(to);
        if let Some(folder) = path.parent() {
            fs::create_dir_all(folder).map_err(|e| format!("{}: {e}", folder.display()))?;
        }
        Destination::check(&path, &inputs)
            .and_then(|d| d.write_bytes(&bytes))
            .map_err(|e| e.to_string())?;
        Ok(to.to_string())
    };
    let evidence = spec_evidence();
    let mut summary = PageSummary {
        cases: names.len(),
        ..PageSummary::default()
    };
    let mut rows = String::new();
    for name in &names {
        let cells: Vec<Option<&JsonCase>> = lookup.iter().map(|l| l.get(name).copied()).collect();
        let present: Vec<&JsonCase> = cells.iter().flatten().copied().collect();
        let all = present.iter().all(|c| matched(&c.status));
        let none = present.iter().all(|c| !matched(&c.status));
        let class = if all {
            summary.all_match += 1;
            "agree"
        } else if none {
            summary.none_match += 1;
            "none"
        } else {
            summary.split += 1;
            "split"
        };
        let first = present[0];
        let rules: Vec<String> = first
            .rules
            .iter()
            .map(|r| {
                let grade = rule_key(r)
                    .and_then(|k| evidence.get(&k))
                    .map_or(String::new(), |g| format!(" <i>{}</i>", esc(g)));
                format!("SPEC {}{grade}", esc(r))
            })
            .collect();
        let _ = write!(
            rows,
            "<tr class=\"{class}\"><td><b>{}</b>{}</td><td class=\"rules\">{}</td><td>",
            esc(name),
            first.title.as_deref().map_or(String::new(), |t| format!(
                "<br><span class=\"rules\">{}</span>",
                esc(t)
            )),
            rules.join("<br>")
        );
        // pointillist's own image, from the first report that drew the case.
        if let Some((i, images)) = cells
            .iter()
            .enumerate()
            .find_map(|(i, c)| c.and_then(|c| c.images.as_ref()).map(|im| (i, im)))
        {
            let file = copy(
                &columns[i].folder.join(&images.pointillist),
                &format!("img/{name}.pointillist.png"),
            )?;
            let _ = write!(
                rows,
                "<img class=\"img thumb\" loading=\"lazy\" src=\"{}\" alt=\"pointillist\">",
                esc(&file)
            );
        }
        rows.push_str("</td>");
        for (i, cell) in cells.iter().enumerate() {
            let Some(c) = cell else {
                rows.push_str("<td>not run</td>");
                continue;
            };
            let _ = write!(
                rows,
                "<td><span class=\"{0}\" title=\"{1}\">{0}</span>",
                esc(&c.status),
                esc(&c.message)
            );
            if c.status == "differs" {
                let _ = write!(rows, " {} px", c.pixels_differing);
            }
            match (&c.unexpected, &c.explanation) {
                (Some(u), _) => {
                    let _ = write!(rows, "<br><b class=\"error\">unexpected</b>: {}", esc(u));
                }
                (None, Some(_)) => rows.push_str(" (explained)"),
                (None, None) => {}
            }
            if !matched(&c.status)
                && let Some(images) = &c.images
            {
                let device = copy(
                    &columns[i].folder.join(&images.device),
                    &format!("img/{name}.d{i}.device.png"),
                )?;
                let diff = copy(
                    &columns[i].folder.join(&images.diff),
                    &format!("img/{name}.d{i}.diff.png"),
                )?;
                let _ = write!(
                    rows,
                    "<details><summary>images</summary><div class=\"imgs\"><figure>\
                     <img class=\"img\" loading=\"lazy\" src=\"{}\" alt=\"device\">\
                     <figcaption>device</figcaption></figure><figure><img class=\"img\" \
                     loading=\"lazy\" src=\"{}\" alt=\"difference\"><figcaption>difference, \
                     magnified</figcaption></figure></div><p class=\"rules\">{}</p>{}</details>",
                    esc(&device),
                    esc(&diff),
                    esc(&c.message),
                    c.explanation.as_ref().map_or(String::new(), |e| format!(
                        "<div class=\"why\"><p><b>D3D9:</b> {}</p><p><b>{}:</b> {}</p></div>",
                        esc(&e.d3d9),
                        esc(&columns[i].label),
                        esc(&e.implementation)
                    ))
                );
            } else if c.status == "error" {
                let _ = write!(rows, "<br><span class=\"rules\">{}</span>", esc(&c.message));
            }
            rows.push_str("</td>");
        }
        rows.push_str("</tr>\n");
    }

    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>pointillist conformance: {} devices</title><style>{STYLE}{PAGE_STYLE}</style>\
         </head><body>\n<h1>pointillist conformance: several devices</h1>\n\
         <p class=\"verdict\">{} cases: <span class=\"match\">{} match on every device</span>, \
         <span class=\"option\">{} split the devices</span>, <span class=\"differs\">{} match on \
         none</span>.</p>\n",
        columns.len(),
        summary.cases,
        summary.all_match,
        summary.split,
        summary.none_match
    );
    h.push_str(
        "<h2>Devices</h2>\n<table class=\"device\">\n<tr><th>column</th><th>adapter</th>\
         <th>d3d9.dll</th><th>Vulkan device</th><th>match</th><th>option</th><th>differs</th>\
         <th>error</th></tr>\n",
    );
    for c in columns {
        let count = |s: &str| c.report.cases.iter().filter(|k| k.status == s).count();
        let _ = writeln!(
            h,
            "<tr><td>{}</td><td>{}</td><td>{}</td><td>{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            esc(&c.label),
            esc(&c.report.device.description),
            esc(c.report.device.d3d9_dll.as_deref().unwrap_or("")),
            esc(c.report.device.vulkan_device.as_deref().unwrap_or("")),
            count("match"),
            count("option"),
            count("differs"),
            count("error")
        );
    }
    h.push_str("</table>\n");
    h.push_str(
        "<h2>Device behaviours</h2>\n<p>Where real D3D9 devices differ (SPEC section 10): the \
         option each device's cases showed, and pointillist's default with its evidence.</p>\n\
         <table>\n<tr><th>switch</th><th>default</th><th>evidence</th>",
    );
    for c in columns {
        let _ = write!(h, "<th>{}</th>", esc(&c.label));
    }
    h.push_str("</tr>\n");
    for def in &BEHAVIOURS {
        let _ = write!(
            h,
            "<tr><td><b>{}</b><br><span class=\"rules\">{} ({})</span></td><td>{}</td><td>{}</td>",
            esc(def.name),
            esc(def.summary),
            esc(def.rule),
            esc(def.default_name()),
            esc(def.evidence.name())
        );
        for c in columns {
            let cell = match c.report.behaviours.get(def.name).and_then(Option::as_deref) {
                Some(o) if o == def.default_name() => {
                    format!("<span class=\"match\">{}</span>", esc(o))
                }
                Some(o) => format!("<span class=\"option\">{}</span>", esc(o)),
                None => "not decided".into(),
            };
            let _ = write!(h, "<td>{cell}</td>");
        }
        h.push_str("</tr>\n");
    }
    h.push_str(
        "</table>\n<h2>Cases</h2>\n<p>Rows where the devices split are marked; a rule's \
         evidence grade (docs/spec/SPEC.md) says how D3D9's behaviour is known: <i>hardware</i> \
         (Windows drivers' record), <i>microsoft-driver</i>, <i>documented</i>, \
         <i>implementations</i>, <i>choice</i>. <label><input type=\"checkbox\" id=\"splits\" \
         onchange=\"document.body.classList.toggle('only-splits', this.checked)\"> only the \
         cases where the devices split or none matches</label></p>\n<table class=\"cases\">\n\
         <tr><th>case</th><th>rules</th><th>pointillist</th>",
    );
    for c in columns {
        let _ = write!(h, "<th>{}</th>", esc(&c.label));
    }
    h.push_str("</tr>\n");
    h.push_str(&rows);
    h.push_str("</table>\n</body></html>\n");
    fs::create_dir_all(out).map_err(|e| format!("{}: {e}", out.display()))?;
    Destination::check(&out.join("index.html"), &inputs)
        .and_then(|d| d.write_bytes(h.as_bytes()))
        .map_err(|e| e.to_string())?;
    Ok(summary)
}

const PAGE_STYLE: &str = "
tr.split td:first-child { border-left: 4px solid #1a56a8; }
tr.none td:first-child { border-left: 4px solid #a15c00; }
body.only-splits tr.agree { display: none; }
.thumb { max-width: 96px; max-height: 96px; }
.cases td { max-width: 24em; }
.cases details .img { width: 10em; height: auto; }
.cases .why { width: auto; }
";

fn same_folder(a: &Path, b: &Path) -> bool {
    match (fs::canonicalize(a), fs::canonicalize(b)) {
        (Ok(a), Ok(b)) => a == b,
        _ => false,
    }
}

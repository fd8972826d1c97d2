//! The report: `report.json` (the schema of docs/CONFORMANCE.md, "The report") and
//! `index.html`, a page read at a glance: the device and a summary per SPEC rule at the top,
//! then one row per case with pointillist's image, the device's and the magnified difference
//! side by side.

use std::collections::BTreeMap;
use std::fmt::Write as _;

use serde::Serialize;

use pointillist_core::behaviour::BEHAVIOURS;

use crate::expect::Status;
use crate::runner::DeviceInfo;

/// The specification the summary names rules from.
const SPEC: &str = include_str!("../../../docs/spec/SPEC.md");

/// The images of a compared case, relative to the report folder.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct CaseImages {
    /// pointillist's image.
    pub pointillist: String,
    /// The device's image.
    pub device: String,
    /// The magnified difference image.
    pub diff: String,
    /// Width and height shown, in CSS pixels (the target magnified like the difference).
    pub shown: (u32, u32),
}

/// One case as the report shows it.
#[derive(Clone, Debug, PartialEq)]
pub struct CaseReport {
    /// The case name.
    pub name: String,
    /// The scene file, as found.
    pub scene: String,
    /// The `[case]` title, if the scene has one.
    pub title: Option<String>,
    /// The SPEC rules the case covers ("2.3").
    pub rules: Vec<String>,
    /// How it ended.
    pub status: Status,
    /// Pixels beyond the tolerance.
    pub pixels_differing: u64,
    /// Largest channel difference.
    pub max_channel_difference: u8,
    /// The tolerance it was compared with, in 1/255 steps.
    pub tolerance: u8,
    /// One line on the outcome.
    pub message: String,
    /// `Err` when the outcome is not the expected one, saying how.
    pub verdict: Result<(), String>,
    /// The expectations' explanation of a known difference: what D3D9 does, what the
    /// implementation does.
    pub explanation: Option<(String, String)>,
    /// The images, when the device drew one.
    pub images: Option<CaseImages>,
    /// Whether the device's image holds the case's own `[[case.expect]]` facts (`None` for a
    /// scene without a `[case]` table or without a device image); `Err` lists what fails.
    pub facts: Option<Result<(), String>>,
    /// For [`Status::Option`]: the behaviour switches and the options under which the case
    /// matches.
    pub matching: Vec<(&'static str, &'static str)>,
    /// The behaviour switches this case decides, with the option the device showed.
    pub shown: BTreeMap<&'static str, &'static str>,
}

#[derive(Serialize)]
struct JsonDevice<'a> {
    description: &'a str,
    max_point_size: f32,
    fvfcaps_psize: bool,
    clip_plane_scaled_points: bool,
    clip_tl_verts: bool,
    w_fog: bool,
    max_active_lights: u32,
    /// With `conform --d3d9`: the DLL's name and version, and the Vulkan device under it.
    #[serde(skip_serializing_if = "Option::is_none")]
    d3d9_dll: Option<&'a str>,
    #[serde(skip_serializing_if = "Option::is_none")]
    vulkan_device: Option<&'a str>,
}

#[derive(Serialize)]
struct JsonImages<'a> {
    pointillist: &'a str,
    device: &'a str,
    diff: &'a str,
}

#[derive(Serialize)]
struct JsonCase<'a> {
    name: &'a str,
    scene: &'a str,
    #[serde(skip_serializing_if = "Option::is_none")]
    title: Option<&'a str>,
    rules: &'a [String],
    status: Status,
    #[serde(skip_serializing_if = "BTreeMap::is_empty")]
    options: BTreeMap<&'static str, &'static str>,
    pixels_differing: u64,
    max_channel_difference: u8,
    message: &'a str,
    /// The images, relative to the report folder, when the device drew one.
    #[serde(skip_serializing_if = "Option::is_none")]
    images: Option<JsonImages<'a>>,
    /// How the outcome departs from the expectations (`null` when as expected).
    unexpected: Option<&'a str>,
    /// The expectations' explanation of a known difference.
    #[serde(skip_serializing_if = "Option::is_none")]
    explanation: Option<JsonExplanation<'a>>,
}

#[derive(Serialize)]
struct JsonExplanation<'a> {
    d3d9: &'a str,
    implementation: &'a str,
}

#[derive(Serialize)]
struct JsonReport<'a> {
    /// The expectations' `implementation` line, when `--expect` gave one.
    #[serde(skip_serializing_if = "Option::is_none")]
    implementation: Option<&'a str>,
    device: JsonDevice<'a>,
    behaviours: &'a BTreeMap<&'static str, Option<&'static str>>,
    cases: Vec<JsonCase<'a>>,
}

/// `report.json`: the implementation as the expectations name it, the device, the option of
/// each behaviour switch its cases showed (`null` when none decided it or they disagree), and
/// every case with its rules and images (what `conform-page` reads).
pub fn json(
    device: &DeviceInfo,
    implementation: Option<&str>,
    behaviours: &BTreeMap<&'static str, Option<&'static str>>,
    cases: &[CaseReport],
) -> String {
    let report = JsonReport {
        implementation,
        device: JsonDevice {
            description: &device.description,
            max_point_size: device.max_point_size,
            fvfcaps_psize: device.fvfcaps_psize,
            clip_plane_scaled_points: device.clip_plane_scaled_points,
            clip_tl_verts: device.clip_tl_verts,
            w_fog: device.w_fog,
            max_active_lights: device.max_active_lights,
            d3d9_dll: device.get("d3d9_dll"),
            vulkan_device: device.get("vulkan_device"),
        },
        behaviours,
        cases: cases
            .iter()
            .map(|c| JsonCase {
                name: &c.name,
                scene: &c.scene,
                title: c.title.as_deref(),
                rules: &c.rules,
                status: c.status,
                options: c.matching.iter().copied().collect(),
                pixels_differing: c.pixels_differing,
                max_channel_difference: c.max_channel_difference,
                message: &c.message,
                images: c.images.as_ref().map(|i| JsonImages {
                    pointillist: &i.pointillist,
                    device: &i.device,
                    diff: &i.diff,
                }),
                unexpected: c.verdict.as_ref().err().map(String::as_str),
                explanation: c
                    .explanation
                    .as_ref()
                    .map(|(d3d9, implementation)| JsonExplanation {
                        d3d9,
                        implementation,
                    }),
            })
            .collect(),
    };
    let mut text = serde_json::to_string_pretty(&report).unwrap_or_default();
    text.push('\n');
    text
}

/// The rules of SPEC.md by number: "2" the section title, "2.3" the item's first words.
pub fn spec_rules() -> BTreeMap<(u32, u32), String> {
    let mut rules = BTreeMap::new();
    let mut section = 0;
    for line in SPEC.lines() {
        if let Some(rest) = line.strip_prefix("## ")
            && let Some((n, title)) = rest.split_once(". ")
            && let Ok(n) = n.parse()
        {
            section = n;
            rules.insert((n, 0), title.to_string());
        } else if section > 0
            && let Some((n, text)) = line.split_once(". ")
            && let Ok(n) = n.parse::<u32>()
        {
            let text = text.replace('`', "");
            let end = text
                .find([':', '(', ';'])
                .or_else(|| text.find(". "))
                .unwrap_or(text.len())
                .min(64);
            let end = (0..=end)
                .rev()
                .find(|&i| text.is_char_boundary(i))
                .unwrap_or(0);
            rules.insert(
                (section, n),
                text[..end].trim_end_matches([',', ' ']).to_string(),
            );
        }
    }
    rules
}

/// The evidence grade of each rule of SPEC.md that states one: the first word after its first
/// `Evidence:` or `Evidence (what):` ("hardware", "microsoft-driver", "documented",
/// "implementations", "choice").
pub fn spec_evidence() -> BTreeMap<(u32, u32), String> {
    let mut grades = BTreeMap::new();
    let (mut section, mut item) = (0, 0);
    for line in SPEC.lines() {
        if let Some(rest) = line.strip_prefix("## ")
            && let Some((n, _)) = rest.split_once(". ")
            && let Ok(n) = n.parse()
        {
            (section, item) = (n, 0);
        } else if let Some((n, _)) = line.split_once(". ")
            && let Ok(n) = n.parse::<u32>()
        {
            item = n;
        } else if let Some((_, rest)) = line.split_once("Evidence")
            && let Some((_, rest)) = rest.split_once(": ")
            && section > 0
        {
            let grade: String = rest
                .chars()
                .take_while(|c| c.is_ascii_lowercase() || *c == '-')
                .collect();
            if !grade.is_empty() {
                grades.entry((section, item)).or_insert(grade);
            }
        }
    }
    grades
}

/// A rule citation as a key: "2.3" is (2, 3), "4" is (4, 0).
pub(crate) fn rule_key(rule: &str) -> Option<(u32, u32)> {
    let (s, i) = rule.split_once('.').unwrap_or((rule, "0"));
    Some((s.parse().ok()?, i.parse().ok()?))
}

pub(crate) fn esc(s: &str) -> String {
    s.replace('&', "&amp;")
        .replace('<', "&lt;")
        .replace('>', "&gt;")
        .replace('"', "&quot;")
}

pub(crate) const STYLE: &str = "
body { font: 14px/1.4 system-ui, sans-serif; margin: 1.5em; color: #222; }
h1 { font-size: 1.5em; margin: 0 0 .3em; }
h2 { font-size: 1.15em; margin: 1.2em 0 .4em; }
table { border-collapse: collapse; }
td, th { border: 1px solid #ccc; padding: 4px 8px; vertical-align: top; text-align: left; }
th { background: #f2f2f2; }
.num { text-align: right; }
.match { color: #176b2c; font-weight: bold; }
.option { color: #1a56a8; font-weight: bold; }
.differs { color: #a15c00; font-weight: bold; }
.error { color: #b00020; font-weight: bold; }
.bad { background: #ffe3e3; }
.verdict { font-size: 1.1em; margin: .6em 0; }
.device td:first-child { font-weight: bold; }
.img { background: repeating-conic-gradient(#ccc 0 25%, #fff 0 50%) 0 0 / 16px 16px;
       image-rendering: pixelated; display: block; }
.imgs { display: flex; gap: 10px; }
.imgs figure { margin: 0; }
.imgs figcaption { font-size: 12px; color: #555; }
.why { width: 30em; font-size: 13px; }
.why p { margin: .3em 0; }
.rules { font-size: 12px; color: #555; }
code { font-size: 12px; }
";

fn status_cell(c: &CaseReport) -> String {
    let mut s = format!("<span class=\"{0}\">{0}</span>", c.status);
    match &c.verdict {
        Ok(()) if c.status != Status::Match => s.push_str(" (expected)"),
        Ok(()) => {}
        Err(e) => {
            let _ = write!(s, "<br><b>{}</b>", esc(e));
        }
    }
    s
}

/// The top of the page: each behaviour switch, the option the device's cases showed, the
/// default and its evidence.
fn behaviour_profile(
    h: &mut String,
    behaviours: &BTreeMap<&'static str, Option<&'static str>>,
    cases: &[CaseReport],
) {
    h.push_str(
        "<h2>Device behaviours</h2>\n<p>Where real D3D9 devices differ (docs/spec/SPEC.md, \
         \"Device behaviours\"): the option this device's cases showed, and pointillist's default \
         with its evidence.</p>\n<table>\n<tr><th>switch</th><th>this device</th>\
         <th>cases deciding</th><th>default</th><th>evidence for the default</th></tr>\n",
    );
    for def in &BEHAVIOURS {
        let deciding = cases
            .iter()
            .filter(|c| c.shown.contains_key(def.name))
            .count();
        let shown = match behaviours.get(def.name).copied().flatten() {
            Some(o) if o == def.default_name() => {
                format!("<span class=\"match\">{}</span>", esc(o))
            }
            Some(o) => format!("<span class=\"option\">{}</span>", esc(o)),
            None if deciding > 0 => "<span class=\"differs\">cases disagree</span>".to_string(),
            None => "not decided".to_string(),
        };
        let _ = writeln!(
            h,
            "<tr><td><b>{}</b><br><span class=\"rules\">{} ({})</span></td><td>{shown}</td>\
             <td class=\"num\">{deciding}</td><td>{}</td><td>{}<br><span class=\"rules\">{}\
             </span></td></tr>",
            esc(def.name),
            esc(def.summary),
            esc(def.rule),
            esc(def.default_name()),
            esc(def.evidence.name()),
            esc(&def.sources.join("; "))
        );
    }
    h.push_str("</table>\n");
}

/// `index.html`.
pub fn html(
    device: &DeviceInfo,
    implementation: Option<&str>,
    behaviours: &BTreeMap<&'static str, Option<&'static str>>,
    cases: &[CaseReport],
) -> String {
    let rules = spec_rules();
    let evidence = spec_evidence();
    let count = |s: Status| cases.iter().filter(|c| c.status == s).count();
    let unexpected = cases.iter().filter(|c| c.verdict.is_err()).count();
    let mut h = String::new();
    let _ = write!(
        h,
        "<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">\
         <title>pointillist conformance: {}</title><style>{STYLE}</style></head><body>\n\
         <h1>pointillist conformance report</h1>\n",
        esc(&device.description)
    );
    let _ = writeln!(
        h,
        "<p class=\"verdict\">{} cases: <span class=\"match\">{} match</span>, \
         <span class=\"option\">{} match under another behaviour option</span>, \
         <span class=\"differs\">{} differ</span>, <span class=\"error\">{} errors</span>. {}</p>",
        cases.len(),
        count(Status::Match),
        count(Status::Option),
        count(Status::Differs),
        count(Status::Error),
        if unexpected == 0 {
            "<span class=\"match\">Every outcome is as expected.</span>".to_string()
        } else {
            format!("<span class=\"error\">{unexpected} unexpected outcomes.</span>")
        }
    );
    behaviour_profile(&mut h, behaviours, cases);
    h.push_str("<h2>Device</h2>\n<table class=\"device\">\n");
    let mut row = |k: &str, v: &str| {
        let _ = writeln!(h, "<tr><td>{}</td><td>{}</td></tr>", esc(k), esc(v));
    };
    row("Adapter", &device.description);
    if let Some(i) = implementation {
        row("Implementation", i);
    }
    for (key, label) in [
        ("wine_version", "Wine"),
        ("d3d9_dll", "d3d9.dll"),
        ("dxvk_version", "DXVK (its log)"),
        ("vulkan_device", "Vulkan device"),
        ("driver", "Driver"),
        ("driver_version", "Driver version"),
    ] {
        if let Some(v) = device.get(key).filter(|v| !v.is_empty()) {
            row(label, v);
        }
    }
    row("MaxPointSize", &format!("{}", device.max_point_size));
    row(
        "D3DFVFCAPS_PSIZE",
        if device.fvfcaps_psize { "yes" } else { "no" },
    );
    row(
        "D3DPMISCCAPS_CLIPPLANESCALEDPOINTS",
        if device.clip_plane_scaled_points {
            "yes"
        } else {
            "no"
        },
    );
    row(
        "D3DPMISCCAPS_CLIPTLVERTS",
        if device.clip_tl_verts { "yes" } else { "no" },
    );
    row(
        "D3DPRASTERCAPS_WFOG",
        if device.w_fog { "yes" } else { "no" },
    );
    row("MaxActiveLights", &device.max_active_lights.to_string());
    h.push_str("</table>\n<p>pointillist renders every case with these caps.</p>\n");

    // The summary: per rule cited, grouped by SPEC section.
    let mut by_rule: BTreeMap<(u32, u32), [usize; 5]> = BTreeMap::new();
    for c in cases {
        for key in c.rules.iter().filter_map(|r| rule_key(r)) {
            let e = by_rule.entry(key).or_default();
            e[c.status as usize] += 1;
            e[4] += usize::from(c.verdict.is_err());
        }
    }
    let uncited = cases.iter().filter(|c| c.rules.is_empty()).count();
    h.push_str(
        "<h2>By SPEC rule</h2>\n<table>\n<tr><th>rule</th><th>evidence</th><th>cases</th>\
         <th>match</th><th>option</th><th>differ</th><th>error</th><th>unexpected</th></tr>\n",
    );
    let mut last_section = 0;
    for (&(s, i), n) in &by_rule {
        if s != last_section {
            last_section = s;
            let title = rules
                .get(&(s, 0))
                .map_or("(not in SPEC.md)", String::as_str);
            let _ = writeln!(h, "<tr><th colspan=\"8\">{s}. {}</th></tr>", esc(title));
        }
        let name = if i == 0 {
            format!("{s}")
        } else {
            format!("{s}.{i}")
        };
        let label = rules
            .get(&(s, i))
            .map_or("(not in SPEC.md)", String::as_str);
        let grade = evidence.get(&(s, i)).map_or("", String::as_str);
        let _ = writeln!(
            h,
            "<tr{}><td><b>{name}</b> {}</td><td>{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td><td class=\"num\">{}</td>\
             <td class=\"num\">{}</td><td class=\"num\">{}</td></tr>",
            if n[4] > 0 { " class=\"bad\"" } else { "" },
            esc(label),
            esc(grade),
            n[0] + n[1] + n[2] + n[3],
            n[0],
            n[1],
            n[2],
            n[3],
            n[4]
        );
    }
    if uncited > 0 {
        let _ = writeln!(
            h,
            "<tr><td>(cases naming no rule)</td><td class=\"num\">{uncited}</td>\
             <td colspan=\"6\"></td></tr>"
        );
    }
    h.push_str("</table>\n");

    h.push_str(
        "<h2>Cases</h2>\n<p>Difference: black to grey where the images are equal (pointillist's \
         image darkened), dark yellow within the tolerance, red beyond it (brighter for larger \
         differences).</p>\n<table>\n<tr><th>case</th><th>pointillist | device | difference</th>\
         </tr>\n",
    );
    for c in cases {
        let _ = write!(
            h,
            "<tr id=\"{0}\"{1}><td class=\"why\"><b>{0}</b> {2}",
            esc(&c.name),
            if c.verdict.is_err() {
                " class=\"bad\""
            } else {
                ""
            },
            status_cell(c)
        );
        if let Some(t) = &c.title {
            let _ = write!(h, "<br>{}", esc(t));
        }
        let _ = write!(h, "<br><code>{}</code>", esc(&c.scene));
        if !c.rules.is_empty() {
            let cited: Vec<String> = c
                .rules
                .iter()
                .map(|r| match rule_key(r).and_then(|k| evidence.get(&k)) {
                    Some(grade) => format!("{r} ({grade})"),
                    None => r.clone(),
                })
                .collect();
            let _ = write!(
                h,
                "<div class=\"rules\">SPEC {}</div>",
                esc(&cited.join(", "))
            );
        }
        let _ = write!(h, "<p>{}</p>", esc(&c.message));
        match &c.facts {
            Some(Ok(())) => h.push_str("<p>The device holds the case's stated facts.</p>"),
            Some(Err(e)) => {
                let _ = write!(
                    h,
                    "<p><b>The device breaks the case's stated facts:</b><br>{}</p>",
                    esc(e).replace('\n', "<br>")
                );
            }
            None => {}
        }
        if let Some((d3d9, imp)) = &c.explanation {
            let _ = write!(
                h,
                "<p><b>D3D9:</b> {}<br><b>This device:</b> {}</p>",
                esc(d3d9),
                esc(imp)
            );
        }
        h.push_str("</td><td>");
        if let Some(im) = &c.images {
            let (w, ht) = im.shown;
            h.push_str("<div class=\"imgs\">");
            for (label, src) in [
                ("pointillist", &im.pointillist),
                ("device", &im.device),
                ("difference", &im.diff),
            ] {
                let _ = write!(
                    h,
                    "<figure><img class=\"img\" src=\"{}\" width=\"{w}\" height=\"{ht}\" \
                     alt=\"{label}\"><figcaption>{label}</figcaption></figure>",
                    esc(src)
                );
            }
            h.push_str("</div>");
        }
        h.push_str("</td></tr>\n");
    }
    h.push_str("</table>\n</body></html>\n");
    h
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn rules_are_read_from_the_specification() {
        let rules = spec_rules();
        assert_eq!(rules[&(2, 0)], "Point size");
        assert_eq!(rules[&(2, 1)], "Input size Si");
        assert_eq!(rules[&(3, 3)], "User clip planes");
        assert_eq!(rules[&(7, 0)], "Both backends");
        assert_eq!(rule_key("2.3"), Some((2, 3)));
        assert_eq!(rule_key("6"), Some((6, 0)));
        assert_eq!(rule_key("x"), None);
    }

    #[test]
    fn every_rule_states_its_evidence() {
        let grades = spec_evidence();
        let words = [
            "hardware",
            "microsoft-driver",
            "documented",
            "implementations",
            "choice",
        ];
        for (key, title) in spec_rules() {
            if key.1 == 0 {
                continue;
            }
            let grade = grades
                .get(&key)
                .unwrap_or_else(|| panic!("SPEC {key:?} {title}"));
            assert!(words.contains(&grade.as_str()), "SPEC {key:?}: {grade}");
        }
    }
}

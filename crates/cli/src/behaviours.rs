//! `pointillist behaviours [--json]`: the device behaviour switches (core's
//! `behaviour::BEHAVIOURS`), their options, defaults and evidence.

use std::fmt::Write as _;

use pointillist_core::behaviour::{BEHAVIOURS, BehaviourDef};

use crate::BehavioursArgs;

/// Prints every switch on standard output, as text or as the JSON array docs/spec/SPEC.md
/// describes.
pub fn run(args: &BehavioursArgs) -> Result<(), String> {
    let text = if args.json { json() } else { text() };
    crate::report::outln!("{}", text.trim_end());
    Ok(())
}

/// `[{"name", "options", "default", "evidence", "sources"}, ...]`, plus the summary, the rule
/// and what each option draws.
fn json() -> String {
    let list: Vec<_> = BEHAVIOURS.iter().map(def_json).collect();
    serde_json::to_string_pretty(&list).expect("plain strings serialise")
}

fn def_json(d: &BehaviourDef) -> serde_json::Value {
    serde_json::json!({
        "name": d.name,
        "options": d.option_names().collect::<Vec<_>>(),
        "default": d.default_name(),
        "evidence": d.evidence.name(),
        "sources": d.sources,
        "summary": d.summary,
        "rule": d.rule,
        "option_effects": d
            .options
            .iter()
            .map(|(o, what)| (o.to_string(), serde_json::Value::from(*what)))
            .collect::<serde_json::Map<_, _>>(),
    })
}

fn text() -> String {
    let mut out = String::from(
        "Device behaviours: where real D3D9 devices differ, or no record decides. Set them with a \
         scene's [behaviour] table or --behaviour NAME=OPTION (render, animate, conform).\n",
    );
    for d in &BEHAVIOURS {
        let _ = writeln!(out, "\n{} ({}): {}", d.name, d.rule, d.summary);
        for (i, (option, what)) in d.options.iter().enumerate() {
            let mark = if i == d.default { " (default)" } else { "" };
            let _ = writeln!(out, "  {option}{mark}: {what}");
        }
        let _ = writeln!(out, "  evidence for the default: {}", d.evidence.name());
        for s in d.sources {
            let _ = writeln!(out, "    - {s}");
        }
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn json_lists_every_switch_with_the_documented_keys() {
        let v: serde_json::Value = serde_json::from_str(&json()).unwrap();
        let list = v.as_array().unwrap();
        assert_eq!(list.len(), BEHAVIOURS.len());
        for (item, def) in list.iter().zip(&BEHAVIOURS) {
            assert_eq!(item["name"], def.name);
            let options: Vec<_> = item["options"]
                .as_array()
                .unwrap()
                .iter()
                .map(|o| o.as_str().unwrap())
                .collect();
            assert_eq!(options, def.option_names().collect::<Vec<_>>());
            assert!(options.contains(&item["default"].as_str().unwrap()));
            assert!(
                [
                    "hardware",
                    "microsoft-driver",
                    "documented",
                    "implementations",
                    "choice"
                ]
                .contains(&item["evidence"].as_str().unwrap()),
                "{item}"
            );
            assert!(!item["sources"].as_array().unwrap().is_empty());
        }
    }
}

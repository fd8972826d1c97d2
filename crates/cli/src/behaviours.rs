//! `pointillist behaviours [--profiles] [--json]`: the device behaviour switches (core's
//! `behaviour::BEHAVIOURS`), their options, defaults and evidence, or the profiles (core's
//! `behaviour::PROFILES`).

use std::fmt::Write as _;

use pointillist_core::behaviour::{BEHAVIOURS, BehaviourDef, BehaviourProfile, PROFILES};

use crate::BehavioursArgs;

/// Prints every switch on standard output, as text or as the JSON array docs/spec/SPEC.md
/// describes.
pub fn run(args: &BehavioursArgs) -> Result<(), String> {
    let text = match (args.profiles, args.json) {
        (false, true) => json(),
        (false, false) => text(),
        (true, true) => profiles_json(),
        (true, false) => profiles_text(),
    };
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

/// `[{"name", "summary", "settings": {SWITCH: OPTION}, "sources"}, ...]`.
fn profiles_json() -> String {
    let list: Vec<_> = PROFILES.iter().map(profile_json).collect();
    serde_json::to_string_pretty(&list).expect("plain strings serialise")
}

fn profile_json(p: &BehaviourProfile) -> serde_json::Value {
    serde_json::json!({
        "name": p.name,
        "summary": p.summary,
        "settings": p
            .settings
            .iter()
            .map(|(s, o)| (s.to_string(), serde_json::Value::from(*o)))
            .collect::<serde_json::Map<_, _>>(),
        "sources": p.sources,
    })
}

fn profiles_text() -> String {
    let mut out = String::from(
        "Behaviour profiles: the options a source shows for a whole device. Set one with \
         profile = \"NAME\" in a scene's [behaviour] table or --behaviour profile=NAME; the \
         switches beside it are applied after it, and the switches it does not name keep \
         their option.\n",
    );
    for p in &PROFILES {
        let _ = writeln!(out, "\n{}: {}", p.name, p.summary);
        for (switch, option) in p.settings {
            let _ = writeln!(out, "  {switch} = {option}");
        }
        for s in p.sources {
            let _ = writeln!(out, "    - {s}");
        }
    }
    out
}

fn text() -> String {
    let mut out = String::from(
        "Device behaviours: where real D3D9 devices differ, or no record decides. Set them with a \
         scene's [behaviour] table or --behaviour NAME=OPTION (render, animate, conform); \
         --profiles lists the profiles that set several at once.\n",
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

    #[test]
    fn profiles_json_lists_every_profile_with_its_settings() {
        let v: serde_json::Value = serde_json::from_str(&profiles_json()).unwrap();
        let list = v.as_array().unwrap();
        assert_eq!(list.len(), PROFILES.len());
        for (item, p) in list.iter().zip(&PROFILES) {
            assert_eq!(item["name"], p.name);
            let settings = item["settings"].as_object().unwrap();
            assert_eq!(settings.len(), p.settings.len());
            for (switch, option) in p.settings {
                assert_eq!(settings[*switch], *option, "{}", p.name);
            }
            assert!(!item["sources"].as_array().unwrap().is_empty());
        }
        assert!(profiles_text().contains("\nwine: "));
    }
}

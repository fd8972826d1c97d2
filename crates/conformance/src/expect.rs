//! Expectations: the outcomes known for one implementation (docs/CONFORMANCE.md,
//! "Expectations"). A case the file does not list is expected to match; a listed case is
//! expected to differ (or to fail), with what D3D9 does and what the implementation does.

use std::collections::BTreeMap;
use std::fmt;
use std::path::Path;

use pointillist_core::behaviour::BehaviourSetting;
use serde::Deserialize;

/// The status a case ends with.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Deserialize, serde::Serialize)]
#[serde(rename_all = "lowercase")]
pub enum Status {
    /// The device drew pointillist's image, within the tolerance.
    Match,
    /// It drew pointillist's image under another option of a device behaviour switch: a
    /// finding about the device, not a departure.
    Option,
    /// It drew something else.
    Differs,
    /// The case could not be compared: a call failed on the device, or the scene did not load.
    Error,
}

impl fmt::Display for Status {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        f.write_str(match self {
            Status::Match => "match",
            Status::Option => "option",
            Status::Differs => "differs",
            Status::Error => "error",
        })
    }
}

/// One known outcome.
#[derive(Clone, Debug, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expected {
    /// The case name (the scene file's name without `.toml`, as the report names it).
    pub case: String,
    /// `differs` or `error`.
    pub status: Status,
    /// For `differs`: when given, the number of pixels must be exactly this.
    pub pixels_differing: Option<u64>,
    /// What a D3D9 device does, by the documented rules (SPEC n.m).
    pub d3d9: String,
    /// What the implementation does instead, and why.
    pub implementation: String,
}

/// An expectations file.
#[derive(Clone, Debug, Default, PartialEq, Eq, Deserialize)]
#[serde(deny_unknown_fields)]
pub struct Expectations {
    /// The implementation the file describes (shown in the report).
    pub implementation: Option<String>,
    /// `[behaviour]`: the option of each device behaviour switch the implementation shows; a
    /// case that matches only under such an option is as expected.
    #[serde(default, rename = "behaviour")]
    pub behaviours: BTreeMap<String, String>,
    /// The known differences.
    #[serde(default, rename = "case")]
    pub cases: Vec<Expected>,
}

impl Expectations {
    /// Reads (at most [`crate::MAX_TEXT_BYTES`]) and checks an expectations file; errors name the
    /// file and line.
    pub fn load(path: &Path) -> Result<Expectations, String> {
        let text = crate::read_text(path)?;
        Self::parse(&text, path)
    }

    /// Parses expectations text; `path` names it in errors.
    pub fn parse(text: &str, path: &Path) -> Result<Expectations, String> {
        let expectations: Expectations = toml::from_str(text).map_err(|e| {
            let line = e
                .span()
                .map(|s| text[..s.start.min(text.len())].matches('\n').count() + 1);
            let at = line.map(|l| format!(":{l}")).unwrap_or_default();
            format!("{}{at}: {}", path.display(), e.message().trim())
        })?;
        for (name, option) in &expectations.behaviours {
            let setting = format!("{name}={option}");
            setting
                .parse::<BehaviourSetting>()
                .map_err(|e| format!("{}: [behaviour] {name}: {e}", path.display()))?;
        }
        let mut seen = std::collections::HashSet::new();
        for (i, c) in expectations.cases.iter().enumerate() {
            let fail = |m: &str| Err(format!("{}: case[{i}] ({}): {m}", path.display(), c.case));
            if c.status == Status::Match {
                return fail("status = \"match\" is the default; list only differences and errors");
            }
            if c.status == Status::Option {
                return fail(
                    "status = \"option\" is no departure; name the device's option in [behaviour]",
                );
            }
            if c.d3d9.trim().is_empty() || c.implementation.trim().is_empty() {
                return fail("`d3d9` and `implementation` must explain the difference");
            }
            if c.pixels_differing.is_some() && c.status != Status::Differs {
                return fail("pixels_differing is only for status = \"differs\"");
            }
            if !seen.insert(c.case.as_str()) {
                return fail("listed twice");
            }
        }
        Ok(expectations)
    }

    /// The expectation of `case`, if listed.
    pub fn get(&self, case: &str) -> Option<&Expected> {
        self.cases.iter().find(|c| c.case == case)
    }

    /// Whether `case` ending with `status` (and `pixels` pixels differing; for
    /// [`Status::Option`], matching under the switches and options `matching`) is as expected;
    /// `Err` says what is unexpected.
    pub fn check(
        &self,
        case: &str,
        status: Status,
        pixels: u64,
        matching: &[(&str, &str)],
    ) -> Result<(), String> {
        match (self.get(case), status) {
            (None, Status::Match) => Ok(()),
            (None, Status::Option) => {
                for &(name, option) in matching {
                    match self.behaviours.get(name) {
                        Some(o) if o == option => {}
                        Some(o) => {
                            return Err(format!(
                                "unexpected: matches with {name} = \"{option}\", the \
                                 expectations' [behaviour] say \"{o}\""
                            ));
                        }
                        None => {
                            return Err(format!(
                                "unexpected: matches with {name} = \"{option}\", which the \
                                 expectations' [behaviour] do not name"
                            ));
                        }
                    }
                }
                Ok(())
            }
            (None, s) => Err(format!("unexpected: {s} (expected to match)")),
            (Some(e), s) if s != e.status => Err(format!(
                "unexpected: {s} (expected to be {}: update the expectations if this is a fix)",
                e.status
            )),
            (Some(e), _) => match e.pixels_differing {
                Some(n) if n != pixels => Err(format!(
                    "unexpected: {pixels} pixels differ, the expectations say {n}"
                )),
                _ => Ok(()),
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    const FILE: &str = r#"
implementation = "Wine 8.0"

[[case]]
case = "sub_pixel"
status = "differs"
pixels_differing = 4
d3d9 = "a 0.5 pixel point between centres covers nothing (SPEC 4.1)"
implementation = "draws one pixel"

[[case]]
case = "lit"
status = "error"
d3d9 = "x"
implementation = "y"
"#;

    #[test]
    fn listed_cases_must_end_as_listed_and_others_must_match() {
        let e = Expectations::parse(FILE, Path::new("wine.toml")).unwrap();
        assert_eq!(e.implementation.as_deref(), Some("Wine 8.0"));
        assert!(e.check("other", Status::Match, 0, &[]).is_ok());
        assert!(e.check("other", Status::Differs, 3, &[]).is_err());
        assert!(e.check("sub_pixel", Status::Differs, 4, &[]).is_ok());
        let changed = e.check("sub_pixel", Status::Differs, 5, &[]).unwrap_err();
        assert!(
            changed.contains("5 pixels") && changed.contains("say 4"),
            "{changed}"
        );
        let fixed = e.check("sub_pixel", Status::Match, 0, &[]).unwrap_err();
        assert!(fixed.contains("expected to be differs"), "{fixed}");
        assert!(e.check("lit", Status::Error, 0, &[]).is_ok());
        assert!(e.check("lit", Status::Differs, 1, &[]).is_err());
    }

    #[test]
    fn an_option_case_is_expected_when_the_behaviour_table_names_its_option() {
        let text = format!("{FILE}\n[behaviour]\nspecular_fog = \"clamped\"\n");
        let e = Expectations::parse(&text, Path::new("wine.toml")).unwrap();
        let clamped = &[("specular_fog", "clamped")];
        assert!(e.check("other", Status::Option, 9, clamped).is_ok());
        let other = e.check("other", Status::Option, 9, &[("specular_fog", "unclamped")]);
        assert!(other.unwrap_err().contains("say \"clamped\""));
        let unnamed = e.check("other", Status::Option, 9, &[("minimum_size", "one_pixel")]);
        assert!(unnamed.unwrap_err().contains("do not name"));
        // Two switches together: each must be the expectations' option.
        let pair = [("specular_fog", "clamped"), ("minimum_size", "one_pixel")];
        assert!(
            e.check("other", Status::Option, 9, &pair)
                .unwrap_err()
                .contains("minimum_size")
        );
        let both = format!("{text}minimum_size = \"one_pixel\"\n");
        let e2 = Expectations::parse(&both, Path::new("wine.toml")).unwrap();
        assert!(e2.check("other", Status::Option, 9, &pair).is_ok());
        // A listed departure that now matches under an option is a change to look at.
        assert!(e.check("sub_pixel", Status::Option, 4, clamped).is_err());
        let p = Path::new("wine.toml");
        let bad = Expectations::parse("[behaviour]\nspecular_fog = \"maybe\"\n", p);
        assert!(bad.unwrap_err().contains("unknown option `maybe`"));
        let listed =
            "[[case]]\ncase = \"a\"\nstatus = \"option\"\nd3d9 = \"x\"\nimplementation = \"y\"";
        assert!(
            Expectations::parse(listed, p)
                .unwrap_err()
                .contains("no departure")
        );
    }

    /// Duplicates are found in one pass: a file near the size limit (100,000 cases) is read as
    /// fast as it parses, not in quadratic time.
    #[test]
    fn many_cases_are_checked_in_one_pass() {
        let text: String = (0..100_000)
            .map(|i| {
                format!(
                    "[[case]]\ncase = \"c{i}\"\nstatus = \"error\"\nd3d9 = \"x\"\n\
                     implementation = \"y\"\n"
                )
            })
            .collect();
        let e = Expectations::parse(&text, Path::new("big.toml")).unwrap();
        assert_eq!(e.cases.len(), 100_000);
        let twice = format!(
            "{text}[[case]]\ncase = \"c7\"\nstatus = \"error\"\nd3d9 = \"x\"\n\
                             implementation = \"y\"\n"
        );
        let e = Expectations::parse(&twice, Path::new("big.toml")).unwrap_err();
        assert!(e.contains("case[100000] (c7): listed twice"), "{e}");
    }

    #[test]
    fn bad_files_name_the_file_the_line_and_the_case() {
        let p = Path::new("wine.toml");
        let e = Expectations::parse("[[case]]\ncase = 3\n", p).unwrap_err();
        assert!(e.starts_with("wine.toml:2: "), "{e}");
        let e = Expectations::parse("[[case]]\ncase = \"a\"\nstatus = \"differs\"\n", p);
        assert!(e.unwrap_err().contains("missing field"));
        let no_why =
            "[[case]]\ncase = \"a\"\nstatus = \"differs\"\nd3d9 = \"\"\nimplementation = \"\"";
        let e = Expectations::parse(no_why, p).unwrap_err();
        assert!(e.contains("case[0] (a)") && e.contains("explain"), "{e}");
        let e = Expectations::parse("colour = 1", p).unwrap_err();
        assert!(e.contains("unknown field"), "{e}");
        let twice = format!(
            "{FILE}\n[[case]]\ncase = \"lit\"\nstatus = \"error\"\nd3d9 = \"x\"\nimplementation = \"y\"\n"
        );
        assert!(
            Expectations::parse(&twice, p)
                .unwrap_err()
                .contains("listed twice")
        );
    }
}

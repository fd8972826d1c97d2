//! Which device behaviour a device's image shows (docs/spec/SPEC.md, "Device behaviours"): a
//! case is rendered again under every other option of every switch; an option that changes
//! pointillist's image and matches the device's is what the device does, and a case that
//! differs only because the device takes another option is a finding about the device, not a
//! departure.

use std::collections::BTreeMap;

use pointillist_core::Behaviours;
use pointillist_core::behaviour::{BEHAVIOURS, BehaviourSet};
use pointillist_core::tolerance::Tolerance;

use crate::compare::compare;
use crate::runner::Image;

/// What one case tells about the device's behaviours.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Classification {
    /// The switches whose options draw this case differently, each with the option whose image
    /// the device drew (when exactly one did).
    pub shown: BTreeMap<&'static str, &'static str>,
    /// For a case that differs under its own behaviours: the switch and option under which it
    /// matches, if one does.
    pub matching: Option<(&'static str, &'static str)>,
}

/// A case's two images and how they compared.
#[derive(Clone, Copy)]
pub struct Compared<'a> {
    /// pointillist's image under the scene's behaviours.
    pub ours: &'a Image,
    /// The device's image.
    pub theirs: &'a Image,
    /// The case's tolerance.
    pub tolerance: Tolerance,
    /// True when `theirs` matches `ours` within `tolerance`.
    pub matched: bool,
}

/// Classifies a case whose image under `base` is `ours` (`matched`: the device's image
/// `theirs` matches it within `tolerance`). `render` draws the case under other behaviours; it
/// is called for the switches in `read` (those the case's draws depend on), one switch changed
/// at a time. Where several options draw the device's image, the one `prefer` names (the
/// expectations' `[behaviour]`) is taken, else the default, else none; a matching case shows
/// its own option, or the preferred one where that draws the case alike.
pub fn classify(
    base: Behaviours,
    read: BehaviourSet,
    prefer: &BTreeMap<String, String>,
    images: Compared<'_>,
    mut render: impl FnMut(Behaviours) -> Result<Image, String>,
) -> Classification {
    let Compared {
        ours,
        theirs,
        tolerance,
        matched,
    } = images;
    let mut out = Classification::default();
    for def in BEHAVIOURS.iter().filter(|d| read.contains(d.name)) {
        let current = base.get(def.name).expect("every switch has an option");
        let mut matching: Vec<&'static str> = Vec::new();
        let mut alike = vec![current];
        let mut decides = false;
        for option in def.option_names().filter(|o| *o != current) {
            let mut alt = base;
            alt.set(def.name, option).expect("an option of the switch");
            let Ok(image) = render(alt) else { continue };
            if image.rgba == ours.rgba {
                alike.push(option); // this option draws the case alike
                continue;
            }
            decides = true;
            if compare(&image, theirs, tolerance).first.is_none() {
                matching.push(option);
            }
        }
        if !decides {
            continue;
        }
        // Several options drawing the device's image alike: the one the expectations name, else
        // the default (the option with the strongest evidence), else undecided.
        let preferred = prefer.get(def.name).map(String::as_str);
        let found = match matching.as_slice() {
            [option] => Some(*option),
            several => several
                .iter()
                .copied()
                .find(|o| Some(*o) == preferred)
                .or_else(|| several.iter().copied().find(|o| *o == def.default_name())),
        };
        match (matched, found) {
            (true, _) if matching.is_empty() => {
                // Matched: the scene's option, or the expected one where it draws alike.
                let shown = alike.iter().copied().find(|o| Some(*o) == preferred);
                out.shown.insert(def.name, shown.unwrap_or(current));
            }
            (false, Some(option)) => {
                out.shown.insert(def.name, option);
                out.matching.get_or_insert((def.name, option));
            }
            _ => {}
        }
    }
    out
}

/// The option each switch's deciding cases showed: `None` when no case decided it or they
/// disagree.
pub fn profile<'a>(
    cases: impl IntoIterator<Item = &'a BTreeMap<&'static str, &'static str>>,
) -> BTreeMap<&'static str, Option<&'static str>> {
    let mut seen: BTreeMap<&'static str, Vec<&'static str>> = BTreeMap::new();
    for shown in cases {
        for (name, option) in shown {
            seen.entry(name).or_default().push(option);
        }
    }
    BEHAVIOURS
        .iter()
        .map(|d| {
            let options = seen.get(d.name).map(Vec::as_slice).unwrap_or_default();
            let agreed = match options {
                [first, rest @ ..] if rest.iter().all(|o| o == first) => Some(*first),
                _ => None,
            };
            (d.name, agreed)
        })
        .collect()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn image(px: u8) -> Image {
        Image {
            width: 1,
            height: 1,
            rgba: vec![px, 0, 0, 255],
        }
    }

    /// A pretend case: `specular_fog` draws 10 unclamped and 20 clamped; the other switches
    /// draw it alike.
    fn render(b: Behaviours) -> Result<Image, String> {
        Ok(image(match b.get("specular_fog") {
            Some("clamped") => 20,
            _ => 10,
        }))
    }

    fn all() -> BehaviourSet {
        let mut set = BehaviourSet::default();
        for d in &BEHAVIOURS {
            set.insert(d.name);
        }
        set
    }

    #[test]
    fn only_the_switches_a_case_reads_are_tried() {
        let base = Behaviours::default();
        let none = BehaviourSet::default();
        let c = classify(
            base,
            none,
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(20),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            |_| panic!("the case reads no switch: nothing to render"),
        );
        assert_eq!(c, Classification::default());
        let mut read = BehaviourSet::default();
        read.insert("specular_fog");
        let mut tried = Vec::new();
        let c = classify(
            base,
            read,
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(20),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            |b| {
                tried.push(b);
                render(b)
            },
        );
        assert_eq!(c.matching, Some(("specular_fog", "clamped")));
        assert_eq!(tried.len(), 1, "one other option of the one switch read");
    }

    #[test]
    fn a_differing_case_that_matches_under_another_option_names_it() {
        let base = Behaviours::default();
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(20),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render,
        );
        assert_eq!(c.matching, Some(("specular_fog", "clamped")));
        assert_eq!(
            c.shown.into_iter().collect::<Vec<_>>(),
            [("specular_fog", "clamped")]
        );
    }

    #[test]
    fn a_matching_case_shows_the_option_it_was_drawn_with() {
        let base = Behaviours::default();
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(10),
                tolerance: Tolerance::Exact,
                matched: true,
            },
            render,
        );
        assert_eq!(c.matching, None);
        assert_eq!(
            c.shown.into_iter().collect::<Vec<_>>(),
            [("specular_fog", "unclamped")]
        );
    }

    #[test]
    fn options_drawing_alike_resolve_to_the_default() {
        // A scene set to `fogged` (30); the device draws 40, as `vertex_fogged_table_step` (the
        // default) and `step` both do: the default is named.
        let mut base = Behaviours::default();
        base.set("fog_start_equals_end", "fogged").unwrap();
        let render40 = |b: Behaviours| {
            Ok(image(match b.get("fog_start_equals_end") {
                Some("fogged") => 30,
                _ => 40,
            }))
        };
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render40,
        );
        assert_eq!(
            c.matching,
            Some(("fog_start_equals_end", "vertex_fogged_table_step"))
        );
        // Two non-default options alike: undecided.
        base.set("fog_start_equals_end", "vertex_fogged_table_step")
            .unwrap();
        let render_two = |b: Behaviours| {
            Ok(image(match b.get("fog_start_equals_end") {
                Some("vertex_fogged_table_step") => 30,
                _ => 40,
            }))
        };
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render_two,
        );
        assert_eq!(c.matching, None);
        // The expectations name one of them: that one.
        let prefer = BTreeMap::from([("fog_start_equals_end".to_string(), "step".to_string())]);
        let c = classify(
            base,
            all(),
            &prefer,
            Compared {
                ours: &image(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render_two,
        );
        assert_eq!(c.matching, Some(("fog_start_equals_end", "step")));
    }

    #[test]
    fn a_true_departure_shows_nothing() {
        let base = Behaviours::default();
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(99),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render,
        );
        assert_eq!(c, Classification::default());
        // Within the tolerance of both options: the case decides nothing.
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &image(10),
                theirs: &image(15),
                tolerance: Tolerance::Steps(10),
                matched: true,
            },
            render,
        );
        assert_eq!(c, Classification::default());
    }

    #[test]
    fn the_profile_keeps_what_the_cases_agree_on() {
        let a = BTreeMap::from([("specular_fog", "clamped"), ("minimum_size", "none")]);
        let b = BTreeMap::from([("specular_fog", "clamped"), ("minimum_size", "one_pixel")]);
        let p = profile([&a, &b]);
        assert_eq!(p["specular_fog"], Some("clamped"));
        assert_eq!(p["minimum_size"], None, "the cases disagree");
        assert_eq!(p["fog_without_specular"], None, "no case decided it");
        assert_eq!(p.len(), BEHAVIOURS.len());
    }
}

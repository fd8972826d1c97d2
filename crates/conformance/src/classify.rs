//! Which device behaviour a device's image shows (docs/spec/SPEC.md, "Device behaviours"): a
//! case is rendered again under every other option of every switch; an option that changes
//! pointillist's image and matches the device's is what the device does, and a case that
//! differs only because the device takes another option is a finding about the device, not a
//! departure.

use std::collections::BTreeMap;

use pointillist_core::Behaviours;
use pointillist_core::behaviour::{BEHAVIOURS, BehaviourSet};
use pointillist_core::tolerance::Tolerance;

use crate::compare::{Drawn, compare};
use crate::runner::Image;

/// What one case tells about the device's behaviours.
#[derive(Clone, Debug, Default, PartialEq, Eq)]
pub struct Classification {
    /// The switches whose options draw this case differently, each with the option whose image
    /// the device drew (when exactly one did).
    pub shown: BTreeMap<&'static str, &'static str>,
    /// For a case that differs under its own behaviours: the switches and options under which
    /// it matches (one switch, or two together where no single one does); empty when none do.
    pub matching: Vec<(&'static str, &'static str)>,
}

/// The most renders a differing case may spend on pairs of switches.
const MAX_PAIR_RENDERS: usize = 24;

/// A case's two images and how they compared.
#[derive(Clone, Copy)]
pub struct Compared<'a> {
    /// pointillist's image under the scene's behaviours (and its nudged images where the
    /// device's differs, SPEC 7).
    pub ours: &'a Drawn,
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
/// its own option, or the preferred one where that draws the case alike. A case that differs
/// under every single option is rendered under two switches changed together (pairs of the
/// switches in `read`, the preferred options first, at most 24 renders): a
/// pair whose image matches the device's is what the device does.
pub fn classify(
    base: Behaviours,
    read: BehaviourSet,
    prefer: &BTreeMap<String, String>,
    images: Compared<'_>,
    mut render: impl FnMut(Behaviours) -> Result<Drawn, String>,
) -> Classification {
    let Compared {
        ours,
        theirs,
        tolerance,
        matched,
    } = images;
    let mut out = Classification::default();
    // True once an option of one switch draws the device's image, decided or not.
    let mut single = false;
    for def in BEHAVIOURS.iter().filter(|d| read.contains(d.name)) {
        let current = base.get(def.name).expect("every switch has an option");
        let mut matching: Vec<&'static str> = Vec::new();
        let mut alike = vec![current];
        let mut decides = false;
        for option in def.option_names().filter(|o| *o != current) {
            let mut alt = base;
            alt.set(def.name, option).expect("an option of the switch");
            let Ok(image) = render(alt) else { continue };
            if image.image.rgba == ours.image.rgba {
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
        single |= !matching.is_empty();
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
                if out.matching.is_empty() {
                    out.matching.push((def.name, option));
                }
            }
            _ => {}
        }
    }
    if !matched
        && !single
        && let Some(pair) = matching_pair(base, read, prefer, images, &mut render)
    {
        for &(name, option) in &pair {
            out.shown.insert(name, option);
        }
        out.matching = pair.to_vec();
    }
    out
}

/// Two switches of `read` changed together under which the device's image matches: the pairs
/// of options that `prefer` names are tried first, then the others, at most
/// [`MAX_PAIR_RENDERS`] renders in all.
fn matching_pair(
    base: Behaviours,
    read: BehaviourSet,
    prefer: &BTreeMap<String, String>,
    images: Compared<'_>,
    render: &mut impl FnMut(Behaviours) -> Result<Drawn, String>,
) -> Option<[(&'static str, &'static str); 2]> {
    let switches: Vec<_> = BEHAVIOURS
        .iter()
        .filter(|d| read.contains(d.name))
        .collect();
    let others = |d: &'static pointillist_core::behaviour::BehaviourDef| {
        let current = base.get(d.name).expect("every switch has an option");
        let preferred = prefer.get(d.name).map(String::as_str);
        let mut options: Vec<&'static str> = d.option_names().filter(|o| *o != current).collect();
        options.sort_by_key(|o| Some(*o) != preferred);
        options
    };
    let mut candidates = Vec::new();
    for (i, a) in switches.iter().enumerate() {
        for b in &switches[i + 1..] {
            for oa in others(a) {
                for ob in others(b) {
                    let preferred = |d: &pointillist_core::behaviour::BehaviourDef, o| {
                        prefer.get(d.name).map(String::as_str) == Some(o)
                    };
                    let rank = usize::from(!preferred(a, oa)) + usize::from(!preferred(b, ob));
                    candidates.push((rank, [(a.name, oa), (b.name, ob)]));
                }
            }
        }
    }
    candidates.sort_by_key(|c| c.0);
    for (_, pair) in candidates.into_iter().take(MAX_PAIR_RENDERS) {
        let mut alt = base;
        for (name, option) in pair {
            alt.set(name, option).expect("an option of the switch");
        }
        let Ok(image) = render(alt) else { continue };
        if image.image.rgba != images.ours.image.rgba
            && compare(&image, images.theirs, images.tolerance)
                .first
                .is_none()
        {
            return Some(pair);
        }
    }
    None
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

    fn drawn(px: u8) -> Drawn {
        image(px).into()
    }

    /// A pretend case: `specular_fog` draws 10 unclamped and 20 clamped; the other switches
    /// draw it alike.
    fn render(b: Behaviours) -> Result<Drawn, String> {
        Ok(drawn(match b.get("specular_fog") {
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
                ours: &drawn(10),
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
                ours: &drawn(10),
                theirs: &image(20),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            |b| {
                tried.push(b);
                render(b)
            },
        );
        assert_eq!(c.matching, [("specular_fog", "clamped")]);
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
                ours: &drawn(10),
                theirs: &image(20),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render,
        );
        assert_eq!(c.matching, [("specular_fog", "clamped")]);
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
                ours: &drawn(10),
                theirs: &image(10),
                tolerance: Tolerance::Exact,
                matched: true,
            },
            render,
        );
        assert!(c.matching.is_empty());
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
            Ok(drawn(match b.get("fog_start_equals_end") {
                Some("fogged") => 30,
                _ => 40,
            }))
        };
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &drawn(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render40,
        );
        assert_eq!(
            c.matching,
            [("fog_start_equals_end", "vertex_fogged_table_step")]
        );
        // Two non-default options alike: undecided.
        base.set("fog_start_equals_end", "vertex_fogged_table_step")
            .unwrap();
        let render_two = |b: Behaviours| {
            Ok(drawn(match b.get("fog_start_equals_end") {
                Some("vertex_fogged_table_step") => 30,
                _ => 40,
            }))
        };
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &drawn(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render_two,
        );
        assert!(c.matching.is_empty());
        // The expectations name one of them: that one.
        let prefer = BTreeMap::from([("fog_start_equals_end".to_string(), "step".to_string())]);
        let c = classify(
            base,
            all(),
            &prefer,
            Compared {
                ours: &drawn(30),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            render_two,
        );
        assert_eq!(c.matching, [("fog_start_equals_end", "step")]);
    }

    #[test]
    fn a_true_departure_shows_nothing() {
        let base = Behaviours::default();
        let c = classify(
            base,
            all(),
            &BTreeMap::new(),
            Compared {
                ours: &drawn(10),
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
                ours: &drawn(10),
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

    /// A case that two switches draw only together (`golden.scaling` on Wine: a scaled
    /// pre-transformed point bounded by another POINTSIZE_MAX default) matches under the pair;
    /// the expectations' options are tried first.
    #[test]
    fn a_case_matching_under_two_switches_together_names_both() {
        let pair_render = |b: Behaviours| {
            let fog = b.get("specular_fog") == Some("clamped");
            let size = b.get("minimum_size") == Some("one_pixel");
            Ok(drawn(match (fog, size) {
                (true, true) => 30,
                (true, false) => 20,
                _ => 10,
            }))
        };
        let mut read = BehaviourSet::default();
        read.insert("specular_fog");
        read.insert("minimum_size");
        read.insert("zero_rhw");
        let prefer = BTreeMap::from([
            ("minimum_size".to_string(), "one_pixel".to_string()),
            ("specular_fog".to_string(), "clamped".to_string()),
        ]);
        let mut renders = 0;
        let c = classify(
            Behaviours::default(),
            read,
            &prefer,
            Compared {
                ours: &drawn(10),
                theirs: &image(30),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            |b| {
                renders += 1;
                pair_render(b)
            },
        );
        assert_eq!(
            c.matching,
            [("specular_fog", "clamped"), ("minimum_size", "one_pixel")]
        );
        assert_eq!(c.shown.get("minimum_size"), Some(&"one_pixel"));
        // Three single renders, then the preferred pair first.
        assert_eq!(renders, 4);
        // No pair draws 40: a departure, after at most the pair budget.
        let mut renders = 0;
        let c = classify(
            Behaviours::default(),
            read,
            &prefer,
            Compared {
                ours: &drawn(10),
                theirs: &image(40),
                tolerance: Tolerance::Exact,
                matched: false,
            },
            |b| {
                renders += 1;
                pair_render(b)
            },
        );
        assert!(c.matching.is_empty());
        assert!(renders <= 3 + MAX_PAIR_RENDERS);
    }
}

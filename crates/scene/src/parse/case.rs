//! The `[case]` table of a conformance case (docs/spec/SCENE.md, "Conformance cases").

use crate::SceneError;
use crate::case::{Case, Expect, Others, is_rule};
use crate::reader::{Value, array, fields, float, index, integer_in, string, u32_value};

use super::Parser;

const CASE_KEYS: &[&str] = &["title", "rules", "source", "others", "expect", "image"];
const EXPECT_KEYS: &[&str] = &[
    "pixel",
    "rect",
    "color",
    "colors",
    "mask",
    "tolerance",
    "depth",
];

impl Parser<'_> {
    /// Reads the `[case]` table; the target must be known (expectations are checked against it).
    pub(crate) fn case(&self, v: &Value<'_>) -> Result<Case, SceneError> {
        let src = &self.src;
        let f = fields(src, v, "case", CASE_KEYS)?;
        let title = string(src, f.require(src, "title")?, "case.title")?.trim();
        if title.is_empty() {
            return Err(src.error(&v.span(), "case.title", "the title is empty"));
        }
        let rules_v = f.require(src, "rules")?;
        let mut rules = Vec::new();
        for (i, r) in array(src, rules_v, "case.rules")?.iter().enumerate() {
            let path = index("case.rules", i);
            let rule = string(src, r, &path)?;
            if !is_rule(rule) {
                return Err(src.error(
                    &r.span(),
                    &path,
                    format!("`{rule}` is not a SPEC item (expected \"n\" or \"n.m\")"),
                ));
            }
            rules.push(rule.to_owned());
        }
        if rules.is_empty() {
            return Err(src.error(&rules_v.span(), "case.rules", "name at least one SPEC item"));
        }
        let source = match f.get("source") {
            None => None,
            Some(s) => Some(string(src, s, "case.source")?.to_owned()),
        };
        let mut expect = Vec::new();
        if let Some(list) = f.get("expect") {
            for (i, e) in array(src, list, "case.expect")?.iter().enumerate() {
                expect.push(self.expect(e, &index("case.expect", i))?);
            }
        }
        let image = match f.get("image") {
            None => None,
            Some(i) => Some(self.base.join(string(src, i, "case.image")?)),
        };
        let others = match f.get("others") {
            None if image.is_some() => Others::Any,
            None => Others::Clear,
            Some(o) => match string(src, o, "case.others")? {
                "clear" => Others::Clear,
                "any" => Others::Any,
                other => {
                    return Err(src.error(
                        &o.span(),
                        "case.others",
                        format!("unknown value `{other}` (expected \"clear\" or \"any\")"),
                    ));
                }
            },
        };
        Ok(Case {
            title: title.to_owned(),
            rules,
            source,
            others,
            expect,
            image,
        })
    }

    fn expect(&self, v: &Value<'_>, path: &str) -> Result<Expect, SceneError> {
        let src = &self.src;
        let f = fields(src, v, path, EXPECT_KEYS)?;
        let (w, h) = (i64::from(self.target.width), i64::from(self.target.height));
        let (key, at) = match (f.get("pixel"), f.get("rect")) {
            (Some(p), None) => ("pixel", p),
            (None, Some(r)) => ("rect", r),
            _ => {
                return Err(src.error(
                    &v.span(),
                    path,
                    "give exactly one of `pixel = [x, y]` and `rect = [x0, y0, x1, y1]`",
                ));
            }
        };
        let at_path = f.path(key);
        let coords = array(src, at, &at_path)?;
        let n = if key == "pixel" { 2 } else { 4 };
        if coords.len() != n {
            return Err(src.error(
                &at.span(),
                &at_path,
                format!("expected {n} integers, found {}", coords.len()),
            ));
        }
        let mut c = [0u32; 4];
        for (i, item) in coords.iter().enumerate() {
            let limit = if i % 2 == 0 { w } else { h };
            c[i] = integer_in(src, item, &index(&at_path, i), 0, limit - 1, false)? as u32;
        }
        let rect = if key == "pixel" {
            [c[0], c[1], c[0], c[1]]
        } else {
            c
        };
        if rect[0] > rect[2] || rect[1] > rect[3] {
            return Err(src.error(
                &at.span(),
                &at_path,
                "the first corner must be left of and above the last",
            ));
        }
        let colors = match (f.get("color"), f.get("colors")) {
            (Some(_), Some(c)) => {
                return Err(src.error(
                    &c.span(),
                    &f.path("colors"),
                    "give `color` or `colors`, not both",
                ));
            }
            (Some(c), None) => vec![u32_value(src, c, &f.path("color"))?],
            (None, Some(c)) => {
                let list = array(src, c, &f.path("colors"))?;
                if list.is_empty() {
                    return Err(src.error(&c.span(), &f.path("colors"), "the list is empty"));
                }
                list.iter()
                    .enumerate()
                    .map(|(i, x)| u32_value(src, x, &index(&f.path("colors"), i)))
                    .collect::<Result<_, _>>()?
            }
            (None, None) => Vec::new(),
        };
        let depth = match f.get("depth") {
            None => None,
            Some(d) => Some(float(src, d, &f.path("depth"))?),
        };
        if colors.is_empty() && depth.is_none() {
            return Err(src.error(
                &v.span(),
                path,
                "give what the pixels must hold: `color`, `colors` or `depth`",
            ));
        }
        let mask = match f.get("mask") {
            None => u32::MAX,
            Some(m) => u32_value(src, m, &f.path("mask"))?,
        };
        let tolerance = match f.get("tolerance") {
            None => 0,
            Some(t) => integer_in(src, t, &f.path("tolerance"), 0, 255, false)? as u8,
        };
        Ok(Expect {
            rect,
            colors,
            mask,
            tolerance,
            depth,
            origin: src.origin(&v.span(), path),
        })
    }
}

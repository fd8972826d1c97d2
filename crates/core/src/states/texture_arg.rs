//! `D3DTA_*`: the texture arguments of `COLORARGn`, `ALPHAARGn` and `RESULTARG` (SPEC 5.1), a
//! selector with the `COMPLEMENT` and `ALPHAREPLICATE` modifiers, read and written by name.

use super::strip_prefix_ci;

/// Mask of the `D3DTA_*` selector bits of a texture argument.
pub const TA_SELECTMASK: u32 = 0xF;
/// `D3DTA_DIFFUSE`: the vertex's diffuse colour.
pub const TA_DIFFUSE: u32 = 0;
/// `D3DTA_CURRENT`: the previous stage's result (diffuse at stage 0).
pub const TA_CURRENT: u32 = 1;
/// `D3DTA_TEXTURE`: the stage's texture sample.
pub const TA_TEXTURE: u32 = 2;
/// `D3DTA_TFACTOR`: the `TEXTUREFACTOR` render state.
pub const TA_TFACTOR: u32 = 3;
/// `D3DTA_SPECULAR`: the vertex's specular colour.
pub const TA_SPECULAR: u32 = 4;
/// `D3DTA_TEMP`: the temporary register.
pub const TA_TEMP: u32 = 5;
/// `D3DTA_CONSTANT`: the stage's `CONSTANT` state.
pub const TA_CONSTANT: u32 = 6;
/// `D3DTA_COMPLEMENT` modifier: `1 - x`.
pub const TA_COMPLEMENT: u32 = 0x10;
/// `D3DTA_ALPHAREPLICATE` modifier: the alpha copied to every channel.
pub const TA_ALPHAREPLICATE: u32 = 0x20;

/// `D3DTA_*` selector names.
const TA_SELECTOR_NAMES: &[(&str, u32)] = &[
    ("DIFFUSE", TA_DIFFUSE),
    ("CURRENT", TA_CURRENT),
    ("TEXTURE", TA_TEXTURE),
    ("TFACTOR", TA_TFACTOR),
    ("SPECULAR", TA_SPECULAR),
    ("TEMP", TA_TEMP),
    ("CONSTANT", TA_CONSTANT),
];

/// `D3DTA_*` modifier names.
const TA_MODIFIER_NAMES: &[(&str, u32)] = &[
    ("COMPLEMENT", TA_COMPLEMENT),
    ("ALPHAREPLICATE", TA_ALPHAREPLICATE),
];

/// Parses a texture argument: one selector and any modifiers joined by `|`, each
/// case-insensitive with an optional `D3DTA_` prefix ("TEXTURE", "texture | complement",
/// "D3DTA_TFACTOR|D3DTA_ALPHAREPLICATE"). `None` when there is not exactly one selector or a
/// word is unknown.
pub fn texture_arg_from_name(s: &str) -> Option<u32> {
    let mut selector = None;
    let mut modifiers = 0;
    for word in s.split('|') {
        let word = strip_prefix_ci(word.trim(), "D3DTA_");
        let find = |table: &[(&str, u32)]| {
            table
                .iter()
                .find(|(n, _)| n.eq_ignore_ascii_case(word))
                .map(|&(_, v)| v)
        };
        if let Some(v) = find(TA_SELECTOR_NAMES) {
            if selector.replace(v).is_some() {
                return None;
            }
        } else {
            modifiers |= find(TA_MODIFIER_NAMES)?;
        }
    }
    selector.map(|sel| sel | modifiers)
}

/// Names a texture argument for messages: "TEXTURE", "TFACTOR | COMPLEMENT | ALPHAREPLICATE";
/// unknown selectors and bits are written in hex.
pub fn texture_arg_name(arg: u32) -> String {
    let sel = arg & TA_SELECTMASK;
    let mut out = match TA_SELECTOR_NAMES.iter().find(|&&(_, v)| v == sel) {
        Some(&(n, _)) => n.to_string(),
        None => format!("{sel:#x}"),
    };
    let mut rest = arg & !TA_SELECTMASK;
    for &(n, v) in TA_MODIFIER_NAMES {
        if rest & v != 0 {
            out.push_str(" | ");
            out.push_str(n);
            rest &= !v;
        }
    }
    if rest != 0 {
        out.push_str(&format!(" | {rest:#x}"));
    }
    out
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn texture_args() {
        assert_eq!(texture_arg_from_name("TEXTURE"), Some(TA_TEXTURE));
        assert_eq!(
            texture_arg_from_name("texture | complement"),
            Some(TA_TEXTURE | TA_COMPLEMENT)
        );
        assert_eq!(
            texture_arg_from_name("D3DTA_TFACTOR|D3DTA_ALPHAREPLICATE"),
            Some(TA_TFACTOR | TA_ALPHAREPLICATE)
        );
        assert_eq!(
            texture_arg_from_name(" alphareplicate|current |COMPLEMENT "),
            Some(TA_CURRENT | TA_ALPHAREPLICATE | TA_COMPLEMENT)
        );
        assert_eq!(texture_arg_from_name("TEXTURE | DIFFUSE"), None);
        assert_eq!(texture_arg_from_name("COMPLEMENT"), None);
        assert_eq!(texture_arg_from_name("TEXTURE |"), None);
        assert_eq!(texture_arg_from_name(""), None);
        assert_eq!(texture_arg_from_name("BOGUS"), None);
        assert_eq!(
            texture_arg_name(TA_TFACTOR | TA_COMPLEMENT | TA_ALPHAREPLICATE),
            "TFACTOR | COMPLEMENT | ALPHAREPLICATE"
        );
        assert_eq!(texture_arg_name(0x109), "0x9 | 0x100");
        for sel in 0..=6 {
            for m in [
                0,
                TA_COMPLEMENT,
                TA_ALPHAREPLICATE,
                TA_COMPLEMENT | TA_ALPHAREPLICATE,
            ] {
                let arg = sel | m;
                assert_eq!(texture_arg_from_name(&texture_arg_name(arg)), Some(arg));
            }
        }
    }
}

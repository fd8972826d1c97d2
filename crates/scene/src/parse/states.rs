//! The `[states]` and `[stage.N]` tables (and a draw's `states` and `stage`): SetRenderState,
//! SetTextureStageState and SetSamplerState by D3D9 name, each value read by its state's kind
//! (SPEC 2.7, 5.1); unknown names and repeated states are errors.

use pointillist_core::states::{
    EnumType, RenderState, SamplerState, TextureStageState, ValueKind, texture_arg_from_name,
};
use toml::Spanned;
use toml::de::{DeString, DeValue};

use super::{MAX_STAGE, Parser};
use crate::reader::{
    Seen, Source, Value, boolean, entries, expected, fields, float, integer_in, join, string,
    table, u32_value,
};
use crate::{Command, SceneError};

impl Parser<'_> {
    pub(super) fn states(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let t = table(&self.src, v, path)?;
        let mut seen = Seen::default();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            let (state, value) = render_state(&self.src, &mut seen, k, v, &path)?;
            self.push(Command::RenderState(state, value), v, &path);
        }
        Ok(())
    }

    pub(super) fn stages(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let t = table(&self.src, v, path)?;
        let mut stages_seen: Vec<(usize, usize)> = Vec::new();
        for (k, v) in entries(t) {
            let path = join(path, k.get_ref());
            let stage = match k.get_ref().parse::<usize>() {
                Ok(n) if n <= MAX_STAGE => {
                    if let Some((_, line)) = stages_seen.iter().find(|(s, _)| *s == n) {
                        return Err(self.src.error(
                            &k.span(),
                            &path,
                            format!(
                                "stage {} is stage {n} again, given on line {line}",
                                k.get_ref()
                            ),
                        ));
                    }
                    stages_seen.push((n, self.src.origin(&k.span(), &path).line));
                    n
                }
                Ok(n) => {
                    return Err(self.src.error(
                        &k.span(),
                        &path,
                        format!("stage {n} is outside 0..={MAX_STAGE}"),
                    ));
                }
                Err(_) => {
                    return Err(self.src.error(
                        &k.span(),
                        &path,
                        format!(
                            "expected a stage number 0..={MAX_STAGE}, found `{}`",
                            k.get_ref()
                        ),
                    ));
                }
            };
            let t = table(&self.src, v, &path)?;
            let mut seen = Seen::default();
            for (k, v) in entries(t) {
                let path = join(&path, k.get_ref());
                let command = match stage_state(&self.src, &mut seen, k, v, &path)? {
                    StageState::Texture(state, value) => Command::TextureStageState {
                        stage,
                        state,
                        value,
                    },
                    StageState::Sampler(state, value) => Command::SamplerState {
                        sampler: stage,
                        state,
                        value,
                    },
                };
                self.push(command, v, &path);
            }
        }
        Ok(())
    }
}

/// The render state (SPEC 2.7) that key `k` of a table names, and its value `v` read by the
/// state's kind; a state that an earlier key of the table (`seen`) named is an error.
pub(super) fn render_state(
    src: &Source<'_>,
    seen: &mut Seen,
    k: &Spanned<DeString<'_>>,
    v: &Value<'_>,
    path: &str,
) -> Result<(RenderState, u32), SceneError> {
    let state = RenderState::from_name(k.get_ref()).ok_or_else(|| {
        src.error(
            &k.span(),
            path,
            format!("unknown render state `{}`", k.get_ref()),
        )
    })?;
    let name = state.name().unwrap_or_default();
    seen.once(src, name, k, path)?;
    let limit = (state == RenderState::ALPHAREF).then_some(255);
    Ok((state, state_value(src, state.kind(), name, limit, v, path)?))
}

/// A state of a stage's table: a texture stage state (SPEC 5.1) or a sampler state (SPEC 5.2)
/// and its value.
pub(super) enum StageState {
    Texture(TextureStageState, u32),
    Sampler(SamplerState, u32),
}

/// The texture stage or sampler state that key `k` of a stage's table names, and its value
/// `v` read by the state's kind; a state that an earlier key of the table (`seen`) named is an
/// error.
pub(super) fn stage_state(
    src: &Source<'_>,
    seen: &mut Seen,
    k: &Spanned<DeString<'_>>,
    v: &Value<'_>,
    path: &str,
) -> Result<StageState, SceneError> {
    let name = k.get_ref().as_ref();
    if let Some(state) = TextureStageState::from_name(name) {
        let canonical = state.name().unwrap_or_default();
        seen.once(src, canonical, k, path)?;
        let value = state_value(src, state.kind(), canonical, None, v, path)?;
        Ok(StageState::Texture(state, value))
    } else if let Some(state) = SamplerState::from_name(name) {
        let canonical = state.name().unwrap_or_default();
        seen.once(src, canonical, k, path)?;
        let value = state_value(src, state.kind(), canonical, None, v, path)?;
        Ok(StageState::Sampler(state, value))
    } else {
        Err(src.error(
            &k.span(),
            path,
            format!("unknown texture stage or sampler state `{name}`"),
        ))
    }
}

/// Reads a state value by its kind; `{ bits = N }` gives the raw 32 bits of any state. `name`
/// is the state's D3D name, `limit` an upper bound for integer states (ALPHAREF: 255).
pub(super) fn state_value(
    src: &Source<'_>,
    kind: ValueKind,
    name: &str,
    limit: Option<i64>,
    v: &Value<'_>,
    path: &str,
) -> Result<u32, SceneError> {
    if let DeValue::Table(_) = v.get_ref() {
        let f = fields(src, v, path, &["bits"])?;
        return u32_value(src, f.require(src, "bits")?, &f.path("bits"));
    }
    match kind {
        ValueKind::Float => float(src, v, path).map(f32::to_bits),
        ValueKind::Bool => boolean(src, v, path).map(u32::from),
        ValueKind::Color => u32_value(src, v, path),
        ValueKind::Int => match limit {
            Some(hi) => integer_in(src, v, path, 0, hi, false).map(|n| n as u32),
            None => u32_value(src, v, path),
        },
        ValueKind::Enum(e) => match v.get_ref() {
            DeValue::String(s) => e.value_from_name(s).ok_or_else(|| {
                let names: Vec<&str> = e.names().iter().map(|(n, _)| *n).collect();
                src.error(
                    &v.span(),
                    path,
                    format!(
                        "unknown {name} value `{s}` (expected one of: {})",
                        names.join(", ")
                    ),
                )
            }),
            DeValue::Boolean(b) if e == EnumType::ZBufferType => Ok(u32::from(*b)),
            _ if e == EnumType::ZBufferType => Err(expected(src, v, path, "true, false or a name")),
            _ => Err(expected(src, v, path, "a name (a string)")),
        },
        ValueKind::TextureArg => {
            let s = string(src, v, path)?;
            texture_arg_from_name(s).ok_or_else(|| {
                src.error(
                    &v.span(),
                    path,
                    format!(
                        "unknown texture argument `{s}` (expected DIFFUSE, CURRENT, TEXTURE, \
                         TFACTOR, SPECULAR, TEMP or CONSTANT, optionally with | COMPLEMENT \
                         and | ALPHAREPLICATE)"
                    ),
                )
            })
        }
    }
}

//! Typed reads from the spanned TOML tree, each failing with a located [`SceneError`].

use std::ops::Range;
use std::path::Path;

use toml::Spanned;
use toml::de::{DeArray, DeString, DeTable, DeValue};

use crate::error::{Origin, SceneError};

/// A spanned TOML value.
pub(crate) type Value<'i> = Spanned<DeValue<'i>>;

/// The scene text and its file name: turns byte spans into located errors.
pub(crate) struct Source<'a> {
    text: &'a str,
    file: &'a Path,
    /// Byte offset of the start of each line.
    line_starts: Vec<usize>,
}

impl<'a> Source<'a> {
    pub(crate) fn new(text: &'a str, file: &'a Path) -> Source<'a> {
        let line_starts = std::iter::once(0)
            .chain(text.match_indices('\n').map(|(i, _)| i + 1))
            .collect();
        Source {
            text,
            file,
            line_starts,
        }
    }

    /// The text at `span`.
    pub(crate) fn text(&self, span: &Range<usize>) -> &'a str {
        self.text.get(span.clone()).unwrap_or_default()
    }

    pub(crate) fn file(&self) -> &'a Path {
        self.file
    }

    /// One-based line and column (in characters) of a byte offset.
    fn position(&self, offset: usize) -> (usize, usize) {
        let offset = offset.min(self.text.len());
        let line = self.line_starts.partition_point(|&s| s <= offset).max(1);
        let start = self.line_starts[line - 1];
        let column = self
            .text
            .get(start..offset)
            .map_or(offset - start, |s| s.chars().count())
            + 1;
        (line, column)
    }

    /// Where the text at `span` is, under `key`.
    pub(crate) fn origin(&self, span: &Range<usize>, key: &str) -> Origin {
        let (line, column) = self.position(span.start);
        Origin {
            line,
            column,
            key: key.to_owned(),
        }
    }

    /// The error `message` about the value at `span`, found under `key`.
    pub(crate) fn error(
        &self,
        span: &Range<usize>,
        key: &str,
        message: impl Into<String>,
    ) -> SceneError {
        self.origin(span, key).error(self.file, message)
    }
}

/// `path.key`, or `key` at the top level.
pub(crate) fn join(path: &str, key: &str) -> String {
    if path.is_empty() {
        key.to_owned()
    } else {
        format!("{path}.{key}")
    }
}

/// `path[index]`.
pub(crate) fn index(path: &str, index: usize) -> String {
    format!("{path}[{index}]")
}

/// "1 value", "3 values".
pub(crate) fn count(n: usize, noun: &str) -> String {
    if n == 1 {
        format!("{n} {noun}")
    } else {
        format!("{n} {noun}s")
    }
}

/// "a string", "an integer", ...: what a value is, for "expected X, found Y" messages.
pub(crate) fn type_name(v: &DeValue<'_>) -> &'static str {
    match v {
        DeValue::String(_) => "a string",
        DeValue::Integer(_) => "an integer",
        DeValue::Float(_) => "a float",
        DeValue::Boolean(_) => "a boolean",
        DeValue::Datetime(_) => "a datetime",
        DeValue::Array(_) => "an array",
        DeValue::Table(_) => "a table",
    }
}

/// A table's entries in the order they appear in the file.
pub(crate) fn entries<'t, 'i>(
    table: &'t DeTable<'i>,
) -> Vec<(&'t Spanned<DeString<'i>>, &'t Value<'i>)> {
    let mut v: Vec<_> = table.iter().collect();
    v.sort_by_key(|(k, _)| k.span().start);
    v
}

/// The states a table has named so far, by canonical name: names are case-insensitive (and may
/// carry the `D3DRS_` prefix), so two keys that name one state are a duplicate key.
#[derive(Default)]
pub(crate) struct Seen {
    /// Canonical name, the key as written, its line.
    names: Vec<(&'static str, String, usize)>,
}

impl Seen {
    /// Records `key`, which names the state `canonical`, or fails when an earlier key of the
    /// table named it.
    pub(crate) fn once(
        &mut self,
        src: &Source<'_>,
        canonical: &'static str,
        key: &Spanned<DeString<'_>>,
        path: &str,
    ) -> Result<(), SceneError> {
        let name = key.get_ref().as_ref();
        if let Some((_, first, line)) = self.names.iter().find(|(c, ..)| *c == canonical) {
            return Err(src.error(
                &key.span(),
                path,
                format!(
                    "`{name}` names the same state as `{first}` on line {line} (state names \
                     are case-insensitive)"
                ),
            ));
        }
        let line = src.origin(&key.span(), path).line;
        self.names.push((canonical, name.to_owned(), line));
        Ok(())
    }
}

/// A table whose keys have been checked against a fixed list.
pub(crate) struct Fields<'t, 'i> {
    /// Key path of the table.
    pub path: String,
    /// Span of the table (its header, or the inline table).
    pub span: Range<usize>,
    table: &'t DeTable<'i>,
}

impl<'t, 'i> Fields<'t, 'i> {
    /// The value of `key`, when given.
    pub(crate) fn get(&self, key: &str) -> Option<&'t Value<'i>> {
        self.table.get(key)
    }

    /// The key path of `key` in this table.
    pub(crate) fn path(&self, key: &str) -> String {
        join(&self.path, key)
    }

    /// The value of `key`, or an error naming the table when it is missing.
    pub(crate) fn require(&self, src: &Source<'_>, key: &str) -> Result<&'t Value<'i>, SceneError> {
        self.get(key)
            .ok_or_else(|| src.error(&self.span, &self.path, format!("missing key `{key}`")))
    }
}

/// Reads `v` as a table whose keys all belong to `allowed`.
pub(crate) fn fields<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
    allowed: &[&str],
) -> Result<Fields<'t, 'i>, SceneError> {
    let table = table(src, v, path)?;
    for (k, _) in entries(table) {
        if !allowed.contains(&k.get_ref().as_ref()) {
            return Err(src.error(
                &k.span(),
                &join(path, k.get_ref()),
                format!("unknown key (expected one of: {})", allowed.join(", ")),
            ));
        }
    }
    Ok(Fields {
        path: path.to_owned(),
        span: v.span(),
        table,
    })
}

/// Reads `v` as a table holding exactly one of `keys` (a choice such as a shape or a matrix
/// maker): returns that key, its value and its key path.
pub(crate) fn one_of<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
    keys: &[&'static str],
) -> Result<(&'static str, &'t Value<'i>, String), SceneError> {
    let f = fields(src, v, path, keys)?;
    let given: Vec<&'static str> = keys
        .iter()
        .copied()
        .filter(|k| f.get(k).is_some())
        .collect();
    let [key] = given[..] else {
        return Err(src.error(
            &v.span(),
            path,
            format!("expected exactly one of: {}", keys.join(", ")),
        ));
    };
    Ok((key, f.require(src, key)?, f.path(key)))
}

/// The error "expected `what`, found <type of v>".
pub(crate) fn expected(src: &Source<'_>, v: &Value<'_>, path: &str, what: &str) -> SceneError {
    src.error(
        &v.span(),
        path,
        format!("expected {what}, found {}", type_name(v.get_ref())),
    )
}

/// Reads a table.
pub(crate) fn table<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
) -> Result<&'t DeTable<'i>, SceneError> {
    match v.get_ref() {
        DeValue::Table(t) => Ok(t),
        _ => Err(expected(src, v, path, "a table")),
    }
}

/// Reads an array.
pub(crate) fn array<'t, 'i>(
    src: &Source<'_>,
    v: &'t Value<'i>,
    path: &str,
) -> Result<&'t DeArray<'i>, SceneError> {
    match v.get_ref() {
        DeValue::Array(a) => Ok(a),
        _ => Err(expected(src, v, path, "an array")),
    }
}

/// Reads a string.
pub(crate) fn string<'t>(
    src: &Source<'_>,
    v: &'t Value<'_>,
    path: &str,
) -> Result<&'t str, SceneError> {
    match v.get_ref() {
        DeValue::String(s) => Ok(s),
        _ => Err(expected(src, v, path, "a string")),
    }
}

/// Reads a boolean.
pub(crate) fn boolean(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<bool, SceneError> {
    match v.get_ref() {
        DeValue::Boolean(b) => Ok(*b),
        _ => Err(expected(src, v, path, "true or false")),
    }
}

/// Reads an integer (any TOML integer that fits an i64).
pub(crate) fn integer(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<i64, SceneError> {
    match v.get_ref() {
        DeValue::Integer(i) => i64::from_str_radix(i.as_str(), i.radix())
            .map_err(|_| src.error(&v.span(), path, format!("integer {i} is too large"))),
        _ => Err(expected(src, v, path, "an integer")),
    }
}

/// Reads an integer in `lo..=hi`; `hex` writes the range in hexadecimal in messages.
pub(crate) fn integer_in(
    src: &Source<'_>,
    v: &Value<'_>,
    path: &str,
    lo: i64,
    hi: i64,
    hex: bool,
) -> Result<i64, SceneError> {
    let n = integer(src, v, path)?;
    if (lo..=hi).contains(&n) {
        Ok(n)
    } else {
        let range = if hex {
            format!("{lo:#X}..={hi:#X}").replace("0X", "0x")
        } else {
            format!("{lo}..={hi}")
        };
        Err(src.error(&v.span(), path, format!("{n} is outside {range}")))
    }
}

/// Reads a u32 (a D3DCOLOR, a mask, raw bits): an integer in `0..=0xFFFFFFFF`.
pub(crate) fn u32_value(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<u32, SceneError> {
    integer_in(src, v, path, 0, u32::MAX.into(), true).map(|n| n as u32)
}

/// Reads a number: a float, or an integer taken as a float. `inf` and `nan` are numbers; a
/// finite literal too large for an f64 is an error.
pub(crate) fn number(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<f64, SceneError> {
    match v.get_ref() {
        DeValue::Integer(i) => match i64::from_str_radix(i.as_str(), i.radix()) {
            Ok(n) => Ok(n as f64),
            Err(_) => i
                .as_str()
                .parse::<f64>()
                .ok()
                .filter(|x| x.is_finite())
                .ok_or_else(|| src.error(&v.span(), path, format!("integer {i} is too large"))),
        },
        DeValue::Float(f) => {
            let text = f.as_str();
            let x = text.parse::<f64>().ok();
            match x {
                Some(x) if x.is_finite() || text.contains("inf") || text.contains("nan") => Ok(x),
                _ => Err(src.error(&v.span(), path, format!("float {text} is out of range"))),
            }
        }
        _ => Err(expected(src, v, path, "a number")),
    }
}

/// Reads a number as an f32: a finite value beyond the f32 range is an error.
pub(crate) fn float(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<f32, SceneError> {
    let x = number(src, v, path)?;
    let y = x as f32;
    if x.is_finite() && !y.is_finite() {
        return Err(src.error(
            &v.span(),
            path,
            format!(
                "{} is outside the range of a 32-bit float",
                src.text(&v.span())
            ),
        ));
    }
    Ok(y)
}

/// Reads a finite f32.
pub(crate) fn finite(src: &Source<'_>, v: &Value<'_>, path: &str) -> Result<f32, SceneError> {
    let x = float(src, v, path)?;
    if x.is_finite() {
        Ok(x)
    } else {
        Err(src.error(
            &v.span(),
            path,
            format!("expected a finite number, found {x}"),
        ))
    }
}

/// Reads a finite f32 in `lo..=hi`.
pub(crate) fn finite_in(
    src: &Source<'_>,
    v: &Value<'_>,
    path: &str,
    lo: f32,
    hi: f32,
) -> Result<f32, SceneError> {
    let x = finite(src, v, path)?;
    if (lo..=hi).contains(&x) {
        Ok(x)
    } else {
        Err(src.error(&v.span(), path, format!("{x} is outside {lo:?}..={hi:?}")))
    }
}

/// Reads an array of exactly `N` numbers as f32s.
pub(crate) fn floats<const N: usize>(
    src: &Source<'_>,
    v: &Value<'_>,
    path: &str,
) -> Result<[f32; N], SceneError> {
    let a = array(src, v, path)?;
    if a.len() != N {
        return Err(src.error(
            &v.span(),
            path,
            format!(
                "expected an array of {N} numbers, found {}",
                count(a.len(), "value")
            ),
        ));
    }
    let mut out = [0.0; N];
    for (i, (o, item)) in out.iter_mut().zip(a.iter()).enumerate() {
        *o = float(src, item, &index(path, i))?;
    }
    Ok(out)
}

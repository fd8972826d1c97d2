//! The `[[draw]]` tables: DrawPrimitive(D3DPT_POINTLIST) with vertices given as typed rows or
//! read from a raw vertex file.

use pointillist_core::MAX_DRAW_VERTICES;
use pointillist_core::fvf::{self, Fvf, FvfError, RowValue};
use toml::de::DeValue;

use super::{Charge, DRAW_KEYS, Parser, check_readable};
use crate::reader::{
    Source, Value, array, expected, fields, index, integer, number, string, u32_value,
};
use crate::{Command, SceneError, VertexBytes};

impl Parser<'_> {
    pub(super) fn draw(&mut self, v: &Value<'_>, path: &str) -> Result<(), SceneError> {
        let f = fields(&self.src, v, path, DRAW_KEYS)?;
        self.changes(&f, false)?;
        let src = &self.src;
        let fvf_v = f.require(src, "fvf")?;
        let fvf_path = f.path("fvf");
        let fvf = match fvf_v.get_ref() {
            DeValue::String(s) => Fvf::parse(s),
            DeValue::Integer(_) => Fvf(u32_value(src, fvf_v, &fvf_path)?).validate(),
            _ => return Err(expected(src, fvf_v, &fvf_path, "a string")),
        }
        .map_err(|e| src.error(&fvf_v.span(), &fvf_path, e.to_string()))?;
        let vertices = match (f.get("vertices"), f.get("file")) {
            (Some(rows), None) => {
                let key = f.path("vertices");
                let bytes = encode_rows(src, fvf, rows, &key)?;
                self.charge(
                    Charge::Vertices,
                    bytes.len() as u64,
                    rows,
                    &key,
                    "these vertices",
                )?;
                bytes.into()
            }
            (None, Some(file)) => self.vertex_file(fvf, file, &f.path("file"))?,
            (None, None) => {
                return Err(src.error(&f.span, path, "missing key `vertices` (or `file`)"));
            }
            (Some(_), Some(file)) => {
                return Err(src.error(
                    &file.span(),
                    &f.path("file"),
                    "`file` cannot be given with `vertices`",
                ));
            }
        };
        self.push(Command::Draw { fvf, vertices }, v, path);
        Ok(())
    }

    /// Maps a raw vertex file ([`VertexBytes`]), after checking from its length that it holds
    /// whole vertices, at most [`MAX_DRAW_VERTICES`] of them, within [`MEMORY_BUDGET`] (SCENE.md,
    /// `file =`).
    fn vertex_file(
        &mut self,
        fvf: Fvf,
        v: &Value<'_>,
        path: &str,
    ) -> Result<VertexBytes, SceneError> {
        let src = &self.src;
        let name = string(src, v, path)?;
        let file = self.base.join(name);
        let len = check_readable(src, v, path, &file, "vertex")?;
        self.inputs.push(file.clone());
        let stride = fvf.stride() as u64;
        if len % stride != 0 {
            return Err(src.error(
                &v.span(),
                path,
                format!(
                    "vertex file `{}` holds {len} bytes, not a multiple of the FVF stride {stride}",
                    file.display(),
                ),
            ));
        }
        if len / stride > MAX_DRAW_VERTICES as u64 {
            return Err(src.error(
                &v.span(),
                path,
                format!(
                    "vertex file `{}` holds {} vertices, above the limit of {MAX_DRAW_VERTICES} \
                     per draw",
                    file.display(),
                    len / stride
                ),
            ));
        }
        self.charge(Charge::Vertices, len, v, path, "this vertex file")?;
        VertexBytes::read_file(&file, len).map_err(|e| self.src.error(&v.span(), path, e))
    }
}

/// Encodes typed vertex rows as FVF bytes.
fn encode_rows(
    src: &Source<'_>,
    fvf: Fvf,
    v: &Value<'_>,
    path: &str,
) -> Result<Vec<u8>, SceneError> {
    let rows = array(src, v, path)?;
    if rows.len() > MAX_DRAW_VERTICES {
        return Err(src.error(
            &v.span(),
            path,
            format!(
                "{} vertices are above the limit of {MAX_DRAW_VERTICES} per draw",
                rows.len()
            ),
        ));
    }
    let mut out = Vec::with_capacity(rows.len() * fvf.stride());
    let mut row = Vec::new();
    for (r, rv) in rows.iter().enumerate() {
        let row_path = index(path, r);
        let cells = array(src, rv, &row_path)?;
        row.clear();
        for (c, cell) in cells.iter().enumerate() {
            let cell_path = index(&row_path, c);
            row.push(match cell.get_ref() {
                DeValue::Integer(_) => RowValue::Int(integer(src, cell, &cell_path)?),
                DeValue::Float(_) => RowValue::Float(number(src, cell, &cell_path)?),
                _ => return Err(expected(src, cell, &cell_path, "a number")),
            });
        }
        fvf::encode_row(fvf, &row, &mut out)
            .map_err(|e: FvfError| src.error(&rv.span(), &row_path, e.to_string()))?;
    }
    Ok(out)
}

//! Flexible vertex formats (D3DFVF_*): parsing, layout, typed rows and raw little-endian bytes.
//!
//! A point list is a byte buffer laid out as its FVF says: position (XYZ, XYZW or XYZRHW), then
//! NORMAL, PSIZE, DIFFUSE, SPECULAR and up to eight texture coordinate sets of 1 to 4 floats,
//! each field little-endian. The pipeline reads vertices in place through a [`Layout`].

use std::fmt;

/// A D3DFVF code.
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub struct Fvf(pub u32);

const POSITION_MASK: u32 = 0x400E;
const TEXCOUNT_MASK: u32 = 0xF00;
const TEXCOUNT_SHIFT: u32 = 8;
/// Every bit pointillist understands: positions, NORMAL, PSIZE, DIFFUSE, SPECULAR, the texture
/// count and the 8 texture coordinate sizes.
const KNOWN_BITS: u32 = POSITION_MASK | 0x10 | 0x20 | 0x40 | 0x80 | TEXCOUNT_MASK | 0xFFFF_0000;

/// Why an FVF code, name list or row is not accepted.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum FvfError {
    /// A name in an FVF expression that is not a D3DFVF flag.
    UnknownName(String),
    /// Bits no D3DFVF flag defines.
    UnknownBits(u32),
    /// The format has no XYZ, XYZW or XYZRHW position.
    NoPosition,
    /// XYZB1..XYZB5 vertex blending, which points do not use and pointillist does not decode.
    BlendWeights,
    /// A typed row with the wrong number of values.
    RowLength {
        /// Values the FVF needs.
        expected: usize,
        /// Values the row has.
        found: usize,
    },
    /// A value of a typed row that does not fit its field.
    RowValue {
        /// Zero-based column in the row.
        column: usize,
        /// The field's name.
        field: &'static str,
        /// What is wrong.
        message: String,
    },
}

impl fmt::Display for FvfError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            FvfError::UnknownName(n) => write!(
                f,
                "unknown FVF flag `{n}` (expected XYZ, XYZW, XYZRHW, NORMAL, PSIZE, DIFFUSE, \
                 SPECULAR, TEX0..TEX8, TEXCOORDSIZE1..4(n) or a number)"
            ),
            FvfError::UnknownBits(b) => write!(f, "unknown FVF bits {b:#x}"),
            FvfError::NoPosition => write!(f, "FVF has no position (XYZ, XYZW or XYZRHW)"),
            FvfError::BlendWeights => {
                write!(f, "vertex blending formats XYZB1..XYZB5 are not supported")
            }
            FvfError::RowLength { expected, found } => {
                write!(f, "row has {found} values, the FVF needs {expected}")
            }
            FvfError::RowValue {
                column,
                field,
                message,
            } => write!(f, "value {} ({field}): {message}", column + 1),
        }
    }
}

impl std::error::Error for FvfError {}

/// One field of a vertex, in FVF order.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Field {
    /// XYZ (3 floats), XYZW or XYZRHW (4 floats).
    Position(usize),
    /// NORMAL: 3 floats, the object-space normal vertex lighting reads (SPEC 8.3).
    Normal,
    /// PSIZE: one float.
    PSize,
    /// DIFFUSE: one D3DCOLOR.
    Diffuse,
    /// SPECULAR: one D3DCOLOR.
    Specular,
    /// A texture coordinate set of `size` floats.
    Tex {
        /// The set's index, 0..8.
        set: usize,
        /// Floats in the set, 1..=4.
        size: usize,
    },
}

impl Field {
    /// Values this field takes in a typed row (and 4-byte words in the buffer).
    pub fn len(self) -> usize {
        match self {
            Field::Position(n) => n,
            Field::Normal => 3,
            Field::PSize | Field::Diffuse | Field::Specular => 1,
            Field::Tex { size, .. } => size,
        }
    }

    /// Never true: every field has at least one value.
    pub fn is_empty(self) -> bool {
        false
    }

    fn name(self) -> &'static str {
        match self {
            Field::Position(_) => "position",
            Field::Normal => "normal",
            Field::PSize => "psize",
            Field::Diffuse => "diffuse",
            Field::Specular => "specular",
            Field::Tex { .. } => "texture coordinate",
        }
    }
}

impl Fvf {
    /// D3DFVF_XYZ: untransformed position.
    pub const XYZ: Fvf = Fvf(0x002);
    /// D3DFVF_XYZRHW: pre-transformed screen position with reciprocal w.
    pub const XYZRHW: Fvf = Fvf(0x004);
    /// D3DFVF_XYZW: untransformed homogeneous position.
    pub const XYZW: Fvf = Fvf(0x4002);
    /// D3DFVF_NORMAL.
    pub const NORMAL: Fvf = Fvf(0x010);
    /// D3DFVF_PSIZE: per-vertex point size.
    pub const PSIZE: Fvf = Fvf(0x020);
    /// D3DFVF_DIFFUSE.
    pub const DIFFUSE: Fvf = Fvf(0x040);
    /// D3DFVF_SPECULAR.
    pub const SPECULAR: Fvf = Fvf(0x080);
    /// D3DFVF_TEX0: no texture coordinates.
    pub const TEX0: Fvf = Fvf(0x000);
    /// D3DFVF_TEX1: one texture coordinate set.
    pub const TEX1: Fvf = Fvf(0x100);
    /// D3DFVF_TEX2.
    pub const TEX2: Fvf = Fvf(0x200);
    /// D3DFVF_TEX3.
    pub const TEX3: Fvf = Fvf(0x300);
    /// D3DFVF_TEX4.
    pub const TEX4: Fvf = Fvf(0x400);
    /// D3DFVF_TEX5.
    pub const TEX5: Fvf = Fvf(0x500);
    /// D3DFVF_TEX6.
    pub const TEX6: Fvf = Fvf(0x600);
    /// D3DFVF_TEX7.
    pub const TEX7: Fvf = Fvf(0x700);
    /// D3DFVF_TEX8.
    pub const TEX8: Fvf = Fvf(0x800);

    /// D3DFVF_TEXCOORDSIZEn(set): the bits that give set `set` `floats` coordinates (1..=4).
    pub const fn texcoord_size(floats: usize, set: usize) -> Fvf {
        let code = match floats {
            1 => 3,
            3 => 1,
            4 => 2,
            _ => 0,
        };
        Fvf(code << (16 + 2 * set as u32))
    }

    /// Parses `"XYZ | PSIZE | DIFFUSE | TEX1"` (names case-insensitive, `D3DFVF_` optional,
    /// `TEXCOORDSIZE3(0)` for set sizes) or a number (`0x142`), then validates it.
    pub fn parse(s: &str) -> Result<Fvf, FvfError> {
        let mut bits = 0u32;
        for part in s.split('|') {
            let part = part.trim();
            let upper = part.to_ascii_uppercase();
            let name = upper.strip_prefix("D3DFVF_").unwrap_or(&upper);
            let flag = if let Some(hex) = name.strip_prefix("0X") {
                u32::from_str_radix(hex, 16).ok()
            } else if name.bytes().all(|b| b.is_ascii_digit()) && !name.is_empty() {
                name.parse().ok()
            } else if let Some(rest) = name.strip_prefix("TEXCOORDSIZE") {
                parse_texcoord_size(rest)
            } else {
                Some(match name {
                    "XYZ" => Fvf::XYZ.0,
                    "XYZRHW" => Fvf::XYZRHW.0,
                    "XYZW" => Fvf::XYZW.0,
                    "NORMAL" => Fvf::NORMAL.0,
                    "PSIZE" => Fvf::PSIZE.0,
                    "DIFFUSE" => Fvf::DIFFUSE.0,
                    "SPECULAR" => Fvf::SPECULAR.0,
                    _ => match name.strip_prefix("TEX").and_then(|n| n.parse::<u32>().ok()) {
                        Some(n @ 0..=8) => n << TEXCOUNT_SHIFT,
                        _ => return Err(FvfError::UnknownName(part.to_string())),
                    },
                })
            };
            bits |= flag.ok_or_else(|| FvfError::UnknownName(part.to_string()))?;
        }
        Fvf(bits).validate()
    }

    /// Checks that the code is one pointillist can decode.
    pub fn validate(self) -> Result<Fvf, FvfError> {
        let unknown = self.0 & !KNOWN_BITS;
        if unknown != 0 {
            return Err(FvfError::UnknownBits(unknown));
        }
        match self.0 & POSITION_MASK {
            0x002 | 0x004 | 0x4002 => {}
            0 => return Err(FvfError::NoPosition),
            _ => return Err(FvfError::BlendWeights),
        }
        if self.tex_count() > 8 {
            return Err(FvfError::UnknownBits(self.0 & TEXCOUNT_MASK));
        }
        Ok(self)
    }

    /// True for XYZRHW: screen-space positions, sized in pixels, never scaled (SPEC 2.2).
    pub fn is_pretransformed(self) -> bool {
        self.0 & POSITION_MASK == Fvf::XYZRHW.0
    }

    /// True when vertices carry PSIZE.
    pub fn has_psize(self) -> bool {
        self.0 & Fvf::PSIZE.0 != 0
    }

    /// Number of texture coordinate sets.
    pub fn tex_count(self) -> usize {
        ((self.0 & TEXCOUNT_MASK) >> TEXCOUNT_SHIFT) as usize
    }

    /// Floats in texture coordinate set `set` (1..=4; 2 unless TEXCOORDSIZEn says otherwise).
    pub fn tex_size(self, set: usize) -> usize {
        match (self.0 >> (16 + 2 * set)) & 3 {
            0 => 2,
            1 => 3,
            2 => 4,
            _ => 1,
        }
    }

    /// The fields of one vertex in buffer order.
    pub fn fields(self) -> impl Iterator<Item = Field> {
        let pos = if self.0 & POSITION_MASK == Fvf::XYZ.0 {
            3
        } else {
            4
        };
        let flag = |f: Fvf, field: Field| (self.0 & f.0 != 0).then_some(field);
        [
            Some(Field::Position(pos)),
            flag(Fvf::NORMAL, Field::Normal),
            flag(Fvf::PSIZE, Field::PSize),
            flag(Fvf::DIFFUSE, Field::Diffuse),
            flag(Fvf::SPECULAR, Field::Specular),
        ]
        .into_iter()
        .flatten()
        .chain((0..self.tex_count()).map(move |set| Field::Tex {
            set,
            size: self.tex_size(set),
        }))
    }

    /// Values in one typed row.
    pub fn row_len(self) -> usize {
        self.fields().map(Field::len).sum()
    }

    /// Bytes per vertex.
    pub fn stride(self) -> usize {
        self.row_len() * 4
    }

    /// Byte offsets of each field, for reading vertices in place.
    pub fn layout(self) -> Layout {
        let mut l = Layout {
            stride: self.stride(),
            position_len: 3,
            normal: None,
            psize: None,
            diffuse: None,
            specular: None,
            tex: [None; 8],
        };
        let mut offset = 0;
        for field in self.fields() {
            match field {
                Field::Position(n) => l.position_len = n,
                Field::Normal => l.normal = Some(offset),
                Field::PSize => l.psize = Some(offset),
                Field::Diffuse => l.diffuse = Some(offset),
                Field::Specular => l.specular = Some(offset),
                Field::Tex { set, size } => l.tex[set] = Some((offset, size)),
            }
            offset += field.len() * 4;
        }
        l
    }
}

fn parse_texcoord_size(rest: &str) -> Option<u32> {
    // "3(0)" -> floats 3, set 0
    let (floats, set) = rest.strip_suffix(')')?.split_once('(')?;
    let floats: usize = floats.trim().parse().ok()?;
    let set: usize = set.trim().parse().ok()?;
    ((1..=4).contains(&floats) && set < 8).then(|| Fvf::texcoord_size(floats, set).0)
}

/// Where each field of a vertex lies in its bytes; computed once per draw.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Layout {
    /// Bytes per vertex.
    pub stride: usize,
    /// 3 (XYZ) or 4 (XYZW, XYZRHW) position floats at offset 0.
    pub position_len: usize,
    /// Offset of NORMAL (three floats).
    pub normal: Option<usize>,
    /// Offset of PSIZE.
    pub psize: Option<usize>,
    /// Offset of DIFFUSE.
    pub diffuse: Option<usize>,
    /// Offset of SPECULAR.
    pub specular: Option<usize>,
    /// Offset and float count of each texture coordinate set.
    pub tex: [Option<(usize, usize)>; 8],
}

/// Reads a little-endian f32 at `offset`; the caller guarantees `offset + 4 <= bytes.len()`.
#[inline]
pub fn read_f32(bytes: &[u8], offset: usize) -> f32 {
    f32::from_bits(read_u32(bytes, offset))
}

/// Reads a little-endian u32 at `offset`; the caller guarantees `offset + 4 <= bytes.len()`.
#[inline]
pub fn read_u32(bytes: &[u8], offset: usize) -> u32 {
    let mut word = [0u8; 4];
    word.copy_from_slice(&bytes[offset..offset + 4]);
    u32::from_le_bytes(word)
}

/// One value of a typed row.
#[derive(Copy, Clone, Debug, PartialEq)]
pub enum RowValue {
    /// A number written with a fraction or exponent.
    Float(f64),
    /// An integer.
    Int(i64),
}

/// Appends one typed row (`x y z [rhw] [psize] [diffuse] [specular] [u v]...`: floats for float
/// fields, integers 0..=0xFFFFFFFF for colours) to `out` as FVF bytes.
pub fn encode_row(fvf: Fvf, row: &[RowValue], out: &mut Vec<u8>) -> Result<(), FvfError> {
    let expected = fvf.row_len();
    if row.len() != expected {
        return Err(FvfError::RowLength {
            expected,
            found: row.len(),
        });
    }
    let mut column = 0;
    for field in fvf.fields() {
        for _ in 0..field.len() {
            let bad = |message: String| FvfError::RowValue {
                column,
                field: field.name(),
                message,
            };
            let word = match (field, row[column]) {
                (Field::Diffuse | Field::Specular, RowValue::Int(v)) => u32::try_from(v)
                    .map_err(|_| bad(format!("colour {v} is outside 0..=0xFFFFFFFF")))?,
                (Field::Diffuse | Field::Specular, RowValue::Float(v)) => {
                    return Err(bad(format!(
                        "colour must be an integer D3DCOLOR, found {v}"
                    )));
                }
                (_, RowValue::Float(v)) => (v as f32).to_bits(),
                (_, RowValue::Int(v)) => (v as f32).to_bits(),
            };
            out.extend_from_slice(&word.to_le_bytes());
            column += 1;
        }
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn parse_names_and_numbers() {
        let f = Fvf::parse("XYZ | PSIZE | diffuse").unwrap();
        assert_eq!(f.0, 0x062);
        assert_eq!(f.stride(), 20);
        assert_eq!(Fvf::parse("0x142").unwrap().0, 0x142);
        assert_eq!(Fvf::parse("D3DFVF_XYZRHW|D3DFVF_TEX2").unwrap().0, 0x204);
        let f = Fvf::parse("XYZ | TEX2 | TEXCOORDSIZE1(0) | TEXCOORDSIZE4(1)").unwrap();
        assert_eq!((f.tex_size(0), f.tex_size(1), f.stride()), (1, 4, 32));
        assert_eq!(
            Fvf::parse("XYZ | COLOR").unwrap_err(),
            FvfError::UnknownName("COLOR".into())
        );
        assert_eq!(Fvf::parse("DIFFUSE").unwrap_err(), FvfError::NoPosition);
        assert_eq!(
            Fvf::parse("0x1002").unwrap_err(),
            FvfError::UnknownBits(0x1000)
        );
        assert_eq!(Fvf::parse("0x006").unwrap_err(), FvfError::BlendWeights);
        assert!(Fvf::parse("XYZ | TEX9").is_err());
    }

    #[test]
    fn layout_follows_fvf_order() {
        let f = Fvf::parse("XYZRHW | NORMAL | PSIZE | DIFFUSE | SPECULAR | TEX2").unwrap();
        let l = f.layout();
        assert_eq!(l.position_len, 4);
        assert_eq!(l.normal, Some(16));
        assert_eq!(l.psize, Some(28));
        assert_eq!(l.diffuse, Some(32));
        assert_eq!(l.specular, Some(36));
        assert_eq!(l.tex[0], Some((40, 2)));
        assert_eq!(l.tex[1], Some((48, 2)));
        assert_eq!(l.stride, 56);
        assert!(f.is_pretransformed());
        let n = Fvf::parse("XYZ | NORMAL | DIFFUSE").unwrap().layout();
        assert_eq!((n.normal, n.diffuse, n.stride), (Some(12), Some(24), 28));
        assert_eq!(Fvf::XYZ.layout().normal, None);
    }

    #[test]
    fn encode_rows_checks_each_value() {
        let f = Fvf::parse("XYZ | PSIZE | DIFFUSE").unwrap();
        let mut out = Vec::new();
        let row = [
            RowValue::Float(0.5),
            RowValue::Int(1),
            RowValue::Float(10.0),
            RowValue::Float(0.1),
            RowValue::Int(0xFFEE_FEFF),
        ];
        encode_row(f, &row, &mut out).unwrap();
        assert_eq!(read_f32(&out, 0), 0.5);
        assert_eq!(read_f32(&out, 4), 1.0);
        assert_eq!(read_f32(&out, 12), 0.1);
        assert_eq!(read_u32(&out, 16), 0xFFEE_FEFF);
        let err = encode_row(f, &row[..4], &mut out).unwrap_err();
        assert_eq!(err.to_string(), "row has 4 values, the FVF needs 5");
        let mut bad = row;
        bad[4] = RowValue::Int(-1);
        let err = encode_row(f, &bad, &mut out).unwrap_err();
        assert_eq!(
            err.to_string(),
            "value 5 (diffuse): colour -1 is outside 0..=0xFFFFFFFF"
        );
    }
}

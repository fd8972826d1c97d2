//! The call stream: a scene's D3D9 calls as a versioned binary file a replayer executes on a
//! real `IDirect3DDevice9` (docs/CONFORMANCE.md, "The call stream", is the format's
//! specification; this module is its one implementation in Rust).
//!
//! Layout, all little-endian: the 8 bytes `PTLCALLS`, `u32` version ([`VERSION`]), `u32`
//! target width and height, `u32` flags ([`FLAG_SOFTWARE_VERTEX_PROCESSING`]); then records,
//! each `u32` opcode, `u32` payload length in bytes and the payload; the last record is
//! [`Op::End`] with an empty payload and nothing may follow it.

use std::fmt;
use std::io::{self, Write};

use pointillist_core::texture::Level;

/// The first eight bytes of every call stream.
pub const MAGIC: [u8; 8] = *b"PTLCALLS";
/// The format version this module writes and reads.
pub const VERSION: u32 = 1;
/// Header flag: create the device with D3DCREATE_SOFTWARE_VERTEXPROCESSING.
pub const FLAG_SOFTWARE_VERTEX_PROCESSING: u32 = 1;
/// Texture id of [`Call::SetTexture`] that unbinds (SetTexture(stage, NULL)).
pub const NO_TEXTURE: u32 = u32::MAX;
/// D3DTS_VIEW.
pub const D3DTS_VIEW: u32 = 2;
/// D3DTS_PROJECTION.
pub const D3DTS_PROJECTION: u32 = 3;
/// D3DTS_WORLD (D3DTS_WORLDMATRIX(0)).
pub const D3DTS_WORLD: u32 = 256;

/// The record opcodes of version 1.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
#[repr(u32)]
pub enum Op {
    /// The end of the stream.
    End = 0,
    /// Clear of the whole target: `u32` D3DCOLOR, `f32` depth.
    Clear = 1,
    /// SetRenderState: `u32` D3DRENDERSTATETYPE, `u32` raw value.
    RenderState = 2,
    /// SetTextureStageState: `u32` stage, `u32` D3DTEXTURESTAGESTATETYPE, `u32` raw value.
    TextureStageState = 3,
    /// SetSamplerState: `u32` sampler, `u32` D3DSAMPLERSTATETYPE, `u32` raw value.
    SamplerState = 4,
    /// CreateTexture (A8R8G8B8, every level given): `u32` id, `u32` level count, then per
    /// level `u32` width, `u32` height and `width * height` `u32` D3DCOLOR texels, rows top
    /// to bottom.
    CreateTexture = 5,
    /// SetTexture: `u32` stage, `u32` texture id or [`NO_TEXTURE`].
    SetTexture = 6,
    /// SetTransform: `u32` D3DTRANSFORMSTATETYPE, 16 `f32`, row by row.
    Transform = 7,
    /// SetViewport: `u32` x, y, width, height, `f32` min_z, max_z.
    Viewport = 8,
    /// SetClipPlane: `u32` index, 4 `f32`.
    ClipPlane = 9,
    /// SetFVF + DrawPrimitiveUP(D3DPT_POINTLIST): `u32` FVF, `u32` stride, `u32` vertex count,
    /// then `count * stride` bytes of vertices.
    DrawPoints = 10,
    /// SetMaterial: D3DMATERIAL9, 17 `f32` (diffuse, ambient, specular, emissive RGBA, power).
    Material = 11,
    /// SetLight: `u32` index, then D3DLIGHT9 (104 bytes: `u32` type and 25 `f32`).
    Light = 12,
    /// LightEnable: `u32` index, `u32` 0 or 1.
    LightEnable = 13,
}

impl Op {
    /// The opcode of a number, if version 1 defines it.
    pub fn from_u32(v: u32) -> Option<Op> {
        use Op::*;
        [
            End,
            Clear,
            RenderState,
            TextureStageState,
            SamplerState,
            CreateTexture,
            SetTexture,
            Transform,
            Viewport,
            ClipPlane,
            DrawPoints,
            Material,
            Light,
            LightEnable,
        ]
        .into_iter()
        .find(|op| *op as u32 == v)
    }
}

/// D3DMATERIAL9.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Material {
    /// Diffuse RGBA.
    pub diffuse: [f32; 4],
    /// Ambient RGBA.
    pub ambient: [f32; 4],
    /// Specular RGBA.
    pub specular: [f32; 4],
    /// Emissive RGBA.
    pub emissive: [f32; 4],
    /// Specular power.
    pub power: f32,
}

/// D3DLIGHT9, field for field.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Light {
    /// D3DLIGHTTYPE: 1 point, 2 spot, 3 directional.
    pub kind: u32,
    /// Diffuse RGBA.
    pub diffuse: [f32; 4],
    /// Specular RGBA.
    pub specular: [f32; 4],
    /// Ambient RGBA.
    pub ambient: [f32; 4],
    /// Position (world space).
    pub position: [f32; 3],
    /// Direction (world space).
    pub direction: [f32; 3],
    /// Range.
    pub range: f32,
    /// Spot falloff.
    pub falloff: f32,
    /// Attenuation0, 1, 2.
    pub attenuation: [f32; 3],
    /// Spot inner cone angle, radians.
    pub theta: f32,
    /// Spot outer cone angle, radians.
    pub phi: f32,
}

/// One record of a stream, decoded.
#[derive(Clone, Debug, PartialEq)]
pub enum Call {
    /// Clear of the whole target and depth buffer.
    Clear {
        /// D3DCOLOR.
        color: u32,
        /// Depth.
        depth: f32,
    },
    /// SetRenderState.
    RenderState {
        /// D3DRENDERSTATETYPE.
        state: u32,
        /// Raw value.
        value: u32,
    },
    /// SetTextureStageState.
    TextureStageState {
        /// Stage.
        stage: u32,
        /// D3DTEXTURESTAGESTATETYPE.
        state: u32,
        /// Raw value.
        value: u32,
    },
    /// SetSamplerState.
    SamplerState {
        /// Sampler.
        sampler: u32,
        /// D3DSAMPLERSTATETYPE.
        state: u32,
        /// Raw value.
        value: u32,
    },
    /// CreateTexture with every level's texels.
    CreateTexture {
        /// The id later [`Call::SetTexture`]s name.
        id: u32,
        /// Level 0 first.
        levels: Vec<Level>,
    },
    /// SetTexture.
    SetTexture {
        /// Stage.
        stage: u32,
        /// Texture id or [`NO_TEXTURE`].
        id: u32,
    },
    /// SetTransform.
    Transform {
        /// D3DTRANSFORMSTATETYPE.
        which: u32,
        /// Rows.
        matrix: [[f32; 4]; 4],
    },
    /// SetViewport.
    Viewport {
        /// x, y, width, height.
        rect: [u32; 4],
        /// min_z, max_z.
        depth: [f32; 2],
    },
    /// SetClipPlane.
    ClipPlane {
        /// Index 0..=5.
        index: u32,
        /// (a, b, c, d).
        plane: [f32; 4],
    },
    /// SetFVF + DrawPrimitiveUP(D3DPT_POINTLIST).
    DrawPoints {
        /// D3DFVF code.
        fvf: u32,
        /// Bytes per vertex.
        stride: u32,
        /// The vertices.
        vertices: Vec<u8>,
    },
    /// SetMaterial.
    Material(Material),
    /// SetLight.
    Light {
        /// Light index.
        index: u32,
        /// The light.
        light: Light,
    },
    /// LightEnable.
    LightEnable {
        /// Light index.
        index: u32,
        /// On or off.
        enable: bool,
    },
}

/// The header of a stream.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Header {
    /// Render target width.
    pub width: u32,
    /// Render target height.
    pub height: u32,
    /// Flags ([`FLAG_SOFTWARE_VERTEX_PROCESSING`]).
    pub flags: u32,
}

/// Writes a stream record by record to `W` (a file, or memory by default) as it goes, so that
/// no copy of a scene's texels and vertices is held; [`CallWriter::finish`] appends the end
/// record and gives back the output, or the first write error (the writes after it are skipped).
#[derive(Debug)]
pub struct CallWriter<W: Write = Vec<u8>> {
    out: W,
    /// A record's fixed fields, reused.
    scratch: Vec<u8>,
    /// Bytes written.
    bytes: u64,
    error: Option<io::Error>,
}

fn put_f32s(out: &mut Vec<u8>, v: &[f32]) {
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

fn put_u32s(out: &mut Vec<u8>, v: &[u32]) {
    for x in v {
        out.extend_from_slice(&x.to_le_bytes());
    }
}

impl CallWriter {
    /// A stream in memory for a target of `header.width` x `header.height`.
    pub fn new(header: Header) -> CallWriter {
        CallWriter::to(Vec::new(), header)
    }
}

impl<W: Write> CallWriter<W> {
    /// A stream written to `out` for a target of `header.width` x `header.height`.
    pub fn to(out: W, header: Header) -> CallWriter<W> {
        let mut w = CallWriter {
            out,
            scratch: MAGIC.to_vec(),
            bytes: 0,
            error: None,
        };
        put_u32s(
            &mut w.scratch,
            &[VERSION, header.width, header.height, header.flags],
        );
        w.flush_scratch();
        w
    }

    /// Writes `bytes` unless a write failed before.
    fn write(&mut self, bytes: &[u8]) {
        if self.error.is_none() {
            match self.out.write_all(bytes) {
                Ok(()) => self.bytes += bytes.len() as u64,
                Err(e) => self.error = Some(e),
            }
        }
    }

    /// Writes and empties the scratch buffer.
    fn flush_scratch(&mut self) {
        let scratch = std::mem::take(&mut self.scratch);
        self.write(&scratch);
        self.scratch = scratch;
        self.scratch.clear();
    }

    /// Starts a record of `op` whose payload is `len` bytes: its header goes to the scratch
    /// buffer. A payload the format cannot state (over 4 GiB) fails the stream.
    fn start(&mut self, op: Op, len: u64) {
        let len = u32::try_from(len).unwrap_or_else(|_| {
            self.error.get_or_insert_with(|| {
                io::Error::other(format!(
                    "a {op:?} record of {len} bytes exceeds the format's 4 GiB"
                ))
            });
            0
        });
        put_u32s(&mut self.scratch, &[op as u32, len]);
    }

    /// Appends a record of fixed size whose payload `body` writes.
    fn record(&mut self, op: Op, body: impl FnOnce(&mut Vec<u8>)) {
        put_u32s(&mut self.scratch, &[op as u32, 0]);
        body(&mut self.scratch);
        let len = (self.scratch.len() - 8) as u32;
        self.scratch[4..8].copy_from_slice(&len.to_le_bytes());
        self.flush_scratch();
    }

    /// Appends `call`.
    pub fn call(&mut self, call: &Call) {
        match call {
            Call::Clear { color, depth } => self.record(Op::Clear, |o| {
                put_u32s(o, &[*color]);
                put_f32s(o, &[*depth]);
            }),
            Call::RenderState { state, value } => {
                self.record(Op::RenderState, |o| put_u32s(o, &[*state, *value]));
            }
            Call::TextureStageState {
                stage,
                state,
                value,
            } => self.record(Op::TextureStageState, |o| {
                put_u32s(o, &[*stage, *state, *value]);
            }),
            Call::SamplerState {
                sampler,
                state,
                value,
            } => self.record(Op::SamplerState, |o| {
                put_u32s(o, &[*sampler, *state, *value]);
            }),
            Call::CreateTexture { id, levels } => self.create_texture(*id, levels),
            Call::SetTexture { stage, id } => {
                self.record(Op::SetTexture, |o| put_u32s(o, &[*stage, *id]));
            }
            Call::Transform { which, matrix } => self.record(Op::Transform, |o| {
                put_u32s(o, &[*which]);
                put_f32s(o, matrix.as_flattened());
            }),
            Call::Viewport { rect, depth } => self.record(Op::Viewport, |o| {
                put_u32s(o, rect);
                put_f32s(o, depth);
            }),
            Call::ClipPlane { index, plane } => self.record(Op::ClipPlane, |o| {
                put_u32s(o, &[*index]);
                put_f32s(o, plane);
            }),
            Call::DrawPoints {
                fvf,
                stride,
                vertices,
            } => self.draw_points(*fvf, *stride, vertices),
            Call::Material(m) => self.record(Op::Material, |o| {
                for c in [m.diffuse, m.ambient, m.specular, m.emissive] {
                    put_f32s(o, &c);
                }
                put_f32s(o, &[m.power]);
            }),
            Call::Light { index, light: l } => self.record(Op::Light, |o| {
                put_u32s(o, &[*index, l.kind]);
                for c in [l.diffuse, l.specular, l.ambient] {
                    put_f32s(o, &c);
                }
                put_f32s(o, &l.position);
                put_f32s(o, &l.direction);
                put_f32s(o, &[l.range, l.falloff]);
                put_f32s(o, &l.attenuation);
                put_f32s(o, &[l.theta, l.phi]);
            }),
            Call::LightEnable { index, enable } => {
                self.record(Op::LightEnable, |o| {
                    put_u32s(o, &[*index, u32::from(*enable)]);
                });
            }
        }
    }

    /// Appends a CreateTexture record, its texels written as they lie.
    pub fn create_texture(&mut self, id: u32, levels: &[Level]) {
        let texels: u64 = levels.iter().map(|l| 8 + l.texels.len() as u64 * 4).sum();
        self.start(Op::CreateTexture, 8 + texels);
        put_u32s(&mut self.scratch, &[id, levels.len() as u32]);
        for l in levels {
            put_u32s(&mut self.scratch, &[l.width, l.height]);
            for chunk in l.texels.chunks(4096) {
                put_u32s(&mut self.scratch, chunk);
                self.flush_scratch();
            }
        }
        self.flush_scratch();
    }

    /// Appends a DrawPoints record, its vertices written as they lie.
    pub fn draw_points(&mut self, fvf: u32, stride: u32, vertices: &[u8]) {
        let count = vertices.len() / stride.max(1) as usize;
        self.start(Op::DrawPoints, 12 + vertices.len() as u64);
        put_u32s(&mut self.scratch, &[fvf, stride, count as u32]);
        self.flush_scratch();
        self.write(vertices);
    }

    /// Appends the end record and flushes: the stream's length in bytes, or the first error.
    /// Nothing may be appended after it.
    pub fn end(&mut self) -> io::Result<u64> {
        self.record(Op::End, |_| {});
        if let Some(e) = self.error.take() {
            return Err(e);
        }
        self.out.flush()?;
        Ok(self.bytes)
    }

    /// [`CallWriter::end`], then the output.
    pub fn finish(mut self) -> io::Result<W> {
        self.end()?;
        Ok(self.out)
    }
}

/// Why a stream could not be read: what is wrong and at which byte offset.
#[derive(Clone, Debug, PartialEq, Eq)]
pub struct FormatError {
    /// Byte offset of the record (or header field) at fault.
    pub offset: usize,
    /// What is wrong.
    pub message: String,
}

impl fmt::Display for FormatError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(f, "call stream, byte {}: {}", self.offset, self.message)
    }
}

impl std::error::Error for FormatError {}

/// Reads little-endian words from a payload, failing with the record's offset when short.
struct Cursor<'a> {
    bytes: &'a [u8],
    at: usize,
    record: usize,
}

impl Cursor<'_> {
    fn u32(&mut self) -> Result<u32, FormatError> {
        let b = self.bytes.get(self.at..self.at + 4).ok_or(FormatError {
            offset: self.record,
            message: "record payload too short".into(),
        })?;
        self.at += 4;
        Ok(u32::from_le_bytes([b[0], b[1], b[2], b[3]]))
    }

    fn f32(&mut self) -> Result<f32, FormatError> {
        self.u32().map(f32::from_bits)
    }

    fn f32s<const N: usize>(&mut self) -> Result<[f32; N], FormatError> {
        let mut out = [0.0; N];
        for x in &mut out {
            *x = self.f32()?;
        }
        Ok(out)
    }

    fn bytes(&mut self, n: usize) -> Result<&[u8], FormatError> {
        let end = self.at.checked_add(n).filter(|&e| e <= self.bytes.len());
        let end = end.ok_or(FormatError {
            offset: self.record,
            message: "record payload too short".into(),
        })?;
        let out = &self.bytes[self.at..end];
        self.at = end;
        Ok(out)
    }
}

/// Decodes a whole stream: its header and its calls, the end record excluded.
pub fn read_calls(bytes: &[u8]) -> Result<(Header, Vec<Call>), FormatError> {
    let err = |offset: usize, message: String| FormatError { offset, message };
    if bytes.len() < 24 || bytes[..8] != MAGIC {
        return Err(err(0, "not a call stream (no PTLCALLS header)".into()));
    }
    let word = |i: usize| u32::from_le_bytes(bytes[i..i + 4].try_into().unwrap_or([0; 4]));
    if word(8) != VERSION {
        return Err(err(
            8,
            format!("version {} (this reader reads {VERSION})", word(8)),
        ));
    }
    let header = Header {
        width: word(12),
        height: word(16),
        flags: word(20),
    };
    let mut calls = Vec::new();
    let mut at = 24;
    loop {
        if at + 8 > bytes.len() {
            return Err(err(at, "stream ends without an end record".into()));
        }
        let (op, len) = (word(at), word(at + 4) as usize);
        let payload = bytes
            .get(at + 8..at + 8 + len)
            .ok_or_else(|| err(at, format!("record of {len} bytes runs past the end")))?;
        let op = Op::from_u32(op).ok_or_else(|| err(at, format!("unknown opcode {op}")))?;
        let mut c = Cursor {
            bytes: payload,
            at: 0,
            record: at,
        };
        let call = match op {
            Op::End => None,
            Op::Clear => Some(Call::Clear {
                color: c.u32()?,
                depth: c.f32()?,
            }),
            Op::RenderState => Some(Call::RenderState {
                state: c.u32()?,
                value: c.u32()?,
            }),
            Op::TextureStageState => Some(Call::TextureStageState {
                stage: c.u32()?,
                state: c.u32()?,
                value: c.u32()?,
            }),
            Op::SamplerState => Some(Call::SamplerState {
                sampler: c.u32()?,
                state: c.u32()?,
                value: c.u32()?,
            }),
            Op::CreateTexture => {
                let id = c.u32()?;
                let count = c.u32()?;
                let mut levels = Vec::new();
                for _ in 0..count {
                    let (width, height) = (c.u32()?, c.u32()?);
                    let n = (width as usize)
                        .checked_mul(height as usize)
                        .and_then(|n| n.checked_mul(4))
                        .ok_or_else(|| err(at, "texture level too large".into()))?;
                    let texels = c
                        .bytes(n)?
                        .chunks_exact(4)
                        .map(|t| u32::from_le_bytes([t[0], t[1], t[2], t[3]]))
                        .collect();
                    levels.push(Level {
                        width,
                        height,
                        texels,
                    });
                }
                Some(Call::CreateTexture { id, levels })
            }
            Op::SetTexture => Some(Call::SetTexture {
                stage: c.u32()?,
                id: c.u32()?,
            }),
            Op::Transform => {
                let which = c.u32()?;
                let f: [f32; 16] = c.f32s()?;
                let mut matrix = [[0.0; 4]; 4];
                for (i, row) in matrix.iter_mut().enumerate() {
                    row.copy_from_slice(&f[i * 4..i * 4 + 4]);
                }
                Some(Call::Transform { which, matrix })
            }
            Op::Viewport => Some(Call::Viewport {
                rect: [c.u32()?, c.u32()?, c.u32()?, c.u32()?],
                depth: c.f32s()?,
            }),
            Op::ClipPlane => Some(Call::ClipPlane {
                index: c.u32()?,
                plane: c.f32s()?,
            }),
            Op::DrawPoints => {
                let (fvf, stride, count) = (c.u32()?, c.u32()?, c.u32()? as usize);
                let n = count
                    .checked_mul(stride as usize)
                    .ok_or_else(|| err(at, "vertex count too large".into()))?;
                Some(Call::DrawPoints {
                    fvf,
                    stride,
                    vertices: c.bytes(n)?.to_vec(),
                })
            }
            Op::Material => Some(Call::Material(Material {
                diffuse: c.f32s()?,
                ambient: c.f32s()?,
                specular: c.f32s()?,
                emissive: c.f32s()?,
                power: c.f32()?,
            })),
            Op::Light => Some(Call::Light {
                index: c.u32()?,
                light: Light {
                    kind: c.u32()?,
                    diffuse: c.f32s()?,
                    specular: c.f32s()?,
                    ambient: c.f32s()?,
                    position: c.f32s()?,
                    direction: c.f32s()?,
                    range: c.f32()?,
                    falloff: c.f32()?,
                    attenuation: c.f32s()?,
                    theta: c.f32()?,
                    phi: c.f32()?,
                },
            }),
            Op::LightEnable => Some(Call::LightEnable {
                index: c.u32()?,
                enable: c.u32()? != 0,
            }),
        };
        if c.at != payload.len() {
            return Err(err(
                at,
                format!(
                    "{op:?} record has {} bytes, its fields {}",
                    payload.len(),
                    c.at
                ),
            ));
        }
        at += 8 + len;
        match call {
            Some(call) => calls.push(call),
            None if at == bytes.len() => return Ok((header, calls)),
            None => return Err(err(at, "bytes after the end record".into())),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The opcodes are written three times: [`Op`], the replayer's C enum (which this reads
    /// from `replayer/replayer.c`) and the table of docs/CONFORMANCE.md. The three agree, name
    /// for name and number for number.
    #[test]
    fn opcodes_agree_with_the_replayer_and_the_docs() {
        let root = std::path::Path::new(env!("CARGO_MANIFEST_DIR"));
        let c = std::fs::read_to_string(root.join("replayer/replayer.c")).unwrap();
        let start = c.find("OP_END = 0").expect("the replayer's opcode enum");
        let body = &c[start..start + c[start..].find('}').unwrap()];
        let c_names: Vec<String> = body
            .split(',')
            .map(|item| item.split('=').next().unwrap().trim().to_owned())
            .filter(|name| !name.is_empty())
            .collect();
        let camel = |name: &str| -> String {
            name.trim_start_matches("OP_")
                .split('_')
                .map(|w| w[..1].to_owned() + &w[1..].to_lowercase())
                .collect()
        };
        let rust: Vec<String> = (0..)
            .map_while(Op::from_u32)
            .map(|op| format!("{op:?}"))
            .collect();
        let from_c: Vec<String> = c_names.iter().map(|n| camel(n)).collect();
        assert_eq!(from_c, rust, "replayer.c's enum and Op");

        let docs = std::fs::read_to_string(root.join("../../docs/CONFORMANCE.md")).unwrap();
        let table = &docs[docs
            .find("| op | call | payload |")
            .expect("the opcode table")..];
        let numbers: Vec<u32> = table
            .lines()
            .skip(2)
            .take_while(|l| l.starts_with('|'))
            .map(|l| l.split('|').nth(1).unwrap().trim().parse().unwrap())
            .collect();
        let expected: Vec<u32> = (0..rust.len() as u32).collect();
        assert_eq!(numbers, expected, "docs/CONFORMANCE.md's opcode table");
        assert!(Op::from_u32(rust.len() as u32).is_none());
    }

    fn every_call() -> Vec<Call> {
        vec![
            Call::Clear {
                color: 0xFF10_2030,
                depth: 0.5,
            },
            Call::RenderState {
                state: 154,
                value: 15.0f32.to_bits(),
            },
            Call::TextureStageState {
                stage: 1,
                state: 1,
                value: 4,
            },
            Call::SamplerState {
                sampler: 0,
                state: 5,
                value: 2,
            },
            Call::CreateTexture {
                id: 7,
                levels: vec![
                    Level {
                        width: 2,
                        height: 1,
                        texels: vec![0xFF00_0000, 0x00FF_FFFF],
                    },
                    Level {
                        width: 1,
                        height: 1,
                        texels: vec![0x8080_8080],
                    },
                ],
            },
            Call::SetTexture { stage: 0, id: 7 },
            Call::SetTexture {
                stage: 0,
                id: NO_TEXTURE,
            },
            Call::Transform {
                which: D3DTS_WORLD,
                matrix: [[1.0, 2.0, 3.0, 4.0]; 4],
            },
            Call::Viewport {
                rect: [1, 2, 30, 40],
                depth: [0.25, 0.75],
            },
            Call::ClipPlane {
                index: 5,
                plane: [1.0, 0.0, -1.0, f32::NAN],
            },
            Call::DrawPoints {
                fvf: 0x44,
                stride: 20,
                vertices: (0..40).collect(),
            },
            Call::Material(Material {
                diffuse: [1.0, 0.5, 0.25, 1.0],
                ambient: [0.0; 4],
                specular: [0.1; 4],
                emissive: [0.2; 4],
                power: 8.0,
            }),
            Call::Light {
                index: 3,
                light: Light {
                    kind: 3,
                    diffuse: [1.0; 4],
                    specular: [0.0; 4],
                    ambient: [0.5; 4],
                    position: [1.0, 2.0, 3.0],
                    direction: [0.0, 0.0, 1.0],
                    range: 100.0,
                    falloff: 1.0,
                    attenuation: [1.0, 0.0, 0.0],
                    theta: 0.5,
                    phi: 1.0,
                },
            },
            Call::LightEnable {
                index: 3,
                enable: true,
            },
        ]
    }

    fn stream(calls: &[Call]) -> Vec<u8> {
        let mut w = CallWriter::new(Header {
            width: 64,
            height: 32,
            flags: FLAG_SOFTWARE_VERTEX_PROCESSING,
        });
        for c in calls {
            w.call(c);
        }
        w.finish().unwrap()
    }

    /// Compares calls bit for bit (a NaN plane must come back as the same NaN).
    fn bits(calls: &[Call]) -> String {
        format!("{calls:?}")
    }

    #[test]
    fn every_record_reads_back_as_written() {
        let calls = every_call();
        let bytes = stream(&calls);
        let (header, back) = read_calls(&bytes).unwrap();
        assert_eq!(header.width, 64);
        assert_eq!(header.height, 32);
        assert_eq!(header.flags, FLAG_SOFTWARE_VERTEX_PROCESSING);
        assert_eq!(bits(&back), bits(&calls));
    }

    #[test]
    fn the_layout_is_the_documented_one() {
        let bytes = stream(&[Call::RenderState {
            state: 154,
            value: 0x4170_0000,
        }]);
        let mut want = b"PTLCALLS".to_vec();
        for w in [1u32, 64, 32, 1, 2, 8, 154, 0x4170_0000, 0, 0] {
            want.extend_from_slice(&w.to_le_bytes());
        }
        assert_eq!(bytes, want);
        let light = stream(&every_call()[12..13]);
        assert_eq!(light.len(), 24 + 8 + 4 + 104 + 8, "D3DLIGHT9 is 104 bytes");
        let material = stream(&every_call()[11..12]);
        assert_eq!(material.len(), 24 + 8 + 68 + 8, "D3DMATERIAL9 is 68 bytes");
    }

    #[test]
    fn damaged_streams_say_what_and_where() {
        let bytes = stream(&every_call());
        let e = read_calls(&bytes[..bytes.len() - 8]).unwrap_err();
        assert_eq!(e.message, "stream ends without an end record");
        let mut bad = bytes.clone();
        bad[24] = 99;
        let e = read_calls(&bad).unwrap_err();
        assert_eq!((e.offset, e.message.as_str()), (24, "unknown opcode 99"));
        let mut v2 = bytes.clone();
        v2[8] = 2;
        assert!(read_calls(&v2).unwrap_err().message.contains("version 2"));
        let mut extra = bytes.clone();
        extra.push(0);
        assert!(
            read_calls(&extra)
                .unwrap_err()
                .message
                .contains("after the end")
        );
        // A clear record claiming 4 payload bytes: its depth is missing.
        let mut short = stream(&every_call()[..1]);
        short[28] = 4;
        short.drain(36..40);
        assert!(
            read_calls(&short)
                .unwrap_err()
                .message
                .contains("too short")
        );
        assert!(read_calls(b"PNG").unwrap_err().message.contains("PTLCALLS"));
    }
}

//! Typed vertices: the fixed-format vertex structs of D3D9 programs (the SDK samples'
//! `CUSTOMVERTEX`) for [`Device::draw_vertices`](super::Device::draw_vertices), each with its
//! D3DFVF code and written as the bytes that format lays out (`crate::fvf`); the tutorial's
//! point-sprite vertex, `XYZ | PSIZE | DIFFUSE`, among them (SPEC 2.1).

use crate::fvf::Fvf;

/// A typed vertex of a fixed FVF, written little-endian in FVF order.
pub trait Vertex {
    /// The format.
    const FVF: Fvf;
    /// Appends this vertex's bytes.
    fn write(&self, out: &mut Vec<u8>);
}

fn put(out: &mut Vec<u8>, words: &[u32]) {
    for w in words {
        out.extend_from_slice(&w.to_le_bytes());
    }
}

/// D3DFVF_XYZ | D3DFVF_DIFFUSE.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct XyzDiffuse {
    /// Object-space position.
    pub position: [f32; 3],
    /// D3DCOLOR.
    pub diffuse: u32,
}

impl Vertex for XyzDiffuse {
    const FVF: Fvf = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);
    fn write(&self, out: &mut Vec<u8>) {
        let p = self.position.map(f32::to_bits);
        put(out, &[p[0], p[1], p[2], self.diffuse]);
    }
}

/// D3DFVF_XYZ | D3DFVF_PSIZE | D3DFVF_DIFFUSE: the vertex of the point-sprite tutorial
/// (docs/spec/SOURCES.md).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct XyzPsizeDiffuse {
    /// Object-space position.
    pub position: [f32; 3],
    /// Per-vertex size.
    pub psize: f32,
    /// D3DCOLOR.
    pub diffuse: u32,
}

impl Vertex for XyzPsizeDiffuse {
    const FVF: Fvf = Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
    fn write(&self, out: &mut Vec<u8>) {
        let p = self.position.map(f32::to_bits);
        put(out, &[p[0], p[1], p[2], self.psize.to_bits(), self.diffuse]);
    }
}

/// D3DFVF_XYZRHW | D3DFVF_DIFFUSE: a pre-transformed point in pixels.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct XyzRhwDiffuse {
    /// Screen x, y, depth z and 1/w.
    pub position: [f32; 4],
    /// D3DCOLOR.
    pub diffuse: u32,
}

impl Vertex for XyzRhwDiffuse {
    const FVF: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0);
    fn write(&self, out: &mut Vec<u8>) {
        let p = self.position.map(f32::to_bits);
        put(out, &[p[0], p[1], p[2], p[3], self.diffuse]);
    }
}

/// D3DFVF_XYZRHW | D3DFVF_PSIZE | D3DFVF_DIFFUSE.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct XyzRhwPsizeDiffuse {
    /// Screen x, y, depth z and 1/w.
    pub position: [f32; 4],
    /// Size in pixels.
    pub psize: f32,
    /// D3DCOLOR.
    pub diffuse: u32,
}

impl Vertex for XyzRhwPsizeDiffuse {
    const FVF: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0);
    fn write(&self, out: &mut Vec<u8>) {
        let p = self.position.map(f32::to_bits);
        put(
            out,
            &[p[0], p[1], p[2], p[3], self.psize.to_bits(), self.diffuse],
        );
    }
}

//! The workloads of docs/PERFORMANCE.md, generated from fixed seeds so every run and every renderer
//! draws the same points.
//!
//! - W1 small sprites: pre-transformed 4 px points, flat colours, ONE/ONE, 1024x768.
//! - W2 textured sprites: 4-8 px, POINTSPRITEENABLE, 16x16 texture, point sampling, MODULATE
//!   with diffuse, ONE/ONE, 1024x768.
//! - W3 big sprites: 64 px, 64x64 texture, bilinear, SRCALPHA/INVSRCALPHA, 1920x1080.
//! - W4 snow storm: perspective points, POINTSCALEENABLE, depth test, alpha blending, 1920x1080.

use std::sync::Arc;

use pointillist_core::fvf::Fvf;
use pointillist_core::math::Mat4;
use pointillist_core::point::PointSetup;
use pointillist_core::states::{Blend, RenderState, SamplerState, TextureFilter};
use pointillist_core::texture::Texture;
use pointillist_core::{Backend, Device, DeviceDesc, DeviceError, TransformType};

/// Which of the four workloads.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub enum Kind {
    /// Small flat sprites.
    W1,
    /// Textured small sprites.
    W2,
    /// Big filtered, alpha-blended sprites.
    W3,
    /// Perspective snow storm.
    W4,
}

impl Kind {
    /// All four, in order.
    pub const ALL: [Kind; 4] = [Kind::W1, Kind::W2, Kind::W3, Kind::W4];

    /// The workload's default point count.
    pub fn default_points(self) -> usize {
        match self {
            Kind::W1 | Kind::W2 => 1_000_000,
            Kind::W3 => 20_000,
            Kind::W4 => 200_000,
        }
    }

    /// "w1".."w4".
    pub fn name(self) -> &'static str {
        match self {
            Kind::W1 => "w1",
            Kind::W2 => "w2",
            Kind::W3 => "w3",
            Kind::W4 => "w4",
        }
    }

    /// Parses "w1".."w4" (case-insensitive).
    pub fn parse(s: &str) -> Option<Kind> {
        match s.to_ascii_lowercase().as_str() {
            "w1" => Some(Kind::W1),
            "w2" => Some(Kind::W2),
            "w3" => Some(Kind::W3),
            "w4" => Some(Kind::W4),
            _ => None,
        }
    }
}

/// One workload: a target, states, a texture and a vertex buffer.
#[derive(Clone, Debug)]
pub struct Workload {
    /// Which one.
    pub kind: Kind,
    /// Target width.
    pub width: u32,
    /// Target height.
    pub height: u32,
    /// D3DCOLOR the target is cleared to each frame.
    pub clear_color: u32,
    /// The vertex format.
    pub fvf: Fvf,
    /// The vertex buffer.
    pub vertices: Vec<u8>,
    /// Number of points.
    pub points: usize,
    /// The stage-0 texture, if any.
    pub texture: Option<Arc<Texture>>,
    /// POINTSIZE for formats without PSIZE.
    pub point_size: f32,
}

/// A xorshift64* generator: the fixed-seed source of every workload.
pub struct Rng(u64);

impl Rng {
    /// A generator from a non-zero seed.
    pub fn new(seed: u64) -> Rng {
        Rng(seed.max(1))
    }

    /// The next 64 random bits.
    pub fn next_u64(&mut self) -> u64 {
        self.0 ^= self.0 >> 12;
        self.0 ^= self.0 << 25;
        self.0 ^= self.0 >> 27;
        self.0.wrapping_mul(0x2545_F491_4F6C_DD1D)
    }

    /// A float in `lo..hi`.
    pub fn range(&mut self, lo: f32, hi: f32) -> f32 {
        let unit = (self.next_u64() >> 40) as f32 / (1u64 << 24) as f32;
        lo + (hi - lo) * unit
    }
}

/// The soft round 64x64 sprite the scenes ship (white, radial alpha falloff).
pub fn particle_texture() -> Arc<Texture> {
    let texels = (0..64 * 64)
        .map(|k| {
            let (x, y) = ((k % 64) as f32 - 31.5, (k / 64) as f32 - 31.5);
            let f = (1.0 - (x * x + y * y).sqrt() / 32.0).clamp(0.0, 1.0);
            let a = (f * f * 255.0).round() as u32;
            a << 24 | 0x00FF_FFFF
        })
        .collect();
    Arc::new(Texture::from_argb(64, 64, texels).expect("64x64 is a valid texture"))
}

/// A 16x16 texture of coloured 4x4 tiles.
fn tile_texture() -> Arc<Texture> {
    let texels = (0..16 * 16)
        .map(|k: u32| {
            let tile = (k % 16) / 4 + 4 * ((k / 16) / 4);
            0xFF00_0000 | ((tile * 0x0011_0D07) & 0x00FF_FFFF) | 0x0040_4040
        })
        .collect();
    Arc::new(Texture::from_argb(16, 16, texels).expect("16x16 is a valid texture"))
}

/// Appends `words` as little-endian bytes.
fn push(out: &mut Vec<u8>, words: impl IntoIterator<Item = u32>) {
    for w in words {
        out.extend_from_slice(&w.to_le_bytes());
    }
}

impl Workload {
    /// Builds workload `kind` with `points` points.
    pub fn new(kind: Kind, points: usize) -> Workload {
        let mut rng = Rng::new(0x5EED_0000 + kind as u64);
        let (width, height) = match kind {
            Kind::W1 | Kind::W2 => (1024, 768),
            Kind::W3 | Kind::W4 => (1920, 1080),
        };
        let fvf = match kind {
            Kind::W1 | Kind::W3 => Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0),
            Kind::W2 => Fvf(Fvf::XYZRHW.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
            Kind::W4 => Fvf(Fvf::XYZ.0 | Fvf::PSIZE.0 | Fvf::DIFFUSE.0),
        };
        let mut vertices = Vec::with_capacity(points * fvf.stride());
        let (w, h) = (width as f32, height as f32);
        for _ in 0..points {
            let color = rng.next_u64() as u32;
            // Position: pre-transformed (x, y, z = 0.5, rhw = 1) on screen, or world space for W4.
            match kind {
                Kind::W4 => {
                    let xyz = [
                        rng.range(-40.0, 40.0),
                        rng.range(-22.0, 22.0),
                        rng.range(2.0, 60.0),
                    ];
                    push(&mut vertices, xyz.map(f32::to_bits));
                }
                Kind::W1 | Kind::W2 | Kind::W3 => {
                    let xyzrhw = [rng.range(0.0, w), rng.range(0.0, h), 0.5, 1.0];
                    push(&mut vertices, xyzrhw.map(f32::to_bits));
                }
            }
            let size = match kind {
                Kind::W2 => Some(rng.range(4.0, 8.0)),
                Kind::W4 => Some(rng.range(0.02, 0.05)),
                Kind::W1 | Kind::W3 => None,
            };
            push(&mut vertices, size.map(f32::to_bits));
            let diffuse = match kind {
                Kind::W1 | Kind::W2 => 0xFF00_0000 | (color & 0x003F_3F3F),
                Kind::W3 => 0x8000_0000 | (color & 0x00FF_FFFF),
                Kind::W4 => 0xC0E0_E8FF,
            };
            push(&mut vertices, [diffuse]);
        }
        Workload {
            kind,
            width,
            height,
            clear_color: 0xFF00_0000,
            fvf,
            vertices,
            points,
            texture: match kind {
                Kind::W1 => None,
                Kind::W2 => Some(tile_texture()),
                Kind::W3 | Kind::W4 => Some(particle_texture()),
            },
            point_size: match kind {
                Kind::W3 => 64.0,
                _ => 4.0,
            },
        }
    }

    /// The pixels a frame draws: every point's covered rectangle inside the target (SPEC 4.1,
    /// 3.2), overlaps counted once per point, as core's per-point stage gives them.
    pub fn covered_pixels(&self) -> Result<u64, DeviceError> {
        let mut device = pointillist_cpu::device(self.device_desc())?;
        self.configure(&mut device)?;
        let points = PointSetup::new(device.state(), self.fvf);
        Ok((0..self.points as u32)
            .filter_map(|i| points.process(&self.vertices, i))
            .map(|p| p.rect.area())
            .sum())
    }

    /// The device the workload draws on.
    pub fn device_desc(&self) -> DeviceDesc {
        DeviceDesc {
            clear_color: self.clear_color,
            ..DeviceDesc::new(self.width, self.height)
        }
    }

    /// The camera of W4: eye at the origin looking down +z, 0.8 rad vertical field of view.
    pub fn projection(&self) -> Mat4 {
        Mat4::perspective_fov_lh(0.8, self.width as f32 / self.height as f32, 1.0, 100.0)
    }

    /// Sets the workload's states on a device.
    pub fn configure<B: Backend>(&self, d: &mut Device<B>) -> Result<(), DeviceError> {
        d.set_render_state(RenderState::POINTSIZE, self.point_size);
        // Vertex colours, not D3D9 lighting (SPEC 8.1), as particle code sets it.
        d.set_render_state(RenderState::LIGHTING, false);
        d.set_render_state(RenderState::ALPHABLENDENABLE, true);
        let (src, dst) = match self.kind {
            Kind::W1 | Kind::W2 => (Blend::One, Blend::One),
            Kind::W3 | Kind::W4 => (Blend::SrcAlpha, Blend::InvSrcAlpha),
        };
        d.set_render_state(RenderState::SRCBLEND, src);
        d.set_render_state(RenderState::DESTBLEND, dst);
        d.set_render_state(RenderState::ZENABLE, self.kind == Kind::W4);
        if self.kind != Kind::W1 {
            d.set_render_state(RenderState::POINTSPRITEENABLE, true);
        }
        if let Some(t) = &self.texture {
            d.set_texture(0, Some(t.clone()))?;
            let filter = match self.kind {
                Kind::W2 => TextureFilter::Point,
                _ => TextureFilter::Linear,
            };
            d.set_sampler_state(0, SamplerState::MINFILTER, filter)?;
            d.set_sampler_state(0, SamplerState::MAGFILTER, filter)?;
        }
        if self.kind == Kind::W4 {
            d.set_render_state(RenderState::POINTSCALEENABLE, true);
            d.set_render_state(RenderState::POINTSCALE_A, 0.0f32);
            d.set_render_state(RenderState::POINTSCALE_C, 1.0f32);
            d.set_transform(TransformType::Projection, self.projection());
        }
        Ok(())
    }
}

//! Columns of data drawn as point sprites: the API behind `pointillist.points` (Python) and
//! its exact Dask path.
//!
//! A [`Plot`] names the target (size, clear colour), a blend preset ([`Blend`]), the data
//! ranges the axes show ([`axes`]) and an optional sprite texture. [`Points`] are columns read
//! in place: x, y, optional depth, sizes and colours, each a constant or one value per point.
//! Drawing turns each point into one pre-transformed vertex (the private `columns` module) and
//! issues ordinary D3D9 draws on a [`Device`], with the states [`Plot::configure`] sets, so the
//! pixels are those of the same vertices and states in a scene file drawn by `pointillist
//! render`.
//!
//! For drawing one set of points in parts on several machines, exactly:
//! - presets that commute ([`Blend::commutes`]) draw each part onto a zero target
//!   ([`Plot::partial`]) and [`Blend::combine`] the images, then the clear colour once
//!   ([`Plot::finish`]);
//! - every other draw is split by screen tiles ([`tiles`]): each point goes, with its index,
//!   to every tile its square overlaps, and each tile draws its points in index order on a
//!   target whose viewport is the tile, so every pixel sees the arithmetic of the full draw.
//!
//! ```
//! use pointillist_plot::{Blend, Column, Plot, Points};
//!
//! let x = [1.0f32, 2.0, 2.0];
//! let y = [1.0f32, 1.0, 1.0];
//! let plot = Plot { blend: Blend::Add, ..Plot::new(4, 3) };
//! let points = Points { color: pointillist_plot::Colors::Constant(0xFF40_2010), ..Points::new(Column::F32(&x), Column::F32(&y)) };
//! let rgba = plot.render(&points).unwrap();
//! let pixel = |i: usize, j: usize| &rgba[(j * 4 + i) * 4..][..4];
//! assert_eq!(pixel(1, 1), [0x40, 0x20, 0x10, 0xFF]);
//! assert_eq!(pixel(2, 1), [0x80, 0x40, 0x20, 0xFF]); // two points added
//! assert_eq!(pixel(0, 0), [0, 0, 0, 0xFF]); // the clear colour
//! ```

pub mod axes;
mod blend;
mod columns;
mod counts;
pub mod marker;
pub mod tiles;

use std::fmt;
use std::sync::Arc;

use pointillist_core::behaviour::Behaviours;
use pointillist_core::color::argb_to_rgba8;
use pointillist_core::device::{
    Backend, Device, DeviceDesc, DeviceError, DeviceState, MAX_TARGET_SIZE, RenderTarget, Viewport,
};
use pointillist_core::point::PixelRect;
use pointillist_core::states::{
    Cmp, RenderState, SamplerState, TA_CURRENT, TA_TEXTURE, TextureAddress, TextureFilter,
    TextureOp, TextureStageState,
};
use pointillist_core::texture::Texture;

pub use axes::{Axis, DataRange, SizeMap};
pub use blend::Blend;
pub use columns::{Colors, Column, Layout, Points, Sizes};
pub use marker::{Marker, SizeUnits};

/// Vertices drawn per draw call: a block of the points is written, drawn, and its buffer
/// reused for the next, so memory does not grow with the points.
pub const BLOCK_VERTICES: usize = 1 << 18;

/// Why a plot cannot be drawn. Each message is one line naming the argument at fault.
#[derive(Clone, Debug, PartialEq)]
#[non_exhaustive]
pub enum PlotError {
    /// A column whose length differs from x's.
    Length {
        /// The column.
        name: &'static str,
        /// Its length.
        len: usize,
        /// x's length.
        x: usize,
    },
    /// A NaN in a column.
    Nan {
        /// The column.
        name: &'static str,
        /// The first row holding NaN.
        row: usize,
    },
    /// A data range that is empty, reversed or not finite.
    Range {
        /// `x_range` or `y_range`.
        name: &'static str,
        /// Its low end.
        lo: f64,
        /// Its high end.
        hi: f64,
    },
    /// An unknown blend preset.
    Blend(String),
    /// A scalar argument out of its domain (a NaN size, a bad tile size).
    Value(String),
    /// Images that cannot be combined.
    Combine(String),
    /// The device refused a call (target size, texture).
    Device(String),
}

impl fmt::Display for PlotError {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        match self {
            PlotError::Length { name, len, x } => {
                write!(
                    f,
                    "{name} has {len} rows but x has {x}; every column needs one row a point"
                )
            }
            PlotError::Nan { name, row } => write!(f, "{name}[{row}] is NaN"),
            PlotError::Range { name, lo, hi } => {
                let (l, h) = (short(*lo), short(*hi));
                if lo.is_finite() && hi.is_finite() && lo < hi {
                    let reason = if (hi - lo).is_finite() {
                        "too narrow"
                    } else {
                        "too wide: hi - lo overflows a float64"
                    };
                    write!(f, "{name} ({l}, {h}) is {reason}")
                } else {
                    write!(
                        f,
                        "{name} ({l}, {h}) must be two finite numbers, low below high"
                    )
                }
            }
            PlotError::Blend(name) => write!(
                f,
                "unknown blend \"{name}\" (expected \"add\", \"alpha\", \"max\" or \"replace\")"
            ),
            PlotError::Value(m) | PlotError::Combine(m) | PlotError::Device(m) => f.write_str(m),
        }
    }
}

/// `v` in the shorter of its decimal and exponent forms (`1e308`, not 309 digits).
fn short(v: f64) -> String {
    let (decimal, exponent) = (v.to_string(), format!("{v:e}"));
    if exponent.len() < decimal.len() {
        exponent
    } else {
        decimal
    }
}

impl std::error::Error for PlotError {}

impl From<DeviceError> for PlotError {
    fn from(e: DeviceError) -> Self {
        PlotError::Device(e.to_string())
    }
}

/// A target and how points are drawn on it.
#[derive(Clone, Debug)]
pub struct Plot {
    /// Target width in pixels.
    pub width: u32,
    /// Target height in pixels.
    pub height: u32,
    /// The blend preset.
    pub blend: Blend,
    /// The D3DCOLOR the target is cleared to before the points.
    pub clear: u32,
    /// The data interval across the target's width; `None`: x is in pixels.
    pub x_range: Option<DataRange>,
    /// The data interval up the target's height; `None`: y is in pixels, downwards.
    pub y_range: Option<DataRange>,
    /// A texture every point shows as a sprite (POINTSPRITEENABLE), modulated by its colour.
    pub texture: Option<Arc<Texture>>,
    /// The shape of each point ([`marker`]); a circle is a sprite of its own, so it cannot
    /// have a `texture` too.
    pub marker: Marker,
    /// What the sizes are measured in ([`marker`]); data units need both ranges.
    pub size_units: SizeUnits,
    /// The device behaviour switches the draw runs with (SPEC "Device behaviours"): every
    /// path (device, counts, partial images, tiles) draws with them.
    pub behaviours: Behaviours,
}

impl Plot {
    /// A `width` x `height` target cleared to opaque black, `add`, pixel coordinates.
    pub fn new(width: u32, height: u32) -> Plot {
        Plot {
            width,
            height,
            blend: Blend::Add,
            clear: 0xFF00_0000,
            x_range: None,
            y_range: None,
            texture: None,
            marker: Marker::Square,
            size_units: SizeUnits::Pixels,
            behaviours: Behaviours::default(),
        }
    }

    /// How sizes become pixels: [`SizeUnits::Data`] takes x's scale (the axes' one formula);
    /// without an x range (which [`Plot::check`] refuses) sizes stay pixels.
    pub fn size_map(&self) -> SizeMap {
        match self.size_units {
            SizeUnits::Pixels => SizeMap(None),
            SizeUnits::Data => SizeMap(
                Axis::x(self.x_range, self.width, "x_range")
                    .ok()
                    .and_then(Axis::scale),
            ),
        }
    }

    /// Whether the points are sprites showing a texture: the plot's, or a circle's disc.
    pub fn textured(&self) -> bool {
        self.texture.is_some() || self.marker == Marker::Circle
    }

    /// The texture of stage 0: the plot's, or the disc of a circle marker.
    pub fn sprite(&self) -> Option<Arc<Texture>> {
        match self.marker {
            Marker::Circle => Some(marker::shared_disc(self.blend)),
            Marker::Square => self.texture.clone(),
        }
    }

    /// The axes of this plot (the one formula of [`axes`]).
    pub fn axes(&self) -> Result<(Axis, Axis), PlotError> {
        Ok((
            Axis::x(self.x_range, self.width, "x_range")?,
            Axis::y(self.y_range, self.height, "y_range")?,
        ))
    }

    /// The render states a draw of `layout` runs with, after the D3D9 defaults: the blend
    /// preset's; POINTSIZE_MIN 0 and POINTSIZE_MAX the device's largest size, 8192 (sizes are
    /// what they say, SPEC 2.3: the D3D9 default minimum of 1 would enlarge smaller points, the
    /// default maximum of 64, SPEC 2.6, would shrink larger ones); POINTSIZE for a constant
    /// size; ZENABLE on with depths (ZFUNC LESSEQUAL, ZWRITEENABLE TRUE, the defaults), off
    /// without; POINTSPRITEENABLE with a texture.
    pub fn render_states(&self, layout: &Layout) -> Vec<(RenderState, u32)> {
        let mut states = self.blend.render_states();
        states.push((RenderState::POINTSIZE_MIN, 0.0f32.to_bits()));
        let largest = DeviceDesc::new(self.width, self.height)
            .caps
            .effective()
            .max_point_size;
        states.push((RenderState::POINTSIZE_MAX, largest.to_bits()));
        if let Some(size) = layout.size {
            let size = self.size_map().map(f64::from(size));
            states.push((RenderState::POINTSIZE, size.to_bits()));
        }
        states.push((RenderState::ZENABLE, u32::from(layout.depth)));
        if self.textured() {
            states.push((RenderState::POINTSPRITEENABLE, 1));
        }
        if self.marker == Marker::Circle && self.blend == Blend::Replace {
            // The last point wins only where its disc covers at least half a texel.
            states.push((RenderState::ALPHATESTENABLE, 1));
            states.push((RenderState::ALPHAREF, 128));
            states.push((RenderState::ALPHAFUNC, Cmp::GreaterEqual as u32));
        }
        states
    }

    /// Stage 0's states with a texture: the colour and the alpha are the texel's times the
    /// point's (MODULATE of TEXTURE and CURRENT). Nothing without a texture (stage 0's defaults
    /// pass the point's colour through).
    pub fn stage_states(&self) -> Vec<(TextureStageState, u32)> {
        if !self.textured() {
            return Vec::new();
        }
        vec![
            (TextureStageState::COLOROP, TextureOp::Modulate as u32),
            (TextureStageState::COLORARG1, TA_TEXTURE),
            (TextureStageState::COLORARG2, TA_CURRENT),
            (TextureStageState::ALPHAOP, TextureOp::Modulate as u32),
            (TextureStageState::ALPHAARG1, TA_TEXTURE),
            (TextureStageState::ALPHAARG2, TA_CURRENT),
        ]
    }

    /// Sampler 0's states with a texture: linear filtering, clamped addresses; a circle's disc
    /// is also filtered between its mip levels (MIPFILTER LINEAR).
    pub fn sampler_states(&self) -> Vec<(SamplerState, u32)> {
        if !self.textured() {
            return Vec::new();
        }
        let mut states = vec![
            (SamplerState::MINFILTER, TextureFilter::Linear as u32),
            (SamplerState::MAGFILTER, TextureFilter::Linear as u32),
            (SamplerState::ADDRESSU, TextureAddress::Clamp as u32),
            (SamplerState::ADDRESSV, TextureAddress::Clamp as u32),
        ];
        if self.marker == Marker::Circle {
            states.push((SamplerState::MIPFILTER, TextureFilter::Linear as u32));
        }
        states
    }

    /// Sets every state of a draw of `layout` on `device` and binds the texture.
    pub fn configure<B: Backend>(
        &self,
        device: &mut Device<B>,
        layout: &Layout,
    ) -> Result<(), PlotError> {
        for (s, v) in self.render_states(layout) {
            device.set_render_state(s, v);
        }
        for (s, v) in self.stage_states() {
            device.set_texture_stage_state(0, s, v)?;
        }
        for (s, v) in self.sampler_states() {
            device.set_sampler_state(0, s, v)?;
        }
        device.set_texture(0, self.sprite())?;
        Ok(())
    }

    /// The device state a draw of `layout` runs with on the whole target, without a device:
    /// what the per-point stage needs to say which pixels a point covers.
    pub fn device_state(&self, layout: &Layout) -> DeviceState {
        let desc = DeviceDesc::new(self.width, self.height);
        let mut state = DeviceState::with_behaviours(
            desc.api,
            desc.caps,
            self.behaviours,
            self.width,
            self.height,
        );
        for (s, v) in self.render_states(layout) {
            state.render_states[s.0 as usize] = v;
        }
        state
    }

    /// The same plot drawn onto a zero target (every channel 0), for the parts of a draw
    /// whose preset commutes; [`Plot::finish`] adds the clear colour at the end.
    pub fn partial(&self) -> Plot {
        Plot {
            clear: 0,
            ..self.clone()
        }
    }

    /// Combines the clear colour into `rgba`, the combined partial images of every part of a
    /// draw (the preset must commute): the pixels of one draw of all the points onto the
    /// target cleared to [`Plot::clear`].
    pub fn finish(&self, rgba: &mut [u8]) -> Result<(), PlotError> {
        let mut out = argb_to_rgba8(self.clear).repeat(rgba.len() / 4);
        self.blend.combine(&mut out, rgba)?;
        rgba.copy_from_slice(&out);
        Ok(())
    }

    /// The number of `points` covering each pixel, saturating at 255, row by row, when the
    /// draw is one of one colour whose pixels depend only on that number (`add`, `max`,
    /// `replace`; no depth, no texture): `None` when it is not. Counts of parts of the points
    /// combined with [`Plot::add_counts`] and mapped by [`Plot::from_counts`] give the pixels
    /// of one draw of all of them, in any order.
    pub fn counts(&self, points: &Points<'_>) -> Result<Option<Vec<u8>>, PlotError> {
        self.check(points)?;
        if counts::counted(self, points).is_none() {
            return Ok(None);
        }
        counts::count(self, points).map(Some)
    }

    /// Adds [`Plot::counts`] of `points` to `sum` (one byte a pixel, row by row), saturating
    /// at 255, without a count image of their own: `Ok(false)`, with `sum` untouched, when the
    /// draw is not counted. Counting several parts of the points into one `sum` gives the counts
    /// of all of them. A `sum` of the wrong size is an error; after any error `sum` may hold
    /// part of the counts.
    pub fn add_counts_of(&self, points: &Points<'_>, sum: &mut [u8]) -> Result<bool, PlotError> {
        self.check(points)?;
        if counts::counted(self, points).is_none() {
            return Ok(false);
        }
        counts::count_into(self, points, sum).map(|()| true)
    }

    /// `sum += counts` pixel by pixel, saturating at 255 (see [`Plot::counts`]).
    pub fn add_counts(sum: &mut [u8], counts: &[u8]) -> Result<(), PlotError> {
        if sum.len() != counts.len() {
            return Err(PlotError::Combine(format!(
                "counts of {} and {} pixels differ in size",
                sum.len(),
                counts.len()
            )));
        }
        counts::add(sum, counts);
        Ok(())
    }

    /// The RGBA8 rows of a draw whose [`Plot::counts`] are `counts`; `points` (of any length)
    /// give the draw's layout and colour.
    pub fn from_counts(&self, points: &Points<'_>, counts: &[u8]) -> Result<Vec<u8>, PlotError> {
        let Some(table) = counts::counted(self, points) else {
            return Err(PlotError::Value("this draw is not counted".into()));
        };
        let pixels = counts::check_len(self, counts)?;
        let mut out = vec![0u8; pixels * 4];
        counts::map(&table, counts, &mut out);
        Ok(out)
    }

    /// Checks that the marker and the size units go with the rest of the plot: a circle is a
    /// sprite of its own (no `texture`), data units need both ranges.
    pub fn check_marker(&self) -> Result<(), PlotError> {
        if self.marker == Marker::Circle && self.texture.is_some() {
            return Err(PlotError::Value(
                "marker=\"circle\" draws its own disc sprite; give texture=None (a texture \
                 is drawn on squares)"
                    .into(),
            ));
        }
        if self.size_units == SizeUnits::Data && (self.x_range.is_none() || self.y_range.is_none())
        {
            return Err(PlotError::Value(
                "size_units=\"data\" measures sizes along x_range: give x_range and y_range".into(),
            ));
        }
        Ok(())
    }

    /// Checks the target size and the scalar arguments.
    pub fn check(&self, points: &Points<'_>) -> Result<usize, PlotError> {
        if let Sizes::Constant(s) = points.size
            && s.is_nan()
        {
            return Err(PlotError::Value("size is NaN".into()));
        }
        self.check_marker()?;
        self.axes()?;
        points.count()
    }

    /// A device of backend `backend` on a target of `width` x `height` cleared to the clear
    /// colour, with every state of a draw of `layout`; its viewport is `viewport` (the whole
    /// target when `None`).
    pub fn device<B: Backend>(
        &self,
        backend: B,
        layout: &Layout,
        (width, height): (u32, u32),
        viewport: Option<PixelRect>,
    ) -> Result<Device<B>, PlotError> {
        let desc = DeviceDesc {
            clear_color: self.clear,
            behaviours: self.behaviours,
            ..DeviceDesc::new(width, height)
        };
        let mut device = Device::new(backend, desc)?;
        if let Some(r) = viewport {
            let size = |a: i32, b: i32| u32::try_from(b - a).unwrap_or(0);
            device.set_viewport(Viewport {
                x: r.x0.max(0) as u32,
                y: r.y0.max(0) as u32,
                width: size(r.x0, r.x1),
                height: size(r.y0, r.y1),
                min_z: 0.0,
                max_z: 1.0,
            })?;
        }
        self.configure(&mut device, layout)?;
        Ok(device)
    }

    /// Draws `points` on `device` (configured by [`Plot::configure`]) in blocks of
    /// [`BLOCK_VERTICES`]: the pixels of one draw of all of them (SPEC 5.5).
    pub fn draw<B: Backend>(
        &self,
        device: &mut Device<B>,
        points: &Points<'_>,
    ) -> Result<(), PlotError> {
        let n = self.check(points)?;
        let axes = self.axes()?;
        let sizes = self.size_map();
        let layout = points.layout();
        let stride = layout.stride();
        let mut words = vec![0u32; n.min(BLOCK_VERTICES) * stride];
        for start in (0..n).step_by(BLOCK_VERTICES) {
            let end = n.min(start + BLOCK_VERTICES);
            let block = &mut words[..(end - start) * stride];
            columns::write_vertices(&points.rows(start..end), axes, sizes, start, block)?;
            device.draw_point_list(layout.fvf(), bytemuck::cast_slice(block))?;
        }
        Ok(())
    }

    /// Draws `points` on the CPU backend and returns the target as RGBA8 rows, top to bottom.
    pub fn render(&self, points: &Points<'_>) -> Result<Vec<u8>, PlotError> {
        // The device's refusal of the size, before the image is allocated.
        let sides = 1..=MAX_TARGET_SIZE;
        if !(sides.contains(&self.width) && sides.contains(&self.height)) {
            let (width, height) = (self.width, self.height);
            return Err(DeviceError::TargetSize { width, height }.into());
        }
        let mut out = vec![0u8; self.width as usize * self.height as usize * 4];
        self.render_into(points, &mut out)?;
        Ok(out)
    }

    /// [`Plot::render`] into `out`, `width * height * 4` bytes.
    pub fn render_into(&self, points: &Points<'_>, out: &mut [u8]) -> Result<(), PlotError> {
        self.check(points)?;
        if counts::render(self, points, out)? {
            return Ok(());
        }
        self.render_on_device(points, out)
    }

    /// [`Plot::render_into`] through a CPU device for every draw: vertices, the backend's
    /// binning and shading. `render_into` counts draws of one colour instead (same pixels).
    pub fn render_on_device(&self, points: &Points<'_>, out: &mut [u8]) -> Result<(), PlotError> {
        self.check(points)?;
        let size = (self.width, self.height);
        let mut device = self.device(
            pointillist_cpu::CpuBackend::new(),
            &points.layout(),
            size,
            None,
        )?;
        self.draw(&mut device, points)?;
        let full = PixelRect {
            x0: 0,
            y0: 0,
            x1: self.width as i32,
            y1: self.height as i32,
        };
        write_rgba8(device.backend_mut().target(), full, out)
    }
}

/// Writes rectangle `rect` of `target` as RGBA8 rows into `out`.
pub fn write_rgba8(
    target: &RenderTarget,
    rect: PixelRect,
    out: &mut [u8],
) -> Result<(), PlotError> {
    let w = (rect.x1 - rect.x0).max(0) as usize;
    let h = (rect.y1 - rect.y0).max(0) as usize;
    if out.len() != w * h * 4
        || rect.x0 < 0
        || rect.y0 < 0
        || rect.x1 as u32 > target.width
        || rect.y1 as u32 > target.height
    {
        return Err(PlotError::Value(format!(
            "an output of {} bytes does not hold {w}x{h} RGBA pixels of the {}x{} target",
            out.len(),
            target.width,
            target.height
        )));
    }
    if out.is_empty() {
        return Ok(());
    }
    let tw = target.width as usize;
    for (j, row) in out.chunks_exact_mut(w * 4).enumerate() {
        let start = (rect.y0 as usize + j) * tw + rect.x0 as usize;
        for (px, &c) in row.chunks_exact_mut(4).zip(&target.color[start..start + w]) {
            px.copy_from_slice(&argb_to_rgba8(c));
        }
    }
    Ok(())
}

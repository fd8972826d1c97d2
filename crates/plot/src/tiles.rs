//! Sort-first drawing by screen tiles: the exact split of a draw whose pixels depend on the
//! order of its points (alpha blending, replace, depth testing).
//!
//! The target is cut into a grid of [`Tiles`]. [`Plot::bin`] sends each point, as its vertex
//! with its global index, to every tile its square overlaps; which pixels a square covers is
//! decided by core's per-point stage ([`PointSetup::process`], SPEC 4.1), the same code the
//! draw runs. [`Plot::render_tile`] draws a tile's vertices, in index order, on a target whose
//! viewport is the tile: pre-transformed positions are not moved (SPEC 1), the viewport only
//! scissors (SPEC 3.2), so every covered pixel of the tile gets exactly the operations, in the
//! same order, that the full draw gives it. Tiles assembled side by side are the full image.

use pointillist_core::device::DeviceError;
use pointillist_core::point::{PixelRect, PointSetup};

use crate::columns::write_vertices;
use crate::{BLOCK_VERTICES, Layout, Plot, PlotError, Points, write_rgba8};

/// A grid of tiles covering a `width` x `height` target, row by row; the last column and row
/// may be narrower.
#[derive(Copy, Clone, Debug, PartialEq, Eq)]
pub struct Tiles {
    width: u32,
    height: u32,
    tile_width: u32,
    tile_height: u32,
}

impl Tiles {
    /// Tiles of `tile_width` x `tile_height` pixels over a `width` x `height` target.
    pub fn new(
        width: u32,
        height: u32,
        tile_width: u32,
        tile_height: u32,
    ) -> Result<Tiles, PlotError> {
        if tile_width == 0 || tile_height == 0 {
            return Err(PlotError::Value(format!(
                "tile size {tile_width}x{tile_height} must be at least 1x1"
            )));
        }
        Ok(Tiles {
            width,
            height,
            tile_width: tile_width.min(width.max(1)),
            tile_height: tile_height.min(height.max(1)),
        })
    }

    /// Tiles across.
    pub fn columns(&self) -> u32 {
        self.width.div_ceil(self.tile_width)
    }

    /// Tiles down.
    pub fn rows(&self) -> u32 {
        self.height.div_ceil(self.tile_height)
    }

    /// The number of tiles.
    pub fn len(&self) -> usize {
        self.columns() as usize * self.rows() as usize
    }

    /// True when there are no tiles (an empty target).
    pub fn is_empty(&self) -> bool {
        self.len() == 0
    }

    /// The pixels of tile `i` (row-major).
    pub fn rect(&self, i: usize) -> PixelRect {
        let (c, r) = ((i as u32 % self.columns()), (i as u32 / self.columns()));
        let (x0, y0) = (c * self.tile_width, r * self.tile_height);
        PixelRect {
            x0: x0 as i32,
            y0: y0 as i32,
            x1: (x0 + self.tile_width).min(self.width) as i32,
            y1: (y0 + self.tile_height).min(self.height) as i32,
        }
    }

    /// The tiles rectangle `r` overlaps, as column and row ranges.
    fn overlapping(&self, r: PixelRect) -> (std::ops::Range<u32>, std::ops::Range<u32>) {
        let first = |a: i32, t: u32| a as u32 / t;
        let last = |b: i32, t: u32| (b as u32 - 1) / t + 1;
        (
            first(r.x0, self.tile_width)..last(r.x1, self.tile_width),
            first(r.y0, self.tile_height)..last(r.y1, self.tile_height),
        )
    }
}

/// The points one tile draws: their vertices ([`Layout::stride`] words each) and their global
/// indices, in index order.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct TileBin {
    /// The vertices, one after another.
    pub vertices: Vec<u32>,
    /// The global index of each vertex.
    pub index: Vec<u64>,
}

impl Plot {
    /// Sends each of `points` (global indices from `first_index` on) to every tile of `tiles`
    /// its square overlaps. Points that draw nothing (dropped by SPEC 3, or covering no pixel)
    /// go nowhere.
    pub fn bin(
        &self,
        points: &Points<'_>,
        first_index: u64,
        tiles: &Tiles,
    ) -> Result<Vec<TileBin>, PlotError> {
        let n = self.check(points)?;
        if (tiles.width, tiles.height) != (self.width, self.height) {
            return Err(PlotError::Value(format!(
                "tiles of a {}x{} target do not fit the {}x{} plot",
                tiles.width, tiles.height, self.width, self.height
            )));
        }
        let axes = self.axes()?;
        let layout = points.layout();
        let stride = layout.stride();
        let setup = PointSetup::new(&self.device_state(&layout), layout.fvf());
        let mut bins = vec![TileBin::default(); tiles.len()];
        let mut words = vec![0u32; n.min(BLOCK_VERTICES) * stride];
        for start in (0..n).step_by(BLOCK_VERTICES) {
            let end = n.min(start + BLOCK_VERTICES);
            let block = &mut words[..(end - start) * stride];
            write_vertices(
                &points.rows(start..end),
                axes,
                self.size_map(),
                start,
                block,
            )?;
            let bytes: &[u8] = bytemuck::cast_slice(block);
            for (k, vertex) in block.chunks_exact(stride).enumerate() {
                let Some(p) = setup.process(bytes, k as u32) else {
                    continue;
                };
                let (columns, rows) = tiles.overlapping(p.rect);
                for r in rows {
                    for c in columns.clone() {
                        let bin = &mut bins[(r * tiles.columns() + c) as usize];
                        bin.vertices.extend_from_slice(vertex);
                        bin.index.push(first_index + (start + k) as u64);
                    }
                }
            }
        }
        Ok(bins)
    }

    /// Draws one tile: `vertices` of `layout`, in the order given (index order), on a target
    /// cleared to the clear colour whose viewport is `rect`; returns the tile's RGBA8 rows.
    pub fn render_tile(
        &self,
        layout: &Layout,
        vertices: &[u32],
        rect: PixelRect,
    ) -> Result<Vec<u8>, PlotError> {
        self.axes()?;
        let inside = 0 <= rect.x0
            && rect.x0 < rect.x1
            && rect.x1 as u32 <= self.width
            && 0 <= rect.y0
            && rect.y0 < rect.y1
            && rect.y1 as u32 <= self.height;
        if !inside {
            return Err(PlotError::Value(format!(
                "tile {rect:?} is not inside the {}x{} target",
                self.width, self.height
            )));
        }
        // A target reaching the tile's far corner: the pixels left of and above the tile
        // exist but are outside the viewport, so nothing is drawn there.
        let size = (rect.x1 as u32, rect.y1 as u32);
        let backend = pointillist_cpu::CpuBackend::new();
        let mut device = self.device(backend, layout, size, Some(rect))?;
        let block = BLOCK_VERTICES * layout.stride();
        for part in vertices.chunks(block) {
            let bytes: &[u8] = bytemuck::cast_slice(part);
            device
                .draw_point_list(layout.fvf(), bytes)
                .map_err(|e: DeviceError| PlotError::from(e))?;
        }
        let (w, h) = ((rect.x1 - rect.x0) as usize, (rect.y1 - rect.y0) as usize);
        let mut out = vec![0u8; w * h * 4];
        write_rgba8(device.backend_mut().target(), rect, &mut out)?;
        Ok(out)
    }
}

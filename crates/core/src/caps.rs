//! Device caps and the built-in caps profiles (SPEC 6).
//!
//! A [`Caps`] is what a device reports; pointillist emulates any of them faithfully. With
//! software vertex processing the runtime emulates sprites, so [`Caps::effective`] lifts the
//! size limits the way the D3D9 runtime does.

use crate::device::lights::MAX_ACTIVE_LIGHTS;

/// How vertices are processed: by the device (its caps rule) or by the runtime (SPEC 6).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Default)]
pub enum VertexProcessing {
    /// D3DCREATE_HARDWARE_VERTEXPROCESSING: the device's caps apply.
    #[default]
    Hardware,
    /// D3DCREATE_SOFTWARE_VERTEXPROCESSING: the runtime emulates point sprites.
    Software,
}

/// The point-sprite and fog part of D3DCAPS9.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct Caps {
    /// D3DCAPS9.MaxPointSize: above 1 means sprites are supported; at most 1 means
    /// single-pixel points (SPEC 2.4).
    pub max_point_size: f32,
    /// D3DFVFCAPS_PSIZE: per-vertex PSIZE is honoured (SPEC 2.1).
    pub per_vertex_point_size: bool,
    /// D3DPMISCCAPS_CLIPPLANESCALEDPOINTS: user clip planes clip the scaled square (SPEC 3.3).
    pub clip_plane_scaled_points: bool,
    /// D3DPMISCCAPS_CLIPTLVERTS: pre-transformed points are clipped by depth under hardware
    /// vertex processing (SPEC 3.1, the `depth_clip` behaviour `vertex_processing`).
    pub clip_tl_verts: bool,
    /// Hardware or software vertex processing.
    pub vertex_processing: VertexProcessing,
    /// D3DPRASTERCAPS_WFOG: table fog from eye-relative w under a non-affine projection
    /// (SPEC 9.5).
    pub w_fog: bool,
    /// D3DCAPS9.MaxActiveLights: how many enabled lights light a vertex; the pipeline carries
    /// at most [`MAX_ACTIVE_LIGHTS`] (SPEC 8.2).
    pub max_active_lights: u32,
}

/// The largest sprite the runtime's software emulation draws (SPEC 6).
pub const SOFTWARE_MAX_POINT_SIZE: f32 = 8192.0;

impl Default for Caps {
    fn default() -> Self {
        Caps::reference()
    }
}

impl Caps {
    /// The names [`Caps::profile`] knows, the default first.
    pub const PROFILES: &'static [&'static str] = &[
        "reference",
        "no_per_vertex_size",
        "single_pixel",
        "vertex_position_clip",
        "software",
    ];

    /// The `reference` profile: 8192-pixel sprites, per-vertex size, scaled-point clipping,
    /// depth clipping of pre-transformed points, w-based table fog, 8 active lights.
    pub const fn reference() -> Caps {
        Caps {
            max_point_size: 8192.0,
            per_vertex_point_size: true,
            clip_plane_scaled_points: true,
            clip_tl_verts: true,
            vertex_processing: VertexProcessing::Hardware,
            w_fog: true,
            max_active_lights: 8,
        }
    }

    /// A built-in profile by name (case-insensitive, `-` and `_` alike):
    /// - `reference`: the default;
    /// - `no_per_vertex_size`: sprites to 64 pixels without D3DFVFCAPS_PSIZE, as on many
    ///   DX8-era cards;
    /// - `single_pixel`: MaxPointSize 1, every point one pixel;
    /// - `vertex_position_clip`: no CLIPPLANESCALEDPOINTS, points kept or dropped whole;
    /// - `software`: a single-pixel device used with software vertex processing, where the
    ///   runtime emulates sprites.
    pub fn profile(name: &str) -> Option<Caps> {
        let name = name.to_ascii_lowercase().replace('-', "_");
        let reference = Caps::reference();
        Some(match name.as_str() {
            "reference" => reference,
            "no_per_vertex_size" => Caps {
                max_point_size: 64.0,
                per_vertex_point_size: false,
                ..reference
            },
            "single_pixel" => Caps {
                max_point_size: 1.0,
                per_vertex_point_size: false,
                clip_plane_scaled_points: false,
                ..reference
            },
            "vertex_position_clip" => Caps {
                clip_plane_scaled_points: false,
                ..reference
            },
            "software" => Caps {
                max_point_size: 1.0,
                per_vertex_point_size: false,
                clip_plane_scaled_points: false,
                vertex_processing: VertexProcessing::Software,
                ..reference
            },
            _ => return None,
        })
    }

    /// The caps the pipeline applies: with software vertex processing, per-vertex size and
    /// sizes up to [`SOFTWARE_MAX_POINT_SIZE`] whatever the device reports (SPEC 6); active
    /// lights at most [`MAX_ACTIVE_LIGHTS`] (SPEC 8.2).
    pub fn effective(&self) -> Caps {
        let lights = self.max_active_lights.min(MAX_ACTIVE_LIGHTS as u32);
        match self.vertex_processing {
            VertexProcessing::Hardware => Caps {
                max_active_lights: lights,
                ..*self
            },
            VertexProcessing::Software => Caps {
                max_point_size: SOFTWARE_MAX_POINT_SIZE,
                per_vertex_point_size: true,
                max_active_lights: lights,
                ..*self
            },
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn spec_6_every_named_profile_exists() {
        for name in Caps::PROFILES {
            assert!(Caps::profile(name).is_some(), "{name}");
        }
        assert_eq!(Caps::profile("Single-Pixel").unwrap().max_point_size, 1.0);
        assert!(Caps::profile("voodoo").is_none());
        assert_eq!(Caps::default(), Caps::profile("reference").unwrap());
    }

    #[test]
    fn spec_6_software_vertex_processing_emulates_sprites() {
        let sw = Caps::profile("software").unwrap().effective();
        assert_eq!(sw.max_point_size, 8192.0);
        assert!(sw.per_vertex_point_size);
        let hw = Caps::profile("single_pixel").unwrap();
        assert_eq!(hw.effective(), hw);
    }
}

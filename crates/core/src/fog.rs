//! Fixed-function fog (SPEC 9): which fog a draw gets, the fog factor of one point and the
//! final blend towards FOGCOLOR.
//!
//! [`FogSetup::new`] resolves the fog states once per draw; the per-point stage asks it for
//! the point's factor ([`FogSetup::factor`]) and the pixel stage blends with [`fog_blend`].
//! For a point every pixel has the same depth, so the factor is computed once per point.

use crate::behaviour::{
    FogStartEqualsEnd, FogWithoutSpecular, PretransformedTableFog, TableFogDepth,
};
use crate::color::{Rgba, unpack};
use crate::device::state::DeviceState;
use crate::fvf::Fvf;
use crate::math::Mat4;
use crate::states::{FogMode, RenderState};

/// Where a draw's fog factor comes from (SPEC 9.2).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum FogSource {
    /// The vertex's SPECULAR alpha; for a vertex without SPECULAR, 0 or 1 as the
    /// `fog_without_specular` behaviour says.
    SpecularAlpha {
        /// The `fog_without_specular` behaviour.
        without: FogWithoutSpecular,
    },
    /// Vertex fog: `formula` of the eye-space depth `|Ze|`, or of the eye distance when
    /// `range` (RANGEFOGENABLE).
    Vertex {
        /// EXP, EXP2 or LINEAR.
        formula: FogMode,
        /// RANGEFOGENABLE.
        range: bool,
    },
    /// Table (pixel) fog: `formula` of the point's `distance`.
    Table {
        /// EXP, EXP2 or LINEAR.
        formula: FogMode,
        /// Which distance (SPEC 9.5).
        distance: TableDistance,
    },
}

/// The distance table fog reads (SPEC 9.5).
#[derive(Copy, Clone, Debug, PartialEq, Eq, Hash)]
pub enum TableDistance {
    /// Eye-relative: the clip-space w (`1 / RHW` for pre-transformed vertices).
    W,
    /// z-based: the point's depth Z, after the viewport maps it to MinZ..MaxZ; a
    /// pre-transformed vertex's Z.
    Depth,
    /// z-based before the viewport: clip-space `z / w` (the `clip_z` option of
    /// `table_fog_depth`); a pre-transformed vertex's Z.
    ClipZ,
}

/// The per-point part of a draw's fog, resolved (SPEC 9); `None` from [`FogSetup::new`] when
/// FOGENABLE is off. The pixel part, FOGCOLOR, is `PixelSetup::fog`.
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FogSetup {
    /// Where the factor comes from.
    pub source: FogSource,
    /// The formula's parameters.
    pub params: FogParams,
}

/// The numbers of the fog formulas, resolved once per draw (SPEC 9.3).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FogParams {
    /// FOGEND.
    pub end: f32,
    /// `1 / (FOGEND - FOGSTART)`, or 0 when FOGSTART == FOGEND and every point is fogged.
    pub scale: f32,
    /// FOGDENSITY.
    pub density: f32,
    /// FOGSTART == FOGEND fogs as a step: 1 nearer than FOGEND, 0 from FOGEND on.
    pub step: bool,
}

impl FogParams {
    /// From FOGSTART, FOGEND and FOGDENSITY; when FOGSTART == FOGEND, `step` says whether LINEAR
    /// fog is a step at FOGEND (else every point is fogged).
    pub fn new(start: f32, end: f32, density: f32, step: bool) -> FogParams {
        let equal = end == start;
        FogParams {
            end,
            scale: if equal { 0.0 } else { 1.0 / (end - start) },
            density,
            step: equal && step,
        }
    }
}

impl FogStartEqualsEnd {
    /// SPEC 9.3: whether LINEAR fog with FOGSTART == FOGEND is a step at FOGEND for vertex
    /// (`table` false) or table fog.
    pub fn step(self, table: bool) -> bool {
        match self {
            FogStartEqualsEnd::VertexFoggedTableStep => table,
            FogStartEqualsEnd::Fogged => false,
            FogStartEqualsEnd::Step => true,
        }
    }
}

/// SPEC 9.3: the fog factor of distance `d` under `formula`, clamped to 0..=1 (NaN to 0):
/// LINEAR `(end - d) / (end - start)` (computed as `(end - d) * scale`, 0 when start == end),
/// EXP `e^-(d * density)`, EXP2 `e^-((d * density)^2)`; NONE is 1.
#[inline]
pub fn fog_factor(formula: FogMode, d: f32, p: &FogParams) -> f32 {
    let f = match formula {
        FogMode::None => 1.0,
        FogMode::Linear if p.step => {
            if d < p.end {
                1.0
            } else {
                0.0
            }
        }
        FogMode::Linear => (p.end - d) * p.scale,
        FogMode::Exp => (-(d * p.density)).exp(),
        FogMode::Exp2 => {
            let x = d * p.density;
            (-(x * x)).exp()
        }
    };
    saturate(f)
}

/// `f` clamped to 0..=1, NaN to 0.
#[inline]
fn saturate(f: f32) -> f32 {
    if f >= 0.0 { f.min(1.0) } else { 0.0 }
}

/// SPEC 9.1: `f * colour + (1 - f) * FOGCOLOR` on red, green and blue; alpha unchanged.
#[inline]
pub fn fog_blend(c: Rgba, f: f32, fog: &Rgba) -> Rgba {
    let g = 1.0 - f;
    [
        c[0] * f + fog[0] * g,
        c[1] * f + fog[1] * g,
        c[2] * f + fog[2] * g,
        c[3],
    ]
}

/// SPEC 9.5: a projection is affine (z-based pixel fog) when its fourth column is (0, 0, 0, 1).
pub fn is_affine(projection: &Mat4) -> bool {
    let m = &projection.0;
    m[0][3] == 0.0 && m[1][3] == 0.0 && m[2][3] == 0.0 && m[3][3] == 1.0
}

impl FogWithoutSpecular {
    /// SPEC 9.2: the fog factor of a vertex without SPECULAR.
    #[inline]
    pub fn factor(self) -> f32 {
        match self {
            FogWithoutSpecular::Fogged => 0.0,
            FogWithoutSpecular::Unfogged => 1.0,
        }
    }
}

/// A point's distances for table fog (SPEC 9.5).
#[derive(Copy, Clone, Debug, PartialEq)]
pub struct FogDepth {
    /// The depth Z (SPEC 1), before the clamp of the depth written (SPEC 3.1).
    pub z: f32,
    /// The clip-space w; `1 / RHW` for a pre-transformed vertex (1 when RHW is 0).
    pub w: f32,
    /// Clip-space `z / w`; a pre-transformed vertex's Z.
    pub clip_z: f32,
}

/// SPEC 9.5: the distance table fog reads. Eye-relative w when the caps have
/// D3DPRASTERCAPS_WFOG (`w_fog`) and the projection is not `affine`, else z-based; the
/// `pretransformed_table_fog` switch can make `pretransformed` draws read w or Z whatever the
/// projection, and `table_fog_depth` says which z transformed points read.
pub fn table_distance(
    w_fog: bool,
    affine: bool,
    pretransformed: bool,
    rhw: PretransformedTableFog,
    depth: TableFogDepth,
) -> TableDistance {
    let w = match (pretransformed, rhw) {
        (true, PretransformedTableFog::W) => w_fog,
        (true, PretransformedTableFog::Z) => false,
        _ => w_fog && !affine,
    };
    match (w, pretransformed, depth) {
        (true, ..) => TableDistance::W,
        (false, false, TableFogDepth::ClipZ) => TableDistance::ClipZ,
        _ => TableDistance::Depth,
    }
}

impl FogSetup {
    /// SPEC 9.1, 9.2: the fog of a draw of `fvf` vertices, `None` when FOGENABLE is off.
    pub fn new(state: &DeviceState, fvf: Fvf) -> Option<FogSetup> {
        let rs = |s: RenderState| state.render_state(s);
        if rs(RenderState::FOGENABLE) == 0 {
            return None;
        }
        let mode = |s| FogMode::from_raw(rs(s)).unwrap_or(FogMode::None);
        let table = mode(RenderState::FOGTABLEMODE);
        let vertex = mode(RenderState::FOGVERTEXMODE);
        let source = if table != FogMode::None {
            FogSource::Table {
                formula: table,
                distance: table_distance(
                    state.caps.effective().w_fog,
                    is_affine(&state.projection),
                    fvf.is_pretransformed(),
                    state.behaviours.pretransformed_table_fog(),
                    state.behaviours.table_fog_depth(),
                ),
            }
        } else if vertex != FogMode::None && !fvf.is_pretransformed() {
            FogSource::Vertex {
                formula: vertex,
                range: rs(RenderState::RANGEFOGENABLE) != 0,
            }
        } else {
            FogSource::SpecularAlpha {
                without: state.behaviours.fog_without_specular(),
            }
        };
        let f = |s| f32::from_bits(rs(s));
        Some(FogSetup {
            source,
            params: FogParams::new(
                f(RenderState::FOGSTART),
                f(RenderState::FOGEND),
                f(RenderState::FOGDENSITY),
                state
                    .behaviours
                    .fog_start_equals_end()
                    .step(matches!(source, FogSource::Table { .. })),
            ),
        })
    }

    /// SPEC 9.2-9.5: the fog factor of one point. `eye` is its eye-space position (untransformed
    /// vertices; unused otherwise), `depth` its distances for table fog and `specular` its
    /// SPECULAR, if the vertex has one.
    #[inline]
    pub fn factor(&self, eye: [f32; 3], depth: &FogDepth, specular: Option<u32>) -> f32 {
        match self.source {
            FogSource::SpecularAlpha { without } => {
                specular.map_or(without.factor(), |s| unpack(s)[3])
            }
            FogSource::Vertex { formula, range } => {
                let d = if range {
                    (eye[0] * eye[0] + eye[1] * eye[1] + eye[2] * eye[2]).sqrt()
                } else {
                    eye[2].abs()
                };
                fog_factor(formula, d, &self.params)
            }
            FogSource::Table { formula, distance } => {
                let d = match distance {
                    TableDistance::W => depth.w,
                    TableDistance::Depth => depth.z,
                    TableDistance::ClipZ => depth.clip_z,
                };
                fog_factor(formula, d, &self.params)
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::caps::Caps;
    use crate::color::{pack, unpack};
    use crate::states::Api;

    fn setup_caps(
        states: &[(RenderState, u32)],
        fvf: Fvf,
        projection: &Mat4,
        caps: Caps,
    ) -> Option<FogSetup> {
        let mut state = DeviceState::new(Api::D3d9, caps, 64, 64);
        for &(s, v) in states {
            state.render_states[s.0 as usize] = v;
        }
        state.projection = *projection;
        FogSetup::new(&state, fvf)
    }

    /// Table fog distances of a point with depth `z` and w `w` (clip z = z: MinZ 0, MaxZ 1).
    fn at(z: f32, w: f32) -> FogDepth {
        FogDepth { z, w, clip_z: z }
    }

    fn setup(states: &[(RenderState, u32)], fvf: Fvf, projection: &Mat4) -> Option<FogSetup> {
        setup_caps(states, fvf, projection, Caps::reference())
    }

    const ON: (RenderState, u32) = (RenderState::FOGENABLE, 1);
    const XYZ_DS: Fvf = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);
    const RHW_DS: Fvf = Fvf(Fvf::XYZRHW.0 | Fvf::DIFFUSE.0 | Fvf::SPECULAR.0);

    fn mode(m: FogMode) -> u32 {
        m as u32
    }

    /// Within one step per colour channel, as Wine's tests compare.
    fn close(a: u32, b: u32) -> bool {
        (0..3).all(|k| ((a >> (8 * k)) & 0xFF).abs_diff((b >> (8 * k)) & 0xFF) <= 1)
    }

    #[test]
    fn spec_9_1_fog_is_off_by_default_and_blends_rgb_only() {
        assert_eq!(setup(&[], XYZ_DS, &Mat4::IDENTITY), None);
        let red = unpack(0xFFFF_0000);
        let green = unpack(0xFF00_FF00);
        // Wine fog_with_shader_test: linear table fog 0.1..0.9 at z = 0.2006 gives 0x00df2000.
        let f = fog_factor(
            FogMode::Linear,
            0.001 + 2.0 / 10.02,
            &FogParams::new(0.1, 0.9, 1.0, false),
        );
        assert_eq!(pack(fog_blend(red, f, &green)), 0xFFDF_2000);
        let half = fog_blend([1.0, 1.0, 1.0, 0.25], 0.5, &[0.0, 0.0, 0.0, 1.0]);
        assert_eq!(half, [0.5, 0.5, 0.5, 0.25]);
    }

    /// Wine fog_test: untransformed vertices with both modes NONE, and pre-transformed ones with
    /// vertex fog, read the factor from the specular alpha; table fog wins over vertex fog.
    #[test]
    fn spec_9_2_which_fog_applies() {
        let t = |states: &[(RenderState, u32)], fvf| {
            setup(states, fvf, &Mat4::IDENTITY).unwrap().source
        };
        assert_eq!(
            t(&[ON], XYZ_DS),
            FogSource::SpecularAlpha {
                without: FogWithoutSpecular::Fogged
            }
        );
        let vertex_linear = (RenderState::FOGVERTEXMODE, mode(FogMode::Linear));
        assert_eq!(
            t(&[ON, vertex_linear], XYZ_DS),
            FogSource::Vertex {
                formula: FogMode::Linear,
                range: false
            }
        );
        assert_eq!(
            t(&[ON, vertex_linear], RHW_DS),
            FogSource::SpecularAlpha {
                without: FogWithoutSpecular::Fogged
            }
        );
        let table_exp = (RenderState::FOGTABLEMODE, mode(FogMode::Exp));
        let range = (RenderState::RANGEFOGENABLE, 1);
        for fvf in [XYZ_DS, RHW_DS] {
            assert_eq!(
                t(&[ON, vertex_linear, table_exp, range], fvf),
                FogSource::Table {
                    formula: FogMode::Exp,
                    distance: TableDistance::Depth
                }
            );
        }
        // An undefined mode value is NONE.
        assert_eq!(
            t(&[ON, (RenderState::FOGTABLEMODE, 9)], XYZ_DS),
            FogSource::SpecularAlpha {
                without: FogWithoutSpecular::Fogged
            }
        );
        let s = setup(&[ON], XYZ_DS, &Mat4::IDENTITY).unwrap();
        assert_eq!(
            s.factor([0.0; 3], &at(0.5, 1.0), Some(0x8000_0000)),
            128.0 / 255.0
        );
        // SPEC 9.2, `fog_without_specular`: no SPECULAR fogs completely, or not at all.
        assert_eq!(s.factor([0.0; 3], &at(0.5, 1.0), None), 0.0);
        let unfogged = (RenderState::FOGENABLE, 1);
        let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 64, 64);
        state.render_states[unfogged.0.0 as usize] = unfogged.1;
        state
            .behaviours
            .apply("fog_without_specular=unfogged")
            .unwrap();
        let s = FogSetup::new(&state, RHW_DS).unwrap();
        assert_eq!(s.factor([0.0; 3], &at(0.5, 1.0), None), 1.0);
        assert_eq!(
            s.factor([0.0; 3], &at(0.5, 1.0), Some(0x4000_0000)),
            64.0 / 255.0
        );
    }

    #[test]
    fn spec_9_3_start_equal_to_end_follows_the_behaviour() {
        let state = |option: &str, table: bool| {
            let mode = if table {
                RenderState::FOGTABLEMODE
            } else {
                RenderState::FOGVERTEXMODE
            };
            let mut s = DeviceState::new(Api::D3d9, Caps::reference(), 8, 8);
            for (k, v) in [
                (RenderState::FOGENABLE, 1),
                (mode, FogMode::Linear as u32),
                (RenderState::FOGSTART, 0.5f32.to_bits()),
                (RenderState::FOGEND, 0.5f32.to_bits()),
            ] {
                s.render_states[k.0 as usize] = v;
            }
            s.behaviours.set("fog_start_equals_end", option).unwrap();
            FogSetup::new(&s, XYZ_DS).unwrap()
        };
        // Vertex fog reads |Ze|, table fog the depth Z (identity projection: both 0.25 here).
        let near = |s: FogSetup| s.factor([0.0, 0.0, 0.25], &at(0.25, 1.0), None);
        for (option, vertex, table) in [
            ("vertex_fogged_table_step", 0.0, 1.0),
            ("fogged", 0.0, 0.0),
            ("step", 1.0, 1.0),
        ] {
            assert_eq!(near(state(option, false)), vertex, "{option} vertex");
            assert_eq!(near(state(option, true)), table, "{option} table");
        }
    }

    #[test]
    fn spec_9_3_formulas() {
        let p = FogParams::new(2.0, 10.0, 0.5, false);
        assert_eq!(fog_factor(FogMode::Linear, 6.0, &p), 0.5);
        assert_eq!(fog_factor(FogMode::Linear, 1.0, &p), 1.0);
        assert_eq!(fog_factor(FogMode::Linear, 11.0, &p), 0.0);
        assert_eq!(fog_factor(FogMode::Exp, 2.0, &p), (-1.0f32).exp());
        assert_eq!(fog_factor(FogMode::Exp2, 4.0, &p), (-4.0f32).exp());
        // Wine fog_test: FOGSTART == FOGEND fogs every point fully, even in front of start.
        let same = FogParams::new(512.0, 512.0, 1.0, false);
        assert_eq!(fog_factor(FogMode::Linear, 0.1, &same), 0.0);
        assert_eq!(fog_factor(FogMode::Linear, 1000.0, &same), 0.0);
        // Wine fog_special_test, D3D9On12 ComputePixelFog: table fog with start == end is a step
        // at the end, fogged from it on (NaN fogged too).
        let step = FogParams::new(0.5, 0.5, 1.0, true);
        assert_eq!(fog_factor(FogMode::Linear, 0.4999, &step), 1.0);
        assert_eq!(fog_factor(FogMode::Linear, 0.5, &step), 0.0);
        assert_eq!(fog_factor(FogMode::Linear, 0.6, &step), 0.0);
        assert_eq!(fog_factor(FogMode::Linear, f32::NAN, &step), 0.0);
        assert!(
            !FogParams::new(0.2, 0.5, 1.0, true).step,
            "only when start == end"
        );
        let nan = FogParams::new(0.0, 1.0, f32::NAN, false);
        assert_eq!(fog_factor(FogMode::Exp, 1.0, &nan), 0.0);
        // Wine fog_with_shader_test, table EXP and EXP2 at z = 0.7994 (density 1): 0x00738c00 and
        // 0x00867900 within 1 step.
        let red = unpack(0xFFFF_0000);
        let green = unpack(0xFF00_FF00);
        let z = 0.001 + 8.0 / 10.02;
        let one = FogParams::new(0.1, 0.9, 1.0, false);
        let exp = pack(fog_blend(red, fog_factor(FogMode::Exp, z, &one), &green));
        let exp2 = pack(fog_blend(red, fog_factor(FogMode::Exp2, z, &one), &green));
        assert!(close(exp, 0xFF73_8C00), "{exp:08x}");
        assert!(close(exp2, 0xFF86_7900), "{exp2:08x}");
    }

    #[test]
    fn spec_9_4_vertex_fog_distance() {
        let linear = [
            ON,
            (RenderState::FOGVERTEXMODE, mode(FogMode::Linear)),
            (RenderState::FOGSTART, 0.0f32.to_bits()),
            (RenderState::FOGEND, 10.0f32.to_bits()),
        ];
        let s = setup(&linear, XYZ_DS, &Mat4::IDENTITY).unwrap();
        assert_eq!(s.factor([3.0, 0.0, -4.0], &at(0.0, 0.0), None), 0.6);
        let mut ranged = linear.to_vec();
        ranged.push((RenderState::RANGEFOGENABLE, 1));
        let s = setup(&ranged, XYZ_DS, &Mat4::IDENTITY).unwrap();
        assert_eq!(s.factor([3.0, 0.0, -4.0], &at(0.0, 0.0), None), 0.5);
    }

    /// Wine fog_test's orthogonal projection (z-based: 0x00e51900 at Z = 0.1) and
    /// test_table_fog_zw (pre-transformed vertices under an identity projection use Z whatever
    /// their RHW); a perspective projection uses w.
    #[test]
    fn spec_9_5_table_fog_depth_is_z_or_w() {
        let table = [ON, (RenderState::FOGTABLEMODE, mode(FogMode::Linear))];
        let ortho = Mat4([
            [1.0, 0.0, 0.0, 0.0],
            [0.0, 1.0, 0.0, 0.0],
            [0.0, 0.0, 1.0, 0.0],
            [0.0, 0.0, -1.0, 1.0],
        ]);
        let s = setup(&table, XYZ_DS, &ortho).unwrap();
        let f = s.factor([0.0; 3], &at(0.1, 1.0), None);
        let c = pack(fog_blend(unpack(0xFFFF_0000), f, &unpack(0xFF00_FF00)));
        assert!(close(c, 0xFFE5_1900), "{c:08x}");
        let s = setup(&table, RHW_DS, &Mat4::IDENTITY).unwrap();
        assert_eq!(
            s.factor([0.0; 3], &at(0.7, 1.0 / 0.3), None),
            s.factor([0.0; 3], &at(0.7, 1.0), None)
        );
        let persp = Mat4::perspective_fov_lh(1.0, 1.0, 1.0, 100.0);
        let s = setup(&table, XYZ_DS, &persp).unwrap();
        assert_eq!(
            s.source,
            FogSource::Table {
                formula: FogMode::Linear,
                distance: TableDistance::W
            }
        );
        let caps = Caps {
            w_fog: false,
            ..Caps::reference()
        };
        let no_wfog = setup_caps(&table, XYZ_DS, &persp, caps).unwrap();
        assert_eq!(
            no_wfog.source,
            FogSource::Table {
                formula: FogMode::Linear,
                distance: TableDistance::Depth
            }
        );
    }

    /// SPEC 9.5's switches: `pretransformed_table_fog` (Wine test_fog: 1 / RHW under a
    /// projection that is not affine, Z under an affine one; DXVK master: always 1 / RHW) and
    /// `table_fog_depth` (the depth after the viewport, or clip z / w before it).
    #[test]
    fn spec_9_5_table_fog_distance_switches() {
        use PretransformedTableFog as P;
        use TableDistance as D;
        use TableFogDepth as T;
        let d = |w_fog, affine, pretransformed, rhw, depth| {
            table_distance(w_fog, affine, pretransformed, rhw, depth)
        };
        for (rhw, affine, expected) in [
            (P::Projection, false, D::W),
            (P::Projection, true, D::Depth),
            (P::W, true, D::W),
            (P::W, false, D::W),
            (P::Z, false, D::Depth),
            (P::Z, true, D::Depth),
        ] {
            for depth in T::ALL.iter().copied() {
                assert_eq!(
                    d(true, affine, true, rhw, depth),
                    expected,
                    "{rhw:?} {affine}"
                );
                assert_eq!(d(false, affine, true, rhw, depth), D::Depth, "no WFOG cap");
            }
            // Transformed points follow the projection whatever the pre-transformed option.
            let own = if affine { D::Depth } else { D::W };
            assert_eq!(d(true, affine, false, rhw, T::Viewport), own);
        }
        assert_eq!(d(true, true, false, P::Projection, T::ClipZ), D::ClipZ);
        assert_eq!(d(true, false, false, P::Projection, T::ClipZ), D::W);
        // The factor reads the chosen distance: viewport MinZ 0.5 puts clip z 0.5 at depth 0.75.
        let mut state = DeviceState::new(Api::D3d9, Caps::reference(), 8, 8);
        for (k, v) in [
            (RenderState::FOGENABLE, 1),
            (RenderState::FOGTABLEMODE, FogMode::Linear as u32),
        ] {
            state.render_states[k.0 as usize] = v;
        }
        let point = FogDepth {
            z: 0.75,
            w: 1.0,
            clip_z: 0.5,
        };
        let viewport = FogSetup::new(&state, XYZ_DS).unwrap();
        assert_eq!(viewport.factor([0.0; 3], &point, None), 0.25);
        state.behaviours.set("table_fog_depth", "clip_z").unwrap();
        let clip = FogSetup::new(&state, XYZ_DS).unwrap();
        assert_eq!(clip.factor([0.0; 3], &point, None), 0.5);
        state.projection = Mat4::perspective_fov_lh(1.0, 1.0, 1.0, 100.0);
        state
            .behaviours
            .set("pretransformed_table_fog", "z")
            .unwrap();
        let rhw = FogSetup::new(&state, RHW_DS).unwrap();
        let far = FogDepth {
            z: 0.25,
            w: 5.0,
            clip_z: 0.25,
        };
        assert_eq!(rhw.factor([0.0; 3], &far, None), 0.75);
    }
}

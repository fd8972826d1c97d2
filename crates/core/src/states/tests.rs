//! Tests across the render, texture-stage and sampler state tables.

use super::*;

#[test]
fn well_known_numbers() {
    assert_eq!(RenderState::ZENABLE.0, 7);
    assert_eq!(RenderState::ALPHABLENDENABLE.0, 27);
    assert_eq!(RenderState::TEXTUREFACTOR.0, 60);
    assert_eq!(RenderState::WRAP7.0, 135);
    assert_eq!(RenderState::LIGHTING.0, 137);
    assert_eq!(RenderState::POINTSIZE.0, 154);
    assert_eq!(RenderState::POINTSIZE_MIN.0, 155);
    assert_eq!(RenderState::POINTSCALE_A.0, 158);
    assert_eq!(RenderState::POINTSIZE_MAX.0, 166);
    assert_eq!(RenderState::COLORWRITEENABLE.0, 168);
    assert_eq!(RenderState::BLENDFACTOR.0, 193);
    assert_eq!(RenderState::WRAP8.0, 198);
    assert_eq!(RenderState::BLENDOPALPHA.0, 209);
    assert_eq!(RenderState::all().len(), 103);
    assert_eq!(TextureStageState::CONSTANT.0, 32);
    assert_eq!(TextureStageState::RESULTARG.0, 28);
    assert_eq!(TextureStageState::all().len(), 18);
    assert_eq!(SamplerState::MIPMAPLODBIAS.0, 8);
    assert_eq!(SamplerState::DMAPOFFSET.0, 13);
    assert_eq!(SamplerState::all().len(), 13);
}

#[test]
fn all_ascending_and_below_count() {
    let rs: Vec<u32> = RenderState::all().iter().map(|s| s.0).collect();
    assert!(rs.windows(2).all(|w| w[0] < w[1]));
    assert!(rs.iter().all(|&id| (id as usize) < RenderState::COUNT));
    let tss: Vec<u32> = TextureStageState::all().iter().map(|s| s.0).collect();
    assert!(tss.windows(2).all(|w| w[0] < w[1]));
    assert!(
        tss.iter()
            .all(|&id| (id as usize) < TextureStageState::COUNT)
    );
    let samp: Vec<u32> = SamplerState::all().iter().map(|s| s.0).collect();
    assert!(samp.windows(2).all(|w| w[0] < w[1]));
    assert!(samp.iter().all(|&id| (id as usize) < SamplerState::COUNT));
}

#[test]
fn state_name_round_trips() {
    for &s in RenderState::all() {
        let name = s.name().unwrap();
        assert_eq!(RenderState::from_name(name), Some(s));
        assert_eq!(RenderState::from_name(&format!("D3DRS_{name}")), Some(s));
        assert_eq!(RenderState::from_name(&name.to_ascii_lowercase()), Some(s));
    }
    for &s in TextureStageState::all() {
        let name = s.name().unwrap();
        assert_eq!(TextureStageState::from_name(name), Some(s));
        assert_eq!(
            TextureStageState::from_name(&format!("d3dtss_{name}")),
            Some(s)
        );
    }
    for &s in SamplerState::all() {
        let name = s.name().unwrap();
        assert_eq!(SamplerState::from_name(name), Some(s));
        assert_eq!(SamplerState::from_name(&format!("D3DSAMP_{name}")), Some(s));
    }
    assert_eq!(
        RenderState::from_name("pointsize_min"),
        Some(RenderState::POINTSIZE_MIN)
    );
    assert_eq!(RenderState::from_name("NOSUCHSTATE"), None);
    assert_eq!(RenderState::from_name("D3DTSS_COLOROP"), None);
    assert_eq!(RenderState(153).name(), None);
    assert_eq!(TextureStageState(12).name(), None);
    assert_eq!(SamplerState(0).name(), None);
}

#[test]
fn other_defaults() {
    let b = crate::behaviour::Behaviours::default();
    let d = |s: RenderState| s.default_value(Api::D3d9, &b, 64.0);
    assert_eq!(d(RenderState::ZENABLE), 1);
    assert_eq!(d(RenderState::ZWRITEENABLE), 1);
    assert_eq!(d(RenderState::ZFUNC), Cmp::LessEqual as u32);
    assert_eq!(d(RenderState::ALPHAFUNC), Cmp::Always as u32);
    assert_eq!(d(RenderState::SRCBLEND), Blend::One as u32);
    assert_eq!(d(RenderState::DESTBLEND), Blend::Zero as u32);
    assert_eq!(d(RenderState::BLENDOP), BlendOp::Add as u32);
    assert_eq!(d(RenderState::COLORWRITEENABLE), 0xF);
    assert_eq!(d(RenderState::TEXTUREFACTOR), 0xFFFF_FFFF);
    assert_eq!(d(RenderState::BLENDFACTOR), 0xFFFF_FFFF);
    assert_eq!(d(RenderState::CLIPPING), 1);
    assert_eq!(d(RenderState::LIGHTING), 1);
    assert_eq!(d(RenderState::CULLMODE), 3);
    assert_eq!(f32::from_bits(d(RenderState::FOGEND)), 1.0);
    assert_eq!(f32::from_bits(d(RenderState::ADAPTIVETESS_Z)), 1.0);
    assert_eq!(d(RenderState(1)), 0);
    // Every enum default except DEBUGMONITORTOKEN's runtime magic names a value.
    for &s in RenderState::all() {
        if let ValueKind::Enum(t) = s.kind()
            && s != RenderState::DEBUGMONITORTOKEN
        {
            assert!(t.value_name(d(s)).is_some(), "{s:?}");
        }
    }
    for stage in 0..8 {
        let t = |s: TextureStageState| s.default_value(stage);
        let (colorop, alphaop) = if stage == 0 {
            (TextureOp::Modulate, TextureOp::SelectArg1)
        } else {
            (TextureOp::Disable, TextureOp::Disable)
        };
        assert_eq!(t(TextureStageState::COLOROP), colorop as u32);
        assert_eq!(t(TextureStageState::ALPHAOP), alphaop as u32);
        assert_eq!(t(TextureStageState::COLORARG1), TA_TEXTURE);
        assert_eq!(t(TextureStageState::COLORARG2), TA_CURRENT);
        assert_eq!(t(TextureStageState::ALPHAARG1), TA_TEXTURE);
        assert_eq!(t(TextureStageState::ALPHAARG2), TA_CURRENT);
        assert_eq!(t(TextureStageState::RESULTARG), TA_CURRENT);
        assert_eq!(t(TextureStageState::TEXCOORDINDEX), stage as u32);
        assert_eq!(t(TextureStageState::CONSTANT), 0);
    }
    assert_eq!(
        SamplerState::ADDRESSU.default_value(),
        TextureAddress::Wrap as u32
    );
    assert_eq!(
        SamplerState::MINFILTER.default_value(),
        TextureFilter::Point as u32
    );
    assert_eq!(
        SamplerState::MIPFILTER.default_value(),
        TextureFilter::None as u32
    );
    assert_eq!(SamplerState::MAXANISOTROPY.default_value(), 1);
}

#[test]
fn kinds_and_affects() {
    assert_eq!(RenderState::POINTSIZE.kind(), ValueKind::Float);
    assert_eq!(
        RenderState::ZENABLE.kind(),
        ValueKind::Enum(EnumType::ZBufferType)
    );
    assert_eq!(
        RenderState::SRCBLENDALPHA.kind(),
        ValueKind::Enum(EnumType::Blend)
    );
    assert_eq!(
        RenderState::CCW_STENCILFUNC.kind(),
        ValueKind::Enum(EnumType::Cmp)
    );
    assert_eq!(RenderState::AMBIENT.kind(), ValueKind::Color);
    assert_eq!(RenderState::CLIPPLANEENABLE.kind(), ValueKind::Int);
    assert_eq!(RenderState::LIGHTING.kind(), ValueKind::Bool);
    assert_eq!(TextureStageState::RESULTARG.kind(), ValueKind::TextureArg);
    assert_eq!(TextureStageState::BUMPENVLSCALE.kind(), ValueKind::Float);
    assert_eq!(SamplerState::MIPMAPLODBIAS.kind(), ValueKind::Float);
    let points: Vec<&str> = RenderState::all()
        .iter()
        .filter(|s| s.affects_points())
        .map(|s| s.name().unwrap())
        .collect();
    assert_eq!(points.len(), 45);
    assert!(RenderState::LIGHTING.affects_points()); // SPEC 8.1
    assert!(RenderState::FOGENABLE.affects_points()); // SPEC 9.1
    assert!(RenderState::FOGVERTEXMODE.affects_points());
    assert!(RenderState::EMISSIVEMATERIALSOURCE.affects_points());
    assert!(!RenderState::CULLMODE.affects_points());
    assert!(!RenderState(153).affects_points());
    assert!(TextureStageState::TEXCOORDINDEX.affects_points());
    assert!(!TextureStageState::BUMPENVMAT00.affects_points());
    assert!(SamplerState::MAXMIPLEVEL.affects_points());
    assert!(!SamplerState::ADDRESSW.affects_points());
}

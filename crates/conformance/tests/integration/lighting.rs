//! SPEC section 8, vertex lighting: the cases of `cases/8-lighting/`, and what a scene cannot
//! state (SetLight's refusals, the light LightEnable creates, the note of a lit draw without a
//! light), through the public device API on both backends.

use crate::common::*;
use pointillist_core::DeviceError;
use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::light::{Light, LightType, Material};
use pointillist_core::states::RenderState;

cases!("8-lighting":
    ambient_from_lights_and_render_state,
    attenuation_and_range,
    light_enable_creates_the_default_light,
    lit_without_a_light_is_ambient_and_emissive,
    material_source_missing_colour_is_the_material,
    normalize_normals,
    normals_go_through_the_inverse_world_view,
    pretransformed_points_are_never_lit,
    singular_world_lights_untransformed_normals,
    specular_directional_local_viewer,
    specular_needs_the_light_in_front,
    specular_point_light,
    specular_point_light_range,
    specular_power_zero,
    specular_spot_light,
);

type Rs = RenderState;

#[test]
fn spec_8_2_set_light_refuses_members_outside_their_ranges() {
    let mut d = dev(8, 8);
    let spot = Light {
        range: 10.0,
        attenuation0: 1.0,
        theta: 0.5,
        phi: 0.4,
        ..Light::zeroed(LightType::Spot)
    };
    let spot = Light {
        direction: [0.0, 0.0, 1.0],
        ..spot
    };
    match d.set_light(3, spot) {
        Err(DeviceError::Light { index: 3, error }) => assert_eq!(error.field, "theta"),
        other => panic!("{other:?}"),
    }
    assert!(
        d.state().lights.get(3).is_none(),
        "a refused SetLight changes nothing"
    );
    let point = Light {
        range: 10.0,
        attenuation2: -0.5,
        ..Light::zeroed(LightType::Point)
    };
    let e = d.set_light(0, point).unwrap_err();
    assert_eq!(
        e.to_string(),
        "SetLight(0): light attenuation2 must be finite and >= 0"
    );
    d.set_light(
        0,
        Light {
            attenuation2: 0.5,
            ..point
        },
    )
    .unwrap();
    assert!(!d.state().lights.get(0).unwrap().enabled);
}

#[test]
fn spec_8_2_light_enable_of_an_unset_index_is_the_default_light() {
    let mut d = dev(8, 8);
    d.light_enable(7, true);
    let slot = d.state().lights.get(7).copied().unwrap();
    assert!(slot.enabled);
    assert_eq!(slot.light, Light::DEFAULT);
    assert_eq!(slot.light.light_type, LightType::Directional);
    assert_eq!(slot.light.diffuse, [1.0, 1.0, 1.0, 0.0]);
    assert_eq!(slot.light.direction, [0.0, 0.0, 1.0]);
}

#[test]
fn spec_8_1_a_lit_draw_without_a_light_is_noted_once() {
    let mut d = dev(8, 8);
    d.set_render_state(Rs::LIGHTING, true);
    let xyz = Fvf(Fvf::XYZ.0 | Fvf::DIFFUSE.0);
    // Pre-transformed points are never lit: no note.
    draw(&mut d, RHW_D, &[f(4.0), f(4.0), f(0.5), f(1.0), WHITE]);
    assert!(d.take_notices().is_empty());
    draw(&mut d, xyz, &[f(0.0), f(0.0), f(0.5), WHITE]);
    draw(&mut d, xyz, &[f(0.0), f(0.0), f(0.5), WHITE]);
    let notes = d.take_notices();
    assert_eq!(notes.len(), 1, "{notes:?}");
    assert!(notes[0].contains("no light is enabled"), "{notes:?}");
    // Black: no light, zero material and AMBIENT; the vertex's alpha (SPEC 8.7).
    assert_eq!(target(&mut d).pixel(4, 4), 0xFF00_0000);
}

#[test]
fn spec_8_2_the_caps_max_active_lights_bound_the_lights_that_light_a_vertex() {
    // Lights 0, 1 and 2 add red, green and blue to a white material facing them.
    let rgb = [
        [1.0, 0.0, 0.0, 0.0],
        [0.0, 1.0, 0.0, 0.0],
        [0.0, 0.0, 1.0, 0.0],
    ];
    let normal = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0);
    for (max_active_lights, want) in [
        (0, 0xFF00_0000u32),
        (1, 0xFFFF_0000),
        (2, 0xFFFF_FF00),
        (8, 0xFFFF_FFFF),
    ] {
        let caps = Caps {
            max_active_lights,
            ..Caps::reference()
        };
        let mut d = dev_caps(8, 8, caps);
        d.set_render_state(Rs::LIGHTING, true);
        d.set_material(Material {
            diffuse: [1.0; 4],
            ambient: [0.0; 4],
            specular: [0.0; 4],
            emissive: [0.0; 4],
            power: 0.0,
        });
        for (i, diffuse) in rgb.iter().enumerate() {
            let light = Light {
                diffuse: *diffuse,
                ..Light::DEFAULT
            };
            d.set_light(i as u32, light).unwrap();
            d.light_enable(i as u32, true);
        }
        // At the target's centre, its normal towards the viewer, against the lights' +z.
        draw(
            &mut d,
            normal,
            &[f(0.0), f(0.0), f(0.5), f(0.0), f(0.0), f(-1.0)],
        );
        assert_eq!(
            target(&mut d).pixel(4, 4),
            want,
            "MaxActiveLights {max_active_lights}"
        );
    }
}

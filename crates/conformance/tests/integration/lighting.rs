//! SPEC section 8, vertex lighting: the cases of `cases/8-lighting/`, and what a scene cannot
//! state (SetLight's refusals, the light LightEnable creates, the note of a lit draw without a
//! light), through the public device API on both backends.

use pointillist_core::caps::Caps;
use pointillist_core::fvf::Fvf;
use pointillist_core::light::{Light, LightType, Material};
use pointillist_core::math::Mat4;
use pointillist_core::states::RenderState;
use pointillist_core::{DeviceError, TransformType};
use pointillist_testkit::{Tolerance, check};

use crate::common::*;

cases!("8-lighting":
    a_disable_does_not_give_its_slot_to_a_waiting_light_under_enable_order,
    a_disable_lets_the_next_lowest_enabled_light_in,
    all_attenuations_zero_draw_black_under_infinite,
    all_attenuations_zero_saturate,
    ambient_from_lights_and_render_state,
    attenuation_and_range,
    light_enable_creates_the_default_light,
    lit_without_a_light_is_ambient_and_emissive,
    material_source_missing_colour_is_the_material,
    max_active_lights_10_lights_with_ten_lights,
    nine_lights_light_the_eight_lowest_indices,
    nine_lights_light_the_first_eight_enabled_under_enable_order,
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
    ten_lights_light_the_eight_lowest_indices,
    ten_lights_light_the_first_eight_enabled_under_enable_order,
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

/// A lit device with a white material (diffuse and ambient) under `behaviour`
/// (`NAME=OPTION`), on a device of `max_active_lights`.
fn lit_dev(behaviour: &str, max_active_lights: u32) -> TestDevice {
    let mut behaviours = pointillist_core::Behaviours::default();
    behaviours.apply(behaviour).unwrap();
    let mut d = dev_desc(pointillist_core::DeviceDesc {
        caps: Caps {
            max_active_lights,
            ..Caps::reference()
        },
        behaviours,
        ..pointillist_core::DeviceDesc::new(8, 8)
    });
    d.set_render_state(Rs::LIGHTING, true);
    d.set_material(Material {
        diffuse: [1.0; 4],
        ambient: [1.0; 4],
        specular: [0.0; 4],
        emissive: [0.0; 4],
        power: 0.0,
    });
    d
}

/// SPEC 8.4, `zero_attenuation`, on both backends: a point light at the eye with all
/// attenuations 0 lights a point at z 0.5 (white material, ambient included). Under
/// `infinite` a channel whose light colour is 0 is NaN, written 0; a nonzero one saturates; a
/// normal facing away makes every diffuse channel NaN; without NORMAL only the ambient term
/// counts. Under `flt_max` a colour 0 adds nothing.
#[test]
fn spec_8_4_zero_attenuation_on_both_backends() {
    let normal = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0);
    let point = Light {
        diffuse: [1.0, 0.0, 1.0, 0.0],
        ambient: [1.0, 1.0, 0.0, 0.0],
        range: 10.0,
        ..Light::zeroed(LightType::Point)
    };
    let spot = Light {
        direction: [0.0, 0.0, 1.0],
        theta: 0.5,
        phi: 1.0,
        ..Light {
            light_type: LightType::Spot,
            ..point
        }
    };
    let towards = [f(0.0), f(0.0), f(0.5), f(0.0), f(0.0), f(-1.0)];
    let away = [f(0.0), f(0.0), f(0.5), f(0.0), f(0.0), f(1.0)];
    for (option, light, fvf, vertex, want) in [
        // ambient r, g: inf; b: 0 * inf = NaN. Diffuse r, b: inf; g: 0 * inf = NaN.
        ("infinite", point, normal, &towards[..], 0xFFFF_0000u32),
        ("flt_max", point, normal, &towards[..], 0xFFFF_FFFF),
        // Facing away: N.L clamps to 0, 0 * inf is NaN in every diffuse channel.
        ("infinite", point, normal, &away[..], 0xFF00_0000),
        ("flt_max", point, normal, &away[..], 0xFFFF_FF00),
        // Without NORMAL: no diffuse term, the ambient one only.
        ("infinite", point, XYZ, &towards[..3], 0xFFFF_FF00),
        ("flt_max", point, XYZ, &towards[..3], 0xFFFF_FF00),
        // A spot light inside its cone: the same as the point light.
        ("infinite", spot, normal, &towards[..], 0xFFFF_0000),
    ] {
        let mut d = lit_dev(&format!("zero_attenuation={option}"), 8);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_light(0, light).unwrap();
        d.light_enable(0, true);
        draw(&mut d, fvf, vertex);
        assert_eq!(
            target(&mut d).pixel(4, 4),
            want,
            "{option} {:?} {fvf:?} {vertex:x?}",
            light.light_type
        );
    }
}

/// SPEC 8.2, `light_order`, on both backends: ten lights each adding its own colour, on
/// devices of 8 and 10, enabled from index 9 down; under `enable_order` slots follow the
/// enables, and a disable frees one that an overflowing light takes only when enabled again.
#[test]
fn spec_8_2_light_order_on_both_backends() {
    // Light k adds 1/16 of red for k < 5, of green for k >= 5, and light 9 blue.
    let colour = |k: u32| match k {
        9 => [0.0, 0.0, 1.0, 0.0],
        k if k < 5 => [1.0 / 16.0, 0.0, 0.0, 0.0],
        _ => [0.0, 1.0 / 16.0, 0.0, 0.0],
    };
    let normal = Fvf(Fvf::XYZ.0 | Fvf::NORMAL.0);
    let vertex = [f(0.0), f(0.0), f(0.5), f(0.0), f(0.0), f(-1.0)];
    let pixel = |d: &mut TestDevice| {
        d.clear(0xFF00_0000, 1.0).unwrap();
        draw(d, normal, &vertex);
        target(d).pixel(4, 4)
    };
    // 5 reds, 3 greens (lights 0..7) = 0x50, 0x30; or 9..2: blue, 4 greens, 3 reds.
    for (option, max, want) in [
        ("lowest_indices", 8, 0xFF50_3000u32),
        ("enable_order", 8, 0xFF30_40FF),
        ("lowest_indices", 10, 0xFF50_40FF),
        ("enable_order", 10, 0xFF50_40FF),
    ] {
        let mut d = lit_dev(&format!("light_order={option}"), max);
        d.set_render_state(Rs::POINTSIZE, 3.0f32);
        d.set_material(Material {
            diffuse: [1.0; 4],
            ambient: [0.0; 4],
            specular: [0.0; 4],
            emissive: [0.0; 4],
            power: 0.0,
        });
        for k in (0..10).rev() {
            let light = Light {
                diffuse: colour(k),
                ..Light::DEFAULT
            };
            d.set_light(k, light).unwrap();
            d.light_enable(k, true);
        }
        assert_eq!(pixel(&mut d), want, "{option}, MaxActiveLights {max}");
        if max == 8 {
            // Disable light 9: under enable_order its slot is free and lights 0 and 1, which
            // found none, still light nothing; enabling 0 again takes it.
            d.light_enable(9, false);
            let after = if option == "enable_order" {
                0xFF30_4000
            } else {
                0xFF50_3000
            };
            assert_eq!(pixel(&mut d), after, "{option} after a disable");
            d.light_enable(0, true);
            let again = if option == "enable_order" {
                0xFF40_4000
            } else {
                0xFF50_3000
            };
            assert_eq!(pixel(&mut d), again, "{option} after enabling 0 again");
        }
    }
}

/// SPEC 8: every light type, attenuation, range, spot cones, specular with a local and an
/// infinite viewer, material sources, NORMALIZENORMALS, on both backends.
#[test]
fn spec_8_lighting_each_light_type() {
    use pointillist_core::light::{Light, LightType, Material};
    let mut r = Rng(0x11_6475);
    let grid = lit_grid(&mut r);
    let lights = [
        Light {
            diffuse: [0.9, 0.8, 0.7, 1.0],
            specular: [1.0, 1.0, 1.0, 1.0],
            ambient: [0.1, 0.1, 0.2, 0.0],
            direction: [0.3, -0.5, 1.0],
            ..Light::zeroed(LightType::Directional)
        },
        Light {
            diffuse: [0.2, 0.9, 0.3, 1.0],
            specular: [0.5, 1.0, 0.5, 1.0],
            ambient: [0.0, 0.2, 0.0, 0.0],
            position: [1.0, 1.0, 1.0],
            range: 5.5,
            attenuation0: 0.5,
            attenuation1: 0.2,
            attenuation2: 0.05,
            ..Light::zeroed(LightType::Point)
        },
        Light {
            diffuse: [1.0, 0.3, 0.2, 1.0],
            specular: [1.0, 0.5, 0.5, 0.5],
            position: [-1.0, 0.5, -1.0],
            direction: [0.2, -0.1, 1.0],
            range: 20.0,
            attenuation0: 1.0,
            falloff: 2.0,
            theta: 0.3,
            phi: 0.8,
            ..Light::zeroed(LightType::Spot)
        },
    ];
    for case in 0..6 {
        let name = format!("spec_8_lighting_{case}");
        check(&name, 96, 72, Tolerance::Exact, |d| {
            perspective(d, 96.0 / 72.0);
            d.set_render_state(RenderState::LIGHTING, true);
            d.set_transform(
                TransformType::View,
                Mat4::look_at_lh([0.2, 0.3, -1.0], [0.0, 0.0, 4.0], [0.0, 1.0, 0.0]),
            );
            d.set_render_state(RenderState::POINTSIZE, 5.0f32);
            d.set_render_state(RenderState::SPECULARENABLE, case % 3 != 2);
            d.set_render_state(RenderState::LOCALVIEWER, case % 2 == 0);
            d.set_render_state(RenderState::NORMALIZENORMALS, case < 4);
            d.set_render_state(RenderState::AMBIENT, 0xFF20_1008u32);
            if case == 3 {
                d.set_render_state(RenderState::AMBIENTMATERIALSOURCE, 1u32);
                d.set_render_state(RenderState::EMISSIVEMATERIALSOURCE, 2u32);
                d.set_render_state(RenderState::DIFFUSEMATERIALSOURCE, 0u32);
            }
            if case == 5 {
                d.set_render_state(RenderState::COLORVERTEX, false);
            }
            d.set_material(Material {
                diffuse: [0.8, 0.7, 0.9, 0.75],
                ambient: [0.5, 0.5, 0.5, 1.0],
                specular: [0.9, 0.9, 0.9, 1.0],
                emissive: [0.05, 0.0, 0.1, 0.0],
                power: [8.0, 20.0, 0.0][case % 3],
            });
            for (k, l) in lights.iter().enumerate() {
                if case == 4 && k == 0 {
                    continue; // only the positional lights
                }
                d.set_light(k as u32 * 2, *l)?;
                d.light_enable(k as u32 * 2, true);
            }
            d.draw_point_list(LIT_FVF, &grid)
        });
    }
}

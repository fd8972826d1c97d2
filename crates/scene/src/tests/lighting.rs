//! Unit tests of the `[material]` and `[[light]]` tables (docs/spec/SCENE.md, SPEC 8): what
//! they parse to, their errors, and a replay on the CPU backend.

use pointillist_core::light::{Light, LightType, Material};

use crate::Command;
use crate::tests::{err, ok};

fn lighting(s: &crate::Scene) -> Vec<&Command> {
    s.steps
        .iter()
        .map(|s| &s.command)
        .filter(|c| {
            matches!(
                c,
                Command::Material(_) | Command::Light { .. } | Command::LightEnable { .. }
            )
        })
        .collect()
}

#[test]
fn material_members_default_to_zero() {
    let s = ok("[material]\ndiffuse = [1, 0.5, 0.25, 1]\npower = 8\n");
    assert_eq!(
        lighting(&s),
        [&Command::Material(Material {
            diffuse: [1.0, 0.5, 0.25, 1.0],
            power: 8.0,
            ..Material::default()
        })]
    );
}

#[test]
fn lights_set_then_enable_in_file_order() {
    let s = ok(
        "[[light]]\nindex = 2\ntype = \"point\"\ndiffuse = [1, 1, 1, 1]\n\
                position = [0, 1, 2]\nrange = 10\nattenuation1 = 0.5\nenable = true\n\
                [[light]]\nindex = 7\nenable = true\n",
    );
    let point = Light {
        diffuse: [1.0; 4],
        position: [0.0, 1.0, 2.0],
        range: 10.0,
        attenuation1: 0.5,
        ..Light::zeroed(LightType::Point)
    };
    assert_eq!(
        lighting(&s),
        [
            &Command::Light {
                index: 2,
                light: point
            },
            &Command::LightEnable {
                index: 2,
                enable: true
            },
            &Command::LightEnable {
                index: 7,
                enable: true
            },
        ]
    );
}

#[test]
fn per_draw_material_and_lights() {
    let s = ok("[[draw]]\nfvf = \"XYZ\"\nvertices = []\n\
                material = { emissive = [0, 0, 1, 1] }\n\
                light = [{ index = 0, enable = false }, \
                { index = 1, type = \"DIRECTIONAL\", direction = [0, -1, 0] }]\n");
    let l = lighting(&s);
    assert_eq!(l.len(), 3);
    assert!(matches!(l[0], Command::Material(m) if m.emissive == [0.0, 0.0, 1.0, 1.0]));
    assert_eq!(
        l[1],
        &Command::LightEnable {
            index: 0,
            enable: false
        }
    );
    assert!(
        matches!(l[2], Command::Light { index: 1, light } if light.direction == [0.0, -1.0, 0.0])
    );
    // The changes come before the draw.
    assert!(matches!(
        s.steps.last().unwrap().command,
        Command::Draw { .. }
    ));
}

#[test]
fn light_errors_name_file_line_and_key() {
    assert_eq!(
        err(
            "[[light]]\nindex = 0\ntype = \"SPOT\"\ndirection = [0, 0, 1]\nrange = 5\n\
             theta = 1.0\nphi = 0.5\n"
        ),
        "tests/data/test.toml:10:9: light[0].theta: must be in 0..=phi radians"
    );
    assert_eq!(
        err("[[light]]\nindex = 0\ntype = \"POINT\"\nrange = 5\nattenuation2 = -1\n"),
        "tests/data/test.toml:9:16: light[0].attenuation2: must be finite and >= 0"
    );
    assert_eq!(
        err("[[light]]\nindex = 3\ntype = \"DIRECTIONAL\"\n"),
        "tests/data/test.toml:5:1: light[0].direction: must be finite and nonzero"
    );
    assert_eq!(
        err("[[light]]\nindex = 0\ntype = \"area\"\n"),
        "tests/data/test.toml:7:8: light[0].type: unknown light type `area` (expected POINT, \
         SPOT or DIRECTIONAL)"
    );
    assert_eq!(
        err("[[light]]\nindex = 0\nrange = 4\n"),
        "tests/data/test.toml:5:1: light[0]: missing key `type`"
    );
    assert_eq!(
        err("[[light]]\nindex = 0\n"),
        "tests/data/test.toml:5:1: light[0]: a light needs `enable` or its members (`type` and \
         those it uses)"
    );
    assert_eq!(
        err("[[light]]\nindex = -1\nenable = true\n"),
        "tests/data/test.toml:6:9: light[0].index: -1 is outside 0..=4294967295"
    );
    assert_eq!(
        err("[material]\ndiffuse = [1, 1, 1]\n"),
        "tests/data/test.toml:6:11: material.diffuse: expected an array of 4 numbers, found 3 \
         values"
    );
    assert_eq!(
        err("[material]\npower = nan\n"),
        "tests/data/test.toml:6:9: material.power: expected a finite number, found NaN"
    );
    assert_eq!(
        err("[material]\nshine = 3\n"),
        "tests/data/test.toml:6:1: material.shine: unknown key (expected one of: diffuse, \
         ambient, specular, emissive, power)"
    );
}

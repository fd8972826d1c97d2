//! `Plot::render`: where points land, what each preset does to pixels, and what it refuses.

use pointillist_core::device::DeviceDesc;
use pointillist_core::fvf::Fvf;
use pointillist_core::states::{Blend as D3dBlend, RenderState};
use pointillist_plot::{
    BLOCK_VERTICES, Blend, Colors, Column, DataRange, Plot, PlotError, Points, Sizes,
};

fn px(rgba: &[u8], width: u32, i: u32, j: u32) -> [u8; 4] {
    let o = ((j * width + i) * 4) as usize;
    rgba[o..o + 4].try_into().unwrap()
}

#[test]
fn data_ranges_put_one_pixel_points_in_histogram_bins() {
    // x in (0, 10] over 5 columns: bins of width 2; y upwards over 4 rows.
    let x = [0.0f64, 1.99, 2.0, 9.99, 10.0];
    let y = [0.0f64, 0.0, 3.99, 1.0, 1.0];
    let plot = Plot {
        x_range: Some(DataRange { lo: 0.0, hi: 10.0 }),
        y_range: Some(DataRange { lo: 0.0, hi: 4.0 }),
        clear: 0,
        ..Plot::new(5, 4)
    };
    let points = Points {
        color: Colors::Constant(0x0101_0101),
        ..Points::new(Column::F64(&x), Column::F64(&y))
    };
    let rgba = plot.render(&points).unwrap();
    let count = |i, j| px(&rgba, 5, i, j)[0];
    assert_eq!(count(0, 3), 1, "x 1.99, y 0: the bottom row");
    assert_eq!(
        count(0, 0),
        1,
        "x 2 (a boundary goes left), y 3.99: the top row"
    );
    assert_eq!(count(4, 2), 2, "x 9.99 and 10, y 1");
    let total: u32 = rgba.chunks(4).map(|p| u32::from(p[0])).sum();
    assert_eq!(total, 4, "x = 0 falls just outside the target");
}

#[test]
fn presets_blend_as_their_render_states_say() {
    let x = [1.0f32, 1.0];
    let y = [0.0f32, 0.0];
    let colors = [0x8040_2010u32, 0x4010_8020];
    let draw = |blend| {
        let plot = Plot {
            blend,
            clear: 0xFF20_2020,
            ..Plot::new(2, 1)
        };
        let points = Points {
            color: Colors::Argb(&colors),
            ..Points::new(Column::F32(&x), Column::F32(&y))
        };
        px(&plot.render(&points).unwrap(), 2, 1, 0)
    };
    assert_eq!(draw(Blend::Add), [0x70, 0xC0, 0x50, 0xFF]);
    assert_eq!(draw(Blend::Max), [0x40, 0x80, 0x20, 0xFF]);
    assert_eq!(draw(Blend::Replace), [0x10, 0x80, 0x20, 0x40]);
    // alpha: first 0x80/255 of (0x40,0x20,0x10) over 0x20s, then 0x40/255 of the second.
    let over = |s: f32, d: f32, a: f32| s * a + d * (1.0 - a);
    let a1 = 128.0 / 255.0;
    let a2 = 64.0 / 255.0;
    let first = [
        over(64.0, 32.0, a1),
        over(32.0, 32.0, a1),
        over(16.0, 32.0, a1),
    ]
    .map(f32::round);
    let second = [
        over(16.0, first[0], a2),
        over(128.0, first[1], a2),
        over(32.0, first[2], a2),
    ]
    .map(|v| v.round() as u8);
    let got = draw(Blend::Alpha);
    assert_eq!(got[..3], second);
}

#[test]
fn sizes_are_exact_with_no_minimum_of_one() {
    // SPEC 4.1: [X - S/2, X + S/2) covers centre i. S = 0.5 at 3.0 covers 3; at 3.5 nothing.
    let x = [3.0f32, 3.5, 6.0];
    let y = [0.0f32, 1.0, 4.0];
    let s = [0.5f32, 0.5, 3.0];
    let plot = Plot {
        clear: 0,
        ..Plot::new(10, 6)
    };
    let points = Points {
        size: Sizes::PerPoint(Column::F32(&s)),
        ..Points::new(Column::F32(&x), Column::F32(&y))
    };
    let rgba = plot.render(&points).unwrap();
    let lit = |j| {
        (0..10)
            .filter(|&i| px(&rgba, 10, i, j)[3] != 0)
            .collect::<Vec<_>>()
    };
    assert_eq!(lit(0), [3]);
    assert_eq!(lit(1), Vec::<u32>::new());
    assert_eq!(lit(2), Vec::<u32>::new());
    assert_eq!(lit(3), [5, 6, 7]);
    assert_eq!(lit(5), [5, 6, 7]);
}

/// SPEC 2.6: D3D9's default POINTSIZE_MAX of 64 would shrink a larger point; a plot sets
/// POINTSIZE_MAX to the device's 8192, so sizes of 100 (constant or per point) are 100 wide.
#[test]
fn sizes_above_64_are_not_clamped_to_the_d3d9_default() {
    let plot = Plot {
        clear: 0,
        ..Plot::new(128, 128)
    };
    for size in [
        Sizes::Constant(100.0),
        Sizes::PerPoint(Column::F32(&[100.0])),
    ] {
        let points = Points {
            size,
            ..Points::new(Column::F32(&[64.0]), Column::F32(&[64.0]))
        };
        let rgba = plot.render(&points).unwrap();
        let row: Vec<u32> = (0..128)
            .filter(|&i| px(&rgba, 128, i, 64)[3] != 0)
            .collect();
        assert_eq!(row, (14..114).collect::<Vec<_>>());
    }
}

#[test]
fn depth_keeps_the_nearer_point_whatever_the_order() {
    let x = [0.0f32, 0.0, 1.0, 1.0];
    let y = [0.0f32; 4];
    let z = [0.2f32, 0.6, 0.6, 0.2];
    let c = [0xFFFF_0000u32, 0xFF00_FF00, 0xFF00_FF00, 0xFFFF_0000];
    let plot = Plot {
        blend: Blend::Replace,
        ..Plot::new(2, 1)
    };
    let points = Points {
        z: Some(Column::F32(&z)),
        color: Colors::Argb(&c),
        ..Points::new(Column::F32(&x), Column::F32(&y))
    };
    let rgba = plot.render(&points).unwrap();
    assert_eq!(px(&rgba, 2, 0, 0), [0xFF, 0, 0, 0xFF]);
    assert_eq!(px(&rgba, 2, 1, 0), [0xFF, 0, 0, 0xFF]);
}

#[test]
fn rgba_colours_are_the_d3dcolors_they_spell() {
    let x = [0.0f32, 1.0];
    let y = [0.0f32, 0.0];
    let argb = [0x8011_2233u32, 0xFF44_5566];
    let rgba = [[0x11u8, 0x22, 0x33, 0x80], [0x44, 0x55, 0x66, 0xFF]];
    let plot = Plot {
        blend: Blend::Replace,
        ..Plot::new(2, 1)
    };
    let draw = |color| {
        plot.render(&Points {
            color,
            ..Points::new(Column::F32(&x), Column::F32(&y))
        })
        .unwrap()
    };
    let a = draw(Colors::Argb(&argb));
    assert_eq!(a, draw(Colors::Rgba(&rgba)));
    assert_eq!(a, [0x11, 0x22, 0x33, 0x80, 0x44, 0x55, 0x66, 0xFF]);
}

/// The points drawn block by block give the pixels of one draw of all their vertices, written
/// here by hand as a scene's `XYZRHW | PSIZE | DIFFUSE` vertex file would hold them.
#[test]
fn blocks_draw_the_pixels_of_one_draw() {
    let n = BLOCK_VERTICES * 2 + 1234;
    let mut s = 7u64;
    let mut next = || {
        s = s
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (s >> 40) as f32 / (1u64 << 24) as f32
    };
    let x: Vec<f32> = (0..n).map(|_| next() * 70.0 - 3.0).collect();
    let y: Vec<f32> = (0..n).map(|_| next() * 50.0 - 3.0).collect();
    let size: Vec<f32> = (0..n).map(|_| next() * 4.0).collect();
    let color: Vec<u32> = (0..n).map(|_| (next() * u32::MAX as f32) as u32).collect();
    let plot = Plot {
        blend: Blend::Alpha,
        ..Plot::new(64, 48)
    };
    let points = Points {
        size: Sizes::PerPoint(Column::F32(&size)),
        color: Colors::Argb(&color),
        ..Points::new(Column::F32(&x), Column::F32(&y))
    };
    let got = plot.render(&points).unwrap();

    let mut device = pointillist_cpu::device(DeviceDesc::new(64, 48)).unwrap();
    device.set_render_state(RenderState::ALPHABLENDENABLE, true);
    device.set_render_state(RenderState::SRCBLEND, D3dBlend::SrcAlpha);
    device.set_render_state(RenderState::DESTBLEND, D3dBlend::InvSrcAlpha);
    device.set_render_state(RenderState::POINTSIZE_MIN, 0.0f32);
    device.set_render_state(RenderState::POINTSIZE_MAX, 8192.0f32);
    device.set_render_state(RenderState::ZENABLE, false);
    let mut bytes = Vec::new();
    for i in 0..n {
        for w in [
            x[i].to_bits(),
            y[i].to_bits(),
            0,
            1.0f32.to_bits(),
            size[i].to_bits(),
            color[i],
        ] {
            bytes.extend_from_slice(&w.to_le_bytes());
        }
    }
    let fvf = Fvf::parse("XYZRHW | PSIZE | DIFFUSE").unwrap();
    device.draw_point_list(fvf, &bytes).unwrap();
    let want = device.read_target().unwrap().to_rgba8();
    assert_eq!(got, want);
}

#[test]
fn bad_input_is_a_one_line_error() {
    let x = [0.0f32, 1.0, 2.0];
    let y2 = [0.0f32, 1.0];
    let nan = [0.0f64, f64::NAN, 1.0];
    let plot = Plot::new(4, 4);
    let err = |points: &Points, plot: &Plot| plot.render(points).unwrap_err().to_string();
    assert_eq!(
        err(&Points::new(Column::F32(&x), Column::F32(&y2)), &plot),
        "y has 2 rows but x has 3; every column needs one row a point"
    );
    assert_eq!(
        err(&Points::new(Column::F32(&x), Column::F64(&nan)), &plot),
        "y[1] is NaN"
    );
    let sized = Points {
        size: Sizes::PerPoint(Column::F64(&nan)),
        ..Points::new(Column::F32(&x), Column::F32(&x))
    };
    assert_eq!(err(&sized, &plot), "size[1] is NaN");
    let ranged = Plot {
        x_range: Some(DataRange { lo: 1.0, hi: 1.0 }),
        ..plot.clone()
    };
    assert_eq!(
        err(&Points::new(Column::F32(&x), Column::F32(&x)), &ranged),
        "x_range (1, 1) must be two finite numbers, low below high"
    );
    assert_eq!(
        err(
            &Points::new(Column::F32(&x), Column::F32(&x)),
            &Plot::new(0, 4)
        ),
        "render target 0x4 is outside 1..=16384 per side"
    );
    // Sizes whose image would overflow or exhaust memory: refused before it is allocated.
    for (w, h) in [(u32::MAX, u32::MAX), (1 << 30, 16)] {
        assert_eq!(
            err(
                &Points::new(Column::F32(&x), Column::F32(&x)),
                &Plot::new(w, h)
            ),
            format!("render target {w}x{h} is outside 1..=16384 per side")
        );
    }
    // Finite ranges whose span overflows, or is too small to scale: the reason, in short.
    let spans = [
        (-1e308, 1e308, "too wide: hi - lo overflows a float64"),
        (0.0, 5e-324, "too narrow"),
    ];
    for (lo, hi, reason) in spans {
        let ranged = Plot {
            x_range: Some(DataRange { lo, hi }),
            ..plot.clone()
        };
        assert_eq!(
            err(&Points::new(Column::F32(&x), Column::F32(&x)), &ranged),
            format!("x_range ({lo:e}, {hi:e}) is {reason}").replace("0e0", "0")
        );
    }
    assert_eq!(
        Blend::from_name("screen").unwrap_err(),
        PlotError::Blend("screen".into())
    );
    // A NaN in a later block is named by its row in the whole column.
    let mut long = vec![0.0f32; BLOCK_VERTICES + 10];
    long[BLOCK_VERTICES + 3] = f32::NAN;
    assert_eq!(
        err(&Points::new(Column::F32(&long), Column::F32(&long)), &plot),
        format!("x[{}] is NaN", BLOCK_VERTICES + 3)
    );
}

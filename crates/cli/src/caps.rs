//! `pointillist caps`: the device caps a scene would get, in D3DCAPS9 terms, and the built-in
//! profiles (SPEC 6).

use std::fmt::Write as _;

use pointillist_core::caps::{Caps, VertexProcessing};
use pointillist_gpu::{AdapterSummary, ClipPlaneMethod};

use crate::{BackendKind, CapsArgs, backend};

/// Prints the caps `args` select (a scene's, a profile's, or the default profile's) and the list
/// of built-in profiles on standard output; with `--backend gpu`, first the adapter the GPU
/// backend runs on and the caps it honours.
pub fn run(args: &CapsArgs) -> Result<(), String> {
    if args.backend == BackendKind::Gpu {
        let ctx = backend::gpu_context()?;
        let limits = ctx.limits();
        print_text(&gpu_report(
            ctx.adapter(),
            limits.max_texture_dimension_2d,
            limits.max_storage_buffer_binding_size,
        ));
    }
    let (source, caps) = match (&args.scene, &args.profile) {
        (Some(path), _) => {
            let scene = pointillist_scene::load(path).map_err(|e| e.to_string())?;
            (format!("scene {}", path.display()), scene.caps)
        }
        (None, Some((name, caps))) => (format!("profile {name}"), *caps),
        (None, None) => (
            format!("profile {} (the default)", Caps::PROFILES[0]),
            Caps::default(),
        ),
    };
    print_text(&report(args.backend.name(), &source, &caps));
    Ok(())
}

/// Prints `text`, whose lines each end with a line feed, on standard output.
fn print_text(text: &str) {
    crate::report::outln!("{}", text.strip_suffix('\n').unwrap_or(text));
}

/// What the GPU backend runs on and which caps it honours.
fn gpu_report(adapter: &AdapterSummary, max_target: u32, max_binding: u64) -> String {
    let honoured = pointillist_gpu::honoured_caps();
    let clip = match adapter.clip_planes {
        ClipPlaneMethod::FragmentDiscard => "evaluated per pixel in the fragment shader",
        ClipPlaneMethod::ClipDistances => "hardware clip distances",
    };
    let mut out = String::new();
    let _ = writeln!(out, "GPU backend adapter: {}", adapter.name);
    let _ = writeln!(
        out,
        "  {} ({}), driver {}",
        adapter.backend, adapter.device_type, adapter.driver
    );
    let _ = writeln!(
        out,
        "  shaders: {}",
        if adapter.no_contraction {
            "SPIR-V whose float arithmetic the driver may not fuse or reorder"
        } else {
            "WGSL through wgpu (exact only where the driver does not fuse or reorder floats)"
        }
    );
    let _ = writeln!(
        out,
        "  sprites are quads built by the vertex shader, so every profile below is honoured \
         exactly:"
    );
    let _ = writeln!(
        out,
        "  it honours MaxPointSize up to {} (not the adapter's native point size range), \
         D3DFVFCAPS_PSIZE, D3DPMISCCAPS_CLIPPLANESCALEDPOINTS (cutting planes {clip})",
        honoured.max_point_size
    );
    let _ = writeln!(
        out,
        "  render targets up to {max_target} pixels a side; up to {} MiB of vertices per draw \
         call (larger draws are split, in order)\n",
        max_binding >> 20
    );
    out
}

/// The whole report: the caps, the effective caps where software vertex processing changes
/// them, and the profile list.
fn report(backend: &str, source: &str, caps: &Caps) -> String {
    let mut out = String::new();
    let _ = writeln!(out, "Device caps of the {backend} backend, {source}:");
    table(&mut out, caps);
    let effective = caps.effective();
    if effective != *caps {
        let _ = writeln!(
            out,
            "\nWith software vertex processing the runtime emulates point sprites; the pipeline \
             applies these caps:"
        );
        table(&mut out, &effective);
    }
    let _ = writeln!(
        out,
        "\nBuilt-in profiles (a scene's [caps] profile = \"NAME\", or caps --profile NAME):"
    );
    let width = Caps::PROFILES.iter().map(|n| n.len()).max().unwrap_or(0);
    for (i, name) in Caps::PROFILES.iter().enumerate() {
        let Some(profile) = Caps::profile(name) else {
            continue;
        };
        let default = if i == 0 { " (default)" } else { "" };
        let _ = writeln!(out, "  {name:<width$}  {}{default}", describe(&profile));
    }
    out
}

/// Appends the five caps fields, one a line, in D3D names.
fn table(out: &mut String, caps: &Caps) {
    let yes_no = |b: bool| if b { "yes" } else { "no" };
    let psize = if caps.per_vertex_point_size {
        "per-vertex D3DFVF_PSIZE is honoured"
    } else {
        "D3DFVF_PSIZE is ignored; D3DRS_POINTSIZE sizes every point"
    };
    let clip = if caps.clip_plane_scaled_points {
        "user clip planes clip the scaled square"
    } else {
        "user clip planes keep or drop whole points by position"
    };
    let (vp, vp_note) = match caps.vertex_processing {
        VertexProcessing::Hardware => (
            "hardware",
            "D3DCREATE_HARDWARE_VERTEXPROCESSING: the device's caps rule",
        ),
        VertexProcessing::Software => (
            "software",
            "D3DCREATE_SOFTWARE_VERTEXPROCESSING: the runtime emulates sprites",
        ),
    };
    let sprites = if caps.max_point_size > 1.0 {
        "point sprites supported"
    } else {
        "single-pixel points only"
    };
    let rows = [
        ("MaxPointSize", caps.max_point_size.to_string(), sprites),
        (
            "D3DFVFCAPS_PSIZE",
            yes_no(caps.per_vertex_point_size).to_string(),
            psize,
        ),
        (
            "D3DPMISCCAPS_CLIPPLANESCALEDPOINTS",
            yes_no(caps.clip_plane_scaled_points).to_string(),
            clip,
        ),
        (
            "D3DPMISCCAPS_CLIPTLVERTS",
            yes_no(caps.clip_tl_verts).to_string(),
            if caps.clip_tl_verts {
                "pre-transformed points clipped by depth with ZENABLE"
            } else {
                "pre-transformed points never clipped by depth"
            },
        ),
        ("vertex processing", vp.to_string(), vp_note),
        (
            "D3DPRASTERCAPS_WFOG",
            yes_no(caps.w_fog).to_string(),
            if caps.w_fog {
                "table fog from w under a perspective projection"
            } else {
                "table fog always from z"
            },
        ),
        (
            "MaxActiveLights",
            caps.max_active_lights.to_string(),
            "enabled lights that light a vertex",
        ),
    ];
    for (name, value, note) in rows {
        let _ = writeln!(out, "  {name:<34}  {value:<8}  {note}");
    }
}

/// A one-line description of a profile, made from its caps so it cannot drift from them.
fn describe(caps: &Caps) -> String {
    let size = if caps.max_point_size > 1.0 {
        format!("sprites up to {} pixels", caps.max_point_size)
    } else {
        "single-pixel points (MaxPointSize 1)".to_string()
    };
    let psize = if caps.per_vertex_point_size {
        "per-vertex PSIZE"
    } else {
        "no D3DFVFCAPS_PSIZE"
    };
    let clip = if caps.clip_plane_scaled_points {
        "scaled-point clipping"
    } else {
        "clipping by vertex position"
    };
    let mut line = format!("{size}, {psize}, {clip}");
    if caps.vertex_processing == VertexProcessing::Software {
        let e = caps.effective();
        let _ = write!(
            line,
            "; software vertex processing: the runtime emulates sprites up to {} pixels",
            e.max_point_size
        );
        if e.per_vertex_point_size && !caps.per_vertex_point_size {
            line.push_str(" with per-vertex PSIZE");
        }
    }
    line
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn every_profile_is_listed_once() {
        let text = report("cpu", "profile reference", &Caps::reference());
        for name in Caps::PROFILES {
            let rows = text
                .lines()
                .filter(|l| l.split_whitespace().next() == Some(name))
                .count();
            assert_eq!(rows, 1, "{name} in\n{text}");
        }
    }

    #[test]
    fn gpu_report_names_the_adapter_and_the_clip_method() {
        let adapter = AdapterSummary {
            name: "llvmpipe".into(),
            backend: "Vulkan".into(),
            device_type: "Cpu".into(),
            driver: "Mesa".into(),
            clip_planes: ClipPlaneMethod::FragmentDiscard,
            no_contraction: true,
        };
        let text = gpu_report(&adapter, 16384, 128 << 20);
        assert!(text.contains("  shaders: SPIR-V whose float"), "{text}");
        assert!(
            text.starts_with("GPU backend adapter: llvmpipe\n"),
            "{text}"
        );
        assert!(text.contains("Vulkan (Cpu)"), "{text}");
        assert!(text.contains("MaxPointSize up to 8192"), "{text}");
        assert!(text.contains("fragment shader"), "{text}");
        assert!(text.contains("128 MiB"), "{text}");
    }

    #[test]
    fn effective_caps_appear_only_when_they_differ() {
        let hw = report("cpu", "x", &Caps::reference());
        assert!(!hw.contains("the pipeline applies"));
        let sw = report("gpu", "x", &Caps::profile("software").unwrap());
        assert!(sw.contains("the pipeline applies"));
        let sizes: Vec<&str> = sw
            .lines()
            .filter(|l| l.trim_start().starts_with("MaxPointSize"))
            .filter_map(|l| l.split_whitespace().nth(1))
            .collect();
        assert_eq!(sizes, ["1", "8192"]);
    }
}

//! The C replayer on a real IDirect3DDevice9: Wine's d3d9 (docs/CONFORMANCE.md). Runs when
//! `POINTILLIST_WINE=1` (CI sets it once Wine, mingw-w64 and Xvfb are installed); elsewhere it
//! says it was skipped.

use std::fs;
use std::path::Path;

use pointillist_conformance::calls::{Call, CallWriter, Header};
use pointillist_conformance::runner::{self, Outcome, Runner, Watch};

fn stream(calls: &[Call], end: bool) -> Vec<u8> {
    let mut w = CallWriter::new(Header {
        width: 4,
        height: 2,
        flags: 0,
    });
    for c in calls {
        w.call(c);
    }
    let mut bytes = w.finish().unwrap();
    if !end {
        bytes.truncate(bytes.len() - 8);
    }
    bytes
}

/// Every HRESULT is checked: a failing call ends its case, named with its arguments and the
/// error, a damaged stream says what is wrong, and the cases after them still run; a case that
/// works comes back with the target's exact pixels, alpha included.
#[test]
fn the_replayer_names_failing_calls_and_goes_on() {
    if std::env::var("POINTILLIST_WINE").ok().as_deref() != Some("1") {
        eprintln!("skipped: set POINTILLIST_WINE=1 to run the replayer under Wine");
        return;
    }
    let tmp = tempfile::tempdir().unwrap();
    let dir = tmp.path().to_path_buf();
    let calls = dir.join("calls");
    fs::create_dir_all(&calls).unwrap();
    let exe = dir.join("replayer.exe");
    runner::build_replayer(&exe).unwrap();
    // Built through a temporary file put in place: nothing else is left beside it.
    let mut listing: Vec<String> = fs::read_dir(&dir)
        .unwrap()
        .map(|e| e.unwrap().file_name().to_string_lossy().into_owned())
        .collect();
    listing.sort();
    assert_eq!(listing, ["calls", "replayer.c", "replayer.exe"]);

    let clear = Call::Clear {
        color: 0x80FF_0000,
        depth: 1.0,
    };
    let point = Call::DrawPoints {
        fvf: 0x44,
        stride: 20,
        vertices: [1.0f32, 0.0, 0.5, 1.0]
            .iter()
            .flat_map(|f| f.to_le_bytes())
            .chain(0xFF00_FF00u32.to_le_bytes())
            .collect(),
    };
    let bad_texture = Call::CreateTexture {
        id: 0,
        levels: vec![pointillist_core::texture::Level {
            width: 0,
            height: 0,
            texels: vec![],
        }],
    };
    let cases = [
        ("a_ok", stream(&[clear.clone(), point.clone()], true)),
        (
            "b_bad_texture",
            stream(&[clear.clone(), bad_texture, point.clone()], true),
        ),
        ("c_truncated", stream(std::slice::from_ref(&clear), false)),
        ("d_ok", stream(&[clear], true)),
    ];
    let names: Vec<String> = cases.iter().map(|c| c.0.to_string()).collect();
    for (name, bytes) in &cases {
        fs::write(calls.join(format!("{name}.calls")), bytes).unwrap();
    }
    let captures = runner::run(
        &Runner::Wine(Some(exe)),
        &calls,
        &names,
        &dir,
        &[],
        &Watch::default(),
    )
    .unwrap();
    let log = fs::read_to_string(dir.join("replayer.log")).unwrap_or_default();
    assert!(
        captures.device.max_point_size > 0.0,
        "{:?}",
        captures.device
    );
    assert!(!captures.device.description.is_empty());

    let pixels = |name: &str| match &captures.outcomes[name] {
        Outcome::Drawn(png) => runner::read_capture(png, 4, 2).unwrap().rgba,
        other => panic!("{name}: {other:?}\n{log}"),
    };
    let red = [0xFF, 0, 0, 0x80];
    let mut want: Vec<u8> = red.repeat(8);
    want[4..8].copy_from_slice(&[0, 0xFF, 0, 0xFF]);
    assert_eq!(pixels("a_ok"), want, "a one-pixel green point at (1, 0)");
    assert_eq!(pixels("d_ok"), red.repeat(8));
    let failed = |name: &str| match &captures.outcomes[name] {
        Outcome::Failed(why) => why.clone(),
        other => panic!("{name}: {other:?}"),
    };
    let e = failed("b_bad_texture");
    assert!(
        e.starts_with("CreateTexture(0x0, 1 levels") && e.contains("D3DERR_INVALIDCALL"),
        "{e}"
    );
    let e = failed("c_truncated");
    assert!(e.contains("ends without an end record"), "{e}");
    assert!(Path::new(&dir.join("device/a_ok.png")).is_file());
}

//! `pointillist export-calls` and `pointillist conform`: the conformance kit
//! (`pointillist-conformance`, docs/CONFORMANCE.md) on the command line.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use pointillist_conformance::runner::{Runner, Watch};
use pointillist_conformance::{Options, conform_with, export, find_cases};

use crate::interrupt::ChildGuard;
use crate::report::printable;
use crate::{CapturePackArgs, ConformArgs, ExportCallsArgs};

/// Exit status of `conform` when a case ends otherwise than expected.
const UNEXPECTED: u8 = 1;
/// Exit status of `conform` when the kit itself cannot run.
const KIT_FAILED: u8 = 2;

/// Runs `pointillist export-calls`: one scene to the file OUT, or scene files and folders to
/// the folder OUT (`NAME.calls` each and `list.txt`, the replayer's argument file). Streams are
/// written to disk as they are made, and put in place only when all are whole and none of them
/// is a file a scene reads.
pub fn run_export(args: &ExportCallsArgs) -> Result<(), String> {
    let out = &args.output;
    let shown = |p: &Path| printable(&p.display().to_string());
    if let [scene] = args.scenes.as_slice()
        && !scene.is_dir()
    {
        let scene = pointillist_scene::load(scene).map_err(|e| e.to_string())?;
        let (ex, file) = export::export_pending(&scene, args.frame, out)?;
        export::commit_outside(vec![file], &scene.inputs)?;
        crate::report::outln!("wrote {} ({} bytes)", shown(out), ex.bytes);
        return Ok(());
    }
    let cases = find_cases(&args.scenes)?;
    export::export_cases(&cases, args.frame, out)?;
    crate::report::outln!(
        "wrote {} call streams and list.txt to {}",
        cases.len(),
        shown(out)
    );
    Ok(())
}

/// Runs `pointillist conform-page`: several reports on one page.
pub fn run_page(args: &crate::ConformPageArgs) -> Result<(), String> {
    let mut columns = Vec::new();
    for r in &args.reports {
        let (label, folder) = match r.split_once('=') {
            Some((l, f)) if !Path::new(r).is_dir() && !l.is_empty() => {
                (Some(l.to_string()), Path::new(f))
            }
            _ => (None, Path::new(r.as_str())),
        };
        columns.push(pointillist_conformance::page::Column::load(folder, label)?);
    }
    let s = pointillist_conformance::page::write(&columns, &args.out)?;
    println!(
        "{} devices, {} cases: {} match on every device, {} split the devices, {} match on \
         none; page: {}",
        columns.len(),
        s.cases,
        s.all_match,
        s.split,
        s.none_match,
        args.out.join("index.html").display()
    );
    Ok(())
}

/// Runs `pointillist capture-pack`: the pack of the cases of the paths given, in the new or
/// empty folder OUT (`pointillist_conformance::pack`).
pub fn run_pack(args: &CapturePackArgs) -> Result<(), String> {
    let out = &args.output;
    let pack = pointillist_conformance::pack::write_pack(&args.paths, out, !args.no_build)?;
    let shown = printable(&out.display().to_string());
    let exe = if pack.built {
        "replayer.exe"
    } else {
        "no replayer.exe (--no-build: build it as source/BUILD.txt says)"
    };
    crate::report::outln!(
        "wrote the capture pack {shown}: {} call streams, {exe}, source/, run.bat, README.txt; \
         copy the folder to a Windows PC and double-click run.bat there",
        pack.cases
    );
    Ok(())
}

/// Parses `--case-timeout` and `--timeout`: seconds above 0.
pub fn parse_seconds(text: &str) -> Result<Duration, String> {
    text.parse::<f64>()
        .ok()
        .filter(|s| *s > 0.0)
        .and_then(|s| Duration::try_from_secs_f64(s).ok())
        .ok_or_else(|| "expected a number of seconds above 0, such as 300 or 0.5".to_string())
}

/// Registers a replayer's process group with the signal handler, which kills it.
fn guard_group(pid: u32) -> Box<dyn std::any::Any> {
    Box::new(ChildGuard::group(pid))
}

/// Runs `pointillist conform` and returns its exit status: 0 when every case ends as expected,
/// 1 when one does not, 2 when the kit cannot run.
pub fn run_conform(args: &ConformArgs) -> ExitCode {
    let runner = if let Some(cmd) = &args.runner_cmd {
        Runner::Command(cmd.clone())
    } else if let Some(dir) = &args.captures {
        Runner::Captures(dir.clone())
    } else if let Some(dll) = &args.d3d9 {
        Runner::WineD3d9 {
            replayer: args.replayer.clone(),
            dll: dll.clone(),
        }
    } else {
        Runner::Wine(args.replayer.clone())
    };
    let opts = Options {
        paths: args.paths.clone(),
        runner,
        report: args.report.clone(),
        expect: args.expect.clone(),
        behaviours: args.behaviours.clone(),
        max_pixels: args.max_pixels,
    };
    let defaults = Watch::default();
    let watch = Watch {
        case_limit: args.case_timeout.unwrap_or(defaults.case_limit),
        total_limit: args.timeout.unwrap_or(defaults.total_limit),
        guard: guard_group,
    };
    let summary = match conform_with(&opts, &watch) {
        Ok(summary) => summary,
        Err(e) => {
            crate::interrupt::wait_if_ending();
            crate::report::error(&e);
            return ExitCode::from(KIT_FAILED);
        }
    };
    for w in &summary.warnings {
        crate::report::warning(w);
    }
    for (case, why) in &summary.unexpected {
        crate::report::errln!("{}", printable(&format!("{case}: {why}")));
    }
    let [m, o, d, e] = summary.counts;
    let shown: Vec<String> = summary
        .behaviours
        .iter()
        .filter_map(|(name, option)| option.map(|o| format!("{name} = {o}")))
        .collect();
    if !shown.is_empty() {
        crate::report::outln!("device behaviours shown: {}", shown.join(", "));
    }
    crate::report::outln!(
        "{} cases: {m} match, {o} match under another behaviour option, {d} differ, {e} errors; \
         {} unexpected; report: {}",
        summary.cases,
        summary.unexpected.len(),
        printable(&args.report.join("index.html").display().to_string())
    );
    if summary.unexpected.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(UNEXPECTED)
    }
}

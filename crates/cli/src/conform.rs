//! `pointillist export-calls` and `pointillist conform`: the conformance kit
//! (`pointillist-conformance`, docs/CONFORMANCE.md) on the command line.

use std::path::Path;
use std::process::ExitCode;
use std::time::Duration;

use pointillist_conformance::runner::{Runner, Watch};
use pointillist_conformance::{Options, conform_with, export, find_cases};

use crate::interrupt::ChildGuard;
use crate::{ConformArgs, ExportCallsArgs};

/// Exit status of `conform` when a case ends otherwise than expected.
const UNEXPECTED: u8 = 1;
/// Exit status of `conform` when the kit itself cannot run.
const KIT_FAILED: u8 = 2;

/// Writes `bytes` to `path` atomically (an existing file is replaced only by a whole one).
fn write_atomic(path: &Path, bytes: &[u8]) -> Result<(), String> {
    pointillist_image::write_file_atomic(path, bytes).map_err(|e| e.to_string())
}

/// Exports one scene's calls.
fn export_one(scene: &Path, frame: Option<u32>) -> Result<Vec<u8>, String> {
    let scene = pointillist_scene::load(scene).map_err(|e| e.to_string())?;
    Ok(export::export(&scene, scene.caps, frame)?.stream)
}

/// Runs `pointillist export-calls`: one scene to the file OUT, or scene files and folders to
/// the folder OUT (`NAME.calls` each and `list.txt`, the replayer's argument file).
pub fn run_export(args: &ExportCallsArgs) -> Result<(), String> {
    if let [scene] = args.scenes.as_slice()
        && !scene.is_dir()
    {
        let bytes = export_one(scene, args.frame)?;
        write_atomic(&args.output, &bytes)?;
        crate::report::outln!("wrote {} ({} bytes)", args.output.display(), bytes.len());
        return Ok(());
    }
    let cases = find_cases(&args.scenes)?;
    std::fs::create_dir_all(&args.output)
        .map_err(|e| format!("cannot create {}: {e}", args.output.display()))?;
    let mut list = String::new();
    for case in &cases {
        let bytes = export_one(&case.scene, args.frame)?;
        write_atomic(&args.output.join(format!("{}.calls", case.name)), &bytes)?;
        list.push_str(&format!("{}.calls\n", case.name));
    }
    write_atomic(&args.output.join("list.txt"), list.as_bytes())?;
    crate::report::outln!(
        "wrote {} call streams and list.txt to {}",
        cases.len(),
        args.output.display()
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
    } else {
        Runner::Wine(args.replayer.clone())
    };
    let opts = Options {
        paths: args.paths.clone(),
        runner,
        report: args.report.clone(),
        expect: args.expect.clone(),
        behaviours: args.behaviours.clone(),
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
            crate::report::errln!("error: {}", e.lines().next().unwrap_or(""));
            return ExitCode::from(KIT_FAILED);
        }
    };
    for w in &summary.warnings {
        crate::report::errln!("warning: {w}");
    }
    for (case, why) in &summary.unexpected {
        crate::report::errln!("{case}: {why}");
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
        args.report.join("index.html").display()
    );
    if summary.unexpected.is_empty() {
        ExitCode::SUCCESS
    } else {
        ExitCode::from(UNEXPECTED)
    }
}

//! Several files (recipes or scripts) in one `run`, one after the other: each file's own
//! output files (so none overwrites another's) beside the shared JUnit file and index page,
//! the lines that name every file a run wrote, and the exit code of the whole command (the
//! worst), each `--set` given to the files that have the parameter. The runs themselves
//! are the pipeline's.

use super::several_reports::SeveralReports;
use super::several_sets::sets_per_file;
use super::{OutputArgs, RunRequest, RunResult};
use crate::session::RunReport;
use std::io::Write;
use std::path::{Path, PathBuf};

/// Runs each of `files` with `base`'s settings (its `file` and its output paths are
/// replaced for each), writing the console output to `out` and problems to `err`; the
/// worst exit code. A stop signal or a panic ends the whole command, after that file's
/// safe stop. With several files, `--junit` is one file with a suite per file and
/// `--report` an index of each file's own report (see [`SeveralReports`]).
pub fn run_many(files: &[PathBuf], base: &RunRequest, out: &mut dyn Write, err: &mut dyn Write) -> i32 {
    if files.len() < 2 {
        return files.first().map_or(super::PASSED, |file| {
            run_one(file, base, base.set, None, out, err).exit_code
        });
    }
    let mut shared = SeveralReports::new(files, &outputs_for(base.outputs, &base.output_dir, None));
    let sets = match sets_per_file(files, base.set) {
        Ok(s) => s,
        Err(e) => {
            let why = e.to_string();
            let _ = writeln!(err, "{why}");
            if let Err(e) = shared.refused(&why) {
                let _ = writeln!(err, "error: {e}");
            }
            return e.exit_code();
        }
    };
    let mut worst = super::PASSED;
    let mut verdicts = Vec::new();
    let mut written: Vec<String> = Vec::new();
    for (i, file) in files.iter().enumerate() {
        let _ = writeln!(
            out,
            "{}== {} {} of {}: {}",
            if i > 0 { "\n" } else { "" },
            if crate::script::is_script(file) {
                "script"
            } else {
                "recipe"
            },
            i + 1,
            files.len(),
            file.display()
        );
        let outputs = OutputArgs {
            junit: None,
            ..outputs_for(base.outputs, &base.output_dir, Some((i + 1, file.as_path())))
        };
        if let Err(e) = shared.starting(outputs.report.as_deref()) {
            let _ = writeln!(err, "error: {e}");
            if i == 0 {
                let _ = writeln!(err, "nothing was sent to a drive");
                return super::INVALID;
            }
        }
        let result = run_one(file, base, &sets[i], Some(&outputs), out, err);
        shared.finished(&result, outputs.report.as_deref());
        written.extend(written_files(&outputs, result.report.as_ref()));
        verdicts.push((file.display().to_string(), result.exit_code));
        worst = worse(worst, result.exit_code);
        if result.exit_code >= 128 || result.exit_code == crate::session::PANIC_EXIT {
            break;
        }
    }
    if let Err(e) = shared.ended() {
        let _ = writeln!(err, "error: {e}");
    }
    let _ = writeln!(out, "\n== {} files:", verdicts.len());
    for (path, code) in &verdicts {
        let _ = writeln!(out, "   exit code {code}  {path}");
    }
    let _ = writeln!(out, "exit code {worst} (the worst of them)");
    let mut all: Vec<String> = shared
        .paths()
        .filter(|p| p.is_file())
        .map(|p| p.display().to_string())
        .collect();
    all.extend(written);
    print_outputs(&all, base.outputs.quiet, out);
    worst
}

/// Runs `file` with `base`'s settings, `set` and `outputs` (`None`: `base`'s, placed
/// under `--output-dir`), then names the files it wrote.
fn run_one(
    file: &Path,
    base: &RunRequest,
    set: &[(String, String)],
    outputs: Option<&OutputArgs>,
    out: &mut dyn Write,
    err: &mut dyn Write,
) -> RunResult {
    let outputs = outputs
        .cloned()
        .unwrap_or_else(|| outputs_for(base.outputs, &base.output_dir, None));
    let request = RunRequest {
        file,
        set,
        outputs: &outputs,
        output_dir: base.output_dir.clone(),
        stop: base.stop.clone(),
        safe_stop: base.safe_stop.clone(),
        observers: base.observers.clone(),
        input: base.input.clone(),
        history: base.history.clone(),
        ..*base
    };
    let result = super::run(&request, out, err);
    print_outputs(
        &written_files(&outputs, result.report.as_ref()),
        outputs.quiet,
        out,
    );
    result
}

/// The exit code that says more: a panic, then a stop signal, then 3, 2, 1, 0.
pub fn worse(a: i32, b: i32) -> i32 {
    let rank = |c: i32| match c {
        0 => 0,
        1 => 1,
        2 => 2,
        c if c == crate::session::PANIC_EXIT => 6,
        c if c >= 128 => 5,
        _ => 3,
    };
    if rank(b) > rank(a) {
        b
    } else {
        a
    }
}

/// The outputs of one recipe: relative paths under `dir`; with several recipes each file
/// name gets the recipe's place and name (`junit.xml` → `junit-2-acceptance-test.xml`) so
/// that no run overwrites another's, even of recipes with the same file name.
pub fn outputs_for(outputs: &OutputArgs, dir: &Path, recipe: Option<(usize, &Path)>) -> OutputArgs {
    let place = |p: &Option<PathBuf>| {
        p.as_ref().map(|p| {
            let p = match recipe {
                Some((n, path)) => {
                    let mut name = p.file_stem().unwrap_or_default().to_os_string();
                    name.push(format!("-{n}-"));
                    name.push(path.file_stem().unwrap_or_default());
                    if let Some(ext) = p.extension() {
                        name.push(".");
                        name.push(ext);
                    }
                    p.with_file_name(name)
                }
                None => p.clone(),
            };
            if dir == Path::new(".") {
                p
            } else {
                dir.join(p)
            }
        })
    };
    OutputArgs {
        trace: place(&outputs.trace),
        csv: place(&outputs.csv),
        junit: place(&outputs.junit),
        report: place(&outputs.report),
        ..outputs.clone()
    }
}

/// Every file one run wrote: its outputs that exist, then the `csv:` files of its steps.
fn written_files(outputs: &OutputArgs, report: Option<&RunReport>) -> Vec<String> {
    let mut files: Vec<String> = [&outputs.trace, &outputs.csv, &outputs.junit, &outputs.report]
        .into_iter()
        .flatten()
        .filter(|p| p.is_file())
        .map(|p| p.display().to_string())
        .collect();
    if let Some(r) = report {
        files.extend(r.csv_files.iter().cloned());
    }
    files
}

/// `outputs  junit.xml, report.html, run-in-stage-1.csv`.
fn print_outputs(files: &[String], quiet: bool, out: &mut dyn Write) {
    if !files.is_empty() && !quiet {
        let _ = writeln!(out, "outputs {}", files.join(", "));
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::run::PASSED;

    #[test]
    fn the_worst_exit_code_wins() {
        let worst = |codes: &[i32]| codes.iter().fold(PASSED, |a, b| worse(a, *b));
        assert_eq!(worst(&[0, 1, 0]), 1);
        assert_eq!(worst(&[1, 3, 2]), 3);
        assert_eq!(worst(&[3, 130, 1]), 130);
        assert_eq!(worst(&[130, 101]), 101);
    }

    #[test]
    fn outputs_of_several_recipes_never_share_a_file() {
        let outputs = OutputArgs {
            junit: Some("ci/junit.xml".into()),
            report: Some("/abs/report.html".into()),
            ..OutputArgs::default()
        };
        let one = outputs_for(&outputs, Path::new("out"), None);
        assert_eq!(one.junit, Some(PathBuf::from("out/ci/junit.xml")));
        assert_eq!(one.report, Some(PathBuf::from("/abs/report.html")));
        let second = outputs_for(&outputs, Path::new("."), Some((2, Path::new("a/x.yaml"))));
        assert_eq!(second.junit, Some(PathBuf::from("ci/junit-2-x.xml")));
        assert_eq!(second.report, Some(PathBuf::from("/abs/report-2-x.html")));
    }
}

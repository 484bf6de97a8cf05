//! The reports a command of several files writes once for all of them: ONE JUnit file with
//! one `<testsuite>` per file (as CI servers read pytest's, Hurl's or Robot's), and an
//! index page at the `--report` name that links each file's own report with its verdict.
//! Both are rewritten whole (atomically) before each file runs and after the last, so the
//! files are complete at every ending: what ran is in them, the file under way says it has
//! not finished, and the files not reached are said as not run. The runs are the pipeline's.

use super::{OutputArgs, RunResult, COMMUNICATION, FAILED, INVALID, PASSED};
use crate::report::{
    html_index, junit_document, junit_not_run_suite, junit_skipped_suite, junit_unfinished_suite,
    write_atomically, IndexEntry, JunitSuite, ReportWriteError,
};
use crate::session::PANIC_EXIT;
use std::path::{Path, PathBuf};

/// The shared reports of a command of several files, and what they hold so far.
pub struct SeveralReports<'a> {
    files: &'a [PathBuf],
    junit: Option<PathBuf>,
    index: Option<PathBuf>,
    suites: Vec<JunitSuite>,
    rows: Vec<IndexEntry>,
    worst: i32,
}

impl<'a> SeveralReports<'a> {
    /// `outputs`' `--junit` and `--report` (already placed under `--output-dir`).
    pub fn new(files: &'a [PathBuf], outputs: &OutputArgs) -> Self {
        SeveralReports {
            files,
            junit: outputs.junit.clone(),
            index: outputs.report.clone(),
            suites: Vec::new(),
            rows: Vec::new(),
            worst: PASSED,
        }
    }

    /// The shared files (for the `outputs` line).
    pub fn paths(&self) -> impl Iterator<Item = &PathBuf> {
        self.junit.iter().chain(self.index.iter())
    }

    /// Before the next file runs: the ones done, the next one as not finished (what a
    /// kill beyond any safe stop leaves), the rest as not run yet.
    pub fn starting(&self, report: Option<&Path>) -> Result<(), ReportWriteError> {
        let i = self.suites.len();
        let Some(file) = self.files.get(i) else {
            return Ok(());
        };
        let shown = file.display().to_string();
        let current = (
            junit_unfinished_suite(&shown, &shown),
            IndexEntry {
                file: shown,
                verdict: "NOT FINISHED".into(),
                passed: false,
                detail: "running, or the command was killed before it could write its report".into(),
                report: report.map(|r| self.href(r)),
            },
        );
        self.write(
            Some(current),
            "not run yet",
            "NOT FINISHED",
            "the files are still running",
        )
    }

    /// After a file ran (or was refused): its suite and its row.
    pub fn finished(&mut self, result: &RunResult, report: Option<&Path>) {
        let i = self.suites.len();
        let shown = self
            .files
            .get(i)
            .map(|f| f.display().to_string())
            .unwrap_or_default();
        let code = result.exit_code;
        let verdict = match (&result.report, code) {
            (Some(r), _) => r.verdict.word().to_string(),
            (None, INVALID) => "NOT RUN — INVALID".into(),
            (None, COMMUNICATION) => "NOT RUN — ERROR".into(),
            (None, _) => "NOT RUN".into(),
        };
        let suite = result
            .junit
            .clone()
            .unwrap_or_else(|| junit_skipped_suite(&shown, "not run: its output files could not be written"));
        self.suites.push(suite);
        self.rows.push(IndexEntry {
            file: shown,
            verdict,
            passed: code == PASSED,
            detail: format!("exit code {code}"),
            report: report.filter(|r| r.is_file()).map(|r| self.href(r)),
        });
        self.worst = super::worse(self.worst, code);
    }

    /// A command refused before any file ran (`why`): every file as not run, invalid.
    pub fn refused(&mut self, why: &str) -> Result<(), ReportWriteError> {
        for file in self.files {
            let shown = file.display().to_string();
            self.suites
                .push(junit_not_run_suite(&shown, &shown, "invalid", why, &[]));
            self.rows.push(IndexEntry {
                file: shown,
                verdict: "NOT RUN — INVALID".into(),
                passed: false,
                detail: format!("exit code {INVALID}"),
                report: None,
            });
        }
        self.worst = INVALID;
        self.ended()
    }

    /// After the last file ran or the command ended early: the files never reached are
    /// skipped, saying why.
    pub fn ended(&self) -> Result<(), ReportWriteError> {
        let why = match self.worst {
            PANIC_EXIT => "not run: the command ended with an internal error before this file".to_string(),
            c if c >= 128 => {
                format!("not run: the command was stopped by a signal (exit code {c}) before this file")
            }
            _ => "not run".to_string(),
        };
        let passed = self.rows.iter().filter(|r| r.passed).count();
        let detail = format!(
            "{passed} of {} file(s) passed; exit code {} (the worst of them)",
            self.files.len(),
            self.worst
        );
        self.write(None, &why, &verdict_word(self.worst), &detail)
    }

    fn write(
        &self,
        current: Option<(JunitSuite, IndexEntry)>,
        rest_why: &str,
        verdict: &str,
        detail: &str,
    ) -> Result<(), ReportWriteError> {
        let done = self.suites.len() + usize::from(current.is_some());
        let rest = self.files.iter().skip(done).map(|f| f.display().to_string());
        if let Some(path) = &self.junit {
            let mut suites: Vec<&JunitSuite> = self.suites.iter().collect();
            let skipped: Vec<JunitSuite> = rest.clone().map(|f| junit_skipped_suite(&f, rest_why)).collect();
            suites.extend(current.as_ref().map(|c| &c.0));
            suites.extend(&skipped);
            write_atomically(path, &junit_document(suites))?;
        }
        if let Some(path) = &self.index {
            let mut rows: Vec<&IndexEntry> = self.rows.iter().collect();
            let not_run: Vec<IndexEntry> = rest
                .map(|file| IndexEntry {
                    file,
                    verdict: "NOT RUN".into(),
                    passed: false,
                    detail: rest_why.trim_start_matches("not run: ").to_string(),
                    report: None,
                })
                .collect();
            rows.extend(current.as_ref().map(|c| &c.1));
            rows.extend(&not_run);
            let passed = verdict == "PASSED";
            write_atomically(path, &html_index(rows, verdict, passed, detail))?;
        }
        Ok(())
    }

    /// A file's report as the index links it: beside the index, its file name.
    fn href(&self, report: &Path) -> String {
        let beside = self.index.as_ref().and_then(|i| i.parent()) == report.parent();
        match report.file_name() {
            Some(name) if beside => name.to_string_lossy().into_owned(),
            _ => report.display().to_string(),
        }
    }
}

/// The word of the whole command's verdict, from its worst exit code.
fn verdict_word(code: i32) -> String {
    match code {
        PASSED => "PASSED".into(),
        FAILED => "FAILED".into(),
        INVALID => "INVALID".into(),
        PANIC_EXIT => "PANIC".into(),
        c if c >= 128 => "INTERRUPTED".into(),
        _ => "ERROR".into(),
    }
}

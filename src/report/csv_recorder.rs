//! `--csv FILE`: every sample of every `sample` step of a run, and the polls of every
//! coast-down and wait for a stable slope (the curves the HTML report plots), streamed in the one samples
//! layout ([`SampleTable`]: long by default, `--csv-wide` for one column per object),
//! through a buffer flushed at least every 250 ms and at every ending, so an aborted run
//! keeps every sample but the last quarter second. An observer: its write errors are kept
//! for the CLI to report, never fail the run.

use crate::output_file_error::OutputFileError;
use crate::session::{ObjectRef, RunInfo, RunObserver, RunReport, SampleTable, LONG_HEADER};
use std::path::Path;
use std::time::{Duration, SystemTime};

/// The header row of the long layout.
pub const CSV_HEADER: [&str; 6] = LONG_HEADER;

pub struct CsvRecorder {
    table: SampleTable,
    /// The iteration-aware id of the step running now (`3`, `7[2].2`).
    step: String,
    /// Wall time at the run's start: the `utc` column is this plus the run time.
    started: SystemTime,
    rows: u64,
    error: Option<String>,
}

impl CsvRecorder {
    /// Creates (truncates) the file, its directory too, and writes the header: the long
    /// layout, or (`wide`) one column per object of `wide`. An unwritable path is an error
    /// here, before the run starts; the message names the path.
    pub fn create(path: &Path, wide: Option<&[ObjectRef]>) -> Result<Self, OutputFileError> {
        Self::create_for(path, wide, false)
    }

    /// [`CsvRecorder::create`] for a run with several drives (`drives`): the long layout
    /// then has a `drive` column.
    pub fn create_for(
        path: &Path,
        wide: Option<&[ObjectRef]>,
        drives: bool,
    ) -> Result<Self, OutputFileError> {
        Ok(CsvRecorder {
            table: SampleTable::open_for(path, wide, false, drives)?,
            step: String::new(),
            started: SystemTime::now(),
            rows: 0,
            error: None,
        })
    }

    pub fn path(&self) -> &Path {
        self.table.path()
    }

    /// Rows written so far.
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The first write error (`cannot write PATH: ...`), after which recording stopped.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Hands every row so far to the file (the run's end does this too).
    pub fn flush_now(&mut self) {
        if let Err(e) = self.table.flush() {
            self.error.get_or_insert(e.to_string());
        }
    }
}

impl RunObserver for CsvRecorder {
    fn run_started(&mut self, _run: &RunInfo, _drive: &str) {
        self.started = SystemTime::now();
    }

    fn step_placed(&mut self, id: &str) {
        self.step.clear();
        self.step.push_str(id);
    }

    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        if self.error.is_some() {
            return;
        }
        let utc = self.started + at;
        match self.table.rows(at, utc, &self.step, objects, values) {
            Ok(n) => self.rows += n,
            Err(e) => self.error = Some(e.to_string()),
        }
    }

    /// Every ending of a run comes through here (a signal, a panic, a lost link too).
    fn run_finished(&mut self, _report: &RunReport) {
        self.flush_now();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::path::PathBuf;

    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir()
            .join(format!("drivescript-csv-{}-{name}", std::process::id()))
            .join("out/samples.csv")
    }

    fn object(name: &str, unit: Option<&str>) -> ObjectRef {
        ObjectRef {
            name: name.into(),
            unit: unit.map(String::from),
        }
    }

    #[test]
    fn rows_carry_the_step_id_and_are_on_disk_while_the_run_goes_on() {
        let path = temp("rows");
        let mut csv = CsvRecorder::create(&path, None).unwrap();
        csv.step_placed("3");
        csv.sample(
            Duration::from_millis(5_100),
            &[
                object("speed_actual", Some("rpm")),
                object("current_actual", Some("A")),
            ],
            &[6000.125, 2.5],
        );
        // Buffered: not one write per row, but on the disk after a flush (every 250 ms,
        // and at every ending of the run).
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time [s],utc,step,object,value,unit\n"
        );
        csv.flush_now();
        csv.step_placed("7[2].2");
        csv.sample(Duration::from_secs(70), &[object("drive_error", None)], &[0.0]);
        csv.flush_now();
        let mut reader = csv::Reader::from_path(&path).unwrap();
        assert_eq!(
            reader.headers().unwrap(),
            &csv::StringRecord::from(CSV_HEADER.to_vec())
        );
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(csv.rows(), 3);
        assert_eq!(&rows[0][0], "5.100");
        assert_eq!(
            (&rows[1][2], &rows[1][3], &rows[1][4], &rows[1][5]),
            ("3", "current_actual", "2.5", "A")
        );
        assert_eq!((&rows[2][0], &rows[2][2], &rows[2][5]), ("70.000", "7[2].2", ""));
        // Absolute time: 64.9 s after the first row's.
        let t = |r: &csv::StringRecord| humantime::parse_rfc3339(&r[1]).unwrap();
        assert_eq!(
            t(&rows[2]).duration_since(t(&rows[0])).unwrap(),
            Duration::from_millis(64_900)
        );
        assert_eq!(csv.error(), None);
        // Closed before their folder goes: Windows removes no folder with an open file.
        drop((csv, reader));
        std::fs::remove_dir_all(path.parent().unwrap().parent().unwrap()).unwrap();
    }

    #[test]
    fn names_with_commas_are_quoted() {
        let path = temp("quote");
        let mut csv = CsvRecorder::create(&path, None).unwrap();
        csv.sample(Duration::ZERO, &[object("odd,name", Some("\"u\""))], &[1.0]);
        csv.flush_now();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.ends_with(",,\"odd,name\",1,\"\"\"u\"\"\"\n"), "{text}");
        drop(csv);
        std::fs::remove_dir_all(path.parent().unwrap().parent().unwrap()).unwrap();
    }

    #[test]
    fn an_unwritable_path_is_refused_with_its_name() {
        let err = CsvRecorder::create(Path::new("/proc/drivescript/x.csv"), None)
            .err()
            .unwrap()
            .to_string();
        assert!(err.contains("/proc/drivescript"), "{err}");
        let dir = std::env::temp_dir();
        let err = CsvRecorder::create(&dir, None).err().unwrap().to_string();
        assert!(err.starts_with("cannot write "), "{err}");
    }
}

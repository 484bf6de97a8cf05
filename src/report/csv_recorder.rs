//! `--csv FILE`: every sample of every `sample` step of a run, streamed in long format
//! (`time [s],step,object,value,unit`, one row per value, since steps sample different
//! objects) and flushed row by row, so an aborted run keeps every sample it took.
//! An observer: its write errors are kept for the CLI to report, never fail the run.

use crate::csv_file::CsvFile;
use crate::session::{write_number, ObjectRef, RunObserver, RunReport, StepInfo};
use std::path::Path;
use std::time::Duration;

/// The header row.
pub const CSV_HEADER: [&str; 5] = ["time [s]", "step", "object", "value", "unit"];

pub struct CsvRecorder {
    file: CsvFile,
    /// The number of the step running now (`3`, `7.2`).
    step: String,
    rows: u64,
    error: Option<String>,
    /// Buffers reused for every row: a day at 100 Hz is millions of rows.
    time_text: String,
    value_text: String,
}

impl CsvRecorder {
    /// Creates (truncates) the file, its directory too, and writes the header. An
    /// unwritable path is an error here, before the run starts; the message names the path.
    pub fn create(path: &Path) -> Result<Self, String> {
        let header: Vec<String> = CSV_HEADER.iter().map(|h| h.to_string()).collect();
        Ok(CsvRecorder {
            file: CsvFile::create(path, &header)?,
            step: String::new(),
            rows: 0,
            error: None,
            time_text: String::new(),
            value_text: String::new(),
        })
    }

    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// Rows written so far (one per sampled value).
    pub fn rows(&self) -> u64 {
        self.rows
    }

    /// The first write error (`cannot write PATH: ...`), after which recording stopped.
    pub fn error(&self) -> Option<&str> {
        self.error.as_deref()
    }

    /// Hands every row so far to the file (the run's end does this too).
    pub fn flush_now(&mut self) {
        if let Err(e) = self.file.flush() {
            self.error.get_or_insert(e);
        }
    }

    fn row(&mut self, record: [&str; 5]) -> Result<(), String> {
        self.file.row(&record)
    }
}

impl RunObserver for CsvRecorder {
    fn step_started(&mut self, step: &StepInfo) {
        self.step = step.number.clone();
    }

    fn sample(&mut self, at: Duration, objects: &[ObjectRef], values: &[f64]) {
        if self.error.is_some() {
            return;
        }
        use std::fmt::Write as _;
        let (mut time, mut value) = (
            std::mem::take(&mut self.time_text),
            std::mem::take(&mut self.value_text),
        );
        time.clear();
        let _ = write!(time, "{:.6}", at.as_secs_f64());
        let step = std::mem::take(&mut self.step);
        for (object, v) in objects.iter().zip(values) {
            value.clear();
            write_number(&mut value, *v);
            let unit = object.unit.as_deref().unwrap_or("");
            if let Err(e) = self.row([&time, &step, &object.name, &value, unit]) {
                self.error = Some(e);
                break;
            }
            self.rows += 1;
        }
        self.step = step;
        (self.time_text, self.value_text) = (time, value);
    }

    /// Every ending of a run comes through here (a signal, a panic, a lost link too).
    fn run_finished(&mut self, _report: &RunReport) {
        self.flush_now();
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::session::StepOrigin;
    use std::path::PathBuf;

    fn temp(name: &str) -> PathBuf {
        std::env::temp_dir()
            .join(format!("drivescript-csv-{}-{name}", std::process::id()))
            .join("out/samples.csv")
    }

    fn step(number: &str) -> StepInfo {
        StepInfo {
            number: number.into(),
            label: "sample".into(),
            origin: StepOrigin {
                path: "r.yaml".into(),
                line: 3,
                column: 5,
            },
            phase: "steps",
            container: false,
        }
    }

    fn object(name: &str, unit: Option<&str>) -> ObjectRef {
        ObjectRef {
            name: name.into(),
            unit: unit.map(String::from),
        }
    }

    #[test]
    fn long_format_rows_are_on_disk_while_the_run_goes_on() {
        let path = temp("rows");
        let mut csv = CsvRecorder::create(&path).unwrap();
        csv.step_started(&step("3"));
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
            "time [s],step,object,value,unit\n"
        );
        csv.flush_now();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time [s],step,object,value,unit\n\
             5.100000,3,speed_actual,6000.125,rpm\n\
             5.100000,3,current_actual,2.5,A\n"
        );
        csv.step_started(&step("7.2"));
        csv.sample(Duration::from_secs(70), &[object("drive_error", None)], &[0.0]);
        csv.flush_now();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(text.ends_with("70.000000,7.2,drive_error,0,\n"), "{text}");
        assert_eq!(csv.rows(), 3);
        assert_eq!(csv.error(), None);

        // And a CSV reader agrees on the columns.
        let mut reader = csv::Reader::from_path(&path).unwrap();
        assert_eq!(
            reader.headers().unwrap(),
            &csv::StringRecord::from(CSV_HEADER.to_vec())
        );
        let rows: Vec<csv::StringRecord> = reader.records().map(Result::unwrap).collect();
        assert_eq!(rows.len(), 3);
        assert_eq!(&rows[1][2], "current_actual");
        drop(csv);
        std::fs::remove_dir_all(path.parent().unwrap().parent().unwrap()).unwrap();
    }

    #[test]
    fn names_with_commas_are_quoted() {
        let path = temp("quote");
        let mut csv = CsvRecorder::create(&path).unwrap();
        csv.sample(Duration::ZERO, &[object("odd,name", Some("\"u\""))], &[1.0]);
        csv.flush_now();
        let text = std::fs::read_to_string(&path).unwrap();
        assert!(
            text.ends_with("0.000000,,\"odd,name\",1,\"\"\"u\"\"\"\n"),
            "{text}"
        );
        drop(csv);
        std::fs::remove_dir_all(path.parent().unwrap().parent().unwrap()).unwrap();
    }

    #[test]
    fn an_unwritable_path_is_refused_with_its_name() {
        let err = CsvRecorder::create(Path::new("/proc/drivescript/x.csv"))
            .err()
            .unwrap();
        assert!(err.contains("/proc/drivescript"), "{err}");
        let dir = std::env::temp_dir();
        let err = CsvRecorder::create(&dir).err().unwrap();
        assert!(err.starts_with("cannot write "), "{err}");
    }
}

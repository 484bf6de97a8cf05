//! The one layout of every samples CSV (`--csv` and the `csv:` files of sample steps).
//! Long, the default: `time [s],utc,step,object,value,unit`, one row per value, so steps
//! that sample different objects share one file and pandas/Excel pivot it as they like.
//! Wide (`--csv-wide`): `time [s],utc,step,OBJECT [UNIT],...`, one column per object, an
//! empty cell where a step did not sample it. `time [s]` counts from the run's start;
//! `utc` is the absolute time (RFC 3339, milliseconds); `step` is the iteration-aware step
//! id (`4[2].3`). Writes through [`CsvFile`]; knows nothing of drives.

use super::{write_number, ObjectRef};
use crate::csv_file::CsvFile;
use crate::output_file_error::OutputFileError;
use std::path::Path;
use std::time::{Duration, SystemTime};

/// The columns of the long layout.
pub const LONG_HEADER: [&str; 6] = ["time [s]", "utc", "step", "object", "value", "unit"];
/// The long layout of a run with several drives: the drive's name in a column of its own.
pub const LONG_HEADER_DRIVES: [&str; 7] = ["time [s]", "utc", "step", "drive", "object", "value", "unit"];

pub struct SampleTable {
    file: CsvFile,
    /// The object columns of the wide layout; `None` for the long one.
    wide: Option<Vec<ObjectRef>>,
    /// The long layout with a `drive` column (a run with several drives, whose objects
    /// are named `left.speed_actual`).
    drive_column: bool,
    /// Buffers reused for every row: a day at 100 Hz is millions of rows.
    time: String,
    utc: String,
    value: String,
    cells: Vec<String>,
}

impl SampleTable {
    /// The header row of the layout: long, or wide with `columns`.
    pub fn header(wide: Option<&[ObjectRef]>) -> Vec<String> {
        match wide {
            None => LONG_HEADER.iter().map(|h| h.to_string()).collect(),
            Some(columns) => {
                let mut h: Vec<String> = LONG_HEADER[..3].iter().map(|h| h.to_string()).collect();
                h.extend(columns.iter().map(|o| match &o.unit {
                    Some(u) => format!("{} [{u}]", o.name),
                    None => o.name.clone(),
                }));
                h
            }
        }
    }

    /// Creates (truncates) `path` with its header, or (`append`) continues a file this run
    /// started. The error names the path.
    pub fn open(path: &Path, wide: Option<&[ObjectRef]>, append: bool) -> Result<Self, OutputFileError> {
        Self::open_for(path, wide, append, false)
    }

    /// [`SampleTable::open`] for a run with several drives (`drives`): the long layout
    /// then has a `drive` column and the object's own name.
    pub fn open_for(
        path: &Path,
        wide: Option<&[ObjectRef]>,
        append: bool,
        drives: bool,
    ) -> Result<Self, OutputFileError> {
        let drive_column = drives && wide.is_none();
        let file = if append {
            CsvFile::append(path)?
        } else if drive_column {
            let header: Vec<String> = LONG_HEADER_DRIVES.iter().map(|h| h.to_string()).collect();
            CsvFile::create(path, &header)?
        } else {
            CsvFile::create(path, &Self::header(wide))?
        };
        Ok(SampleTable {
            file,
            wide: wide.map(<[ObjectRef]>::to_vec),
            drive_column,
            time: String::new(),
            utc: String::new(),
            value: String::new(),
            cells: Vec::new(),
        })
    }

    pub fn path(&self) -> &Path {
        self.file.path()
    }

    /// The rows of one sample: `at` since the run's start, `utc` the wall time. Returns
    /// how many rows were written.
    pub fn rows(
        &mut self,
        at: Duration,
        utc: SystemTime,
        step: &str,
        objects: &[ObjectRef],
        values: &[f64],
    ) -> Result<u64, OutputFileError> {
        use std::fmt::Write as _;
        self.time.clear();
        let _ = write!(self.time, "{:.3}", at.as_secs_f64());
        self.utc.clear();
        let _ = write!(self.utc, "{}", humantime::format_rfc3339_millis(utc));
        match &self.wide {
            None => {
                for (object, v) in objects.iter().zip(values) {
                    self.value.clear();
                    write_number(&mut self.value, *v);
                    let unit = object.unit.as_deref().unwrap_or("");
                    match object.name.split_once('.') {
                        Some((drive, name)) if self.drive_column => {
                            self.file
                                .row(&[&self.time, &self.utc, step, drive, name, &self.value, unit])?
                        }
                        _ => {
                            self.file
                                .row(&[&self.time, &self.utc, step, &object.name, &self.value, unit])?
                        }
                    }
                }
                Ok(objects.len().min(values.len()) as u64)
            }
            Some(columns) => {
                self.cells.clear();
                self.cells
                    .extend([self.time.clone(), self.utc.clone(), step.to_string()]);
                for column in columns {
                    let mut cell = String::new();
                    if let Some(i) = objects.iter().position(|o| o.name == column.name) {
                        if let Some(v) = values.get(i) {
                            write_number(&mut cell, *v);
                        }
                    }
                    self.cells.push(cell);
                }
                self.file.row(&self.cells)?;
                Ok(1)
            }
        }
    }

    pub fn flush(&mut self) -> Result<(), OutputFileError> {
        self.file.flush()
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use std::time::UNIX_EPOCH;

    fn object(name: &str, unit: Option<&str>) -> ObjectRef {
        ObjectRef {
            name: name.into(),
            unit: unit.map(String::from),
        }
    }

    #[test]
    fn long_and_wide_rows_carry_run_time_utc_and_the_step_id() {
        let dir = std::env::temp_dir().join(format!("drivescript-table-{}", std::process::id()));
        let (speed, current) = (
            object("speed_actual", Some("rpm")),
            object("current_actual", Some("A")),
        );
        let utc = UNIX_EPOCH + Duration::from_millis(1_718_000_000_250);
        let long = dir.join("long.csv");
        let mut t = SampleTable::open(&long, None, false).unwrap();
        let n = t
            .rows(
                Duration::from_millis(5_100),
                utc,
                "4[2].3",
                &[speed.clone(), current.clone()],
                &[6000.125, 2.5],
            )
            .unwrap();
        assert_eq!(n, 2);
        t.flush().unwrap();
        assert_eq!(
            std::fs::read_to_string(&long).unwrap(),
            "time [s],utc,step,object,value,unit\n\
             5.100,2024-06-10T06:13:20.250Z,4[2].3,speed_actual,6000.125,rpm\n\
             5.100,2024-06-10T06:13:20.250Z,4[2].3,current_actual,2.5,A\n"
        );
        // Each closed before its folder goes: Windows removes no folder with an open file.
        drop(t);
        let wide = dir.join("wide.csv");
        let columns = [speed.clone(), current.clone()];
        let mut t = SampleTable::open(&wide, Some(&columns), false).unwrap();
        t.rows(Duration::ZERO, utc, "2", std::slice::from_ref(&current), &[0.5])
            .unwrap();
        t.flush().unwrap();
        assert_eq!(
            std::fs::read_to_string(&wide).unwrap(),
            "time [s],utc,step,speed_actual [rpm],current_actual [A]\n\
             0.000,2024-06-10T06:13:20.250Z,2,,0.5\n"
        );
        drop(t);
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn with_several_drives_the_long_layout_names_the_drive_in_its_own_column() {
        let dir =
            std::env::temp_dir().join(format!("drivescript-sample-table-drives-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        std::fs::create_dir_all(&dir).unwrap();
        let path = dir.join("d.csv");
        let objects = [
            object("left.speed_actual", Some("rpm")),
            object("right.speed_actual", Some("rpm")),
        ];
        let mut t = SampleTable::open_for(&path, None, false, true).unwrap();
        t.rows(
            Duration::from_millis(1500),
            SystemTime::UNIX_EPOCH,
            "4",
            &objects,
            &[1.0, 2.0],
        )
        .unwrap();
        t.flush().unwrap();
        assert_eq!(
            std::fs::read_to_string(&path).unwrap(),
            "time [s],utc,step,drive,object,value,unit\n\
             1.500,1970-01-01T00:00:00.000Z,4,left,speed_actual,1,rpm\n\
             1.500,1970-01-01T00:00:00.000Z,4,right,speed_actual,2,rpm\n"
        );
    }
}

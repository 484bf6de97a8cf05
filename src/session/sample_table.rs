//! The one layout of every samples CSV (`--csv` and the `csv:` files of sample steps).
//! Long, the default: `time [s],utc,step,object,value,unit`, one row per value, so steps
//! that sample different objects share one file and pandas/Excel pivot it as they like.
//! Wide (`--csv-wide`): `time [s],utc,step,OBJECT [UNIT],...`, one column per object, an
//! empty cell where a step did not sample it. `time [s]` counts from the run's start;
//! `utc` is the absolute time (RFC 3339, milliseconds); `step` is the iteration-aware step
//! id (`4[2].3`). Writes through [`CsvFile`]; knows nothing of drives.

use super::{push_number, push_seconds, ObjectRef, UtcMillis};
use crate::csv_file::{push_field, CsvFile};
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
    /// The rows of one sample, made in one buffer reused for every sample: a day at
    /// 100 Hz is millions of rows.
    text: Vec<u8>,
    /// What every row of a sample starts with (`time,utc,step`), formatted once per sample.
    head: Vec<u8>,
    utc: UtcMillis,
    /// The objects of the last sample with the text of their rows around the value
    /// (`,drive,object,` and `,unit`), made once for the many samples of a step.
    fields: Vec<ObjectFields>,
}

/// One object of the long layout and its fields, as they are written.
struct ObjectFields {
    object: ObjectRef,
    before: Vec<u8>,
    after: Vec<u8>,
}

impl ObjectFields {
    fn of(object: &ObjectRef, drive_column: bool) -> ObjectFields {
        let mut before = vec![b','];
        match object.name.split_once('.') {
            Some((drive, name)) if drive_column => {
                push_field(&mut before, drive);
                before.push(b',');
                push_field(&mut before, name);
            }
            _ => push_field(&mut before, &object.name),
        }
        before.push(b',');
        let mut after = vec![b','];
        push_field(&mut after, object.unit.as_deref().unwrap_or(""));
        after.push(b'\n');
        ObjectFields {
            object: object.clone(),
            before,
            after,
        }
    }
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
            text: Vec::new(),
            head: Vec::new(),
            utc: UtcMillis::default(),
            fields: Vec::new(),
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
        self.head.clear();
        push_seconds(&mut self.head, at);
        self.head.push(b',');
        self.utc.push(&mut self.head, utc);
        self.head.push(b',');
        push_field(&mut self.head, step);
        self.text.clear();
        let rows = match &self.wide {
            None => {
                let same = self.fields.len() == objects.len()
                    && self.fields.iter().zip(objects).all(|(f, o)| f.object == *o);
                if !same {
                    self.fields = objects
                        .iter()
                        .map(|o| ObjectFields::of(o, self.drive_column))
                        .collect();
                }
                for (fields, v) in self.fields.iter().zip(values) {
                    self.text.extend_from_slice(&self.head);
                    self.text.extend_from_slice(&fields.before);
                    push_number(&mut self.text, *v);
                    self.text.extend_from_slice(&fields.after);
                }
                objects.len().min(values.len()) as u64
            }
            Some(columns) => {
                self.text.extend_from_slice(&self.head);
                for column in columns {
                    self.text.push(b',');
                    if let Some(i) = objects.iter().position(|o| o.name == column.name) {
                        if let Some(v) = values.get(i) {
                            push_number(&mut self.text, *v);
                        }
                    }
                }
                self.text.push(b'\n');
                1
            }
        };
        self.file.rows_text(&self.text)?;
        Ok(rows)
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
        let dir = crate::scratch_dir::scratch_dir("sample-table-drives");
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

    /// The rows as the csv crate and the formatting machinery wrote them before each
    /// sample's shared text was made once: one record per value, every field formatted.
    fn rows_as_before(drives: bool, wide: Option<&[ObjectRef]>, samples: &[Sample]) -> String {
        // Flexible: only the generated names mix objects with and without a drive.
        let mut w = csv::WriterBuilder::new().flexible(true).from_writer(Vec::new());
        for (at, utc, step, objects, values) in samples {
            let time = format!("{:.3}", at.as_secs_f64());
            let utc = humantime::format_rfc3339_millis(*utc).to_string();
            let number = |v: f64| {
                if v == v.trunc() && v.abs() < 1e15 {
                    format!("{}", v as i64)
                } else {
                    let s = format!("{v:.6}");
                    s.trim_end_matches('0').trim_end_matches('.').to_string()
                }
            };
            match wide {
                None => {
                    for (o, v) in objects.iter().zip(values) {
                        let unit = o.unit.clone().unwrap_or_default();
                        match o.name.split_once('.') {
                            Some((d, n)) if drives => {
                                w.write_record([&time, &utc, step, d, n, &number(*v), &unit])
                            }
                            _ => w.write_record([&time, &utc, step, &o.name, &number(*v), &unit]),
                        }
                        .unwrap();
                    }
                }
                Some(columns) => {
                    let mut cells = vec![time.clone(), utc.clone(), step.clone()];
                    for c in columns {
                        let i = objects.iter().position(|o| o.name == c.name);
                        cells.push(
                            i.and_then(|i| values.get(i))
                                .map(|v| number(*v))
                                .unwrap_or_default(),
                        );
                    }
                    w.write_record(&cells).unwrap();
                }
            }
        }
        String::from_utf8(w.into_inner().unwrap()).unwrap()
    }

    type Sample = (Duration, SystemTime, String, Vec<ObjectRef>, Vec<f64>);

    fn samples() -> impl Strategy<Value = Vec<Sample>> {
        let names = prop::sample::select(vec![
            ("speed_actual", Some("rpm")),
            ("left.current_actual", Some("A")),
            ("odd,name", Some("\"u\"")),
            ("drive_error", None),
        ]);
        let value = prop_oneof![
            -1e7f64..1e7,
            (-100_000i64..100_000).prop_map(|n| n as f64 / 1000.0),
            any::<f64>(),
        ];
        let sample = (
            0u64..200_000_000_000,
            0u64..4_000_000_000_000_000,
            "[0-9\\[\\].,]{1,6}",
            prop::collection::vec((names, value), 0..4),
        );
        prop::collection::vec(sample, 0..20).prop_map(|list| {
            list.into_iter()
                .map(|(at, utc, step, values)| {
                    let objects = values.iter().map(|((n, u), _)| object(n, *u)).collect();
                    let numbers = values.iter().map(|(_, v)| *v).collect();
                    (
                        Duration::from_micros(at),
                        UNIX_EPOCH + Duration::from_micros(utc),
                        step,
                        objects,
                        numbers,
                    )
                })
                .collect()
        })
    }

    use proptest::prelude::*;

    proptest! {
        #[test]
        fn rows_are_byte_for_byte_those_written_before(samples in samples(), drives in any::<bool>(), wide in any::<bool>()) {
            let dir = std::env::temp_dir()
                .join(format!("drivescript-sample-table-bytes-{}", std::process::id()));
            let path = dir.join("t.csv");
            let columns = [object("speed_actual", Some("rpm")), object("drive_error", None)];
            let wide = wide.then_some(&columns[..]);
            let _ = std::fs::remove_file(&path);
            let mut t = SampleTable::open_for(&path, wide, true, drives).unwrap();
            for (at, utc, step, objects, values) in &samples {
                t.rows(*at, *utc, step, objects, values).unwrap();
            }
            t.flush().unwrap();
            let written = std::fs::read_to_string(&path).unwrap();
            prop_assert_eq!(written, rows_as_before(drives && wide.is_none(), wide, &samples));
        }
    }
}

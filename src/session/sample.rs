//! `sample`: read objects at a fixed period for a time, keep their statistics window and
//! series, optionally stream them to a CSV file of the step's own.

use super::session::show_duration;
use super::session::{round, Session};
use super::stop::{nth_tick, Stop};
use super::with_unit;
use super::{
    BucketSeries, ObjectRef, SampleTable, SampleWindow, Sampling, Series, SlopeWindow, StepResponse,
    StepSpec, SERIES_BUCKETS,
};
use crate::drive::ReadSet;
use std::time::Duration;

/// The objects of one drive in a sample: the drive's index, the objects' places in the
/// step's list, and the objects looked up once in the drive's dictionary.
type ReadGroup = (usize, Vec<usize>, ReadSet);

impl Session<'_> {
    /// This tick's values, for the watches of the same objects.
    fn lend_to_watches(&mut self, values: &[f64], at: Duration) {
        if self.sampled.values.is_empty() {
            return;
        }
        for (slot, v) in self.sampled.values.iter_mut().zip(values) {
            slot.2 = *v;
        }
        self.sampled.at = at;
    }

    /// The objects of a sample grouped by drive, so that each drive is read in one go.
    fn read_groups(&mut self, objects: &[ObjectRef]) -> Result<Vec<ReadGroup>, Stop> {
        let mut grouped: Vec<(usize, Vec<usize>, Vec<String>)> = Vec::new();
        for (i, o) in objects.iter().enumerate() {
            let name = self.select_object(&o.name)?.to_string();
            match grouped.iter_mut().find(|g| g.0 == self.current) {
                Some(g) => {
                    g.1.push(i);
                    g.2.push(name);
                }
                None => grouped.push((self.current, vec![i], vec![name])),
            }
        }
        let mut groups = Vec::with_capacity(grouped.len());
        for (drive, places, names) in grouped {
            self.current = drive;
            let names: Vec<&str> = names.iter().map(String::as_str).collect();
            let set = self.drive().read_set(&names)?;
            groups.push((drive, places, set));
        }
        Ok(groups)
    }

    /// One sample of every group into `values` (in the step's order of objects); `scratch`
    /// holds a group's values on the way.
    fn read_grouped(
        &mut self,
        groups: &[ReadGroup],
        values: &mut [f64],
        scratch: &mut Vec<f64>,
    ) -> Result<(), Stop> {
        if let [(drive, _, set)] = groups {
            // One drive: straight into `values`, as the objects are in its order.
            self.current = *drive;
            self.drive().read_set_numbers(set, values)?;
            return Ok(());
        }
        for (drive, places, set) in groups {
            scratch.clear();
            scratch.resize(places.len(), 0.0);
            self.current = *drive;
            self.drive().read_set_numbers(set, scratch)?;
            for (place, v) in places.iter().zip(scratch.iter()) {
                values[*place] = *v;
            }
        }
        Ok(())
    }

    /// Reads the sampling's objects every `every` for `duration`; keeps the window for `expect` (with
    /// the response to the step `steps` declares for an object) and the series for the
    /// plots; optionally writes a CSV file. Each tick's values are lent to the watches of
    /// the same objects while it runs (see [`super::watch`]; the step that runs it takes
    /// them back however it ends).
    pub fn sample(
        &mut self,
        sampling: &Sampling,
        steps: &[(String, StepSpec)],
        number: &str,
    ) -> Result<String, Stop> {
        let Sampling {
            objects,
            every,
            duration,
            csv,
        } = sampling;
        let (objects, every, duration) = (objects.as_slice(), *every, *duration);
        let mut writer = match csv.as_ref() {
            Some(p) => {
                let path = self.output_dir.join(p);
                let append = !self.csv_files.insert(path.clone());
                let wide = self.csv_wide.then_some(objects);
                Some(SampleTable::open_for(&path, wide, append, self.several_drives())?)
            }
            None => None,
        };
        let start = self.clock.now();
        let run_start = self.run_start;
        let origin = (start - run_start).as_secs_f64();
        let width = (duration.as_secs_f64() / SERIES_BUCKETS as f64).max(every.as_secs_f64());
        let mut stats: Vec<SampleWindow> = objects
            .iter()
            .map(|o| SampleWindow {
                stats: Default::default(),
                slope: SlopeWindow::new(origin, duration.as_secs_f64(), every.as_secs_f64()),
                response: steps
                    .iter()
                    .find(|(name, _)| *name == o.name)
                    .map(|(_, spec)| StepResponse::new(*spec, origin, duration.as_secs_f64())),
            })
            .collect();
        let mut series: Vec<BucketSeries> =
            objects.iter().map(|_| BucketSeries::new(origin, width)).collect();
        let mut values = vec![0.0; objects.len()];
        let groups = self.read_groups(objects)?;
        // Only a run with watches lends its values; the names are taken once.
        self.sampled.values.clear();
        if !self.watches.is_empty() {
            for o in objects {
                let name = self.select_object(&o.name)?.to_string();
                self.sampled.values.push((self.current, name, 0.0));
            }
        }
        let mut scratch = Vec::new();
        let mut k: u32 = 0;
        let mut late = 0u32;
        let end = start.saturating_add(duration);
        // The step's id is the same for every row; building it per row would cost an
        // allocation per sample.
        let id = match writer {
            Some(_) => self.path.id(),
            None => String::new(),
        };
        loop {
            let due = nth_tick(start, every, k)?;
            if due > end {
                break;
            }
            if self.interrupted() {
                return Err(Stop::Interrupted);
            }
            self.wait(due)?;
            let at = self.clock.now();
            if at > due.saturating_add(every) {
                late += 1;
            }
            let t = (at - run_start).as_secs_f64();
            // All at once: a family whose telegram carries several values answers them in
            // one round trip.
            self.read_grouped(&groups, &mut values, &mut scratch)?;
            self.lend_to_watches(&values, at);
            for (i, v) in values.iter().enumerate() {
                stats[i].push(t, *v);
                series[i].push(t, *v);
            }
            let since_start = at.saturating_sub(run_start);
            if let Some(w) = writer.as_mut() {
                w.rows(since_start, self.clock.wall_time(), &id, objects, &values)?;
            }
            self.observer.sample(since_start, objects, &values);
            // The live line is text for a screen; build it only when one shows it.
            if self.observer.wants_progress() {
                let live = objects
                    .iter()
                    .zip(&values)
                    .map(|(o, v)| format!("{} {}", o.name, with_unit(*v, o.unit.as_deref())))
                    .collect::<Vec<_>>()
                    .join(", ");
                self.observer
                    .step_progress(number, at - start, Some(duration), &live);
            }
            self.watch_fault(false)?;
            k += 1;
        }
        self.sampled.values.clear();
        if let Some(w) = writer.as_mut() {
            w.flush()?;
        }
        let mut summary = Vec::new();
        for ((o, w), points) in objects.iter().zip(stats).zip(series) {
            let s = w.stats;
            summary.push(format!(
                "{} mean {} min {} max {}",
                o.name,
                with_unit(round(s.mean), o.unit.as_deref()),
                with_unit(round(s.min), o.unit.as_deref()),
                with_unit(round(s.max), o.unit.as_deref())
            ));
            let marks = w.response.as_ref().map(StepResponse::marks);
            self.windows.insert(o.name.clone(), w);
            self.window_steps.insert(o.name.clone(), self.path.id());
            self.report.series.push(Series {
                object: o.name.clone(),
                unit: o.unit.clone(),
                step: self.path.id(),
                points: points.points(),
                samples: Some(s),
                marks,
            });
        }
        let late_note = if late > 0 {
            let took = self.clock.now().saturating_sub(start).as_secs_f64();
            format!(
                "; {late} sample(s) late, the step took {took:.2} s: the line is too slow for every {}",
                show_duration(every)
            )
        } else {
            String::new()
        };
        Ok(format!("{k} samples: {}{late_note}", summary.join("; ")))
    }
}

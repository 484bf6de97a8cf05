//! Run length costs no memory: counted, not timed. A long sample step keeps a bounded
//! series per object, and a long repeat a bounded list of step records, with the verdict
//! and the statistics unchanged.

use crate::reports::markup::{html, rows, texts};
use crate::support::{assert_has, InProcessRun};
use drivescript::report::html_report;
use drivescript::session::{MAX_RECORDS, SERIES_BUCKETS};

fn run(name: &str, text: &str) -> (i32, drivescript::session::RunReport) {
    let dir = std::env::temp_dir().join(format!("drivescript-bounded-{}-{name}", std::process::id()));
    std::fs::create_dir_all(&dir).expect("dir");
    let recipe = dir.join("recipe.yaml");
    std::fs::write(&recipe, text).expect("recipe");
    let mut run = InProcessRun::new(recipe);
    run.output_dir = dir.clone();
    let (result, output) = run.run();
    let _ = std::fs::remove_dir_all(&dir);
    let report = result.report.unwrap_or_else(|| panic!("{output}"));
    (result.exit_code, report)
}

#[test]
fn a_long_sample_step_keeps_a_bounded_series_and_its_peaks() {
    let (code, report) = run(
        "sample",
        "name: Half an hour at 100 Hz
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 6000 rpm }
  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % }, timeout: 10 s }
  - sample: { objects: [speed_actual, current_actual], every: 10 ms, for: 30 min }
  - expect: { speed_actual: { mean: { near: 6000 rpm, within: 0.1 % } } }
",
    );
    assert_eq!(code, 0);
    assert_eq!(report.series.len(), 2);
    for s in &report.series {
        // 180 001 samples each, kept in at most twice the bucket count.
        assert!(s.points.len() <= 2 * SERIES_BUCKETS, "{} points", s.points.len());
        assert!(s.points.len() >= SERIES_BUCKETS / 2, "{} points", s.points.len());
    }
    let mean = report
        .checks
        .iter()
        .find(|c| c.statistic.as_deref() == Some("mean"))
        .expect("mean check");
    assert!((mean.measured.unwrap_or(0.0) - 6000.0).abs() < 1.0);
}

/// A window of more samples than the run keeps for its plot: the HTML caption gives the
/// statistics of every sample the step took, as the checks do, and says how many of them
/// the plot shows.
#[test]
fn a_bucketed_window_is_captioned_with_all_its_samples() {
    let (code, report) = run(
        "caption",
        "name: Bucketed
steps:
  - go_to: operation_enabled
  - set: { speed_setpoint: 6000 rpm }
  - wait_until: { speed_actual: { near: 6000 rpm, within: 1 % }, timeout: 10 s }
  - sample: { objects: [speed_actual], every: 10 ms, for: 18 s }
  - expect: { speed_actual: { mean: { near: 6000 rpm, within: 1 % } } }
",
    );
    assert_eq!(code, 0);
    assert!(report.steps.iter().any(|s| s.detail.starts_with("1801 samples")));
    let kept = report.series[0].points.len();
    assert!(kept < 1801, "{kept} points kept");
    let page = html_report(&report);
    let doc = html(&page).unwrap_or_else(|e| panic!("{e}"));
    let caption = texts(&doc, "figcaption").remove(0);
    let mean_check = rows(&doc, "checks")
        .into_iter()
        .find(|row| row[0].contains("mean"))
        .expect("the mean check's row");
    assert_has(
        &caption,
        &[
            &format!("{kept} of 1801 points shown (min and max of each interval)"),
            &format!("mean {},", mean_check[1]),
        ],
    );
}

#[test]
fn a_long_repeat_keeps_a_bounded_list_of_steps() {
    let (code, report) = run(
        "repeat",
        "name: Many reads
steps:
  - repeat: { times: 15000, steps: [ { read: speed_actual } ] }
",
    );
    assert_eq!(code, 0);
    assert!(
        report.steps.len() <= MAX_RECORDS + 10,
        "{} steps",
        report.steps.len()
    );
    assert!(report.omitted_steps >= 5_000, "{} omitted", report.omitted_steps);
    // The top-level step and the safe stop are always kept.
    assert!(report.steps.iter().any(|s| s.number == "1"));
    assert!(report.steps.iter().any(|s| s.phase == "finally"));
}

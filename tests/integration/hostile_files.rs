//! Hostile files stay bounded: an EDS/DCF object name of any length is shown without a
//! panic by `read` and `diff`; thousands of problems in an EDS or a recipe are reported as
//! the first 100 and a count of the others (each problem shown renders its snippet from
//! the file, so showing all of them cost time and memory quadratic in their number).

use crate::support::{cli, drivescript, scratch};

/// A DCF whose object 0x2100 (the simulated drive's velocity loop gain, REAL32) has a name
/// of 70 000 characters, over the 65 535 `format!` can pad to.
fn long_name_dcf(dir: &std::path::Path) -> String {
    let name = "A".repeat(70_000);
    let text = format!(
        "[FileInfo]\nFileName=long.dcf\n[DeviceComissioning]\nNodeID=1\n[2100]\nParameterName={name}\nDataType=0x0008\nAccessType=rw\nParameterValue=2.5\n"
    );
    let path = dir.join("long.dcf");
    std::fs::write(&path, text).expect("dcf");
    path.display().to_string()
}

#[test]
fn an_object_name_over_65535_characters_neither_panics_read_nor_diff() {
    let dir = scratch("long-name");
    let dcf = long_name_dcf(&dir);
    let stdout = cli(&["read", "0x2100", "--drive", "canopen", "--dictionary", &dcf], 0).stdout;
    assert!(stdout.contains(&"a".repeat(70_000)), "the whole name is shown");
    assert!(
        stdout.contains("1.5"),
        "{}",
        &stdout[stdout.len().saturating_sub(200)..]
    );
    // The DCF's 2.5 against the simulated drive's 1.5: one difference, named in full.
    let stdout = cli(&["diff", &dcf, "--drive", "canopen", "--dictionary", &dcf], 1).stdout;
    assert!(
        stdout.contains(&"a".repeat(70_000)) && stdout.contains("changed"),
        "{}",
        &stdout[..200.min(stdout.len())]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

/// How many problems a rendering shows (each is headed `×`).
fn shown(stderr: &str) -> usize {
    stderr.matches('×').count()
}

#[test]
fn an_eds_with_thousands_of_problems_reports_the_first_100_and_counts_the_rest() {
    let dir = scratch("eds-problems");
    let sections: String = (0..2000)
        .map(|i| {
            format!(
                "[{:04X}]\nParameterName=X{i}\nDataType=bad\nAccessType=rw\n",
                0x2000 + i
            )
        })
        .collect();
    let path = dir.join("bad.eds");
    std::fs::write(&path, format!("[FileInfo]\nFileName=bad.eds\n{sections}")).expect("eds");
    let out = drivescript(
        &[
            "objects",
            "--drive",
            "canopen",
            "--dictionary",
            &path.display().to_string(),
        ],
        "",
    );
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(shown(&stderr), 100, "{}", &stderr[..500.min(stderr.len())]);
    assert!(
        stderr.contains(
            "`DataType=bad` is not a data type code (and 1999 more problems; the first 100 are shown)"
        ),
        "{}",
        &stderr[..500.min(stderr.len())]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

#[test]
fn a_recipe_with_thousands_of_problems_reports_the_first_100_and_counts_the_rest() {
    let dir = scratch("recipe-problems");
    let steps: String = (0..2000)
        .map(|i| format!("  - read: no_such_object_{i}\n"))
        .collect();
    let path = dir.join("many.yaml");
    std::fs::write(&path, format!("name: Many problems\nsteps:\n{steps}")).expect("recipe");
    let out = drivescript(&["check", &path.display().to_string()], "");
    let stderr = String::from_utf8_lossy(&out.stderr);
    assert_eq!(out.status.code(), Some(2), "{stderr}");
    assert_eq!(shown(&stderr), 100, "{}", &stderr[..500.min(stderr.len())]);
    assert!(
        stderr.contains("… and 1900 more problems (the first 100 are shown)"),
        "{}",
        &stderr[stderr.len().saturating_sub(300)..]
    );
    assert!(
        stderr.contains("2000 problems found; nothing was sent"),
        "{}",
        &stderr[stderr.len().saturating_sub(300)..]
    );
    // The problems shown keep their did-you-mean help.
    assert!(
        stderr.contains("unknown object `no_such_object_0`"),
        "{}",
        &stderr[..500.min(stderr.len())]
    );
    let _ = std::fs::remove_dir_all(&dir);
}

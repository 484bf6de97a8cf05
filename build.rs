//! Build information for `drivescript --version`: the git commit the binary was built
//! from and the build date (UTC; `SOURCE_DATE_EPOCH` when set, for reproducible builds).
//! A source tree without git (a release tarball, a vendored copy) builds as well and
//! says `commit unknown`.

use std::process::Command;
use std::time::{Duration, SystemTime, UNIX_EPOCH};

fn git(args: &[&str]) -> Option<String> {
    let out = Command::new("git").args(args).output().ok()?;
    if !out.status.success() {
        return None;
    }
    let text = String::from_utf8(out.stdout).ok()?.trim().to_string();
    (!text.is_empty()).then_some(text)
}

fn main() {
    let commit = git(&["rev-parse", "--short=10", "HEAD"]).unwrap_or_else(|| "unknown".into());
    // Rebuild the information when HEAD moves (a commit, a checkout), not on every build.
    for file in [
        git(&["rev-parse", "--git-path", "HEAD"]),
        git(&["symbolic-ref", "-q", "HEAD"]).and_then(|r| git(&["rev-parse", "--git-path", &r])),
    ]
    .into_iter()
    .flatten()
    {
        if std::path::Path::new(&file).exists() {
            println!("cargo:rerun-if-changed={file}");
        }
    }
    println!("cargo:rerun-if-changed=build.rs");
    println!("cargo:rerun-if-env-changed=SOURCE_DATE_EPOCH");
    let built = std::env::var("SOURCE_DATE_EPOCH")
        .ok()
        .and_then(|s| s.trim().parse::<u64>().ok())
        .map(|s| UNIX_EPOCH + Duration::from_secs(s))
        .unwrap_or_else(SystemTime::now);
    let date = humantime::format_rfc3339_seconds(built).to_string();
    let date = date.get(..10).unwrap_or(&date);
    println!("cargo:rustc-env=DRIVESCRIPT_COMMIT={commit}");
    println!("cargo:rustc-env=DRIVESCRIPT_BUILD_DATE={date}");
}

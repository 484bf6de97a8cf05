//! The manual (`docs/`) and the README stay true (issue 42): their command examples run as
//! written against the simulated drive with the output they show (trycmd), every link and
//! include between them leads somewhere, every page is in the book's summary, and the
//! generated recipe reference is what the loader and the schema say today.

use crate::support::{assert_has, cli, repo_root};
use std::path::{Path, PathBuf};

/// The Markdown files of the manual, and the README.
fn pages() -> Vec<PathBuf> {
    fn walk(dir: &Path, out: &mut Vec<PathBuf>) {
        for entry in std::fs::read_dir(dir).expect("docs/src") {
            let path = entry.expect("entry").path();
            if path.is_dir() {
                walk(&path, out);
            } else if path.extension().and_then(|e| e.to_str()) == Some("md") {
                out.push(path);
            }
        }
    }
    let mut out = vec![repo_root().join("README.md")];
    walk(&repo_root().join("docs/src"), &mut out);
    out.sort();
    out
}

/// Each page of [`pages`] with its text.
fn page_texts() -> impl Iterator<Item = (PathBuf, String)> {
    pages().into_iter().map(|page| {
        let text = std::fs::read_to_string(&page).expect("page");
        (page, text)
    })
}

/// The lines of `text` outside its fenced code blocks.
fn prose_lines(text: &str) -> impl Iterator<Item = &str> {
    let mut fenced = false;
    text.lines().filter(move |line| {
        let fence = line.trim_start().starts_with("```");
        fenced ^= fence;
        !fenced && !fence
    })
}

/// The headings of a page as mdBook makes their anchors: lower case, spaces as `-`, other
/// punctuation dropped.
fn anchors(text: &str) -> Vec<String> {
    prose_lines(text)
        .filter(|line| line.starts_with('#'))
        .map(|line| {
            line.trim_start_matches('#')
                .trim()
                .to_lowercase()
                .chars()
                .filter_map(|c| match c {
                    ' ' => Some('-'),
                    c if c.is_alphanumeric() || c == '-' || c == '_' => Some(c),
                    _ => None,
                })
                .collect()
        })
        .collect()
}

/// The targets of the Markdown links `[text](target)` and of mdBook's `{{#include path}}`
/// in `text`, outside code blocks (an include is inside one).
fn links(text: &str) -> Vec<String> {
    let mut out: Vec<String> = text
        .lines()
        .filter_map(|line| line.trim().strip_prefix("{{#include "))
        .map(|rest| rest.trim_end_matches("}}").trim().to_string())
        .collect();
    for line in prose_lines(text) {
        let mut rest = line;
        while let Some(at) = rest.find("](") {
            let after = &rest[at + 2..];
            let Some(end) = after.find(')') else { break };
            out.push(after[..end].to_string());
            rest = &after[end..];
        }
    }
    out
}

#[test]
fn every_link_and_include_of_the_manual_and_the_readme_leads_somewhere() {
    let mut broken = Vec::new();
    let mut checked = 0;
    for (page, text) in page_texts() {
        for target in links(&text) {
            if target.starts_with("http://")
                || target.starts_with("https://")
                || target.starts_with("mailto:")
            {
                continue;
            }
            checked += 1;
            let (path, anchor) = match target.split_once('#') {
                Some((p, a)) => (p, Some(a)),
                None => (target.as_str(), None),
            };
            let file = if path.is_empty() {
                page.clone()
            } else {
                page.parent().expect("folder").join(path)
            };
            if !file.exists() {
                broken.push(format!("{}: {target} (no such file)", page.display()));
                continue;
            }
            if let Some(anchor) = anchor {
                let text = std::fs::read_to_string(&file).unwrap_or_default();
                if !anchors(&text).iter().any(|a| a == anchor) {
                    broken.push(format!("{}: {target} (no such heading)", page.display()));
                }
            }
        }
    }
    assert!(broken.is_empty(), "broken links:\n{}", broken.join("\n"));
    assert!(checked > 40, "only {checked} links");
}

#[test]
fn every_page_of_the_manual_is_in_its_summary() {
    let src = repo_root().join("docs/src");
    let summary = std::fs::read_to_string(src.join("SUMMARY.md")).expect("SUMMARY.md");
    let listed = links(&summary);
    for page in pages().iter().filter(|p| p.starts_with(&src)) {
        let relative = page
            .strip_prefix(&src)
            .expect("in docs/src")
            .to_string_lossy()
            .replace('\\', "/");
        if relative == "SUMMARY.md" {
            continue;
        }
        assert!(
            listed.contains(&relative),
            "docs/src/{relative} is not in SUMMARY.md"
        );
    }
}

/// The reference is generated: a step kind, key or default changed in the loader or the
/// schema without the page being regenerated fails here.
#[test]
fn the_recipe_reference_is_what_the_loader_and_the_schema_say() {
    let generated = cli(&["schema", "--reference"], 0).stdout;
    let committed =
        std::fs::read_to_string(repo_root().join("docs/src/reference/recipe.md")).unwrap_or_default();
    assert!(
        committed == generated,
        "docs/src/reference/recipe.md is out of date: run \
         `cargo run -- schema --reference > docs/src/reference/recipe.md`"
    );
    assert_has(
        &generated,
        &[
            "wait_until",
            "`timeout`",
            "10 s",
            "coast_down",
            "10 min",
            "brake_to_standstill",
        ],
    );
}

/// The `console` blocks of the README and the manual: each `$ drivescript …` runs as
/// written (from the repository's root, against the simulated drive) and prints what the
/// block shows (`...` and `[..]` stand for what changes from run to run).
#[test]
#[cfg_attr(
    windows,
    ignore = "the examples show what a Linux shell prints: paths with / where Windows shows \\, Linux ports (/dev/ttyUSB0), sh pipes"
)]
fn the_examples_of_the_readme_and_the_manual_run_as_shown() {
    trycmd::TestCases::new()
        .register_bin("drivescript", Path::new(env!("CARGO_BIN_EXE_drivescript")))
        .case(repo_root().join("README.md"))
        .case(repo_root().join("docs/src/**/*.md"));
}

/// The language of each fenced block of `text` with its first line (1-based) and its lines.
fn fenced_blocks(text: &str) -> Vec<(usize, String, Vec<&str>)> {
    let mut out = Vec::new();
    let mut open: Option<(usize, String, Vec<&str>)> = None;
    for (n, line) in text.lines().enumerate() {
        let fence = line.trim_start().strip_prefix("```");
        match (open.take(), fence) {
            (None, Some(info)) => open = Some((n + 1, info.trim().to_string(), Vec::new())),
            (Some(block), Some(_)) => out.push(block),
            (Some(mut block), None) => {
                block.2.push(line);
                open = Some(block);
            }
            (None, None) => {}
        }
    }
    out
}

/// Every command example is run: a block that shows commands is a `console` block trycmd
/// runs against the simulated drive (above). A command that needs a real port or a person
/// at a prompt is shown in a `text` block without a `$ ` prompt, so that it reads as what it
/// is: not an example this suite runs. A shell block, a prompt outside a console block or
/// a console block trycmd is told to skip is refused here.
#[test]
fn every_command_example_of_the_readme_and_the_manual_is_run() {
    let mut not_run = Vec::new();
    let mut run = 0;
    for (page, text) in page_texts() {
        for (line, info, body) in fenced_blocks(&text) {
            let place = format!("{}:{line}", page.display());
            let prompted = body.iter().any(|l| l.trim_start().starts_with("$ "));
            let indented = text.lines().nth(line - 1).is_some_and(|l| l.starts_with(' '));
            let language = info.split(',').next().unwrap_or_default();
            match language {
                "console" | "trycmd" if info.contains("ignore") => {
                    not_run.push(format!("{place}: a console block trycmd skips ({info})"))
                }
                "console" | "trycmd" if indented => not_run.push(format!(
                    "{place}: an indented console block, which trycmd does not see: start its \
                     fence at the line's first column"
                )),
                "console" | "trycmd" => run += usize::from(prompted),
                "sh" | "bash" | "shell" | "zsh" => not_run.push(format!(
                    "{place}: a `{language}` block: make it a `console` block with its output, \
                     or `text` when it needs hardware"
                )),
                _ if prompted => not_run.push(format!(
                    "{place}: `$ ` commands in a `{info}` block: make it a `console` block, or \
                     drop the prompts when it needs hardware"
                )),
                _ => {}
            }
        }
    }
    assert!(
        not_run.is_empty(),
        "command examples not run:\n{}",
        not_run.join("\n")
    );
    assert!(run >= 15, "only {run} console blocks with commands");
}

/// The README is read in five minutes: at most 250 lines; its first recipe is the shipped
/// file as it is, and every path of its layout table exists.
#[test]
fn the_readme_is_short_and_what_it_shows_exists() {
    let readme = std::fs::read_to_string(repo_root().join("README.md")).expect("README.md");
    assert!(readme.lines().count() <= 250, "{} lines", readme.lines().count());
    let recipe =
        std::fs::read_to_string(repo_root().join("recipes/first-recipe.yaml")).expect("first recipe");
    assert!(
        readme.contains(&format!("```yaml\n{recipe}```")),
        "the README shows recipes/first-recipe.yaml as it is"
    );
    assert!(recipe.lines().count() <= 20, "a 20-line first recipe");
    let mut paths = 0;
    for row in readme.lines().filter(|l| l.starts_with("| `")) {
        let first_cell = row.split('|').nth(1).unwrap_or_default();
        for path in first_cell.split('`').skip(1).step_by(2) {
            assert!(
                repo_root().join(path).exists(),
                "README layout names {path}, which does not exist"
            );
            paths += 1;
        }
    }
    assert!(paths >= 15, "only {paths} paths in the layout table");
}

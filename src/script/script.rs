//! A checked script: its file, name, header (`script_header`), the compiled program and
//! the `--set` parameters, and the loading that checks it (syntax in the sandboxed engine,
//! calls of functions no one provides, then the literal drive calls against the
//! dictionary). Every problem is reported at
//! once; nothing here runs the script or talks to a drive.

use super::bridge::Bridge;
use super::drive_api::register;
use super::drive_in_condition::conditions_using_the_drive;
use super::literal_calls::{literal_calls, Arg};
use super::operator_api::literal_prompts;
use super::sandbox::sandbox;
use super::script_error::parse_error;
use super::script_header::Header;
use super::static_check::{check_calls, literal_writes, named_literal_writes};
use super::unknown_calls::unknown_calls;
use super::ScriptInvalid;
use crate::diag::{read_source, Diagnostic, Diagnostics, Source, Span};
use crate::dictionary::Dictionary;
use crate::recipe::{DriveDecl, SafeStopChoice};
use rhai::AST;
use std::path::Path;
use std::sync::Arc;

/// True for a file the script front end runs (`.rhai`).
pub fn is_script(path: &Path) -> bool {
    path.extension().and_then(|e| e.to_str()) == Some("rhai")
}

pub struct Script {
    /// `//! name: ...` in the header, else the file name.
    pub name: String,
    pub path: String,
    pub source: Arc<Source>,
    pub ast: AST,
    /// `--set` parameters, as given.
    pub params: Vec<(String, String)>,
    /// The script defines `fn finally(d)`, which replaces the default finally.
    pub has_finally: bool,
    /// Drive calls written with literal words (for `check`'s summary).
    pub calls: usize,
    /// The numbers the script's literal `set` calls write, in the object's unit, for the
    /// run's comparison with the limits the drive itself reports. With `//! drives:`, the
    /// calls on a variable given one named drive (`let left = drive("left")`), named
    /// `left.speed_setpoint`; which drive other calls go to is known only as it runs.
    pub written: Vec<crate::recipe::WrittenValue>,
    /// The `d.watch` calls written wholly with literals, in a script with one drive: what
    /// `check` compares with the line; the others are known only as the script runs.
    pub watches: Vec<crate::session::Watch>,
    /// The operator calls written with a literal question (`confirm("Guard closed?")`),
    /// with their places: a run without a terminal needs an answer for each.
    pub prompts: Vec<(crate::session::Prompt, crate::session::StepOrigin)>,
    /// `//! link: channel=cyclic, velocity_scaling=24000rpm`: settings of the family's
    /// link, as a recipe's `link:` gives them (the command line wins).
    pub link: Vec<(String, String)>,
    /// The named drives of `//! drives: left = sd2 @ dnc:2, right = sd2 @ dnc:3`; empty
    /// for a script with one drive.
    pub drives: Vec<DriveDecl>,
    /// `//! leave_enabled: true`: after a successful run the drive is left as the script
    /// left it, as a recipe's `leave_enabled: true`.
    pub leave_enabled: bool,
    /// `//! safe_stop: timeout=2 min, standstill=20 rpm`, as a recipe's `safe_stop:`
    /// (the command line's options win).
    pub safe_stop: SafeStopChoice,
}

/// The drives a script's header declares and the dictionary each names, read before the
/// script is loaded so that each drive's dictionary can be loaded first.
pub fn declared_script_drives(path: &Path) -> Vec<(String, String)> {
    match read_source(path) {
        Ok(source) => Header::read(&source)
            .drives
            .into_iter()
            .map(|d| (d.name, d.drive))
            .collect(),
        Err(_) => Vec::new(),
    }
}

/// The parameters a script file reads with `param("name", …)`, found before it is loaded,
/// so that a run of several files can give each `--set` to the files that have it.
pub fn declared_script_params(path: &Path) -> Vec<String> {
    let Ok(source) = read_source(path) else {
        return Vec::new();
    };
    let mut names: Vec<String> = Vec::new();
    for c in literal_calls(&source) {
        if let (false, "param", Some((Arg::Text(name), _))) = (c.method, c.name.as_str(), c.args.first()) {
            if !names.contains(name) {
                names.push(name.clone());
            }
        }
    }
    names
}

/// Loads and checks a script that may declare several drives: `drives` holds each one's
/// dictionary; `dictionary` is the first's, or the one of a script with one drive.
pub fn load_script_for(
    path: &Path,
    dictionary: &Dictionary,
    drives: &[(String, Arc<Dictionary>)],
    set: &[(String, String)],
) -> Result<Script, ScriptInvalid> {
    if drives.is_empty() {
        return load_script(path, dictionary, set);
    }
    match read_source(path) {
        Ok(source) => load_source_for(source, dictionary, drives, set),
        Err(_) => load_script(path, dictionary, set),
    }
}

/// Loads and checks a script file. `set` are the `--set` parameters.
pub fn load_script(
    path: &Path,
    dictionary: &Dictionary,
    set: &[(String, String)],
) -> Result<Script, ScriptInvalid> {
    let shown = path.display().to_string();
    match read_source(path) {
        Ok(source) => load_source(source, dictionary, set),
        Err(e) => {
            let start = Span::start_of(&Source::new(shown.as_str(), ""));
            let help = e.help().unwrap_or_else(|| {
                "check the path; scripts are Rhai files such as recipes/speed-sweep.rhai".into()
            });
            let problem =
                Diagnostic::at(&start, e.sentence(&format!("the script {shown}")), "").with_help(help);
            Err(ScriptInvalid {
                path: shown,
                problems: std::iter::once(problem).collect(),
            })
        }
    }
}

/// Checks script text (tests, and files already read).
pub fn load_script_text(
    path: &str,
    text: &str,
    dictionary: &Dictionary,
    set: &[(String, String)],
) -> Result<Script, ScriptInvalid> {
    load_source(Source::new(path, text), dictionary, set)
}

fn load_source(
    source: Arc<Source>,
    dictionary: &Dictionary,
    set: &[(String, String)],
) -> Result<Script, ScriptInvalid> {
    load_source_for(source, dictionary, &[], set)
}

fn load_source_for(
    source: Arc<Source>,
    dictionary: &Dictionary,
    drives: &[(String, Arc<Dictionary>)],
    set: &[(String, String)],
) -> Result<Script, ScriptInvalid> {
    let path = source.path().to_string();
    let mut problems = Diagnostics::new();
    let mut header = Header::read(&source);
    problems.extend(std::mem::take(&mut header.problems));
    for (decl, span) in header.drives.iter().zip(&header.drive_spans) {
        if !drives.iter().any(|(n, _)| *n == decl.name) {
            problems.push(
                Diagnostic::at(span, format!("no dictionary was loaded for drive `{}`", decl.name), "drive")
                    .with_help("write each drive as `name = DICTIONARY @ ADDRESS`, e.g. `//! drives: left = sd2 @ dnc:2, right = sd2 @ dnc:3`"),
            );
        }
    }
    if let (Some((_, span)), false) = (&header.drive, header.drives.is_empty()) {
        problems.push(
            Diagnostic::at(
                span,
                "a script names either one `drive:` or several `drives:`, not both",
                "drive and drives",
            )
            .with_help("name this drive in the `drives:` line"),
        );
    }
    if let Some((drive, span)) = &header.drive {
        if !dictionary.is_for_drive(drive) {
            let name = dictionary.name();
            problems.push(
                Diagnostic::at(
                    span,
                    format!("this script is for drive `{drive}`, the dictionary in use is `{name}`"),
                    "other drive family",
                )
                .with_help(format!(
                    "run it with --drive and the dictionary it is for, or change the line to `//! drive: {name}`"
                )),
            );
        }
    }
    let ast = match sandbox().compile(source.text()) {
        Ok(ast) => {
            let mut engine = sandbox();
            register(
                &mut engine,
                &Arc::new(Bridge::detached(Arc::new(dictionary.clone()))),
            );
            problems.extend(unknown_calls(&ast, &engine, &source));
            Some(ast)
        }
        Err(e) => {
            problems.push(parse_error(&source, &e));
            None
        }
    };
    let calls = literal_calls(&source);
    problems.extend(conditions_using_the_drive(&source));
    if drives.is_empty() {
        problems.extend(check_calls(&calls, dictionary, set, &path));
    } else {
        // Which drive a call goes to is known only when the script runs: a literal is a
        // problem when no drive's dictionary takes it (the run refuses the others before
        // anything is sent).
        let runs: Vec<Vec<Diagnostic>> = drives
            .iter()
            .map(|(_, d)| check_calls(&calls, d, set, &path))
            .collect();
        let place = |d: &Diagnostic| d.located().split(": ").next().unwrap_or_default().to_string();
        for d in runs[0].iter() {
            if runs.iter().all(|r| r.iter().any(|o| place(o) == place(d))) {
                problems.push(d.clone());
            }
        }
    }
    let mut has_finally = false;
    if let Some(ast) = &ast {
        for f in ast.iter_functions().filter(|f| f.name == "finally") {
            if f.params.len() == 1 {
                has_finally = true;
            } else {
                let at = calls
                    .iter()
                    .find(|c| c.name == "finally" && !c.method)
                    .map(|c| c.span.clone())
                    .unwrap_or_else(|| Span::start_of(&source));
                problems.push(
                    Diagnostic::at(&at, "`finally` must take the drive as its one parameter", "here")
                        .with_help("write `fn finally(d) { ... }`"),
                );
            }
        }
    }
    let prompts = literal_prompts(&calls, &source);
    match ast {
        Some(ast) if problems.is_empty() => Ok(Script {
            name: header.name.unwrap_or_else(|| file_stem(&path)),
            link: header.link,
            path,
            source,
            ast,
            params: set.to_vec(),
            has_finally,
            calls: calls.len(),
            prompts,
            written: if drives.is_empty() {
                literal_writes(&calls, dictionary)
            } else {
                named_literal_writes(&calls, drives)
            },
            watches: match drives.is_empty() {
                true => super::watch_api::literal_watches(&calls, dictionary),
                false => Vec::new(),
            },
            drives: header.drives,
            leave_enabled: header.leave_enabled,
            safe_stop: header.safe_stop,
        }),
        _ => Err(ScriptInvalid {
            path,
            problems: problems.sorted(),
        }),
    }
}

fn file_stem(path: &str) -> String {
    Path::new(path)
        .file_stem()
        .and_then(|s| s.to_str())
        .unwrap_or(path)
        .to_string()
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sd2() -> Arc<Dictionary> {
        std::sync::Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary("sd2")
                .expect("the built-in dictionary"),
        )
    }

    fn problems(text: &str, set: &[(String, String)]) -> Vec<String> {
        match load_script_text("t.rhai", text, &sd2(), set) {
            Ok(_) => Vec::new(),
            Err(e) => e.problems.iter().map(|d| d.located()).collect(),
        }
    }

    /// With named drives, a literal write on a variable given one drive is compared with
    /// that drive's limits, named as a recipe names it; a variable given both is not.
    #[test]
    fn named_drives_literal_writes_belong_to_the_drive_their_variable_names() {
        let text = "//! drives: left = sd2 @ dnc:2, right = sd2 @ dnc:3\nlet l = drive(\"left\");\nlet r = drive(\"right\");\nlet x = drive(\"left\");\nx = drive(\"right\");\nr.set(\"speed_setpoint\", 2000.0, \"rpm\");\nl.set(\"speed_setpoint\", 1000.0, \"rpm\");\nx.set(\"speed_setpoint\", 3000.0, \"rpm\");\n";
        let drives = vec![("left".to_string(), sd2()), ("right".to_string(), sd2())];
        let script = load_source_for(Source::new("two.rhai", text), &sd2(), &drives, &[]).expect("valid");
        let written: Vec<(String, f64, usize)> = script
            .written
            .iter()
            .map(|w| (w.object.name.clone(), w.value, w.origin.line))
            .collect();
        assert_eq!(
            written,
            [
                ("right.speed_setpoint".to_string(), 2000.0, 6),
                ("left.speed_setpoint".to_string(), 1000.0, 7)
            ]
        );
    }

    #[test]
    fn the_header_names_the_script_and_its_drive_family() {
        let script = load_script_text(
            "x/sweep.rhai",
            "//! drive: sd2\n//! name: Sweep\nlet d = drive();\n",
            &sd2(),
            &[],
        )
        .unwrap_or_else(|e| panic!("{}", e.render(false)));
        assert_eq!(script.name, "Sweep");
        assert!(!script.has_finally);
        let plain = load_script_text("x/sweep.rhai", "let x = 1;\n", &sd2(), &[]).expect("valid");
        assert_eq!(plain.name, "sweep");
        assert_eq!(
            problems("//! drive: lenze-931\nlet x = 1;\n", &[]),
            ["t.rhai:1:12: this script is for drive `lenze-931`, the dictionary in use is `sd2`"]
        );
    }

    /// `//! drive:` names a dictionary (what --drive takes) or its family; the message
    /// names the dictionary in use, not its family.
    #[test]
    fn the_header_drive_is_a_dictionary_or_its_family_and_messages_name_the_dictionary() {
        let ct = Arc::new(
            crate::family::Registry::builtin()
                .load_dictionary("ct-unidrive-sp")
                .expect("the built-in dictionary"),
        );
        let check = |text: &str| match load_script_text("t.rhai", text, &ct, &[]) {
            Ok(_) => Vec::new(),
            Err(e) => e.problems.iter().map(|d| d.located()).collect(),
        };
        assert_eq!(
            check("//! drive: ct-unidrive-sp\nlet x = 1;\n"),
            Vec::<String>::new()
        );
        assert_eq!(
            check(&format!("//! drive: {}\nlet x = 1;\n", ct.family())),
            Vec::<String>::new()
        );
        // A script written before family ids were unified.
        assert_eq!(check("//! drive: ct_ansi\nlet x = 1;\n"), Vec::<String>::new());
        assert_eq!(
            check("//! drive: sd2\nlet x = 1;\n"),
            ["t.rhai:1:12: this script is for drive `sd2`, the dictionary in use is `ct-unidrive-sp`"]
        );
    }

    #[test]
    fn finally_takes_the_drive() {
        let script =
            load_script_text("t.rhai", "fn finally(d) { d.shutdown(); }\n", &sd2(), &[]).expect("valid");
        assert!(script.has_finally);
        let p = problems("fn finally() { }\n", &[]);
        assert_eq!(
            p,
            ["t.rhai:1:4: `finally` must take the drive as its one parameter"]
        );
    }

    #[test]
    fn literal_calls_are_checked_and_computed_ones_left_to_the_run() {
        assert!(problems("let d = drive();\nlet n = \"speed_\" + \"x\";\nd.read(n);\n", &[]).is_empty());
        let p = problems(
            "let d = drive();\nd.read(\"bogus\");\nd.wait_until(\"speed_actual\", |v| v > 1.0, \"3 parsecs\");\nd.set(\"ident\", 5);\nlet s = d.sample([\"speed_actual\"], \"1 s\", \"1 min\");\nlet m = s.mean(\"curent_actual\");\nexpect_near(\"x\", 1.0, 1.0, \"lots\");\n",
            &[],
        );
        assert_eq!(p.len(), 5, "{p:#?}");
        let starts = [
            "t.rhai:2:8: unknown object `bogus`",
            "t.rhai:3:43: `3 parsecs` is not a duration",
            "t.rhai:4:7: ident is read-only",
            "t.rhai:6:16: unknown object `curent_actual`",
            "t.rhai:7:28: `lots` is not a tolerance",
        ];
        for (problem, start) in p.iter().zip(starts) {
            assert!(problem.starts_with(start), "{p:#?}");
        }
    }

    #[test]
    fn a_samples_csv_file_is_text_under_the_output_directory() {
        let ok =
            "let d = drive();\nlet s = d.sample([\"speed_actual\"], \"1 s\", \"1 min\", \"sweep.csv\");\n";
        assert!(problems(ok, &[]).is_empty());
        let computed =
            "let d = drive();\nlet s = d.sample([\"speed_actual\"], \"1 s\", \"1 min\", `s${1}.csv`);\n";
        assert!(problems(computed, &[]).is_empty());
        let p = problems(
            "let d = drive();\nlet s = d.sample([\"speed_actual\"], \"1 s\", \"1 min\", \"../x.csv\");\nlet t = d.sample([\"speed_actual\"], \"1 s\", \"1 min\", 5);\n",
            &[],
        );
        assert_eq!(
            p,
            [
                "t.rhai:2:52: `../x.csv` is outside the output directory",
                "t.rhai:3:52: the csv file of a sample is named with text",
            ]
        );
    }

    #[test]
    fn a_state_a_script_compares_with_must_exist() {
        assert!(problems("let d = drive();\nif d.state() == \"fault\" {}\n", &[]).is_empty());
        let p = problems("let d = drive();\nif d.state() != \"faul\" {}\n", &[]);
        assert_eq!(p, ["t.rhai:2:17: unknown state `faul`"]);
    }

    #[test]
    fn every_set_parameter_must_be_read() {
        let set = [("speed".to_string(), "4000rpm".to_string())];
        assert!(problems("let s = param(\"speed\");\n", &set).is_empty());
        let p = problems("let s = param(\"sped\", 1);\n", &set);
        assert_eq!(p, ["t.rhai: --set speed: the script reads no parameter `speed`"]);
    }
}

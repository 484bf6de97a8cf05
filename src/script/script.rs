//! A checked script: its file, name, drive family line, the compiled program and the
//! `--set` parameters, and the loading that checks it (syntax in the sandboxed engine,
//! then the literal drive calls against the dictionary). Every problem is reported at
//! once; nothing here runs the script or talks to a drive.

use super::literal_calls::{literal_calls, LineIndex};
use super::sandbox::sandbox;
use super::script_error::parse_error;
use super::script_invalid::ScriptInvalid;
use super::static_check::check_calls;
use crate::diag::{read_source, Diagnostic, Diagnostics, Source, Span};
use crate::dictionary::Dictionary;
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
    let path = source.path().to_string();
    let mut problems = Diagnostics::new();
    let header = Header::read(&source);
    if let Some((family, span)) = &header.drive {
        if family != dictionary.family() {
            problems.push(
                Diagnostic::at(
                    span,
                    format!(
                        "this script is for drive `{family}`, the dictionary in use is `{}`",
                        dictionary.family()
                    ),
                    "other drive family",
                )
                .with_help(format!(
                    "run it with --drive {family}, or change the line to `//! drive: {}`",
                    dictionary.family()
                )),
            );
        }
    }
    let ast = match sandbox().compile(source.text()) {
        Ok(ast) => Some(ast),
        Err(e) => {
            problems.push(parse_error(&source, &e));
            None
        }
    };
    let calls = literal_calls(&source);
    problems.extend(check_calls(&calls, dictionary, set, &path));
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
    match ast {
        Some(ast) if problems.is_empty() => Ok(Script {
            name: header.name.unwrap_or_else(|| file_stem(&path)),
            path,
            source,
            ast,
            params: set.to_vec(),
            has_finally,
            calls: calls.len(),
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

/// The `//!` lines at the top: `//! drive: sd2`, `//! name: Speed sweep`.
struct Header {
    drive: Option<(String, Span)>,
    name: Option<String>,
}

impl Header {
    fn read(source: &Arc<Source>) -> Header {
        let mut header = Header {
            drive: None,
            name: None,
        };
        let index = LineIndex::new(source.text());
        let mut offset = 0;
        for line in source.text().split_inclusive('\n') {
            let Some(rest) = line.trim_start().strip_prefix("//!") else {
                break;
            };
            if let Some((key, value)) = rest.split_once(':') {
                let value_text = value.trim();
                match key.trim() {
                    "drive" if header.drive.is_none() => {
                        let at = offset + line.find(value_text).unwrap_or(0);
                        header.drive =
                            Some((value_text.to_string(), index.span(source, at, value_text.len())));
                    }
                    "name" if header.name.is_none() => header.name = Some(value_text.to_string()),
                    _ => {}
                }
            }
            offset += line.len();
        }
        header
    }
}

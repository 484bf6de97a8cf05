//! A parameter backup as a YAML file: which drive it came from (family, address, identity),
//! when and by which tool, and per object its name, address, value with unit and raw value
//! (or the error that kept it from being read). Writes and reads the file; must not talk to
//! a drive.

use crate::diag::{
    expected, read_source, Diagnostic, Diagnostics, Reader, Shape, Source, TextFileError, YamlNode,
};
use std::sync::Arc;

/// Why a parameter file could not be used: it could not be read, or what it says is wrong
/// (every problem with its place in the file).
#[derive(Debug, thiserror::Error)]
pub enum ParameterFileError {
    #[error("{}", .0.sentence("the parameter file"))]
    Read(TextFileError),
    #[error("{}", .0.render(false))]
    Invalid(Diagnostics),
}

/// `0x1017` → (0x1017, 0), `0x1018/2` → (0x1018, 2): how [`ParameterFile::from_dcf`]
/// names a DCF's objects.
fn dcf_index(text: &str) -> Option<(u16, u32)> {
    let hex = text.strip_prefix("0x")?;
    let (index, sub) = hex.split_once('/').unwrap_or((hex, "0"));
    Some((u16::from_str_radix(index, 16).ok()?, sub.parse().ok()?))
}

/// What `drivescript backup` writes; the first key tells the file from a recipe.
pub const FORMAT_KEY: &str = "drivescript_parameters";
pub const FORMAT_VERSION: i64 = 1;

#[derive(Debug, Clone, PartialEq)]
pub struct ParameterFile {
    /// The drive family (`sd2`) and the dictionary the names come from.
    pub family: String,
    pub dictionary: String,
    /// The drive's address as the user gave it, and as the family shows it.
    pub address: String,
    /// Identity objects (firmware, ident string) and their values, for the restore guard.
    pub identity: Vec<(String, String)>,
    /// UTC, `2026-11-22T12:58:36Z`.
    pub date: String,
    /// `drivescript 0.1.0`.
    pub tool: String,
    pub objects: Vec<SavedObject>,
}

#[derive(Debug, Clone, PartialEq)]
pub struct SavedObject {
    pub name: String,
    /// In the family's words: `index 352 (0x0160)`.
    pub address: String,
    /// What was read: the value as shown (`6000 rpm`) and the raw value (`6000000`); or the
    /// error.
    pub reading: Reading,
}

#[derive(Debug, Clone, PartialEq)]
pub enum Reading {
    Value { shown: String, raw: String },
    Error(String),
}

impl SavedObject {
    pub fn raw(&self) -> Option<&str> {
        match &self.reading {
            Reading::Value { raw, .. } => Some(raw),
            Reading::Error(_) => None,
        }
    }

    pub fn shown(&self) -> Option<&str> {
        match &self.reading {
            Reading::Value { shown, .. } => Some(shown),
            Reading::Error(_) => None,
        }
    }
}

/// A YAML double-quoted scalar (JSON string syntax is valid YAML).
fn quoted(text: &str) -> String {
    serde_json::to_string(text).unwrap_or_else(|_| format!("{text:?}"))
}

impl ParameterFile {
    pub fn to_yaml(&self) -> String {
        let mut out = String::new();
        out.push_str("# Drive parameters saved by drivescript. Compare with `drivescript diff FILE`,\n");
        out.push_str("# write back with `drivescript restore FILE --apply`.\n");
        out.push_str(&format!("{FORMAT_KEY}: {FORMAT_VERSION}\n"));
        out.push_str(&format!("family: {}\n", quoted(&self.family)));
        out.push_str(&format!("dictionary: {}\n", quoted(&self.dictionary)));
        out.push_str(&format!("address: {}\n", quoted(&self.address)));
        out.push_str(&format!("date: {}\n", quoted(&self.date)));
        out.push_str(&format!("tool: {}\n", quoted(&self.tool)));
        if self.identity.is_empty() {
            out.push_str("identity: {}\n");
        } else {
            out.push_str("identity:\n");
            for (name, value) in &self.identity {
                out.push_str(&format!("  {name}: {}\n", quoted(value)));
            }
        }
        if self.objects.is_empty() {
            out.push_str("objects: []\n");
        } else {
            out.push_str("objects:\n");
        }
        for o in &self.objects {
            out.push_str(&format!("  - name: {}\n", quoted(&o.name)));
            out.push_str(&format!("    address: {}\n", quoted(&o.address)));
            match &o.reading {
                Reading::Value { shown, raw } => {
                    out.push_str(&format!("    value: {}\n", quoted(shown)));
                    out.push_str(&format!("    raw: {}\n", quoted(raw)));
                }
                Reading::Error(e) => out.push_str(&format!("    error: {}\n", quoted(e))),
            }
        }
        out
    }

    /// Reads a backup file, or a CANopen DCF as a parameter set; every problem is reported
    /// with its place in the file.
    pub fn load(path: &std::path::Path) -> Result<ParameterFile, ParameterFileError> {
        let source = read_source(path).map_err(ParameterFileError::Read)?;
        if crate::dictionary::is_eds_path(path) {
            return Self::from_dcf(&source).map_err(ParameterFileError::Invalid);
        }
        Self::parse(&source).map_err(ParameterFileError::Invalid)
    }

    /// A DCF's `ParameterValue`s as a parameter set. Objects are named by their index
    /// (`0x1017`) and family and dictionary are left open: [`Self::named_by`] gives them
    /// the dictionary's names once it is known.
    pub fn from_dcf(source: &Arc<Source>) -> Result<ParameterFile, Diagnostics> {
        let values = crate::dictionary::dcf_parameter_values(source)?;
        Ok(ParameterFile {
            family: String::new(),
            dictionary: String::new(),
            address: String::new(),
            identity: Vec::new(),
            date: String::new(),
            tool: format!("DCF {}", source.path()),
            objects: values
                .into_iter()
                .map(|(index, raw)| SavedObject {
                    name: index.clone(),
                    address: index,
                    reading: Reading::Value {
                        shown: raw.clone(),
                        raw,
                    },
                })
                .collect(),
        })
    }

    /// A DCF's parameter set in `dictionary`'s words: its family, and each object by the
    /// dictionary's name for it (the DCF given with `--dictionary` makes its indexes
    /// aliases). A backup file is left as it is.
    pub fn named_by(&mut self, dictionary: &crate::dictionary::Dictionary) {
        if !self.family.is_empty() {
            return;
        }
        self.family = dictionary.family().to_string();
        for o in &mut self.objects {
            let by_index = dcf_index(&o.address).and_then(|(i, sub)| dictionary.by_address(i, sub));
            if let Some(def) = dictionary.get(&o.name).or(by_index) {
                o.name = def.name.clone();
            }
        }
    }

    pub fn parse(source: &Arc<Source>) -> Result<ParameterFile, Diagnostics> {
        let mut diagnostics = Diagnostics::new();
        let file = {
            let mut r = Reader::new(&mut diagnostics);
            match YamlNode::parse(source) {
                Ok(root) => read_file(&mut r, &root),
                Err(e) => {
                    r.report(e.diagnostic(source.path(), None));
                    None
                }
            }
        };
        match file {
            Some(f) if diagnostics.is_empty() => Ok(f),
            _ => Err(diagnostics),
        }
    }
}

const KEYS: &[&str] = &[
    FORMAT_KEY,
    "family",
    "dictionary",
    "address",
    "date",
    "tool",
    "identity",
    "objects",
];
const OBJECT_KEYS: &[&str] = &["name", "address", "value", "raw", "error"];

fn read_file(r: &mut Reader, root: &YamlNode) -> Option<ParameterFile> {
    let shape = Shape::new("this parameter file", KEYS)
        .require(&[FORMAT_KEY, "family", "objects"])
        .help("a parameter file is what `drivescript backup` writes");
    let f = r.fields(root, &shape)?;
    if let Some(n) = f.get(FORMAT_KEY) {
        r.int(n, "the format version", FORMAT_VERSION, FORMAT_VERSION);
    }
    let text = |r: &mut Reader, key: &str| f.get(key).and_then(|n| r.scalar_text(n, key)).unwrap_or_default();
    // Backups taken before family ids were unified say `ct_ansi`: read as `ct-ansi`.
    let family = crate::dictionary::family_id(&text(r, "family"));
    let dictionary = text(r, "dictionary");
    let address = text(r, "address");
    let date = text(r, "date");
    let tool = text(r, "tool");
    let mut identity = Vec::new();
    if let Some(n) = f.get("identity") {
        match n.entries() {
            Some(entries) => {
                for (k, v) in entries {
                    if let Some(value) = r.scalar_text(v, "an identity value") {
                        identity.push((k.value.clone(), value));
                    }
                }
            }
            None => r.report(expected(n, "`identity`", "a mapping of object names to values")),
        }
    }
    let mut objects = Vec::new();
    if let Some(list) = f
        .get("objects")
        .and_then(|n| r.list(n, "`objects`", "a list of saved objects"))
    {
        for item in list {
            if let Some(o) = read_object(r, item) {
                objects.push(o);
            }
        }
    }
    Some(ParameterFile {
        family,
        dictionary,
        address,
        identity,
        date,
        tool,
        objects,
    })
}

fn read_object(r: &mut Reader, node: &YamlNode) -> Option<SavedObject> {
    let shape = Shape::new("this saved object", OBJECT_KEYS).require(&["name"]);
    let f = r.fields(node, &shape)?;
    let name = r.scalar_text(f.get("name")?, "`name`")?;
    let address = f
        .get("address")
        .and_then(|n| r.scalar_text(n, "`address`"))
        .unwrap_or_default();
    let reading = match (f.get("raw"), f.get("error")) {
        (Some(raw), None) => Reading::Value {
            shown: f
                .get("value")
                .and_then(|n| r.scalar_text(n, "`value`"))
                .unwrap_or_default(),
            raw: r.scalar_text(raw, "`raw`")?,
        },
        (None, Some(e)) => Reading::Error(r.scalar_text(e, "`error`")?),
        _ => {
            r.report(Diagnostic::at(
                &node.span,
                format!("`{name}` needs either `raw` (the value read) or `error` (why it could not be read)"),
                "neither or both",
            ));
            return None;
        }
    };
    Some(SavedObject {
        name,
        address,
        reading,
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn sample() -> ParameterFile {
        ParameterFile {
            family: "sd2".into(),
            dictionary: "sd2".into(),
            address: "DNC address 2".into(),
            identity: vec![("ident".into(), "Test \"Motor\"".into())],
            date: "2026-11-22T12:00:00Z".into(),
            tool: "drivescript 0.1.0".into(),
            objects: vec![
                SavedObject {
                    name: "parameter_set".into(),
                    address: "index 352 (0x0160)".into(),
                    reading: Reading::Value {
                        shown: "3".into(),
                        raw: "3".into(),
                    },
                },
                SavedObject {
                    name: "max_speed".into(),
                    address: "#1.06".into(),
                    reading: Reading::Error(
                        "drive 2 refused: 0x8B object does not exist\nsecond line".into(),
                    ),
                },
            ],
        }
    }

    #[test]
    fn a_written_file_reads_back_the_same() {
        let f = sample();
        let text = f.to_yaml();
        let back = ParameterFile::parse(&Source::new("backup.yaml", text.as_str())).unwrap();
        assert_eq!(back, f);
    }

    #[test]
    fn a_former_family_id_reads_as_todays() {
        let text = "drivescript_parameters: 1\nfamily: ct_ansi\nobjects:\n  - name: a\n    raw: \"1\"\n";
        let file = ParameterFile::parse(&Source::new("old.yaml", text)).unwrap();
        assert_eq!(file.family, "ct-ansi");
    }

    #[test]
    fn problems_are_located() {
        let text =
            "drivescript_parameters: 1\nfamily: sd2\nobjects:\n  - name: a\n    raw: \"1\"\n  - name: b\n";
        let e = ParameterFile::parse(&Source::new("p.yaml", text)).unwrap_err();
        let shown = e.render(false);
        assert!(shown.contains("p.yaml:6"), "{shown}");
        assert!(shown.contains("either `raw`"), "{shown}");
        let e = ParameterFile::parse(&Source::new("r.yaml", "name: A recipe\nsteps: []\n")).unwrap_err();
        assert!(
            e.render(false).contains("drivescript_parameters"),
            "{}",
            e.render(false)
        );
    }

    #[test]
    fn a_file_that_cannot_be_read_or_used_says_which() {
        let dir = std::env::temp_dir().join(format!("drivescript-pf-{}", std::process::id()));
        std::fs::create_dir_all(&dir).unwrap();
        let missing = dir.join("missing.yaml");
        let e = ParameterFile::load(&missing).unwrap_err();
        assert!(matches!(e, ParameterFileError::Read(_)), "{e:?}");
        assert!(
            e.to_string().starts_with("cannot read the parameter file: "),
            "{e}"
        );
        let recipe = dir.join("recipe.yaml");
        std::fs::write(&recipe, "name: A recipe\nsteps: []\n").unwrap();
        let e = ParameterFile::load(&recipe).unwrap_err();
        assert!(matches!(e, ParameterFileError::Invalid(_)), "{e:?}");
        assert!(e.to_string().contains("drivescript_parameters"), "{e}");
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

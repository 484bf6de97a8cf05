//! What a mapping in a file may hold: the name people know it by (`this sample`, `an
//! object`), its keys, the required ones (with what to write), an example, and whether
//! `key:` with nothing after it counts as absent. Data for [`super::Reader::fields`]; it
//! checks nothing itself.

/// The keys of one kind of mapping.
#[derive(Debug, Clone)]
pub struct Shape<'a> {
    pub(crate) what: &'a str,
    /// `None`: any key (names of objects, parameters), so none is unknown.
    pub(crate) allowed: Option<Vec<&'a str>>,
    /// Each required key and, when known, what to write for it.
    pub(crate) required: Vec<(&'a str, Option<String>)>,
    /// What to write, for a node that is not a mapping at all.
    pub(crate) help: Option<String>,
    pub(crate) nothing_is_absent: bool,
}

impl<'a> Shape<'a> {
    /// A mapping called `what` in messages (`this sample`, `an object`, `the limits file`)
    /// whose keys are `allowed`.
    pub fn new(what: &'a str, allowed: &[&'a str]) -> Self {
        Shape {
            what,
            allowed: Some(allowed.to_vec()),
            required: Vec::new(),
            help: None,
            nothing_is_absent: false,
        }
    }

    /// A mapping whose keys are names chosen by the writer (objects to set, parameters).
    pub fn any_keys(what: &'a str) -> Self {
        Shape {
            allowed: None,
            ..Shape::new(what, &[])
        }
    }

    /// Keys that must be given, reported in this order when missing.
    pub fn require(mut self, keys: &[&'a str]) -> Self {
        self.required.extend(keys.iter().map(|k| (*k, None)));
        self
    }

    /// A key that must be given; the help says to add it with `meaning`.
    pub fn require_as(mut self, key: &'a str, meaning: impl Into<String>) -> Self {
        self.required.push((key, Some(meaning.into())));
        self
    }

    /// An example shown when the node is not a mapping at all: ``e.g. `{example}` ``.
    pub fn example(mut self, example: &str) -> Self {
        self.help = Some(format!("e.g. `{example}`"));
        self
    }

    /// Help shown when the node is not a mapping at all.
    pub fn help(mut self, help: impl Into<String>) -> Self {
        self.help = Some(help.into());
        self
    }

    /// `key:` or `key: ~` counts as not given (dictionaries, limits files). Otherwise it is
    /// a value, "nothing" (in a recipe, `finally:` with nothing means "no finally steps").
    pub fn nothing_is_absent(mut self) -> Self {
        self.nothing_is_absent = true;
        self
    }
}

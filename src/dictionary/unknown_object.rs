//! A name that is neither an object nor an alias in the dictionary, with up to three
//! "did you mean" suggestions. Pure data.

use crate::diag::suggestion_text;
use std::fmt;

#[derive(Debug, Clone, PartialEq, Eq)]
pub struct UnknownObject {
    pub name: String,
    /// The dictionary's name (what `--drive` takes).
    pub dictionary: String,
    /// Object names, best first (at most three).
    pub suggestions: Vec<String>,
}

impl UnknownObject {
    /// `did you mean `speed_setpoint`?`, or a pointer to `drivescript objects`.
    pub fn help(&self) -> String {
        suggestion_text(&self.suggestions).unwrap_or_else(|| objects_command(Some(&self.dictionary)))
    }
}

/// Where to see a dictionary's objects: `drivescript objects` with the `--drive` that
/// names it (the family id is no `--drive` value), or with the same flags when it is
/// not a built-in one.
pub fn objects_command(drive: Option<&str>) -> String {
    match drive {
        Some(name) => format!("`drivescript objects --drive {name}` lists the objects"),
        None => "`drivescript objects` with the same --drive and --dictionary lists the objects".to_string(),
    }
}

impl fmt::Display for UnknownObject {
    fn fmt(&self, f: &mut fmt::Formatter<'_>) -> fmt::Result {
        write!(
            f,
            "no object `{}` in the {} dictionary",
            self.name, self.dictionary
        )?;
        if let Some(s) = suggestion_text(&self.suggestions) {
            write!(f, "; {s}")?;
        }
        Ok(())
    }
}

impl std::error::Error for UnknownObject {}

impl miette::Diagnostic for UnknownObject {
    fn help<'a>(&'a self) -> Option<Box<dyn fmt::Display + 'a>> {
        Some(Box::new(self.help()))
    }
}

#[cfg(test)]
mod tests {
    /// The pointer names the dictionary, which is what --drive takes.
    #[test]
    fn the_help_names_the_dictionary_for_drive() {
        let ct = crate::family::Registry::builtin()
            .load_dictionary("ct-unidrive-sp")
            .expect("built-in dictionary");
        let e = ct.lookup("zzzzzzzzzzzz").unwrap_err();
        assert_eq!(
            e.help(),
            "`drivescript objects --drive ct-unidrive-sp` lists the objects"
        );
        assert!(e
            .to_string()
            .starts_with("no object `zzzzzzzzzzzz` in the ct-unidrive-sp dictionary"));
    }
}

//! An object as an operation names it: the dictionary's name, resolved from any alias, and
//! its unit for messages and CSV headers. Plain data.

/// An object as a step names it, resolved to its dictionary name.
#[derive(Debug, Clone, PartialEq)]
pub struct ObjectRef {
    /// The dictionary's name (an alias in the recipe is resolved to this).
    pub name: String,
    /// The object's engineering unit symbol, for messages and CSV headers.
    pub unit: Option<String>,
}

impl ObjectRef {
    /// `speed_actual, current_actual`: the objects of a step, as its label names them.
    pub fn names(objects: &[ObjectRef]) -> String {
        objects
            .iter()
            .map(|o| o.name.as_str())
            .collect::<Vec<_>>()
            .join(", ")
    }
}

impl std::fmt::Display for ObjectRef {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(&self.name)
    }
}

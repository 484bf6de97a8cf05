//! Where an operation was written (file:line:column of a recipe step or a script call),
//! so every report and diagnostic can point at it. Plain data.

/// Where a step was written: `recipes/run-in.yaml:12:5`.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct StepOrigin {
    pub path: String,
    pub line: usize,
    pub column: usize,
}

impl std::fmt::Display for StepOrigin {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}:{}", self.path, self.line, self.column)
    }
}

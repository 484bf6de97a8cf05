//! The seam between the store and a database: run one statement with parameters, read
//! rows back as plain values. SQLite and PostgreSQL each implement it; everything above
//! speaks one SQL dialect (`$1` placeholders, `ON CONFLICT`), parameters only, never SQL
//! built from values.

use super::StoreError;

/// One parameter or one column of a row.
#[derive(Debug, Clone, PartialEq)]
pub enum Value {
    Null,
    Int(i64),
    Real(f64),
    Text(String),
}

impl Value {
    pub fn text(&self) -> Option<&str> {
        match self {
            Value::Text(s) => Some(s),
            _ => None,
        }
    }
    pub fn int(&self) -> Option<i64> {
        match self {
            Value::Int(i) => Some(*i),
            Value::Real(r) => Some(*r as i64),
            _ => None,
        }
    }
    pub fn real(&self) -> Option<f64> {
        match self {
            Value::Real(r) => Some(*r),
            Value::Int(i) => Some(*i as f64),
            _ => None,
        }
    }
}

impl From<Option<String>> for Value {
    fn from(v: Option<String>) -> Value {
        v.map_or(Value::Null, Value::Text)
    }
}
impl From<Option<&str>> for Value {
    fn from(v: Option<&str>) -> Value {
        v.map_or(Value::Null, |s| Value::Text(s.to_string()))
    }
}
impl From<&str> for Value {
    fn from(v: &str) -> Value {
        Value::Text(v.to_string())
    }
}
impl From<String> for Value {
    fn from(v: String) -> Value {
        Value::Text(v)
    }
}
impl From<Option<f64>> for Value {
    fn from(v: Option<f64>) -> Value {
        v.filter(|v| v.is_finite()).map_or(Value::Null, Value::Real)
    }
}
impl From<i64> for Value {
    fn from(v: i64) -> Value {
        Value::Int(v)
    }
}
impl From<bool> for Value {
    fn from(v: bool) -> Value {
        Value::Int(i64::from(v))
    }
}

/// A database the store runs its statements on.
pub trait Backend: Send {
    /// Runs one statement; the number of rows it changed.
    fn execute(&mut self, sql: &str, params: &[Value]) -> Result<u64, StoreError>;
    /// Runs one query; its rows.
    fn query(&mut self, sql: &str, params: &[Value]) -> Result<Vec<Vec<Value>>, StoreError>;
    /// Runs several statements without parameters (the schema).
    fn batch(&mut self, sql: &str) -> Result<(), StoreError>;
    /// The query of the names of the tables there are.
    fn tables_query(&self) -> &'static str;
    /// The names of the tables there are, to tell an empty database from a foreign one.
    fn tables(&mut self) -> Result<Vec<String>, StoreError> {
        let rows = self.query(self.tables_query(), &[])?;
        Ok(rows
            .into_iter()
            .filter_map(|r| r.first().and_then(|v| v.text().map(str::to_string)))
            .collect())
    }
    /// Begins the transaction that applies migrations, holding off every other process
    /// that opens the store at the same moment.
    fn begin_exclusive(&mut self) -> Result<(), StoreError>;
    /// Begins the transaction that writes a batch of records (the writer's, a run's
    /// delivery from the spool).
    fn begin_write(&mut self) -> Result<(), StoreError> {
        self.batch("BEGIN")
    }
    /// Settings for a database known to be a store (never for one that may be another
    /// application's: those are left untouched).
    fn settle(&mut self) -> Result<(), StoreError> {
        Ok(())
    }
    /// Moves what is committed into the database's own file where a database keeps it
    /// elsewhere first (SQLite's write-ahead log), so that file alone holds every run.
    fn checkpoint(&mut self) {}
    /// The store as users name it, without a password.
    fn name(&self) -> &str;
}

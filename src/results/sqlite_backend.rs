//! The embedded store: one SQLite file (rusqlite with its bundled SQLite, so nothing is
//! installed or started), in WAL mode so that several processes write to it at once and
//! readers never wait. A file that is no SQLite database is refused with its path.

use super::backend::{Backend, Value};
use super::StoreError;
use rusqlite::types::{ToSqlOutput, ValueRef};
use rusqlite::{Connection, OpenFlags};
use std::path::Path;
use std::time::Duration;

/// How long a statement waits for another process's write lock before the store counts
/// as unreachable (and the run spools).
const BUSY_TIMEOUT: Duration = Duration::from_secs(5);

pub struct SqliteBackend {
    connection: Connection,
    name: String,
}

impl SqliteBackend {
    /// Opens (creating when `create`) the file at `path`.
    pub fn open(path: &Path, create: bool) -> Result<SqliteBackend, StoreError> {
        let name = path.display().to_string();
        let unreachable = |why: String| StoreError::Unreachable {
            store: name.clone(),
            why,
        };
        if create {
            if let Some(dir) = path.parent().filter(|d| !d.as_os_str().is_empty()) {
                std::fs::create_dir_all(dir)
                    .map_err(|e| unreachable(format!("cannot create {}: {e}", dir.display())))?;
            }
        }
        if path.is_dir() {
            return Err(StoreError::Foreign {
                store: name.clone(),
                why: format!(
                    "it is a directory; name the store's file, such as {}",
                    path.join("results.sqlite").display()
                ),
            });
        }
        if !create && !path.is_file() {
            return Err(StoreError::NotFound(format!(
                "there is no results store at {name} (no run has been recorded there yet)"
            )));
        }
        let mut flags = OpenFlags::SQLITE_OPEN_READ_WRITE | OpenFlags::SQLITE_OPEN_NO_MUTEX;
        if create {
            flags |= OpenFlags::SQLITE_OPEN_CREATE;
        }
        let connection = Connection::open_with_flags(path, flags).map_err(|e| unreachable(e.to_string()))?;
        let mut backend = SqliteBackend { connection, name };
        backend
            .connection
            .busy_timeout(BUSY_TIMEOUT)
            .map_err(|e| backend.error(e))?;
        // The first read tells a damaged or foreign file (SQLite says "file is not a
        // database") from a store; the journal mode is set only once the schema says the
        // file is a store ([`Backend::settle`]), so another application's file is left
        // as it was.
        backend.tables()?;
        Ok(backend)
    }

    fn error(&self, e: rusqlite::Error) -> StoreError {
        use rusqlite::ErrorCode;
        match e.sqlite_error_code() {
            Some(ErrorCode::NotADatabase | ErrorCode::DatabaseCorrupt) => StoreError::Foreign {
                store: self.name.clone(),
                why: format!("the file is damaged or of another kind ({e})"),
            },
            Some(
                ErrorCode::DatabaseBusy
                | ErrorCode::DatabaseLocked
                | ErrorCode::CannotOpen
                | ErrorCode::ReadOnly
                | ErrorCode::DiskFull
                | ErrorCode::SystemIoFailure
                | ErrorCode::PermissionDenied,
            ) => StoreError::Unreachable {
                store: self.name.clone(),
                why: e.to_string(),
            },
            _ => StoreError::Query {
                store: self.name.clone(),
                why: e.to_string(),
            },
        }
    }
}

/// `$3` → `?3`: SQLite takes `$NAME` for a named parameter numbered by first appearance,
/// `?N` for the N-th; the store's SQL means the N-th.
fn numbered(sql: &str) -> String {
    let mut out = String::with_capacity(sql.len());
    let mut chars = sql.chars().peekable();
    while let Some(c) = chars.next() {
        if c == '$' && chars.peek().is_some_and(char::is_ascii_digit) {
            out.push('?');
        } else {
            out.push(c);
        }
    }
    out
}

struct Param<'a>(&'a Value);

impl rusqlite::ToSql for Param<'_> {
    fn to_sql(&self) -> rusqlite::Result<ToSqlOutput<'_>> {
        Ok(match self.0 {
            Value::Null => ToSqlOutput::Borrowed(ValueRef::Null),
            Value::Int(i) => ToSqlOutput::Borrowed(ValueRef::Integer(*i)),
            Value::Real(r) => ToSqlOutput::Borrowed(ValueRef::Real(*r)),
            Value::Text(s) => ToSqlOutput::Borrowed(ValueRef::Text(s.as_bytes())),
        })
    }
}

fn params(values: &[Value]) -> impl rusqlite::Params + '_ {
    rusqlite::params_from_iter(values.iter().map(Param))
}

impl Backend for SqliteBackend {
    fn execute(&mut self, sql: &str, values: &[Value]) -> Result<u64, StoreError> {
        let mut statement = self
            .connection
            .prepare_cached(&numbered(sql))
            .map_err(|e| self.error(e))?;
        let n = statement.execute(params(values)).map_err(|e| self.error(e))?;
        Ok(n as u64)
    }

    fn query(&mut self, sql: &str, values: &[Value]) -> Result<Vec<Vec<Value>>, StoreError> {
        let mut statement = self
            .connection
            .prepare_cached(&numbered(sql))
            .map_err(|e| self.error(e))?;
        let columns = statement.column_count();
        let mut rows = statement.query(params(values)).map_err(|e| self.error(e))?;
        let mut out = Vec::new();
        loop {
            let row = match rows.next() {
                Ok(Some(row)) => row,
                Ok(None) => break,
                Err(e) => return Err(self.error(e)),
            };
            let mut values = Vec::with_capacity(columns);
            for i in 0..columns {
                values.push(match row.get_ref(i) {
                    Ok(ValueRef::Integer(n)) => Value::Int(n),
                    Ok(ValueRef::Real(r)) => Value::Real(r),
                    Ok(ValueRef::Text(t)) => Value::Text(String::from_utf8_lossy(t).into_owned()),
                    _ => Value::Null,
                });
            }
            out.push(values);
        }
        Ok(out)
    }

    fn batch(&mut self, sql: &str) -> Result<(), StoreError> {
        self.connection
            .execute_batch(&numbered(sql))
            .map_err(|e| self.error(e))
    }

    fn tables_query(&self) -> &'static str {
        "SELECT name FROM sqlite_master WHERE type = 'table' AND name NOT LIKE 'sqlite_%'"
    }

    fn begin_exclusive(&mut self) -> Result<(), StoreError> {
        self.batch("BEGIN IMMEDIATE")
    }

    /// IMMEDIATE: the write lock at once, so two writers wait for each other (busy
    /// timeout) instead of one failing when its read turns into a write.
    fn begin_write(&mut self) -> Result<(), StoreError> {
        self.batch("BEGIN IMMEDIATE")
    }

    /// WAL: concurrent writers from several processes, readers never blocked; NORMAL
    /// keeps every commit across a process kill (only a power cut may lose the last).
    fn settle(&mut self) -> Result<(), StoreError> {
        let _ = self.connection.pragma_update(None, "journal_mode", "WAL");
        let _ = self.connection.pragma_update(None, "synchronous", "NORMAL");
        Ok(())
    }

    /// PASSIVE: copies what it can without waiting for other processes' readers or
    /// writers; the next run's checkpoint copies the rest.
    fn checkpoint(&mut self) {
        let _ = self
            .connection
            .query_row("PRAGMA wal_checkpoint(PASSIVE)", [], |_| Ok(()));
    }

    fn name(&self) -> &str {
        &self.name
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn dollar_placeholders_become_numbered_ones() {
        assert_eq!(
            numbered("SET a = $2 WHERE id = $1 AND b = '$x'"),
            "SET a = ?2 WHERE id = ?1 AND b = '$x'"
        );
    }
}

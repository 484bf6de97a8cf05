//! Where the results go: a SQLite file (the default in the user's data directory, or
//! `--results PATH` / `DRIVESCRIPT_RESULTS`) or a PostgreSQL server (`postgres://…`), with
//! the name messages show (never a password) and the spool file of records not yet
//! delivered.

use super::postgres_backend::{postgres_name, PostgresBackend};
use super::sqlite_backend::SqliteBackend;
use super::{Store, StoreError};
use std::path::{Path, PathBuf};

/// The environment variable naming the store, as `--results` does.
pub const RESULTS_ENV: &str = "DRIVESCRIPT_RESULTS";

#[derive(Debug, Clone, PartialEq, Eq)]
pub enum Locator {
    Sqlite(PathBuf),
    Postgres(String),
}

impl Locator {
    /// `postgres://…` or `postgresql://…` is a server; anything else a file path.
    pub fn parse(text: &str) -> Locator {
        let t = text.trim();
        if t.starts_with("postgres://") || t.starts_with("postgresql://") {
            Locator::Postgres(t.to_string())
        } else {
            Locator::Sqlite(PathBuf::from(text))
        }
    }

    /// The store named by `flag` (`--results`), else by [`RESULTS_ENV`], else the default
    /// file in the user's data directory; with whether it was named (not the default).
    /// `None` when nothing names one and there is no data directory.
    pub fn resolve(flag: Option<&str>) -> Option<(Locator, bool)> {
        if let Some(f) = flag {
            return Some((Locator::parse(f), true));
        }
        if let Some(v) = std::env::var(RESULTS_ENV).ok().filter(|v| !v.trim().is_empty()) {
            return Some((Locator::parse(&v), true));
        }
        data_dir().map(|d| (Locator::Sqlite(d.join("results.sqlite")), false))
    }

    /// The store as messages show it: a path, or the server without its password.
    pub fn name(&self) -> String {
        match self {
            Locator::Sqlite(p) => p.display().to_string(),
            Locator::Postgres(url) => postgres_name(url),
        }
    }

    /// Opens the store and brings its schema up to date; `create` makes a missing SQLite
    /// file (a run does, a query does not).
    pub fn open(&self, create: bool) -> Result<Store, StoreError> {
        let backend: Box<dyn super::Backend> = match self {
            Locator::Sqlite(path) => Box::new(SqliteBackend::open(path, create)?),
            Locator::Postgres(url) => Box::new(PostgresBackend::connect(url)?),
        };
        Store::new(backend)
    }

    /// The file that holds records the store could not take, until they are delivered:
    /// beside a SQLite file, in the data directory for a server.
    pub fn spool_path(&self) -> PathBuf {
        match self {
            Locator::Sqlite(p) => {
                let mut name = p.file_name().unwrap_or_default().to_os_string();
                name.push(".spool");
                p.with_file_name(name)
            }
            Locator::Postgres(_) => {
                let safe: String = self
                    .name()
                    .trim_start_matches("postgres://")
                    .chars()
                    .map(|c| {
                        if c.is_ascii_alphanumeric() || c == '.' || c == '-' {
                            c
                        } else {
                            '_'
                        }
                    })
                    .collect();
                data_dir()
                    .unwrap_or_else(std::env::temp_dir)
                    .join(format!("postgres-{safe}.spool"))
            }
        }
    }
}

/// Where the default store and the spools live: `%LOCALAPPDATA%\drivescript` on Windows
/// (the machine's own folder, not the roaming one: a bench's records stay on the bench),
/// elsewhere `$XDG_DATA_HOME/drivescript`, else `~/.local/share/drivescript`.
pub fn data_dir() -> Option<PathBuf> {
    data_dir_of(cfg!(windows), |name| std::env::var_os(name))
}

fn data_dir_of(windows: bool, var: impl Fn(&str) -> Option<std::ffi::OsString>) -> Option<PathBuf> {
    let absolute = |name| var(name).map(PathBuf::from).filter(|p| p.is_absolute());
    let base = if windows {
        absolute("LOCALAPPDATA")?
    } else {
        absolute("XDG_DATA_HOME").or_else(|| var("HOME").map(|h| Path::new(&h).join(".local/share")))?
    };
    Some(base.join("drivescript"))
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_data_folder_is_the_platforms_own() {
        let root = Path::new(if cfg!(windows) { r"C:\" } else { "/" });
        let (local, data, home) = (root.join("local"), root.join("data"), root.join("home"));
        let env = |names: &[&str]| {
            let set: Vec<(String, PathBuf)> = [
                ("LOCALAPPDATA", &local),
                ("XDG_DATA_HOME", &data),
                ("HOME", &home),
            ]
            .into_iter()
            .filter(|(n, _)| names.contains(n))
            .map(|(n, p)| (n.to_string(), p.clone()))
            .collect();
            move |name: &str| {
                set.iter()
                    .find(|(n, _)| n == name)
                    .map(|(_, p)| p.clone().into_os_string())
            }
        };
        let all = ["LOCALAPPDATA", "XDG_DATA_HOME", "HOME"];
        assert_eq!(data_dir_of(true, env(&all)), Some(local.join("drivescript")));
        assert_eq!(data_dir_of(false, env(&all)), Some(data.join("drivescript")));
        assert_eq!(
            data_dir_of(false, env(&["HOME"])),
            Some(home.join(".local/share").join("drivescript"))
        );
        // On Windows HOME is no answer: without its folder there is no default.
        assert_eq!(data_dir_of(true, env(&["HOME"])), None);
    }

    #[test]
    fn a_server_is_named_without_its_password() {
        let l = Locator::parse("postgres://bench:s3cret@db.example:5433/results?sslmode=require");
        assert!(matches!(l, Locator::Postgres(_)));
        assert_eq!(l.name(), "postgres://bench@db.example:5433/results");
        assert!(!l.spool_path().display().to_string().contains("s3cret"));
        assert_eq!(
            Locator::parse("/tmp/r.sqlite").spool_path(),
            PathBuf::from("/tmp/r.sqlite.spool")
        );
    }
}

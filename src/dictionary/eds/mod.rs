//! CiA 306 electronic data sheets (EDS) and device configuration files (DCF) as
//! dictionaries: the INI text, numbers with `$NODEID`, data and access types, the file's
//! objects, and those objects as dictionary entries. Reading only; no I/O beyond what the
//! dictionary loader hands in, and nothing of transports or families.

mod eds_file;
mod eds_number;
mod eds_objects;
mod eds_type;
mod ini_text;

pub(crate) use eds_file::{EdsEntry, EdsFile};
pub(crate) use eds_number::EdsNumber;
pub(crate) use eds_objects::{eds_objects, EdsObjects};

/// True for a path the EDS reader reads: `.eds` or `.dcf`, in any case.
pub fn is_eds_path(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf"))
}

#[cfg(test)]
mod eds_tests;

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
pub(crate) use eds_objects::{eds_objects, EdsObjects, OnBuiltIn};

/// A DCF's `ParameterValue`s of its read-write objects, as a parameter set: each object
/// by its index (`0x1017`, `0x1018/2`, which the EDS's objects have as an alias) and its
/// value (numbers in decimal, `$NODEID` resolved with the DCF's node id; text as written).
/// Every problem located.
pub fn dcf_parameter_values(
    source: &std::sync::Arc<crate::diag::Source>,
) -> Result<Vec<(String, String)>, crate::diag::Diagnostics> {
    use crate::diag::{Diagnostic, Diagnostics};
    use crate::dictionary::DataType;
    let mut problems = Diagnostics::new();
    let file = EdsFile::parse(source, &mut problems);
    let mut values = Vec::new();
    for entry in &file.entries {
        let (Some(text), crate::dictionary::Access::ReadWrite) = (&entry.parameter_value, entry.access)
        else {
            continue;
        };
        // A DOMAIN is not a parameter: a DCF gives its contents as a file to download.
        let Ok((data_type, _)) = entry.data_type.carried() else {
            continue;
        };
        if data_type == DataType::Domain {
            continue;
        }
        // The value as the parameter set holds it, or the one problem with it.
        let value = if let Some(single) = data_type.float_single() {
            // The shortest text of the float, as a backup and a read show it.
            crate::dictionary::Real::parse(text, single)
                .map(|real| real.to_string())
                .ok_or_else(|| {
                    Diagnostic::at(
                        &entry.span,
                        format!("`ParameterValue={text}` is not a number; a {} value is a decimal such as 1.5 or -3.4E+38", entry.data_type.name()),
                        "expected a float",
                    )
                })
        } else if data_type == DataType::Octets {
            // CiA 306 writes an OCTET_STRING's value as hex digits.
            crate::hex::parse_hex(text)
                .map(|bytes| crate::hex::to_hex(&bytes))
                .map_err(|why| {
                    Diagnostic::at(
                        &entry.span,
                        format!("`ParameterValue` of an OCTET_STRING: {why}"),
                        "expected hex bytes",
                    )
                })
        } else if data_type.is_integer() {
            match EdsNumber::parse(text).map(|n| n.resolve(file.node_id)) {
                Ok(Some(n)) => Ok(n.to_string()),
                Ok(None) => Err(Diagnostic::at(
                    &entry.span,
                    format!("`ParameterValue={text}` needs the node id"),
                    "no node id",
                )
                .with_help("give it in [DeviceComissioning] NodeID")),
                Err(why) => Err(Diagnostic::at(
                    &entry.span,
                    format!("`ParameterValue`: {why}"),
                    "expected a number",
                )),
            }
        } else {
            Ok(text.clone())
        };
        match value {
            Ok(value) => values.push((eds_objects::index_text(entry), value)),
            Err(problem) => problems.push(problem),
        }
    }
    if problems.is_empty() {
        Ok(values)
    } else {
        Err(problems)
    }
}

/// True for a path the EDS reader reads: `.eds` or `.dcf`, in any case.
pub fn is_eds_path(path: &std::path::Path) -> bool {
    path.extension()
        .and_then(|e| e.to_str())
        .is_some_and(|e| e.eq_ignore_ascii_case("eds") || e.eq_ignore_ascii_case("dcf"))
}

#[cfg(test)]
mod eds_tests;

//! What a device's own file (an EDS or DCF) says of one object, kept with the object so
//! `objects` can show it: the file's type, access, limits and default as written there,
//! and, for an object a built-in dictionary also describes, which fields the file changed
//! (the file wins: it is the device's word; the built-in entry keeps its name, unit and
//! scale). Pure data and the one merge rule; no I/O, nothing of EDS syntax.

use super::access::Access;
use super::address::Address;
use super::data_type::DataType;
use super::object_def::ObjectDef;
use super::value::format_number;

/// One object as its device's file gives it.
#[derive(Debug, Clone, PartialEq)]
pub struct FileEntry {
    /// The file, as its path was given.
    pub file: String,
    /// 1-based line of the object's section.
    pub line: usize,
    pub address: Address,
    /// The file's name of the object: `Controlword`, `Identity object/Vendor-ID`.
    pub name: String,
    /// The CiA 301 data type code (`0x0004`) and its name (`INTEGER32`).
    pub type_code: u16,
    pub type_name: String,
    /// `AccessType` as written, in lower case (`ro`, `const`, `rww`).
    pub access: String,
    /// `LowLimit`/`HighLimit` in the object's raw counts (`$NODEID` resolved; hex limits
    /// of signed types as two's complement).
    pub low: Option<f64>,
    pub high: Option<f64>,
    /// `DefaultValue` as written.
    pub default: Option<String>,
    /// Where the file and a built-in entry for the same object differ; empty for an object
    /// only the file describes.
    pub overrides: Vec<FieldOverride>,
}

/// One field the device's file decided against a built-in dictionary's entry.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct FieldOverride {
    /// `type`, `access`, `min` or `max`.
    pub field: &'static str,
    /// The file's value (in the object's unit for limits), and the built-in one replaced.
    pub file: String,
    pub built_in: String,
}

impl FileEntry {
    /// `from drive.eds:12: type i16 (built-in i32); max 5000 (built-in 60000)`; `None`
    /// when the file changed nothing.
    pub fn overrides_line(&self) -> Option<String> {
        if self.overrides.is_empty() {
            return None;
        }
        let fields: Vec<String> = self
            .overrides
            .iter()
            .map(|o| format!("{} {} (built-in {})", o.field, o.file, o.built_in))
            .collect();
        Some(format!("from {}:{}: {}", self.file, self.line, fields.join("; ")))
    }

    /// Lays this file entry over `object`, the built-in dictionary's entry for the same
    /// address: the file's `data_type` and `access` replace the built-in ones, its
    /// `limits` (low and high in raw counts as they apply, times the built-in scale)
    /// replace the built-in limits, and a type
    /// that changes width keeps the remaining limits inside its range. The built-in name,
    /// unit, scale and description stay. A string keeps the built-in length (a file's
    /// VISIBLE_STRING has none). Every changed field is recorded in `overrides`.
    pub(crate) fn lay_over(
        mut self,
        object: &mut ObjectDef,
        data_type: DataType,
        access: Access,
        limits: (Option<f64>, Option<f64>),
    ) {
        let strings = matches!(
            (object.data_type, data_type),
            (DataType::String { .. }, DataType::String { .. })
        );
        if data_type != object.data_type && !strings {
            self.overrides.push(FieldOverride {
                field: "type",
                file: format!("{data_type} ({})", self.type_name),
                built_in: object.data_type.to_string(),
            });
            object.data_type = data_type;
        }
        if access != object.access {
            self.overrides.push(FieldOverride {
                field: "access",
                file: self.access.clone(),
                built_in: object.access.id().to_string(),
            });
            object.access = access;
            object.parameter &= object.readable() && object.writable();
        }
        let scale = object.scale;
        let in_unit = |raw: f64| raw * scale;
        let (low, high) = match scale < 0.0 {
            true => (limits.1.map(in_unit), limits.0.map(in_unit)),
            false => (limits.0.map(in_unit), limits.1.map(in_unit)),
        };
        let type_range = object
            .data_type
            .range()
            .map(|(lo, hi)| sorted(in_unit(lo as f64), in_unit(hi as f64)));
        let min = low.or(object.min).map(|m| match type_range {
            Some((lo, _)) => m.max(lo),
            None => m,
        });
        let max = high.or(object.max).map(|m| match type_range {
            Some((_, hi)) => m.min(hi),
            None => m,
        });
        for (field, new, old) in [("min", min, object.min), ("max", max, object.max)] {
            if new != old {
                self.overrides.push(FieldOverride {
                    field,
                    file: limit_text(new),
                    built_in: limit_text(old),
                });
            }
        }
        object.min = min;
        object.max = max;
        if let Some(default) = &self.default {
            object
                .description
                .push_str(&format!(" Default in {}: {default}.", self.file));
        }
        object.file = Some(Box::new(self));
    }
}

fn sorted(a: f64, b: f64) -> (f64, f64) {
    if a <= b {
        (a, b)
    } else {
        (b, a)
    }
}

fn limit_text(limit: Option<f64>) -> String {
    limit.map_or_else(|| "none".to_string(), |v| format_number(v, 9))
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::dictionary::Unit;

    fn target_velocity() -> ObjectDef {
        let mut o = ObjectDef::new(
            "speed_setpoint",
            Address::indexed(0x60FF, 0),
            DataType::I32,
            Access::ReadWrite,
        );
        o.unit = Some(Unit::Rpm);
        o.min = Some(-60000.0);
        o.max = Some(60000.0);
        o
    }

    fn file(type_name: &str, access: &str, low: Option<f64>, high: Option<f64>) -> FileEntry {
        FileEntry {
            file: "servo.eds".into(),
            line: 12,
            address: Address::indexed(0x60FF, 0),
            name: "Target velocity".into(),
            type_code: 4,
            type_name: type_name.into(),
            access: access.into(),
            low,
            high,
            default: Some("0".into()),
            overrides: Vec::new(),
        }
    }

    #[test]
    fn the_files_limits_type_and_access_win_and_say_what_they_replaced() {
        let mut o = target_velocity();
        let f = file("INTEGER32", "rww", Some(-5000.0), Some(5000.0));
        let limits = (f.low, f.high);
        f.lay_over(&mut o, DataType::I32, Access::ReadWrite, limits);
        assert_eq!((o.min, o.max), (Some(-5000.0), Some(5000.0)));
        let f = o.file.as_ref().unwrap();
        assert_eq!(
            f.overrides_line().unwrap(),
            "from servo.eds:12: min -5000 (built-in -60000); max 5000 (built-in 60000)"
        );
        assert_eq!(o.unit, Some(Unit::Rpm), "the built-in unit stays");
        assert!(o.description.contains("Default in servo.eds: 0."));

        let mut o = target_velocity();
        file("INTEGER16", "ro", None, None).lay_over(&mut o, DataType::I16, Access::ReadOnly, (None, None));
        assert_eq!((o.data_type, o.access), (DataType::I16, Access::ReadOnly));
        // The built-in ±60000 does not fit an INTEGER16: the type's range bounds it.
        assert_eq!((o.min, o.max), (Some(-32768.0), Some(32767.0)));
        let line = o.file.as_ref().unwrap().overrides_line().unwrap();
        assert!(line.contains("type i16 (INTEGER16) (built-in i32)"), "{line}");
        assert!(line.contains("access ro (built-in rw)"), "{line}");
    }

    #[test]
    fn a_scaled_object_takes_the_files_raw_limits_in_its_unit() {
        let mut o = target_velocity();
        o.scale = 0.1;
        file("INTEGER32", "rw", None, None).lay_over(
            &mut o,
            DataType::I32,
            Access::ReadWrite,
            (Some(-100.0), Some(200.0)),
        );
        assert_eq!((o.min, o.max), (Some(-10.0), Some(20.0)));
        let mut same = target_velocity();
        file("INTEGER32", "rw", None, None).lay_over(
            &mut same,
            DataType::I32,
            Access::ReadWrite,
            (None, None),
        );
        assert_eq!(same.file.unwrap().overrides_line(), None);
    }
}

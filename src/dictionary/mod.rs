//! Object dictionaries: the named objects of a drive family (address, type, unit and scale,
//! access, limits, aliases) and its device-control profile, read from YAML with every
//! problem located, plus engineering units and the conversions between quantities and raw
//! bytes. File format: each family's built-in dictionary under `dictionary/` is an example.
//!
//! A test bench's limits file caps speed and current on top of any dictionary.
//!
//! The only I/O here is reading dictionary and limits files. This layer must not know transports or
//! links, and it does not decide whether a write is allowed (the drive layer checks
//! [`ObjectDef::access`]).

mod access;
mod address;
mod bench_cap;
mod bench_limits;
mod data_type;
#[allow(clippy::module_inception)]
mod dictionary;
mod dictionary_error;
pub(crate) mod eds;
mod family_id;
mod file_entry;
mod format;
mod object_def;
#[cfg(test)]
mod object_def_tests;
mod object_reader;
mod pole_pairs;
mod profile;
mod profile_reader;
mod quantity;
mod quantity_reader;
mod reader;
mod real;
mod role;
mod unit;
mod unknown_object;
mod validate;
mod value;
mod value_error;
mod wire_value_error;

pub use access::Access;
pub use address::{Address, AddressError, AddressParser};
pub use bench_cap::BenchCap;
pub use bench_limits::{BenchLimits, LimitsRoute, LIMITS_ENV, LIMITS_FILE_NAME};
pub use data_type::{DataType, DataTypeError, MAX_BLOCK_LEN, MAX_STRING_LEN};
pub use dictionary::Dictionary;
pub use dictionary_error::DictionaryError;
pub use eds::{dcf_parameter_values, is_eds_path};
pub use family_id::{family_id, is_family_id, is_former_spelling};
pub use file_entry::{FieldOverride, FileEntry};
pub use format::Format;
pub use object_def::{DecimalPlaces, ObjectDef};
pub use pole_pairs::{is_pole_pairs_setting, speed_frequency, PolePairs, MAX_POLE_PAIRS, POLE_PAIRS_SETTING};
pub use profile::{CommandWrite, ObjectWrite, Profile, RoleBinding, StateMask};
pub use quantity::Quantity;
pub(crate) use quantity_reader::read_dimensioned;
pub use real::Real;
pub use role::Role;
pub use unit::{Dimension, Unit};
pub use unknown_object::{objects_command, UnknownObject};
pub use value::{RawValue, Value};
pub use value_error::ValueError;
pub use wire_value_error::WireValueError;

//! Why a value cannot be written to, or read from, an object: not a number, unknown or
//! wrong unit, outside the object's limits (its own or the bench's) or its type's range,
//! wrong byte count.
//! Every message names the object, the limit and the unit. Pure data.

use super::data_type::DataType;
use super::unit::Unit;
use crate::diag::suggestion_text;

#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ValueError {
    #[error("no value: write a number with an optional unit, e.g. `6000 rpm`")]
    Empty,

    #[error("{origin}: the {dictionary} dictionary gives no `pole_pairs`, so its speeds are not an inverter's output frequency and pole pairs change nothing; for an inverter, give `pole_pairs: N` in your own dictionary (--dictionary FILE) with its speed objects' scale for those pole pairs")]
    PolePairsNotUsed { dictionary: String, origin: String },

    #[error("`{text}` is not a number{hint}")]
    NotANumber {
        text: String,
        /// Starts with `: ` when present.
        hint: String,
    },

    #[error("{}", unknown_unit(unit, suggestions))]
    UnknownUnit { unit: String, suggestions: Vec<String> },

    /// A unit of a value an operator types in: a drive unit or a hand-measured one.
    #[error("{}", unknown_measured_unit(unit, suggestions))]
    UnknownMeasuredUnit { unit: String, suggestions: Vec<String> },

    #[error("{}", wrong_unit(*unit, object, *object_unit))]
    WrongUnit {
        unit: Unit,
        object: String,
        object_unit: Option<Unit>,
    },

    /// Hz for an rpm object (or the reverse) where the dictionary does not say the
    /// motor's pole pairs, which the conversion needs.
    #[error("{unit} is not a unit of {object} ({object_unit}) as it stands: the dictionary does not say the motor's pole pairs, which turn {unit} into {object_unit} (rpm = Hz × 60 / pole pairs); give `pole_pairs: N` in the dictionary (for an inverter whose {object_unit} are its output frequency; then `--link-option pole-pairs=N` or a recipe's `link: {{ pole_pairs: N }}` sets another motor's), or write the value in {object_unit}")]
    NoPolePairs {
        unit: Unit,
        object: String,
        object_unit: Unit,
    },

    #[error("`{text}` is not a number of pole pairs: give a whole number from 1 to 32 (a 4-pole motor has 2 pole pairs)")]
    BadPolePairs { text: String },

    #[error("{value} is above the maximum of {object}, {limit}")]
    AboveMax {
        object: String,
        value: String,
        limit: String,
    },

    #[error("{value} is below the minimum of {object}, {limit}")]
    BelowMin {
        object: String,
        value: String,
        limit: String,
    },

    #[error("{value} exceeds the bench limit {limit} of {object} ({origin})")]
    AboveBenchLimit {
        object: String,
        value: String,
        limit: String,
        /// `limits file /x/drivescript-limits.yaml`
        origin: String,
    },

    #[error("{value} is below the bench limit {limit} of {object} ({origin})")]
    BelowBenchLimit {
        object: String,
        value: String,
        limit: String,
        origin: String,
    },

    #[error("{value} is {counts} counts, outside the range of {object}'s type {data_type}: {range}")]
    OutOfTypeRange {
        object: String,
        value: String,
        counts: String,
        data_type: DataType,
        /// The type's range in the object's unit (and in counts when they differ).
        range: String,
    },

    #[error("{value} is beyond the largest {data_type} of {object}, ±{max}")]
    BeyondFloat {
        object: String,
        value: String,
        data_type: DataType,
        max: String,
    },

    #[error("{object} holds text ({data_type}); give text, not a number")]
    NumberForText { object: String, data_type: DataType },

    #[error("{object} holds a number ({data_type}); give a number, not text")]
    TextForNumber { object: String, data_type: DataType },

    #[error("text of {len} characters is too long for {object}: at most {max}")]
    TextTooLong { object: String, len: usize, max: u8 },

    #[error("{object} takes plain ASCII text; {found:?} is not allowed")]
    TextNotAscii { object: String, found: char },

    #[error("{object} holds bytes, written as hex such as `01 0a ff`: {why}")]
    NotHexBytes { object: String, why: String },

    #[error("{len} bytes are too many for {object} ({data_type}): at most {max}, what one SDO transfer carries here")]
    BlockTooLong {
        object: String,
        data_type: DataType,
        len: usize,
        max: usize,
    },

    #[error("{object} is a DOMAIN, a block of data (a program, a table) that a CANopen tool downloads as a whole: drivescript reads it, up to {max} bytes, but never writes it")]
    DomainNotWritten { object: String, max: usize },

    #[error("{object} ({data_type}) takes {expected} bytes, got {actual}")]
    WrongByteCount {
        object: String,
        data_type: DataType,
        /// `4`, or `1 to 33` for strings.
        expected: String,
        actual: usize,
    },
}

fn unknown_unit(unit: &str, suggestions: &[String]) -> String {
    let known: Vec<&str> = Unit::symbols().collect();
    let mut text = format!("unknown unit `{unit}` (known units: {})", known.join(", "));
    if let Some(s) = suggestion_text(suggestions) {
        text.push_str("; ");
        text.push_str(&s);
    }
    text
}

fn unknown_measured_unit(unit: &str, suggestions: &[String]) -> String {
    let known: Vec<&str> = Unit::symbols().chain(Unit::MEASURED.map(Unit::symbol)).collect();
    let mut text = format!("unknown unit `{unit}` (known units: {})", known.join(", "));
    if let Some(s) = suggestion_text(suggestions) {
        text.push_str("; ");
        text.push_str(&s);
    }
    text
}

fn wrong_unit(unit: Unit, object: &str, object_unit: Option<Unit>) -> String {
    match object_unit {
        Some(u) => format!(
            "{unit} is not a unit of {object} ({u}): {unit} measures {}, {u} measures {}",
            unit.dimension().name(),
            u.dimension().name()
        ),
        None => format!("{unit} given, but {object} has no unit: give a plain number"),
    }
}

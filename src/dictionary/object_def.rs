//! One named object of a dictionary: address, type, unit and scale, access, limits, and
//! the conversions between engineering quantities and the bytes on the wire.
//! Pure arithmetic: it must not do I/O, and it knows nothing of transports or links.
//! Whether a write is allowed (`access`) is checked by the drive layer, not here.

use super::access::Access;
use super::address::Address;
use super::bench_cap::BenchCap;
use super::data_type::{DataType, MAX_BLOCK_LEN};
use super::file_entry::FileEntry;
use super::format::Format;
use super::pole_pairs::{is_speed_and_frequency, speed_frequency};
use super::quantity::Quantity;
use super::real::Real;
use super::unit::Unit;
use super::value::{decimals_of, format_number, RawValue, Value};
use super::value_error::ValueError;
use crate::diag::Span;

/// How many decimal places a decimal-text value is sent with.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum DecimalPlaces {
    /// The object's own (`decimals:` in the dictionary); the scale is 10^−places.
    Fixed(u8),
    /// As many as the value given has (`1500.5` is sent as `1500.5`, `3` as `3`): for an
    /// object named in the family's notation, whose places no dictionary gives. The scale
    /// is 1 and the drive judges the value.
    AsGiven,
}

#[derive(Debug, Clone)]
pub struct ObjectDef {
    /// The identifier recipes use: `[a-z][a-z0-9_]*`.
    pub name: String,
    /// Other names that find this object (the manual's, older ones); matched ignoring case.
    pub aliases: Vec<String>,
    pub address: Address,
    pub data_type: DataType,
    /// Engineering unit; `None` for raw counts and bit fields.
    pub unit: Option<Unit>,
    /// Engineering units per raw count (e.g. 0.001 for speeds counted in 0.001 rpm).
    pub scale: f64,
    /// Set for drives that carry values as decimal text (Control Techniques: `+1500.5`):
    /// values go to the drive as exact [`RawValue::Decimal`], never through a float.
    pub decimal_places: Option<DecimalPlaces>,
    pub access: Access,
    /// Limits in engineering units (tightened by the bench limits, see [`Self::bench`]).
    pub min: Option<f64>,
    pub max: Option<f64>,
    /// Set when a bench limits file tightened `min` or `max`: refusals then say so.
    pub bench: Option<BenchCap>,
    pub format: Format,
    pub description: String,
    /// Why the entry is not confirmed by a source (type, unit or index guessed or
    /// provided by the simulator); `None` when the sources give it.
    pub unconfirmed: Option<String>,
    /// A setting of the drive (`parameter: true`) that `backup` saves and `restore` writes
    /// back, as opposed to a live value (actual speed), a command or an identity.
    pub parameter: bool,
    /// What the device's own file (EDS/DCF) says of the object, and which fields of a
    /// built-in entry it replaced; `None` for an object only a YAML dictionary gives.
    pub file: Option<Box<FileEntry>>,
    /// The motor's pole pairs, on a speed object whose counts are an inverter's output
    /// frequency (its dictionary says `pole_pairs:`): then Hz converts to and from its rpm.
    pub pole_pairs: Option<u32>,
    /// Where the entry is defined (the `- name:` mapping).
    pub span: Span,
    /// Where the name and each alias are written (same order as [`ObjectDef::names`]);
    /// empty for objects built in code.
    pub(crate) name_spans: Vec<Span>,
}

impl ObjectDef {
    /// An object with scale 1, no unit, no limits, decimal display (for code and tests;
    /// dictionaries come from files).
    pub fn new(name: impl Into<String>, address: Address, data_type: DataType, access: Access) -> Self {
        ObjectDef {
            name: name.into(),
            aliases: Vec::new(),
            address,
            data_type,
            unit: None,
            scale: 1.0,
            decimal_places: None,
            access,
            min: None,
            max: None,
            bench: None,
            format: Format::Decimal,
            description: String::new(),
            unconfirmed: None,
            parameter: false,
            file: None,
            pole_pairs: None,
            span: Span::unknown(),
            name_spans: Vec::new(),
        }
    }

    /// Tightens the limits to `±cap` (in the object's unit) when that is narrower, and
    /// marks the sides the bench now decides. `origin` names the limits file.
    pub(crate) fn cap_at(&mut self, cap: f64, origin: &str) {
        let max = self.max.is_none_or(|m| cap <= m);
        let min = self.min.is_none_or(|m| -cap >= m);
        if max {
            self.max = Some(cap);
        }
        if min {
            self.min = Some(-cap);
        }
        if max || min {
            self.bench = Some(BenchCap {
                origin: origin.to_string(),
                max,
                min,
            });
        }
    }

    /// Where the `i`-th of [`ObjectDef::names`] is written (the object's span when unknown).
    pub(crate) fn name_span(&self, i: usize) -> &Span {
        self.name_spans.get(i).unwrap_or(&self.span)
    }

    /// `speed_actual (VCTRL_VELOCITY_ACTUAL_VALUE_UUNIT)`: the name and the first alias.
    pub fn display_name(&self) -> String {
        match self.aliases.first() {
            Some(alias) => format!("{} ({alias})", self.name),
            None => self.name.clone(),
        }
    }

    /// True when `name` is this object's name or one of its aliases, ignoring case.
    pub fn is_named(&self, name: &str) -> bool {
        self.names().any(|n| n.eq_ignore_ascii_case(name))
    }

    /// The name, then the aliases.
    pub fn names(&self) -> impl Iterator<Item = &str> {
        std::iter::once(self.name.as_str()).chain(self.aliases.iter().map(String::as_str))
    }

    pub fn readable(&self) -> bool {
        self.access.readable()
    }

    pub fn writable(&self) -> bool {
        self.access.writable()
    }

    /// Decimal places one count resolves in the object's unit (scale 0.001 → 3).
    pub fn decimals(&self) -> usize {
        decimals_of(self.scale)
    }

    /// The engineering value of a raw count: count × scale, computed as a division where
    /// the scale is 1/n so that 1003647 counts are exactly 1003.647 rpm.
    pub fn engineering(&self, counts: i64) -> f64 {
        self.engineering_of(counts as f64)
    }

    /// [`Self::engineering`] of a raw count or float.
    fn engineering_of(&self, raw: f64) -> f64 {
        match self.inverse_scale() {
            Some(n) => raw / n,
            None => raw * self.scale,
        }
    }

    /// Raw counts for an engineering value, rounded to the nearest count.
    fn counts_of(&self, value: f64) -> f64 {
        match self.inverse_scale() {
            Some(n) => (value * n).round(),
            None => (value / self.scale).round(),
        }
    }

    /// `n` when the scale is 1/n for a whole n.
    fn inverse_scale(&self) -> Option<f64> {
        let n = 1.0 / self.scale;
        let whole = n.round();
        (n >= 1.0 && (n - whole).abs() < 1e-9 * n).then_some(whole)
    }

    /// `60000 rpm`: a value in the object's unit, with the decimals a count resolves.
    pub(crate) fn with_unit(&self, value: f64) -> String {
        let number = format_number(value, self.decimals() + 3);
        match self.unit {
            Some(u) => format!("{number} {u}"),
            None => number,
        }
    }

    /// `value` given in `from` expressed in the object's own unit: within a dimension, and
    /// between Hz and rpm where the object knows the motor's pole pairs. The refusal says
    /// what is missing: the pole pairs for Hz on an rpm object, else the unit.
    pub fn in_own_unit(&self, value: f64, from: Unit) -> Result<f64, ValueError> {
        let Some(own) = self.unit else {
            return Err(ValueError::WrongUnit {
                unit: from,
                object: self.name.clone(),
                object_unit: None,
            });
        };
        if let Some(v) = from.convert(value, own) {
            return Ok(v);
        }
        match self.pole_pairs {
            Some(pairs) => speed_frequency(value, from, own, pairs),
            None if is_speed_and_frequency(from, own) => {
                return Err(ValueError::NoPolePairs {
                    unit: from,
                    object: self.name.clone(),
                    object_unit: own,
                })
            }
            None => None,
        }
        .ok_or_else(|| ValueError::WrongUnit {
            unit: from,
            object: self.name.clone(),
            object_unit: Some(own),
        })
    }

    /// How many of `to` one of the object's own unit is (`read_as(…, "Hz")`, a value shown
    /// in Hz); the same refusals as [`Self::in_own_unit`].
    pub fn factor_to(&self, to: Unit) -> Result<f64, ValueError> {
        // Where there is a plain conversion it is used as it stands (exact 0.001 for krpm).
        match self.unit.and_then(|own| own.convert(1.0, to)) {
            Some(factor) => Ok(factor),
            None => self.in_own_unit(1.0, to).map(|one| 1.0 / one),
        }
    }

    /// Converts an engineering quantity to the raw count to write: unit conversion within a
    /// dimension (a bare number is read in the object's unit, not as counts), scale,
    /// rounding to the nearest count. Refuses a value outside `[min, max]` or outside the
    /// type's range, saying the limit and its unit.
    pub fn to_raw(&self, quantity: &Quantity) -> Result<RawValue, ValueError> {
        let number_for_text = || ValueError::NumberForText {
            object: self.name.clone(),
            data_type: self.data_type,
        };
        if !self.data_type.is_number() {
            return Err(number_for_text());
        }
        let value = match (quantity.unit, self.unit) {
            (None, _) => quantity.value,
            (Some(given), _) => self.in_own_unit(quantity.value, given)?,
        };
        if !value.is_finite() {
            return Err(ValueError::NotANumber {
                text: quantity.to_string(),
                hint: ": not a finite number".into(),
            });
        }
        if let Some(single) = self.data_type.float_single() {
            return self.real_to_raw(quantity, value, single);
        }
        let Some((lo, hi)) = self.data_type.range() else {
            return Err(number_for_text());
        };
        // A whole number in the object's own unit at one count per unit is the count itself,
        // exactly (a 64-bit count a float cannot hold); anything else is converted, scaled
        // and rounded to the nearest count (a float beyond 128 bits saturates, beyond every
        // type's range all the same).
        let exact = self.exact_count(quantity);
        let counts = exact.unwrap_or_else(|| self.counts_of(value) as i128);
        let given = match (quantity.unit, self.unit, exact) {
            (Some(g), Some(own), _) if g != own => format!("{quantity} ({})", self.with_unit(value)),
            (_, _, Some(n)) => Quantity::integer(n, self.unit).to_string(),
            _ => self.with_unit(value),
        };
        let (above, below) = match exact {
            Some(n) => (
                self.max.filter(|max| !max.is_nan() && n > max.floor() as i128),
                self.min.filter(|min| !min.is_nan() && n < min.ceil() as i128),
            ),
            None => {
                let rounded = self.engineering(counts.clamp(i64::MIN.into(), i64::MAX.into()) as i64);
                let tolerance = self.scale * 1e-6;
                (
                    self.max.filter(|max| rounded > max + tolerance),
                    self.min.filter(|min| rounded < min - tolerance),
                )
            }
        };
        if let Some(max) = above {
            return Err(self.beyond(given, max, true));
        }
        if let Some(min) = below {
            return Err(self.beyond(given, min, false));
        }
        let in_range = i64::try_from(counts).ok().filter(|c| (lo..=hi).contains(c));
        let Some(count) = in_range else {
            return Err(ValueError::OutOfTypeRange {
                object: self.name.clone(),
                value: given,
                counts: counts.to_string(),
                data_type: self.data_type,
                range: self.range_text(lo, hi),
            });
        };
        Ok(match self.decimal_places {
            // Rounded to a whole count above, so the digits are exact: 1500.5 rpm with one
            // place is 15005 × 10⁻¹ and goes on the wire as `1500.5`.
            Some(DecimalPlaces::Fixed(places)) => RawValue::Decimal {
                digits: count,
                places,
            },
            Some(DecimalPlaces::AsGiven) => as_given(value).ok_or_else(|| ValueError::NotANumber {
                text: quantity.to_string(),
                hint: ": more digits than a decimal data field carries (at most 10 decimal places)".into(),
            })?,
            None => RawValue::Int(count),
        })
    }

    /// The count of a whole number given in the object's own unit (or bare) where one
    /// count is one unit (scale 1, as every EDS object): the number itself, exactly.
    fn exact_count(&self, quantity: &Quantity) -> Option<i128> {
        let own_unit = quantity.unit.is_none() || quantity.unit == self.unit;
        (self.scale == 1.0 && own_unit)
            .then(|| quantity.whole())
            .flatten()
    }

    /// The engineering quantity of a raw count: at scale 1 the count itself, exactly.
    fn quantity_of(&self, count: i64) -> Quantity {
        match self.scale == 1.0 {
            true => Quantity::integer(count.into(), self.unit),
            false => Quantity::new(self.engineering(count), self.unit),
        }
    }

    /// The type's range `lo..=hi` (in counts) in the object's unit, exact at scale 1, with
    /// the counts where they differ: `-2147483.648 rpm..=2147483.647 rpm
    /// (-2147483648..=2147483647 counts)`, `0..=72057594037927935`.
    fn range_text(&self, lo: i64, hi: i64) -> String {
        let shown = |count: i64| match self.scale == 1.0 {
            true => self.quantity_of(count).to_string(),
            false => self.with_unit(self.engineering(count)),
        };
        let mut range = format!("{}..={}", shown(lo), shown(hi));
        if self.unit.is_some() || self.scale != 1.0 {
            range.push_str(&format!(" ({lo}..={hi} counts)"));
        }
        range
    }

    /// A float object's raw value for `value` (in its unit, finite): value ÷ scale in the
    /// type's precision, nothing rounded to counts. The limits are compared with the value
    /// as it will be stored, exactly (an EDS gives them as floats).
    fn real_to_raw(&self, quantity: &Quantity, value: f64, single: bool) -> Result<RawValue, ValueError> {
        let in_own_unit = Quantity::new(value, self.unit);
        let given = match (quantity.unit, self.unit) {
            (Some(g), Some(own)) if g != own => format!("{quantity} ({in_own_unit})"),
            _ => in_own_unit.to_string(),
        };
        let real = Real::of(value / self.scale, single);
        let stored = self.engineering_of(real.value());
        if !stored.is_finite() {
            let max = Real::of(if single { f64::from(f32::MAX) } else { f64::MAX }, single);
            return Err(ValueError::BeyondFloat {
                object: self.name.clone(),
                value: given,
                data_type: self.data_type,
                max: max.to_string(),
            });
        }
        if let Some(max) = self.max.filter(|max| stored > *max) {
            return Err(self.beyond(given, max, true));
        }
        if let Some(min) = self.min.filter(|min| stored < *min) {
            return Err(self.beyond(given, min, false));
        }
        Ok(RawValue::Real(real))
    }

    /// The refusal of `value` beyond `limit`, above the maximum or below the minimum; it
    /// names the bench limits file when that set the limit.
    fn beyond(&self, value: String, limit: f64, above: bool) -> ValueError {
        let (object, limit) = (self.name.clone(), self.with_unit(limit));
        let bench = self.bench.as_ref().filter(|b| if above { b.max } else { b.min });
        let origin = bench.map(|b| b.origin.clone());
        match (origin, above) {
            (Some(origin), true) => ValueError::AboveBenchLimit {
                object,
                value,
                limit,
                origin,
            },
            (Some(origin), false) => ValueError::BelowBenchLimit {
                object,
                value,
                limit,
                origin,
            },
            (None, true) => ValueError::AboveMax { object, value, limit },
            (None, false) => ValueError::BelowMin { object, value, limit },
        }
    }

    /// Checks text for a string object (plain printable ASCII, at most the type's maximum),
    /// a UTF-16 one (any text of at most [`MAX_BLOCK_LEN`] bytes) or a byte string (hex,
    /// `01 0a ff`); a DOMAIN is never written.
    pub fn text_to_raw(&self, text: &str) -> Result<RawValue, ValueError> {
        let too_long = |len| ValueError::BlockTooLong {
            object: self.name.clone(),
            data_type: self.data_type,
            len,
            max: MAX_BLOCK_LEN,
        };
        let max = match self.data_type {
            DataType::String { max } => max,
            DataType::Unicode => {
                let len = 2 * text.encode_utf16().count();
                return match len <= MAX_BLOCK_LEN {
                    true => Ok(RawValue::Text(text.to_string())),
                    false => Err(too_long(len)),
                };
            }
            DataType::Octets => {
                let bytes = crate::hex::parse_hex(text).map_err(|e| ValueError::NotHexBytes {
                    object: self.name.clone(),
                    why: e.to_string(),
                })?;
                return match bytes.len() <= MAX_BLOCK_LEN {
                    true => Ok(RawValue::Bytes(bytes)),
                    false => Err(too_long(bytes.len())),
                };
            }
            DataType::Domain => {
                return Err(ValueError::DomainNotWritten {
                    object: self.name.clone(),
                    max: MAX_BLOCK_LEN,
                })
            }
            _ => {
                return Err(ValueError::TextForNumber {
                    object: self.name.clone(),
                    data_type: self.data_type,
                })
            }
        };
        if let Some(found) = text.chars().find(|c| !(c.is_ascii_graphic() || *c == ' ')) {
            return Err(ValueError::TextNotAscii {
                object: self.name.clone(),
                found,
            });
        }
        let len = text.chars().count();
        if len > usize::from(max) {
            return Err(ValueError::TextTooLong {
                object: self.name.clone(),
                len,
                max,
            });
        }
        Ok(RawValue::Text(text.to_string()))
    }

    /// The value as the drive holds it, read with the object's type, scale and unit. A raw
    /// value of the wrong kind (text for a number, or the reverse) is refused.
    pub fn value_of(&self, raw: RawValue) -> Result<Value, ValueError> {
        let width = self.data_type.size();
        let is_text = !self.data_type.is_number();
        let quantity = self.quantity_of_raw(&raw)?;
        let decimals = match raw {
            RawValue::Decimal { places, .. } => usize::from(places),
            _ if is_text => 0,
            _ => self.decimals(),
        };
        let format = if is_text { Format::Decimal } else { self.format };
        Ok(Value {
            raw,
            quantity,
            format,
            width,
            decimals,
        })
    }

    /// The quantity of [`Self::value_of`] alone (`None` for text), for readers that want
    /// only the number: a sample of millions needs no digits or format.
    pub fn quantity_of_raw(&self, raw: &RawValue) -> Result<Option<Quantity>, ValueError> {
        let is_text = !self.data_type.is_number();
        Ok(match (raw, is_text) {
            (RawValue::Text(_) | RawValue::Bytes(_), true) => None,
            (RawValue::Int(count), false) => Some(self.quantity_of(*count)),
            // NaN and infinities stay what they are: shown as such, never a limit passed.
            (RawValue::Real(r), false) => Some(Quantity::new(self.engineering_of(r.value()), self.unit)),
            // Drives that send decimal text carry the value itself, not a count.
            (RawValue::Decimal { digits, places }, false) => Some(Quantity::new(
                *digits as f64 / 10f64.powi(i32::from(*places)),
                self.unit,
            )),
            (RawValue::Text(_) | RawValue::Bytes(_), false) => {
                return Err(ValueError::TextForNumber {
                    object: self.name.clone(),
                    data_type: self.data_type,
                })
            }
            (_, true) => {
                return Err(ValueError::NumberForText {
                    object: self.name.clone(),
                    data_type: self.data_type,
                })
            }
        })
    }
}

/// The decimal a value was written as: Rust prints the shortest text that reads back as
/// the same float, which for a number typed with a few decimals is that number.
fn as_given(value: f64) -> Option<RawValue> {
    let text = format!("{value}");
    let (whole, frac) = text.split_once('.').unwrap_or((&text, ""));
    let places = u8::try_from(frac.len()).ok().filter(|p| *p <= 10)?;
    let digits: i64 = format!("{whole}{frac}").parse().ok()?;
    Some(RawValue::Decimal { digits, places })
}

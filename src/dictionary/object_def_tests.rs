//! The conversions of [`ObjectDef`] between engineering quantities, counts and the raw
//! values on the wire: units, scale, limits, type ranges, floats, decimals and text.

use super::object_def::*;
use super::{Access, Address, DataType, Quantity, RawValue, Real, Unit, ValueError};
use proptest::prelude::*;

/// An i32 object counting thousandths of `unit`.
fn milli(name: &str, index: u16, access: Access, unit: Unit) -> ObjectDef {
    let mut o = ObjectDef::new(name, Address::indexed(index, 0), DataType::I32, access);
    o.unit = Some(unit);
    o.scale = 0.001;
    o
}

fn control_word() -> ObjectDef {
    ObjectDef::new(
        "control_word",
        Address::indexed(68, 0),
        DataType::U16,
        Access::ReadWrite,
    )
}

fn speed_setpoint() -> ObjectDef {
    let mut o = milli("speed_setpoint", 395, Access::ReadWrite, Unit::Rpm);
    o.min = Some(-60000.0);
    o.max = Some(60000.0);
    o
}

fn refused(o: &ObjectDef, text: &str) -> ValueError {
    o.to_raw(&Quantity::parse(text).unwrap()).unwrap_err()
}

fn counts_for(o: &ObjectDef, text: &str) -> RawValue {
    o.to_raw(&Quantity::parse(text).unwrap()).unwrap()
}

#[test]
fn floats_are_written_as_the_nearest_float_and_read_as_they_are() {
    let mut gain = ObjectDef::new(
        "gain",
        Address::indexed(0x2100, 0),
        DataType::F32,
        Access::ReadWrite,
    );
    gain.unit = Some(Unit::Rpm);
    gain.scale = 0.5;
    gain.min = Some(0.0);
    gain.max = Some(100.0);
    // 2.75 rpm at 0.5 rpm per raw unit is the float 5.5, exactly.
    assert_eq!(
        counts_for(&gain, "2.75 rpm"),
        RawValue::Real(Real::Single(5.5f32.to_bits()))
    );
    assert_eq!(
        counts_for(&gain, "1.1"),
        RawValue::Real(Real::Single(2.2f32.to_bits())),
        "not rounded to counts"
    );
    assert!(matches!(refused(&gain, "100.5 rpm"), ValueError::AboveMax { .. }));
    assert!(matches!(refused(&gain, "-1 rpm"), ValueError::BelowMin { .. }));
    let huge = ObjectDef::new(
        "huge",
        Address::indexed(0x2101, 0),
        DataType::F32,
        Access::ReadWrite,
    );
    let e = refused(&huge, "1e39").to_string();
    assert_eq!(e, "1e39 is beyond the largest f32 of huge, ±3.4028235e38");
    let v = gain
        .value_of(RawValue::Real(Real::Single(5.5f32.to_bits())))
        .unwrap();
    assert_eq!((v.number(), v.to_string()), (Some(2.75), "2.75 rpm".to_string()));
    let nan = gain
        .value_of(RawValue::Real(Real::Single(f32::NAN.to_bits())))
        .unwrap();
    assert_eq!(nan.to_string(), "NaN rpm");
    assert!(nan.number().is_some_and(f64::is_nan));
    let inf = huge
        .value_of(RawValue::Real(Real::Single(f32::NEG_INFINITY.to_bits())))
        .unwrap();
    assert_eq!(inf.to_string(), "-inf");
    assert!(matches!(
        gain.text_to_raw("x"),
        Err(ValueError::TextForNumber { .. })
    ));
    assert!(huge.value_of(RawValue::Text("x".into())).is_err());
}

#[test]
fn bytes_and_utf16_text_and_domains() {
    let obj = |t| ObjectDef::new("key", Address::indexed(0x2104, 0), t, Access::ReadWrite);
    assert_eq!(
        obj(DataType::Octets).text_to_raw("ca fe"),
        Ok(RawValue::Bytes(vec![0xca, 0xfe]))
    );
    let e = obj(DataType::Octets)
        .text_to_raw("cafez")
        .unwrap_err()
        .to_string();
    assert!(
        e.starts_with("key holds bytes, written as hex such as `01 0a ff`"),
        "{e}"
    );
    let long = "00 ".repeat(257);
    assert!(matches!(
        obj(DataType::Octets).text_to_raw(&long),
        Err(ValueError::BlockTooLong {
            len: 257,
            max: 256,
            ..
        })
    ));
    assert_eq!(
        obj(DataType::Unicode).text_to_raw("Motör"),
        Ok(RawValue::Text("Motör".into()))
    );
    let e = obj(DataType::Domain).text_to_raw("00").unwrap_err().to_string();
    assert!(e.contains("is a DOMAIN") && e.contains("never writes it"), "{e}");
    assert!(matches!(
        obj(DataType::Octets).to_raw(&Quantity::parse("1").unwrap()),
        Err(ValueError::NumberForText { .. })
    ));
    let v = obj(DataType::Octets)
        .value_of(RawValue::Bytes(vec![1, 0xff]))
        .unwrap();
    assert_eq!((v.to_string(), v.number()), ("01 ff".to_string(), None));
}

#[test]
fn speeds_to_counts() {
    let o = speed_setpoint();
    let c = RawValue::Int;
    assert_eq!(counts_for(&o, "1000 rpm"), c(1_000_000));
    assert_eq!(counts_for(&o, "6000 rpm"), c(6_000_000));
    assert_eq!(counts_for(&o, "6500 rpm"), c(6_500_000));
    assert_eq!(counts_for(&o, "18000 rpm"), c(18_000_000));
    assert_eq!(counts_for(&o, "6 krpm"), c(6_000_000));
    assert_eq!(counts_for(&o, "6000"), c(6_000_000), "a bare number is in rpm");
    assert_eq!(counts_for(&o, "-3000 rpm"), c(-3_000_000));
    assert_eq!(counts_for(&o, "0.0004 rpm"), c(0), "rounds to the nearest count");
    assert_eq!(counts_for(&o, "0.0005 rpm"), c(1));
    assert_eq!(
        counts_for(&o, "60000 rpm"),
        c(60_000_000),
        "the limit itself is allowed"
    );
}

#[test]
fn limits_are_refused_with_the_limit_and_unit() {
    let o = speed_setpoint();
    for (given, refusal) in [
        (
            "70000 rpm",
            "70000 rpm is above the maximum of speed_setpoint, 60000 rpm",
        ),
        (
            "-61 krpm",
            "-61 krpm (-61000 rpm) is below the minimum of speed_setpoint, -60000 rpm",
        ),
    ] {
        assert_eq!(refused(&o, given).to_string(), refusal);
    }
}

#[test]
fn bench_caps_tighten_and_say_so() {
    let mut o = speed_setpoint();
    o.cap_at(6000.0, "limits file /x/drivescript-limits.yaml");
    assert_eq!((o.min, o.max), (Some(-6000.0), Some(6000.0)));
    let e = refused(&o, "6500 rpm");
    assert_eq!(
        e.to_string(),
        "6500 rpm exceeds the bench limit 6000 rpm of speed_setpoint (limits file /x/drivescript-limits.yaml)"
    );
    let e = refused(&o, "-6.5 krpm");
    assert!(
        e.to_string()
            .starts_with("-6.5 krpm (-6500 rpm) is below the bench limit -6000 rpm"),
        "{e}"
    );
    assert!(o.to_raw(&Quantity::parse("6000 rpm").unwrap()).is_ok());
    // A cap wider than the object's own limits changes nothing.
    let mut o = speed_setpoint();
    o.cap_at(70000.0, "limits file b.yaml");
    assert_eq!(
        (o.min, o.max, o.bench.is_none()),
        (Some(-60000.0), Some(60000.0), true)
    );
    // Only the side the cap tightens is the bench's.
    let mut o = speed_setpoint();
    o.min = Some(0.0);
    o.cap_at(6000.0, "limits file b.yaml");
    assert_eq!((o.min, o.max), (Some(0.0), Some(6000.0)));
    let e = refused(&o, "-1 rpm");
    assert!(matches!(e, ValueError::BelowMin { .. }), "{e}");
}

#[test]
fn type_range_is_refused_with_the_range_in_units() {
    let mut o = speed_setpoint();
    o.min = None;
    o.max = None;
    let e = refused(&o, "3000000 rpm");
    assert_eq!(
        e.to_string(),
        "3000000 rpm is 3000000000 counts, outside the range of speed_setpoint's type i32: \
         -2147483.648 rpm..=2147483.647 rpm (-2147483648..=2147483647 counts)"
    );
    let cw = control_word();
    let e = cw.to_raw(&Quantity::new(-1.0, None)).unwrap_err();
    assert_eq!(
        e.to_string(),
        "-1 is -1 counts, outside the range of control_word's type u16: 0..=65535"
    );
    assert_eq!(
        cw.to_raw(&Quantity::parse("0x0F").unwrap()),
        Ok(RawValue::Int(15))
    );
}

#[test]
fn wrong_units_are_refused() {
    let current = milli("current_actual", 400, Access::ReadOnly, Unit::Ampere);
    let e = refused(&current, "6000 rpm");
    assert!(
        e.to_string()
            .starts_with("rpm is not a unit of current_actual (A)"),
        "{e}"
    );
    assert_eq!(
        current.to_raw(&Quantity::parse("1500 mA").unwrap()),
        Ok(RawValue::Int(1500))
    );
    let cw = control_word();
    let e = refused(&cw, "6 rpm");
    assert_eq!(
        e.to_string(),
        "rpm given, but control_word has no unit: give a plain number"
    );
    assert!(cw.to_raw(&Quantity::new(f64::NAN, None)).is_err());
}

fn ident() -> ObjectDef {
    ObjectDef::new(
        "ident",
        Address::indexed(22, 0),
        DataType::String { max: 32 },
        Access::ReadOnly,
    )
}

#[test]
fn raw_values_read_with_type_scale_and_unit() {
    let v = speed_setpoint().value_of(RawValue::Int(1_003_647)).unwrap();
    assert_eq!(v.to_string(), "1003.647 rpm");
    assert_eq!(v.number(), Some(1003.647));
    let t = ident().value_of(RawValue::Text("Test Motor".into())).unwrap();
    assert_eq!(t.to_string(), "\"Test Motor\"");
    let d = speed_setpoint()
        .value_of(RawValue::Decimal {
            digits: 15005,
            places: 1,
        })
        .unwrap();
    assert_eq!(d.to_string(), "1500.5 rpm");
    assert!(speed_setpoint().value_of(RawValue::Text("x".into())).is_err());
    assert!(ident().value_of(RawValue::Int(1)).is_err());
}

#[test]
fn text_values() {
    assert_eq!(
        ident().text_to_raw("Spindle 1"),
        Ok(RawValue::Text("Spindle 1".into()))
    );
    assert!(matches!(
        ident().text_to_raw(&"x".repeat(33)),
        Err(ValueError::TextTooLong { len: 33, max: 32, .. })
    ));
    assert!(matches!(
        ident().text_to_raw("Motör"),
        Err(ValueError::TextNotAscii { found: 'ö', .. })
    ));
    assert!(matches!(
        speed_setpoint().text_to_raw("fast"),
        Err(ValueError::TextForNumber { .. })
    ));
    assert!(matches!(
        ident().to_raw(&Quantity::new(1.0, None)),
        Err(ValueError::NumberForText { .. })
    ));
}

#[test]
fn access_helpers() {
    assert!(speed_setpoint().writable() && speed_setpoint().readable());
    assert!(!ident().writable() && ident().readable());
}

fn decimal_speed() -> ObjectDef {
    let mut o = speed_setpoint();
    o.scale = 0.1;
    o.decimal_places = Some(DecimalPlaces::Fixed(1));
    o
}

#[test]
fn values_as_given_keep_the_decimals_typed() {
    let mut o = ObjectDef::new("#1.21", Address::indexed(1, 21), DataType::I32, Access::ReadWrite);
    o.decimal_places = Some(DecimalPlaces::AsGiven);
    let d = |digits, places| RawValue::Decimal { digits, places };
    assert_eq!(counts_for(&o, "1500.5"), d(15005, 1));
    assert_eq!(counts_for(&o, "-34.55"), d(-3455, 2));
    assert_eq!(counts_for(&o, "131"), d(131, 0));
    assert!(o.to_raw(&Quantity::parse("0.000000000001").unwrap()).is_err());
}

#[test]
fn decimal_objects_convert_exactly() {
    let o = decimal_speed();
    let d = |digits, places| RawValue::Decimal { digits, places };
    assert_eq!(counts_for(&o, "1500.5 rpm"), d(15005, 1));
    assert_eq!(counts_for(&o, "1500.5 rpm").to_string(), "1500.5");
    assert_eq!(counts_for(&o, "-34.5"), d(-345, 1));
    assert_eq!(counts_for(&o, "1500.3 rpm").to_string(), "1500.3");
    assert_eq!(counts_for(&o, "1.5 krpm"), d(15000, 1));
    let v = o.value_of(d(15005, 1)).unwrap();
    assert_eq!(v.to_string(), "1500.5 rpm");
}

proptest! {
    #[test]
    fn decimal_text_round_trips_exactly(tenths in -600_000i64..=600_000) {
        let o = decimal_speed();
        let text = RawValue::Decimal { digits: tenths, places: 1 }.to_string();
        let raw = o.to_raw(&Quantity::parse(&text).unwrap()).unwrap();
        prop_assert_eq!(raw.to_string(), text);
    }

    #[test]
    fn to_raw_value_of_round_trip_within_one_count(v in -60000.0f64..=60000.0) {
        let o = speed_setpoint();
        let raw = o.to_raw(&Quantity::new(v, Some(Unit::Rpm))).unwrap();
        let back = o.value_of(raw.clone()).unwrap().number().unwrap();
        prop_assert!((back - v).abs() <= o.scale, "{} → {:?} → {}", v, raw, back);
    }

    #[test]
    fn round_trip_every_integer_type(t in 0usize..6, count in any::<i64>(), scale in prop::sample::select(vec![1.0, 0.1, 0.001, 0.25, 2.0])) {
        let data_type = DataType::INTEGERS[t];
        let (lo, hi) = data_type.range().unwrap();
        let count = lo + (count.rem_euclid(hi - lo + 1));
        let mut o = ObjectDef::new("x", Address::indexed(1, 0), data_type, Access::ReadWrite);
        o.scale = scale;
        o.unit = Some(Unit::Volt);
        let value = o.engineering(count);
        let raw = o.to_raw(&Quantity::new(value, Some(Unit::Volt))).unwrap();
        prop_assert_eq!(raw, RawValue::Int(count));
    }
}

/// The EDS integer types wider than a float's 53 bits, as an EDS gives them: scale 1.
const WIDE: [DataType; 6] = [
    DataType::I64,
    DataType::U64,
    DataType::int(7, true),
    DataType::int(7, false),
    DataType::int(6, true),
    DataType::int(6, false),
];

fn wide(data_type: DataType) -> ObjectDef {
    ObjectDef::new(
        "counter",
        Address::indexed(0x2107, 0),
        data_type,
        Access::ReadWrite,
    )
}

/// Every end of every wide type is written and shown to the unit, and one count beyond is
/// refused with the exact count and range: i64::MIN, 2^63 − 1 for u64 (as far as counts go
/// here), −2^55 and 2^56 − 1.
#[test]
fn wide_integers_are_exact_at_both_ends_of_their_type() {
    let u56 = DataType::int(7, false);
    let i56 = DataType::int(7, true);
    for (data_type, end) in [
        (DataType::I64, i64::MIN),
        (DataType::I64, i64::MAX),
        (DataType::U64, i64::MAX),
        (DataType::U64, 0),
        (u56, (1 << 56) - 1),
        (i56, -(1 << 55)),
        (i56, (1 << 55) - 1),
        (DataType::U64, (1 << 53) + 1),
    ] {
        let o = wide(data_type);
        let text = end.to_string();
        assert_eq!(counts_for(&o, &text), RawValue::Int(end), "{data_type}: {text}");
        let shown = o.value_of(RawValue::Int(end)).unwrap();
        assert_eq!(shown.to_string(), text);
        assert_eq!(shown.quantity.and_then(|q| q.whole()), Some(end.into()));
    }
    let beyond = |data_type, text: &str| refused(&wide(data_type), text).to_string();
    assert_eq!(
        beyond(u56, "72057594037927936"),
        "72057594037927936 is 72057594037927936 counts, outside the range of counter's type u56: 0..=72057594037927935"
    );
    assert_eq!(
        beyond(i56, "-36028797018963969"),
        "-36028797018963969 is -36028797018963969 counts, outside the range of counter's type i56: -36028797018963968..=36028797018963967"
    );
    assert_eq!(
        beyond(DataType::U64, "9223372036854775808"),
        "9223372036854775808 is 9223372036854775808 counts, outside the range of counter's type u64: 0..=9223372036854775807"
    );
    assert!(beyond(DataType::I64, "-9223372036854775809").contains("-9223372036854775809 counts"));
    assert!(beyond(DataType::U64, "18446744073709551615").contains("outside the range"));
    // Written as a float beyond 2^63 (no exact integer given), refused all the same, never
    // sent saturated.
    assert!(beyond(DataType::U64, "9.223372036854775808e18").contains("outside the range"));
}

/// Limits of a wide object compare with its count exactly; a fraction is rounded to the
/// nearest count as ever.
#[test]
fn wide_limits_compare_exactly() {
    let mut o = wide(DataType::I64);
    o.max = Some(9_007_199_254_740_992.0);
    o.min = Some(-10.5);
    assert_eq!(counts_for(&o, "9007199254740992"), RawValue::Int(1 << 53));
    let e = refused(&o, "9007199254740993").to_string();
    assert_eq!(
        e,
        "9007199254740993 is above the maximum of counter, 9007199254740992"
    );
    assert_eq!(counts_for(&o, "-10"), RawValue::Int(-10));
    assert!(matches!(refused(&o, "-11"), ValueError::BelowMin { .. }));
    assert_eq!(counts_for(&o, "2.5"), RawValue::Int(3));
}

proptest! {
    /// Any count of a wide type goes from its text to the same count, and back to the
    /// same text; the next count beyond either end is refused.
    #[test]
    fn wide_counts_round_trip_exactly(t in 0usize..WIDE.len(), count in any::<i64>()) {
        let data_type = WIDE[t];
        let (lo, hi) = data_type.range().unwrap();
        let span = i128::from(hi) - i128::from(lo) + 1;
        let count = (i128::from(lo) + i128::from(count).rem_euclid(span)) as i64;
        let o = wide(data_type);
        prop_assert_eq!(o.to_raw(&Quantity::parse(&count.to_string()).unwrap()), Ok(RawValue::Int(count)));
        prop_assert_eq!(o.value_of(RawValue::Int(count)).unwrap().to_string(), count.to_string());
        let below = i128::from(lo) - 1;
        let above = i128::from(hi) + 1;
        prop_assert!(o.to_raw(&Quantity::parse(&below.to_string()).unwrap()).is_err());
        prop_assert!(o.to_raw(&Quantity::parse(&above.to_string()).unwrap()).is_err());
    }
}

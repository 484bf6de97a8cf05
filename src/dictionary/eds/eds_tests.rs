//! The EDS reader on files written for the tests from CiA 306 (`tests/eds/`): every data
//! and access type, `$NODEID`, CompactSubObj, a RECORD, object links, malformed lines, and
//! no panic on any text.

use super::{eds_objects, EdsFile};
use crate::diag::{Diagnostics, Source};
use crate::dictionary::{Access, Address, DataType, Dictionary, Format};
use proptest::prelude::*;
use std::collections::HashSet;

fn base() -> Dictionary {
    Dictionary::from_yaml(
        "base.yaml",
        "family: canopen\nobjects:\n  - name: status_word\n    index: 0x6041\n    type: u16\n    access: ro\n",
    )
    .unwrap()
}

fn every_type() -> Dictionary {
    let mut d = base();
    let path = concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/every-type.dcf");
    d.extend_from(path).unwrap();
    d
}

#[test]
fn every_carried_type_and_access_type_becomes_an_object() {
    let d = every_type();
    let o = |name: &str| d.get(name).unwrap_or_else(|| panic!("{name}"));
    let t = |name: &str| (o(name).data_type, o(name).access);
    assert_eq!(t("flag"), (DataType::U8, Access::ReadWrite));
    assert_eq!((o("flag").min, o("flag").max), (Some(0.0), Some(1.0)));
    assert_eq!(t("small_signed"), (DataType::I8, Access::ReadWrite));
    assert_eq!(t("medium_signed"), (DataType::I16, Access::ReadWrite));
    assert_eq!(t("large_signed"), (DataType::I32, Access::WriteOnly));
    assert_eq!(t("small_unsigned"), (DataType::U8, Access::ReadWrite));
    assert_eq!(t("medium_unsigned"), (DataType::U16, Access::ReadWrite));
    assert_eq!(t("large_unsigned"), (DataType::U32, Access::ReadWrite));
    assert_eq!(t("signed_64"), (DataType::I64, Access::ReadWrite));
    assert_eq!(t("unsigned_64"), (DataType::U64, Access::ReadWrite));
    assert_eq!(t("device_name"), (DataType::String { max: 47 }, Access::ReadOnly));
    assert_eq!(
        t("identity_object_highest_sub_index_supported").1,
        Access::ReadOnly
    );
    assert_eq!(
        (o("small_signed").min, o("small_signed").max),
        (Some(-100.0), Some(100.0))
    );
    // HighLimit=017 is octal.
    assert_eq!(o("small_unsigned").max, Some(15.0));
    assert!(o("device_name").description.contains("default every type"));
    assert_eq!(o("device_type").format, Format::Hex);
}

#[test]
fn names_aliases_records_and_links() {
    let d = every_type();
    let vendor = d.get("identity_object_vendor_id").unwrap();
    assert_eq!(vendor.address, Address::indexed(0x1018, 1));
    assert_eq!(d.get("0x1018/2").unwrap().name, "identity_object_product_code");
    assert_eq!(
        d.get("Identity object/Product code").unwrap().address,
        Address::indexed(0x1018, 2)
    );
    assert_eq!(d.get("0x1000").unwrap().name, "device_type");
    assert_eq!(d.get("Device type").unwrap().name, "device_type");
    // Two objects called Reserved: the second gets its index.
    assert_eq!(d.get("reserved").unwrap().address, Address::indexed(0x2101, 0));
    assert_eq!(
        d.get("reserved_2102").unwrap().address,
        Address::indexed(0x2102, 0)
    );
    // The dictionary's own status_word is kept; the EDS's Controlword is added.
    // An object the dictionary has already gains the EDS's index and name as aliases.
    assert_eq!(d.get("0x6041").unwrap().name, "status_word");
    assert_eq!(d.get("Statusword").unwrap().name, "status_word");
    assert_eq!(
        d.objects()
            .filter(|o| o.address == Address::indexed(0x6041, 0))
            .count(),
        1
    );
    assert_eq!(d.get("controlword").unwrap().address, Address::indexed(0x2200, 0));
    assert!(d
        .get("linked")
        .unwrap()
        .description
        .contains("linked with 0x2100, 0x2005"));
    assert!(
        !d.get("controlword").unwrap().parameter,
        "PDO-mapped process data"
    );
    assert!(d.get("producer_heartbeat_time").unwrap().parameter);
}

#[test]
fn compact_sub_objects_node_id_and_parameter_values() {
    let d = every_type();
    let count = d.get("0x2100/0").unwrap();
    assert_eq!((count.data_type, count.access), (DataType::U8, Access::ReadOnly));
    assert_eq!(
        d.get("gains_proportional").unwrap().address,
        Address::indexed(0x2100, 1)
    );
    assert_eq!(d.get("gains_integral").unwrap().data_type, DataType::U16);
    assert_eq!(
        d.get("gains_gains3").unwrap().address,
        Address::indexed(0x2100, 3)
    );
    // $NODEID+0x80 with the DCF's node id 5.
    let emcy = d.get("cob_id_emcy").unwrap();
    assert_eq!((emcy.min, emcy.max), (Some(133.0), Some(133.0)));
    let mut out = Diagnostics::new();
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/every-type.dcf")).unwrap();
    let file = EdsFile::parse(&Source::new("every-type.dcf", text), &mut out);
    assert!(out.is_empty());
    assert_eq!(file.node_id, Some(5));
    let objects = eds_objects(&file, &HashSet::new(), &HashSet::new(), &|_| None);
    assert!(objects
        .parameter_values
        .contains(&("producer_heartbeat_time".into(), "250".into())));
    assert!(objects
        .parameter_values
        .contains(&("gains_integral".into(), "20".into())));
}

#[test]
fn every_basic_type_is_carried_in_its_own_width() {
    let d = every_type();
    let t = |name: &str| d.get(name).unwrap_or_else(|| panic!("{name}")).data_type;
    let int = DataType::int;
    assert_eq!(t("signed_24"), int(3, true));
    assert_eq!(t("signed_40"), int(5, true));
    assert_eq!(t("signed_48"), int(6, true));
    assert_eq!(t("signed_56"), int(7, true));
    assert_eq!(t("unsigned_24"), int(3, false));
    assert_eq!(t("unsigned_40"), int(5, false));
    assert_eq!(t("unsigned_48"), int(6, false));
    assert_eq!(t("unsigned_56"), int(7, false));
    assert_eq!(t("real_value"), DataType::F32);
    assert_eq!(t("real_64"), DataType::F64);
    assert_eq!(t("octets"), DataType::Octets);
    assert_eq!(t("unicode"), DataType::Unicode);
    assert_eq!(t("program"), DataType::Domain);
    // Limits of a REAL are floats; an integer's are clamped to its width.
    let real = d.get("real_value").unwrap();
    assert_eq!((real.min, real.max), (Some(-3.4e38), Some(1500.0)));
    assert_eq!(real.format, Format::Decimal);
    let signed_24 = d.get("signed_24").unwrap();
    assert_eq!(
        (signed_24.min, signed_24.max),
        (Some(-8_388_608.0), Some(8_388_607.0))
    );
    // A DOMAIN is read, never a parameter to restore.
    assert!(!d.get("program").unwrap().parameter);
    assert!(d.get("octets").unwrap().parameter && real.parameter);
}

#[test]
fn a_type_not_carried_is_left_out_with_a_note_at_its_entry() {
    let d = every_type();
    assert!(d.get("time_of_day").is_none());
    let note = d
        .notes()
        .iter()
        .find(|n| n.message().contains("0x200C"))
        .unwrap_or_else(|| panic!("{:?}", d.notes()));
    assert!(
        note.message().contains(
            "left out: 0x200C (TIME_OF_DAY (0x000C) is not one of the basic types drivescript carries"
        ),
        "{}",
        note.message()
    );
    let text =
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/every-type.dcf")).unwrap();
    let line = text.lines().position(|l| l == "[200C]").unwrap() + 1;
    assert_eq!(note.line(), line, "located at the entry's section");
}

#[test]
fn a_dcfs_floats_and_bytes_are_parameter_values_in_their_shortest_text() {
    let source = crate::diag::Source::new(
        "every-type.dcf",
        std::fs::read_to_string(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/every-type.dcf")).unwrap(),
    );
    let values = super::dcf_parameter_values(&source).unwrap();
    let value = |index: &str| values.iter().find(|(i, _)| i == index).map(|(_, v)| v.as_str());
    assert_eq!(value("0x2007"), Some("1.25"));
    assert_eq!(value("0x2011"), Some("0.1"));
    assert_eq!(value("0x2013"), Some("-2"));
    assert_eq!(value("0x2009"), Some("0a 0b"));
    assert_eq!(value("0x200F"), None, "a DOMAIN is no parameter");
    let bad = crate::diag::Source::new(
        "bad.dcf",
        "[FileInfo]\nFileName=bad.dcf\n[2000]\nParameterName=Gain\nDataType=0x0008\nAccessType=rw\nParameterValue=1,5\n",
    );
    let problems = super::dcf_parameter_values(&bad).unwrap_err();
    let first = problems.iter().next().unwrap();
    assert!(first
        .message()
        .contains("`ParameterValue=1,5` is not a number; a REAL32 value is a decimal"));
    assert_eq!(first.line(), 3);
}

#[test]
fn node_id_limits_without_a_node_are_left_off_with_a_note() {
    let text = "[FileInfo]\nFileName=x.eds\n[1014]\nParameterName=COB-ID EMCY\nDataType=0x0007\nAccessType=rw\nLowLimit=$NODEID+0x80\n";
    let mut out = Diagnostics::new();
    let file = EdsFile::parse(&Source::new("x.eds", text), &mut out);
    let objects = eds_objects(&file, &HashSet::new(), &HashSet::new(), &|_| None);
    assert_eq!(objects.objects[0].min, None);
    assert!(objects.notes[0]
        .message()
        .contains("$NODEID are left off for 0x1014"));
}

fn canopen_with(file: &str) -> Dictionary {
    let mut d = crate::family::Registry::builtin()
        .load_dictionary("canopen")
        .expect("the built-in canopen dictionary");
    d.extend_from(format!("{}/tests/eds/{file}", env!("CARGO_MANIFEST_DIR")))
        .unwrap_or_else(|e| panic!("{e}"));
    d
}

#[test]
fn the_devices_file_wins_over_the_built_in_entry_which_keeps_name_unit_and_scale() {
    let d = canopen_with("servo-limits.eds");
    let speed = d.get("speed_setpoint").unwrap();
    assert_eq!((speed.min, speed.max), (Some(-5000.0), Some(5000.0)));
    assert_eq!(speed.unit, Some(crate::dictionary::Unit::Rpm));
    let line = speed.file.as_ref().unwrap().overrides_line().unwrap();
    assert!(
        line.contains("min -5000 (built-in -60000); max 5000 (built-in 60000)"),
        "{line}"
    );
    let refused = speed.to_raw(&crate::dictionary::Quantity::new(10000.0, None));
    assert!(refused.is_err(), "{refused:?}");
    let modes = d.get("modes_of_operation").unwrap();
    assert_eq!(modes.access, Access::WriteOnly);
    let actual = d.get("speed_actual").unwrap();
    assert_eq!(actual.data_type, DataType::I16);
    assert_eq!(actual.name, "speed_actual", "the built-in name stays");
    // Hex limits of signed types are two's complement at the type's width.
    let wide = d.get("wide").unwrap();
    assert_eq!(
        (wide.min, wide.max),
        (Some(-2_147_483_648.0), Some(2_147_483_647.0))
    );
    assert_eq!(d.get("wide64").unwrap().min, Some(-10.0));
    // A TIME_OF_DAY object is listed as one drivescript cannot access, not dropped.
    let listed: Vec<&str> = d.not_accessible().iter().map(|f| f.name.as_str()).collect();
    assert_eq!(listed, ["Clock"]);
    assert_eq!(d.not_accessible()[0].type_name, "TIME_OF_DAY (0x000C)");
    // 0x1012 is listed in [OptionalObjects] without its section: a note at its line.
    let note = d
        .notes()
        .iter()
        .find(|n| n.message().contains("0x1012"))
        .unwrap_or_else(|| panic!("{:?}", d.notes()));
    assert_eq!(note.line(), 15);
}

#[test]
fn a_file_in_windows_1252_is_read_with_a_note_saying_so_once() {
    let dir = std::env::temp_dir().join(format!("drivescript-eds-1252-{}", std::process::id()));
    std::fs::create_dir_all(&dir).unwrap();
    let path = dir.join("cp1252.eds");
    // 0x94 is a closing quote and 0xB0 a degree sign in Windows-1252, neither UTF-8.
    let mut bytes = b"[FileInfo]\nFileName=cp1252.eds\n[2000]\nParameterName=Temp \xB0C \x94x\x94\nDataType=0x0006\nAccessType=ro\n".to_vec();
    bytes.extend_from_slice(b"[2001]\nParameterName=Other \xB5s\nDataType=0x0006\nAccessType=ro\n");
    std::fs::write(&path, bytes).unwrap();
    let mut d = base();
    d.extend_from(&path).unwrap_or_else(|e| panic!("{e}"));
    let _ = std::fs::remove_dir_all(&dir);
    assert!(d.get("Temp °C \u{201D}x\u{201D}").is_some());
    assert!(d.get("Other µs").is_some());
    let notes: Vec<&str> = d
        .notes()
        .iter()
        .map(|n| n.message())
        .filter(|m| m.contains("Windows-1252"))
        .collect();
    assert_eq!(notes.len(), 1, "{notes:?}");
}

#[test]
fn a_listed_object_without_its_section_is_a_note_not_a_refusal() {
    let mut out = Diagnostics::new();
    let text = "[FileInfo]\nFileName=x.eds\n[OptionalObjects]\nSupportedObjects=2\n1=0x2000\n2=0x2001\n[2000]\nParameterName=Here\nDataType=0x0006\nAccessType=ro\n";
    let file = EdsFile::parse(&Source::new("x.eds", text), &mut out);
    assert!(out.is_empty(), "{}", out.render(false));
    assert_eq!(file.notes.len(), 1);
    assert_eq!(file.notes[0].line(), 6);
    assert!(file.notes[0]
        .message()
        .contains("lists 0x2001, but there is no `[2001]` section"));
    assert_eq!(file.entries.len(), 1);
}

#[test]
fn malformed_lines_are_each_located_with_what_was_expected() {
    let mut d = base();
    let e = d
        .extend_from(concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/malformed.eds"))
        .unwrap_err();
    let found: Vec<(usize, String)> = e
        .problems()
        .map(|p| (p.line(), p.message().to_string()))
        .collect();
    let expected: [(usize, &str); 11] = [
        (1, "`Description=` comes before any `[section]`"),
        (4, "a line that is neither `[section]` nor `key=value`"),
        (5, "a section header without its closing `]`"),
        (8, "`[2000]` has no `AccessType=`"),
        (13, "`DataType=twelve` is not a data type code"),
        (18, "`readwrite` is not an access type; CiA 306 has ro, wo, rw, rwr, rww and const"),
        (19, "`[2003]` has no `ParameterName=`"),
        (26, "`LowLimit`: `$NODEID*2` is not a $NODEID expression; expected `$NODEID`, `$NODEID+0x180` or `0x180+$NODEID`"),
        (27, "`HighLimit`: `09` starts with 0, which makes it octal in an EDS, but it has digits beyond 7"),
        (30, "`ObjectType=0x5` is not an object type"),
        (33, "`ParameterName` is given twice in `[2006]`"),
    ];
    for (line, message) in expected {
        assert!(
            found.contains(&(line, message.to_string())),
            "{line} {message}\n{found:#?}"
        );
    }
    assert!(
        found.contains(&(36, "section `[2006]` is written twice".into())),
        "{found:#?}"
    );
    assert_eq!(found.len(), 12, "{found:#?}");
    assert_eq!(
        e.first().path(),
        concat!(env!("CARGO_MANIFEST_DIR"), "/tests/eds/malformed.eds")
    );
    assert_eq!(d.objects().count(), 1, "a refused file adds nothing");
}

#[test]
fn an_empty_file_says_what_an_eds_is() {
    let mut out = Diagnostics::new();
    EdsFile::parse(&Source::new("e.eds", "; nothing\n"), &mut out);
    assert!(out.iter().next().unwrap().help().unwrap().contains("[FileInfo]"));
}

proptest! {
    #[test]
    fn no_panic_on_any_text(text in ".{0,400}") {
        let mut out = Diagnostics::new();
        let file = EdsFile::parse(&Source::new("p.eds", text), &mut out);
        let _ = eds_objects(&file, &HashSet::new(), &HashSet::new(), &|_| None);
    }

    #[test]
    fn no_panic_on_eds_shaped_text(
        lines in proptest::collection::vec(
            prop_oneof![
                "\\[[0-9A-Fa-f]{4}(sub[0-9A-Fa-f]{1,3})?(Name|Value|ObjectLinks)?\\]",
                "(ParameterName|ObjectType|DataType|AccessType|LowLimit|HighLimit|DefaultValue|ParameterValue|CompactSubObj|SubNumber|PDOMapping|NodeID|1|2)=[-$A-Za-z0-9x+. ]{0,12}",
                "\\[(DeviceComissioning|MandatoryObjects|OptionalObjects|FileInfo)\\]",
                // Objects the built-in canopen dictionary has, so the file's word is laid
                // over its entries.
                "\\[(6040|6041|6060|606C|60FF|6079|1017)\\]",
                "(LowLimit|HighLimit)=(0x[0-9A-F]{1,17}|-?[0-9]{1,20})",
                "DataType=0x000[1-9A-F]",
                ".{0,20}",
            ],
            0..40,
        )
    ) {
        let mut out = Diagnostics::new();
        let source = Source::new("p.eds", lines.join("\n"));
        let file = EdsFile::parse(&source, &mut out);
        let canopen = crate::family::Registry::builtin()
            .load_dictionary("canopen")
            .expect("built-in canopen dictionary");
        let occupied: HashSet<Address> = canopen.objects().map(|o| o.address).collect();
        let objects = eds_objects(&file, &HashSet::new(), &occupied, &|_| None);
        for on in objects.on_built_in {
            let mut def = canopen
                .objects()
                .find(|d| d.address == on.file.address)
                .cloned()
                .expect("an occupied address");
            on.file.lay_over(&mut def, on.data_type, on.access, on.limits);
            if let (Some(min), Some(max)) = (def.min, def.max) {
                prop_assert!(min.is_finite() && max.is_finite());
            }
        }
        let _ = super::dcf_parameter_values(&source);
    }

    #[test]
    fn hex_limits_of_signed_types_stay_within_their_width(
        text in "0x[0-9A-Fa-f]{1,18}|-?[0-9]{1,20}|\\$NODEID\\+0x[0-9A-F]{1,4}",
        bits in prop_oneof![Just(8u32), Just(16), Just(24), Just(32), Just(40), Just(48), Just(56), Just(64)],
    ) {
        if let Ok(limit) = super::eds_number::EdsLimit::parse(&text, false) {
            let signed = limit.signed_at(&text, bits).resolve(Some(1));
            if let (Some(v), true) = (signed, text.starts_with("0x")) {
                let half = 2f64.powi(bits as i32 - 1);
                // In the type's range, or beyond its width (left for the range check).
                prop_assert!(v >= -half && (v < half || v >= 2.0 * half), "{text} at {bits}: {v}");
            }
        }
    }

    #[test]
    fn any_bytes_are_windows_1252_text(bytes in proptest::collection::vec(any::<u8>(), 0..200)) {
        let text = crate::diag::windows_1252(&bytes);
        prop_assert_eq!(text.chars().count(), bytes.len());
    }
}

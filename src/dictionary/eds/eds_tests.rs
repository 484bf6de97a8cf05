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
    let int = |bytes, signed| DataType::Int { bytes, signed };
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
    let expected: [(usize, &str); 12] = [
        (1, "`Description=` comes before any `[section]`"),
        (4, "a line that is neither `[section]` nor `key=value`"),
        (5, "a section header without its closing `]`"),
        (7, "[OptionalObjects] lists 0x2009, but there is no `[2009]` section"),
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
    assert_eq!(found.len(), 13, "{found:#?}");
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
                "\\[(DeviceComissioning|MandatoryObjects|FileInfo)\\]",
                ".{0,20}",
            ],
            0..40,
        )
    ) {
        let mut out = Diagnostics::new();
        let source = Source::new("p.eds", lines.join("\n"));
        let file = EdsFile::parse(&source, &mut out);
        let _ = eds_objects(&file, &HashSet::new(), &HashSet::new(), &|_| None);
        let _ = super::dcf_parameter_values(&source);
    }
}

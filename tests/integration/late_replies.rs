//! A drive that answers later than the reply timeout, in every family, through a real line:
//! a pseudo-terminal for the serial families, TCP for Modbus TCP, SLCAN on a
//! pseudo-terminal for CANopen. Every value read must be the one its own request asked for
//! — what the same drive answering at once gives — never the answer to an earlier request
//! that came late (a Modbus slave answering after 300 ms to a 200 ms timeout used to make
//! each read show the previous register: `speed_actual` 18 rpm, the raw status word).

use crate::support::{command, Simulator};

/// The simulated drive answers this late; the reads wait this long for each reply.
const LATENCY: &str = "reply-latency=300ms";
const TIMEOUT: &str = "200ms";
/// Enough attempts that a reply 300 ms late is met by a later attempt even on a loaded
/// machine (three, the default, left a Windows process under Wine with none); each
/// attempt puts another late reply on the line, which must be told apart too.
const RETRIES: &str = "8";

struct Family {
    drive: &'static str,
    /// How `simulate` serves it and how `read` reaches the endpoint it prints.
    serve: &'static str,
    connect: &'static str,
    /// Objects whose values differ from one another at standstill where the dictionary
    /// allows, so a reply taken for the wrong request shows.
    objects: &'static [&'static str],
    extra: &'static [&'static str],
}

/// `read --json` of the family's objects from a freshly served simulated drive, answering
/// late or not; the exit code and what was printed.
fn read(family: &Family, late: bool) -> (Option<i32>, String, String) {
    let mut sim_args = vec![family.serve, "--drive", family.drive];
    if late {
        sim_args.extend(["--sim", LATENCY]);
    }
    let sim = Simulator::start(&sim_args);
    let endpoint = match family.connect {
        "--can" => format!("slcan:{}", sim.endpoint),
        _ => sim.endpoint.clone(),
    };
    let out = command()
        .args([
            "read",
            "--json",
            "--drive",
            family.drive,
            family.connect,
            &endpoint,
        ])
        .args(["--timeout", if late { TIMEOUT } else { "1s" }])
        .args(["--retries", RETRIES])
        .args(family.extra)
        .args(family.objects)
        .output()
        .expect("drivescript read runs");
    drop(sim);
    (
        out.status.code(),
        String::from_utf8_lossy(&out.stdout).into_owned(),
        String::from_utf8_lossy(&out.stderr).into_owned(),
    )
}

/// The late drive's values are the prompt drive's, every one, and the reads succeed.
fn every_value_from_its_own_reply(family: Family) {
    let (code, prompt, err) = read(&family, false);
    assert_eq!(code, Some(0), "{} answering at once: {prompt}{err}", family.drive);
    let values: serde_json::Value = serde_json::from_str(&prompt).expect("read --json prints JSON");
    assert_eq!(
        values.as_array().map(Vec::len),
        Some(family.objects.len()),
        "{prompt}"
    );
    let (code, late, err) = read(&family, true);
    assert!(
        same_readings(&late, &values),
        "{} answering after 300 ms to a 200 ms timeout read other values than when it answers at once (stderr: {err})\n  late: {late}\nprompt: {prompt}",
        family.drive
    );
    assert_eq!(code, Some(0), "{err}");
}

/// The simulated DC link's noise (±0.3 V about 325.3 V): a retried request's reply is a
/// later sample of the same object, which may differ by this much; any other object's
/// value is far from it.
const DC_LINK_NOISE_V: f64 = 0.6;

/// Whether `late` (`read --json`) holds the objects of `prompt` in order with their
/// values, the DC-link voltage within its noise: how often a slow drive's requests are
/// retried (and so which sample answers) follows the line's timing, not the protocol.
fn same_readings(late: &str, prompt: &serde_json::Value) -> bool {
    let Ok(serde_json::Value::Array(late)) = serde_json::from_str::<serde_json::Value>(late) else {
        return false;
    };
    let prompt = prompt.as_array().map(Vec::as_slice).unwrap_or_default();
    late.len() == prompt.len()
        && late.iter().zip(prompt).all(|(l, p)| {
            let noisy = p["object"] == "bus_voltage" && l["object"] == "bus_voltage";
            match (l["value"].as_f64(), p["value"].as_f64()) {
                (Some(a), Some(b)) if noisy => (a - b).abs() <= DC_LINK_NOISE_V && l["unit"] == p["unit"],
                _ => l == p,
            }
        })
}

/// The objects read back from a Modbus inverter, RTU or TCP: status, values and text.
const INVERTER_OBJECTS: &[&str] = &[
    "status_word",
    "speed_actual",
    "carrier_frequency",
    "bus_voltage",
    "ident",
    "fault_code",
];

#[test]
fn a_late_modbus_rtu_slave_never_gives_another_registers_value() {
    every_value_from_its_own_reply(Family {
        drive: "modbus-inverter",
        serve: "--pty",
        connect: "--port",
        objects: INVERTER_OBJECTS,
        extra: &[],
    });
}

#[test]
fn a_late_sd2_drive_never_gives_another_objects_value() {
    every_value_from_its_own_reply(Family {
        drive: "sd2",
        serve: "--pty",
        connect: "--port",
        objects: &[
            "status_word",
            "bus_voltage",
            "power_stage_load",
            "speed_actual",
            "drive_error",
            "motor_temperature",
        ],
        extra: &[],
    });
}

#[test]
fn a_late_control_techniques_drive_never_gives_another_parameters_value() {
    every_value_from_its_own_reply(Family {
        drive: "ct-unidrive-sp",
        serve: "--pty",
        connect: "--port",
        objects: &[
            "max_speed",
            "reference_selector",
            "speed_setpoint",
            "bus_voltage",
            "control_word",
            "status_word",
        ],
        extra: &[],
    });
}

#[test]
fn a_late_lenze_931_drive_never_gives_another_objects_value() {
    every_value_from_its_own_reply(Family {
        drive: "lenze-931",
        serve: "--pty",
        connect: "--port",
        objects: &["0x0001", "0x0010", "0x0013", "0x0014", "0x0021", "0x0022"],
        extra: &["--type", "u32"],
    });
}

#[test]
fn a_late_modbus_tcp_server_is_told_apart_by_transaction_id() {
    every_value_from_its_own_reply(Family {
        drive: "modbus-tcp-inverter",
        serve: "--tcp=127.0.0.1:0",
        connect: "--tcp",
        objects: INVERTER_OBJECTS,
        extra: &[],
    });
}

#[test]
fn a_late_canopen_node_is_told_apart_by_node_and_object() {
    every_value_from_its_own_reply(Family {
        drive: "canopen",
        serve: "--slcan-pty",
        connect: "--can",
        objects: &[
            "device_type",
            "status_word",
            "heartbeat_time",
            "quick_stop_option",
            "bus_voltage",
            "status_word",
        ],
        extra: &[],
    });
}

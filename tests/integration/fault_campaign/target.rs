//! The simulated drives the campaign runs against, one per family and channel: what a
//! recipe names to reach it, which of its objects the generated steps use, and which
//! faults it can have. Data only.

/// One family's simulated drive as recipes reach it.
#[derive(Debug, Clone, Copy)]
pub struct Target {
    /// Short name in seeds' reports and kept cases' folder names.
    pub name: &'static str,
    /// The recipe's `drive:` (and `link:`) lines.
    pub header: &'static str,
    /// The dictionary has a device-control profile (state, speed, stop commands).
    pub controlled: bool,
    /// The state below operation enabled a recipe goes to with the power stage off.
    pub off_state: &'static str,
    /// Highest speed a generated step asks for, in rpm.
    pub top_rpm: u32,
    /// The object that names the drive's fault, read by `on_fault`.
    pub fault_object: &'static str,
    /// Objects a `read` step reads.
    pub reads: &'static [&'static str],
    /// A text object and the value it holds, for a text `expect` (profile-less drives).
    pub text_check: Option<(&'static str, &'static str)>,
    /// A numeric object that can be sampled and its mean checked, with a band that holds it.
    pub sampled: Option<&'static str>,
    /// A CANopen node: EMCY frames (and for a CiA 402 node, a heartbeat).
    pub can: bool,
    /// The node sends a heartbeat the link watches.
    pub heartbeat: bool,
}

/// The built-in SD2 over its service channel: a drive with a profile that turns up to
/// 6000 rpm; the other targets say how they differ from it.
const SD2: Target = Target {
    name: "sd2",
    header: "drive: sd2\n",
    controlled: true,
    off_state: "ready_to_switch_on",
    top_rpm: 6000,
    fault_object: "drive_error",
    reads: &["speed_actual", "status_word", "bus_voltage"],
    text_check: None,
    sampled: Some("speed_actual"),
    can: false,
    heartbeat: false,
};

/// A Modbus inverter: stops in switched on, up to 3000 rpm, its fault in `fault_code`.
const MODBUS: Target = Target {
    off_state: "switched_on",
    top_rpm: 3000,
    fault_object: "fault_code",
    ..SD2
};

/// A drive without a device-control profile: it is only read and checked.
const UNCONTROLLED: Target = Target {
    controlled: false,
    top_rpm: 0,
    ..SD2
};

pub const TARGETS: [Target; 8] = [
    SD2,
    Target {
        name: "sd2_cyclic",
        header: "drive: sd2\nlink: { channel: cyclic, velocity_scaling: 24000 rpm }\n",
        reads: &["speed_actual", "status_word"],
        ..SD2
    },
    Target {
        name: "ct_ansi",
        header: "drive: ct-unidrive-sp\n",
        off_state: "switched_on",
        top_rpm: 1500,
        fault_object: "last_trip",
        ..SD2
    },
    Target {
        name: "lenze_931",
        header: "drive: lenze-931\n",
        fault_object: "boot_state",
        reads: &["ident", "boot_state", "firmware_version"],
        text_check: Some(("boot_state", "APPLICATION")),
        sampled: None,
        ..UNCONTROLLED
    },
    Target {
        name: "lenze_9400",
        header: "drive: lenze-9400\n",
        fault_object: "heatsink_temperature",
        reads: &["ident", "heatsink_temperature", "rated_motor_current"],
        sampled: Some("heatsink_temperature"),
        can: true,
        ..UNCONTROLLED
    },
    Target {
        name: "canopen",
        header: "drive: canopen\n",
        can: true,
        heartbeat: true,
        ..SD2
    },
    Target {
        name: "modbus_rtu",
        header: "drive: sunfar-e500\n",
        reads: &["speed_actual", "current_actual"],
        ..MODBUS
    },
    Target {
        name: "modbus_tcp",
        header: "drive: modbus-tcp-inverter\n",
        reads: &["speed_actual", "bus_voltage"],
        ..MODBUS
    },
];

/// The target a seed runs against: seeds go round the families, so any run of
/// consecutive seeds covers them evenly.
pub fn target_of(seed: u64) -> Target {
    TARGETS[(seed % TARGETS.len() as u64) as usize]
}

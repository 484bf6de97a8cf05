//! The SD2 objects of the simulated drive: Read/Write Wide Object by index onto the
//! family-neutral drive model (scaling, sizes, SD2 error codes), and the cyclic telegram's
//! process data. No bytes on the wire here beyond each object's data field.

use super::sim_objects::{
    SimObject, ACTUAL_CURRENT, ACTUAL_SPEED, ACTUAL_SPEED_2, BUS_VOLTAGE, CONTROL_WORD, DRIVE_ERROR,
    IDENT_MAX, IDENT_STRING, MOTOR_TEMPERATURE, PARAMETER_SET, POWER_STAGE_LOAD, SPEED_SETPOINT, STATUS_WORD,
    STORE_PARAMETERS,
};
use crate::family::sd2::codec::{Cyclic, Data, ErrorCode};
use crate::sim::{DriveModel, ModelRefusal};

/// The value that triggers "store parameters".
const STORE_COMMAND: u16 = 1;
/// 0x3FFF in the cyclic telegram is 100 % of the velocity scaling.
const CYCLIC_FULL_SCALE: f64 = 16383.0;

fn refusal(r: ModelRefusal) -> ErrorCode {
    match r {
        ModelRefusal::TooHigh => ErrorCode::TOO_HIGH,
        ModelRefusal::TooLow => ErrorCode::TOO_LOW,
        ModelRefusal::OutOfRange => ErrorCode::RANGE_EXCEEDED,
        ModelRefusal::NotInThisState => ErrorCode::STATE_OF_CONTROL,
    }
}

/// Read Wide Object.
pub(crate) fn read(m: &mut DriveModel, index: u16, subindex: u32) -> Result<Data, ErrorCode> {
    SimObject::find(index)?.check_read(subindex)?;
    Ok(match index {
        IDENT_STRING => ident(m),
        BUS_VOLTAGE => u16_data(counts_u16(m.measured_bus_voltage_v() * 10.0)),
        POWER_STAGE_LOAD => u16_data(counts_u16(m.power_stage_load_percent() * 10.0)),
        STATUS_WORD => u16_data(m.status_word()),
        CONTROL_WORD => u16_data(m.control_word()),
        ACTUAL_SPEED | ACTUAL_SPEED_2 => i32_data(counts_i32(m.measured_speed_rpm() * 1000.0)),
        PARAMETER_SET => u16_data(m.parameter_set()),
        SPEED_SETPOINT => i32_data(counts_i32(m.setpoint_rpm() * 1000.0)),
        ACTUAL_CURRENT => i32_data(counts_i32(m.measured_current_a() * 1000.0)),
        DRIVE_ERROR => u16_data(m.drive_error()),
        MOTOR_TEMPERATURE => i32_data(counts_i32(m.motor_temperature_c() * 10.0)),
        _ => return Err(INTERNAL_INCOMPATIBILITY),
    })
}

/// Write Wide Object.
pub(crate) fn write(
    m: &mut DriveModel,
    index: u16,
    subindex: u32,
    bytes: &[u8],
    reset_blocked: bool,
) -> Result<(), ErrorCode> {
    SimObject::find(index)?.check_write(subindex, bytes.len())?;
    match (index, bytes) {
        (CONTROL_WORD, &[lo, hi]) => {
            m.write_control_word(u16::from_le_bytes([lo, hi]), reset_blocked);
        }
        (PARAMETER_SET, &[lo, hi]) => m
            .set_parameter_set(u16::from_le_bytes([lo, hi]))
            .map_err(refusal)?,
        (SPEED_SETPOINT, &[a, b, c, d]) => {
            let milli_rpm = f64::from(i32::from_le_bytes([a, b, c, d]));
            m.set_setpoint_rpm(milli_rpm / 1000.0).map_err(refusal)?;
        }
        (STORE_PARAMETERS, &[lo, hi]) => {
            if u16::from_le_bytes([lo, hi]) != STORE_COMMAND {
                return Err(ErrorCode::RANGE_EXCEEDED);
            }
        }
        _ => return Err(INTERNAL_INCOMPATIBILITY),
    }
    Ok(())
}

/// The cyclic telegram's speed reference: a fraction of the velocity scaling.
pub(crate) fn set_speed_reference(m: &mut DriveModel, reference: i16) {
    m.set_speed_fraction(f64::from(reference) / CYCLIC_FULL_SCALE);
}

/// The drive's process data in a cyclic reply.
pub(crate) fn cyclic_reply(m: &mut DriveModel, header: [u8; 2]) -> Cyclic {
    let speed = m.measured_speed_rpm() / m.config().velocity_scaling_rpm * CYCLIC_FULL_SCALE;
    let current = m.measured_current_a() * 100.0;
    Cyclic::reply(
        header,
        m.status_word(),
        counts_i16(speed),
        m.drive_error(),
        counts_i16(current),
    )
}

fn ident(m: &DriveModel) -> Data {
    let chars = m.ident().as_bytes();
    let chars = &chars[..chars.len().min(IDENT_MAX)];
    let mut out = Vec::with_capacity(IDENT_MAX + 2);
    out.push(IDENT_MAX as u8);
    out.extend_from_slice(chars);
    if chars.len() < IDENT_MAX {
        out.push(0);
    }
    Data::new(&out).unwrap_or_default()
}

const INTERNAL_INCOMPATIBILITY: ErrorCode = ErrorCode(0x8F);

fn u16_data(v: u16) -> Data {
    Data::new(&v.to_le_bytes()).unwrap_or_default()
}

fn i32_data(v: i32) -> Data {
    Data::new(&v.to_le_bytes()).unwrap_or_default()
}

// `as` from f64 saturates at the integer's bounds (and maps NaN to 0), which is the clamp wanted.
fn counts_u16(v: f64) -> u16 {
    v.round() as u16
}

fn counts_i16(v: f64) -> i16 {
    v.round() as i16
}

fn counts_i32(v: f64) -> i32 {
    v.round() as i32
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::drive::DeviceState;
    use crate::sim::SimConfig;
    use std::time::Duration;

    fn model() -> DriveModel {
        DriveModel::new(SimConfig::default())
    }

    fn u16_of(d: Data) -> u16 {
        u16::from_le_bytes([d.as_slice()[0], d.as_slice()[1]])
    }

    fn i32_of(d: Data) -> i32 {
        let s = d.as_slice();
        i32::from_le_bytes([s[0], s[1], s[2], s[3]])
    }

    fn secs(s: f64) -> Duration {
        Duration::from_secs_f64(s)
    }

    #[test]
    fn every_object_has_a_value_of_its_size_or_is_write_only() {
        let mut m = model();
        for o in super::super::sim_objects::OBJECTS {
            match read(&mut m, o.index, 0) {
                Ok(d) if o.index == IDENT_STRING => assert_eq!(d.len(), 12),
                Ok(d) => assert_eq!(d.len(), o.size(), "object {}", o.index),
                Err(e) => assert_eq!((o.index, e), (STORE_PARAMETERS, ErrorCode::WRITE_ONLY)),
            }
        }
    }

    #[test]
    fn measurements_at_rest_and_at_speed() {
        let mut m = model();
        // At rest, power off: exact zeros and nominal voltage.
        assert_eq!(i32_of(read(&mut m, ACTUAL_SPEED, 0).unwrap()), 0);
        assert_eq!(i32_of(read(&mut m, ACTUAL_CURRENT, 0).unwrap()), 0);
        assert_eq!(u16_of(read(&mut m, POWER_STAGE_LOAD, 0).unwrap()), 0);
        let v = u16_of(read(&mut m, BUS_VOLTAGE, 0).unwrap());
        assert!((3250..=3256).contains(&v), "{v}");
        write(&mut m, SPEED_SETPOINT, 0, &10_000_000i32.to_le_bytes(), false).unwrap();
        m.enable_for_test();
        m.advance_to(secs(10.0));
        let speed = i32_of(read(&mut m, ACTUAL_SPEED, 0).unwrap());
        assert!((speed - 10_000_000).abs() <= 500, "{speed}");
        let current = i32_of(read(&mut m, ACTUAL_CURRENT, 0).unwrap());
        assert!((current - 800).abs() <= 5, "{current}");
        // 0.8 A of 20 A = 4.0 % = 40 counts.
        assert_eq!(u16_of(read(&mut m, POWER_STAGE_LOAD, 0).unwrap()), 40);
        let v = u16_of(read(&mut m, BUS_VOLTAGE, 0).unwrap());
        assert!((3246..=3252).contains(&v), "{v}");
        assert_eq!(u16_of(read(&mut m, STATUS_WORD, 0).unwrap()), 0x0637);
    }

    #[test]
    fn parameter_set_range_and_state() {
        let mut m = model();
        assert_eq!(
            write(&mut m, PARAMETER_SET, 0, &64u16.to_le_bytes(), false),
            Ok(())
        );
        assert_eq!(u16_of(read(&mut m, PARAMETER_SET, 0).unwrap()), 64);
        assert_eq!(
            write(&mut m, PARAMETER_SET, 0, &65u16.to_le_bytes(), false),
            Err(ErrorCode::RANGE_EXCEEDED)
        );
        m.enable_for_test();
        assert_eq!(
            write(&mut m, PARAMETER_SET, 0, &1u16.to_le_bytes(), false),
            Err(ErrorCode::STATE_OF_CONTROL)
        );
        assert_eq!(u16_of(read(&mut m, PARAMETER_SET, 0).unwrap()), 64);
    }

    #[test]
    fn quick_stop_at_rest_ends_at_once() {
        let mut m = model();
        m.enable_for_test();
        m.write_control_word(2, false);
        assert_eq!(m.state(), DeviceState::SwitchOnDisabled);
    }
}

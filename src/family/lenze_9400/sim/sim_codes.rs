//! The codes the simulated 9400 node holds, and how each is read and written against the
//! drive model. Values the sources do not give (the firmware's revision and build, the
//! product string, the temperature model) are the simulator's own and said to be so.
//! No bytes on the wire here: values go in and out as the SDO value bytes.

use super::super::codec::AbortCode;
use crate::family::canopen::sim::{ObjectStore, Place, SdoLogged};
use crate::sim::{DriveModel, SimCore};

/// The firmware version the simulated node reports (C00099): the `05.00.xx.yy` form of the
/// manuals, with revision and build made up for the simulator.
pub const FIRMWARE_VERSION: &str = "05.00.12.07";
/// The product type it reports (C00200): "FHB" marks a 9400 HighLine in the sources; the
/// rest is the simulator's.
pub const PRODUCT_TYPE: &str = "simulated 9400 HighLine FHB";

const fn at(code: u16, subcode: u8) -> Place {
    (0x5FFF - code, subcode)
}

pub const C00099_FIRMWARE: Place = at(99, 0);
pub const C00200_PRODUCT: Place = at(200, 0);
pub const C00061_HEATSINK: Place = at(61, 0);
pub const C00088_RATED_CURRENT: Place = at(88, 0);
pub const C00011_REFERENCE_SPEED: Place = at(11, 0);
pub const C00002_16_ENABLE: Place = at(2, 16);

/// The values the node stores (its parameters); measured values come from the model.
#[derive(Debug, Clone, PartialEq, Eq)]
pub struct SimCodes {
    /// C00088 in 0.1 A (factor 10).
    pub rated_current: i32,
    /// C00011, held as written (the simulator does not give it a meaning).
    pub reference_speed: i32,
    /// C00002/16: 1 enable, 0 inhibit the controller (from the 8400 sources, unconfirmed).
    pub enable: i32,
}

impl Default for SimCodes {
    fn default() -> Self {
        SimCodes {
            rated_current: 102,
            reference_speed: 0,
            enable: 0,
        }
    }
}

/// Whether any subindex of `index` exists (for the right abort code).
fn index_exists(index: u16) -> bool {
    [
        C00099_FIRMWARE,
        C00200_PRODUCT,
        C00061_HEATSINK,
        C00088_RATED_CURRENT,
        C00011_REFERENCE_SPEED,
        C00002_16_ENABLE,
    ]
    .iter()
    .any(|(i, _)| *i == index)
}

fn missing(place: Place) -> AbortCode {
    if index_exists(place.0) {
        AbortCode::SUBINDEX_DOES_NOT_EXIST
    } else {
        AbortCode::OBJECT_DOES_NOT_EXIST
    }
}

impl ObjectStore for SimCodes {
    fn read(&mut self, core: &mut SimCore<SdoLogged>, place: Place) -> Result<Vec<u8>, AbortCode> {
        SimCodes::read(self, &mut core.model, place)
    }
    fn write(&mut self, _: &mut SimCore<SdoLogged>, place: Place, bytes: &[u8]) -> Result<(), AbortCode> {
        SimCodes::write(self, place, bytes)
    }
}

impl SimCodes {
    /// The value bytes of a read.
    pub fn read(&self, model: &mut DriveModel, place: Place) -> Result<Vec<u8>, AbortCode> {
        Ok(match place {
            C00099_FIRMWARE => FIRMWARE_VERSION.as_bytes().to_vec(),
            C00200_PRODUCT => PRODUCT_TYPE.as_bytes().to_vec(),
            C00061_HEATSINK => {
                // 43 °C at rest as in the manual's example, warming with the power stage's load.
                let celsius = 43.0 + model.power_stage_load_percent() / 5.0;
                (celsius.round() as i32).to_le_bytes().to_vec()
            }
            C00088_RATED_CURRENT => self.rated_current.to_le_bytes().to_vec(),
            C00011_REFERENCE_SPEED => self.reference_speed.to_le_bytes().to_vec(),
            C00002_16_ENABLE => self.enable.to_le_bytes().to_vec(),
            other => return Err(missing(other)),
        })
    }

    /// Stores a write. Integers arrive in 1 to 4 bytes and are widened as signed.
    pub fn write(&mut self, place: Place, bytes: &[u8]) -> Result<(), AbortCode> {
        let int = || -> Result<i32, AbortCode> {
            if bytes.is_empty() || bytes.len() > 4 {
                return Err(AbortCode::LENGTH_MISMATCH);
            }
            let mut buf = [0u8; 4];
            buf[..bytes.len()].copy_from_slice(bytes);
            let shift = 32 - 8 * bytes.len() as u32;
            Ok((i32::from_le_bytes(buf) << shift) >> shift)
        };
        match place {
            C00099_FIRMWARE | C00200_PRODUCT | C00061_HEATSINK => Err(AbortCode::READ_ONLY),
            C00088_RATED_CURRENT => {
                let v = int()?;
                if v < 0 {
                    return Err(AbortCode::VALUE_TOO_LOW);
                }
                self.rated_current = v;
                Ok(())
            }
            C00011_REFERENCE_SPEED => {
                self.reference_speed = int()?;
                Ok(())
            }
            C00002_16_ENABLE => match int()? {
                v @ (0 | 1) => {
                    self.enable = v;
                    Ok(())
                }
                _ => Err(AbortCode::VALUE_RANGE_EXCEEDED),
            },
            other => Err(missing(other)),
        }
    }
}

//! Object access to a CANopen node: SDO uploads and downloads over an [`SdoLink`], with
//! values converted by [`super::sdo_value`], and for a CiA 402 node the NMT state its
//! device control needs ([`NmtMaster`]).

use super::nmt_master::NmtMaster;
use super::sdo_link::SdoLink;
use super::sdo_value;
use crate::dictionary::{Address, DataType, RawValue};
use crate::drive::{AccessError, ObjectAccess, WriteOutcome, WriteResult};
use crate::link::CoreLink;
use std::time::Duration;

pub struct SdoAccess {
    link: SdoLink,
    nmt: Option<NmtMaster>,
}

impl SdoAccess {
    pub fn new(link: SdoLink, nmt: Option<NmtMaster>) -> Self {
        SdoAccess { link, nmt }
    }

    pub fn link(&self) -> &SdoLink {
        &self.link
    }

    fn subindex(address: &Address) -> Result<(u16, u8), AccessError> {
        let Address::Indexed { index, subindex } = *address;
        let sub = u8::try_from(subindex)
            .map_err(|_| AccessError::Encode(format!("SDO subindexes are 0..=255, not {subindex}")))?;
        Ok((index, sub))
    }
}

impl ObjectAccess for SdoAccess {
    fn read(&mut self, address: &Address, data_type: DataType) -> Result<RawValue, AccessError> {
        let (index, subindex) = Self::subindex(address)?;
        let value = self.link.upload(index, subindex)?;
        sdo_value::decode(&value, data_type).map_err(|detail| AccessError::UnexpectedReply {
            port: self.link.port().to_string(),
            address: format!("node {}", self.link.node()),
            request: format!("read {}", self.link.object_text(index, subindex)),
            detail: detail.to_string(),
        })
    }

    fn write(&mut self, address: &Address, value: &RawValue, data_type: DataType) -> WriteResult {
        let (index, subindex) = Self::subindex(address)?;
        let bytes = sdo_value::encode(value, data_type).map_err(|e| AccessError::Encode(e.to_string()))?;
        if let Some(nmt) = &mut self.nmt {
            nmt.before_write(&mut self.link, (index, subindex), &bytes)?;
        }
        self.link.download(index, subindex, &bytes)?;
        Ok(WriteOutcome::Stored)
    }

    fn keep_alive(&mut self) -> Result<Option<Duration>, AccessError> {
        self.link.check_node()
    }

    fn notices(&mut self) -> Vec<String> {
        self.nmt.as_mut().map(NmtMaster::take_notices).unwrap_or_default()
    }

    fn release(&mut self) -> Option<String> {
        self.nmt.as_mut()?.release(&mut self.link)
    }

    fn withhold_release(&mut self) -> Option<String> {
        self.nmt.as_mut()?.withhold(&mut self.link)
    }

    fn reported_fault(&mut self) -> Option<String> {
        self.link.reported_fault()
    }

    fn error_code_text(&self, code: u16) -> Option<&'static str> {
        Some(super::codec::error_code_text(code))
    }

    fn port(&self) -> String {
        format!("node {} on {}", self.link.node(), self.link.port())
    }

    crate::link_access_core!();
}

//! The `go_to` step: a target state (`go_to: operation_enabled`, or with a `timeout` per
//! transition). It must not plan the path of commands; the session does that when it runs.

use crate::diag::{Shape, YamlNode};
use crate::drive::device_control::DeviceState;
use crate::recipe::loader::{Loader, DEFAULT_GO_TO_TIMEOUT};
use crate::recipe::step::StepKind;

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn go_to(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let (state_node, what, timeout, drive) = match body.entries() {
            Some(_) => {
                let shape = Shape::new("this go_to", &["state", "timeout", "drive"]).require(&["state"]);
                let f = self.r.fields(body, &shape)?;
                let timeout = match f.get("timeout") {
                    Some(t) => self.duration(t, "timeout")?,
                    None => DEFAULT_GO_TO_TIMEOUT,
                };
                let drive = match f.get("drive") {
                    Some(n) => Some((self.r.scalar_text(n, "`drive`")?, n.span.clone())),
                    None => None,
                };
                (f.get("state")?, "`state`", timeout, drive)
            }
            None => (body, "`go_to`", DEFAULT_GO_TO_TIMEOUT, None),
        };
        let state = match &drive {
            Some((name, span)) => self.on_drive(name, span, |l| l.state(state_node, what))??,
            None => {
                let mut found = None;
                let ok = self.on_every_drive(|l| {
                    found = l.state(state_node, what);
                    found.is_some()
                });
                if !ok {
                    return None;
                }
                found?
            }
        };
        let drive = drive.map(|(name, _)| name);
        if matches!(
            state,
            DeviceState::Fault | DeviceState::FaultReactionActive | DeviceState::NotReadyToSwitchOn
        ) {
            return self.refuse(
                &state_node.span,
                format!(
                    "`{}` is entered by the drive itself, no command leads there",
                    state.id()
                ),
                "cannot be commanded",
                None,
            );
        }
        let label = match &drive {
            Some(d) => format!("go to {} ({d})", state.id()),
            None => format!("go to {}", state.id()),
        };
        Some((
            StepKind::GoTo {
                state,
                timeout,
                drive,
            },
            label,
        ))
    }
}

//! The `set` step: objects and the values to write, each checked against the object's
//! type, unit and limits before anything is sent. It must not write anything.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::Loader;
use crate::recipe::step::StepKind;
use crate::session::{ObjectRef, SetValue};

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn set(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::any_keys("`set`").example("set: { speed_setpoint: 6000 rpm }");
        let writes = self.per_object(body, &shape, |this, def, r, k, v| {
            if !this.writable(&def, &k.span, "set") {
                return None;
            }
            let what = format!("`{}`", k.value);
            if !def.data_type.is_number() {
                let t = this.text(v, &what)?;
                return match def.text_to_raw(&t) {
                    Ok(_) => Some((r, SetValue::Text(t))),
                    Err(e) => this.refuse(&v.span, e.to_string(), "refused", None),
                };
            }
            let n = this.quantity_for(&def, v, &what, true)?;
            Some((r, SetValue::Number(n)))
        })?;
        let help = Some("e.g. `set: { speed_setpoint: 6000 rpm }`".into());
        let writes = self.not_empty(writes, body, "set names no object", help)?;
        let label = format!(
            "set {}",
            writes
                .iter()
                .map(|(o, v)| format!("{} = {}", o.name, show_set_value(v, o)))
                .collect::<Vec<_>>()
                .join(", ")
        );
        Some((StepKind::Set(writes), label))
    }
}

fn show_set_value(v: &SetValue, o: &ObjectRef) -> String {
    match v {
        SetValue::Text(t) => format!("\"{t}\""),
        SetValue::Number(n) => crate::session::exact_with_unit(n, o.unit.as_deref()),
    }
}

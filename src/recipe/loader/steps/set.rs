//! The `set` step: objects and the values to write, each checked against the object's
//! type, unit and limits before anything is sent. It must not write anything.

use crate::diag::{Shape, YamlNode};
use crate::recipe::loader::Loader;
use crate::recipe::step::StepKind;
use crate::session::{ObjectRef, SetValue};

impl Loader<'_, '_> {
    pub(in crate::recipe::loader) fn set(&mut self, body: &YamlNode) -> Option<(StepKind, String)> {
        let shape = Shape::any_keys("`set`").example("set: { speed_setpoint: 6000 rpm }");
        let f = self.r.fields(body, &shape)?;
        let mut writes = Vec::new();
        let mut ok = true;
        for (k, v) in f.entries() {
            let Some((def, r)) = self.object(&k.value, &k.span) else {
                ok = false;
                continue;
            };
            if !def.writable() {
                self.problem(
                    &k.span,
                    format!("{} is read-only and cannot be set", def.name),
                    "read-only",
                    None,
                );
                ok = false;
                continue;
            }
            let what = format!("`{}`", k.value);
            if !def.data_type.is_number() {
                match self.text(v, &what) {
                    Some(t) => match def.text_to_raw(&t) {
                        Ok(_) => writes.push((r, SetValue::Text(t))),
                        Err(e) => {
                            self.problem(&v.span, e.to_string(), "refused", None);
                            ok = false;
                        }
                    },
                    None => ok = false,
                }
                continue;
            }
            match self.quantity_for(&def, v, &what, true) {
                Some(n) => writes.push((r, SetValue::Number(n))),
                None => ok = false,
            }
        }
        if writes.is_empty() && ok {
            return self.refuse(
                &body.span,
                "set names no object",
                "empty",
                Some("e.g. `set: { speed_setpoint: 6000 rpm }`".into()),
            );
        }
        let label = format!(
            "set {}",
            writes
                .iter()
                .map(|(o, v)| format!("{} = {}", o.name, show_set_value(v, o)))
                .collect::<Vec<_>>()
                .join(", ")
        );
        ok.then_some((StepKind::Set(writes), label))
    }
}

fn show_set_value(v: &SetValue, o: &ObjectRef) -> String {
    match v {
        SetValue::Text(t) => format!("\"{t}\""),
        SetValue::Number(n) => crate::session::exact_with_unit(n, o.unit.as_deref()),
    }
}

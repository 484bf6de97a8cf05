use super::*;
use std::path::Path;

fn leftovers(text: &str) -> Vec<String> {
    let dictionary = crate::family::Registry::builtin()
        .load_dictionary(crate::family::DEFAULT_DICTIONARY)
        .expect("built-in dictionary");
    let recipe = crate::recipe::load_recipe_text("r.yaml", text, Path::new("."), &dictionary, &[])
        .expect("a valid recipe");
    leftover_setpoints(&recipe, "speed_setpoint")
        .iter()
        .map(|l| l.to_string())
        .collect()
}

#[test]
fn an_enable_after_a_disable_with_the_old_setpoint_standing_is_found_at_its_place() {
    let text = "name: x\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 12000 rpm }\n  - go_to: operation_enabled\n  - go_to: ready_to_switch_on\n  - go_to: operation_enabled\n";
    assert_eq!(
        leftovers(text),
        ["r.yaml:7:5: this enable starts the drive at speed_setpoint = 12000 rpm, left standing from r.yaml:4:5 though the drive was disabled at r.yaml:6:5; set the setpoint (0 rpm, or the speed wanted) right before enabling"]
    );
}

#[test]
fn a_new_setpoint_a_zero_or_a_coast_down_before_the_enable_is_no_leftover() {
    for between in [
        "  - set: { speed_setpoint: 3000 rpm }\n",
        "  - set: { speed_setpoint: 0 rpm }\n",
    ] {
        let text = format!("name: x\ndrive: sd2\nsteps:\n  - set: {{ speed_setpoint: 12000 rpm }}\n  - go_to: operation_enabled\n  - shutdown\n{between}  - go_to: operation_enabled\n");
        assert_eq!(leftovers(&text), Vec::<String>::new(), "{between}");
    }
    let coast = "name: x\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 6000 rpm }\n  - go_to: operation_enabled\n  - coast_down: { from: 5900 rpm, below: 100 rpm, expect: { below: 30 s } }\n  - go_to: operation_enabled\n";
    assert_eq!(leftovers(coast), Vec::<String>::new());
}

#[test]
fn inside_a_repeat_the_disable_and_enable_are_followed_in_order() {
    let text = "name: x\ndrive: sd2\nsteps:\n  - set: { speed_setpoint: 6000 rpm }\n  - repeat:\n      times: 2\n      steps:\n        - go_to: operation_enabled\n        - disable_operation\n  - enable_operation\n";
    assert_eq!(leftovers(text).len(), 1, "{:?}", leftovers(text));
}

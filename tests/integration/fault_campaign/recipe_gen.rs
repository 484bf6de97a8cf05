//! The campaign's recipes, generated from the step grammar by a seeded generator: set,
//! go_to (up, and down to ready to switch on), wait_until, dwell, read, sample with expect,
//! ramp, coast_down (also as the last step, and followed by an enable with the old setpoint
//! standing), repeat and attempts (sometimes with `on_failure: stop`, also for the whole recipe;
//! sometimes a `watch:` on the speed),
//! own `finally` and `on_fault`. Mostly recipes that pass on a healthy drive, some with a
//! check that fails, so that a fault is what changes the ending. Text only; nothing runs.

use super::target::Target;

/// A small, fast generator (SplitMix64): the same seed gives the same numbers everywhere.
pub struct Rng(u64);

impl Rng {
    pub fn new(seed: u64) -> Rng {
        Rng(seed ^ 0x5DEE_CE66_D1CE_4E5B)
    }

    pub fn next(&mut self) -> u64 {
        self.0 = self.0.wrapping_add(0x9E37_79B9_7F4A_7C15);
        let mut z = self.0;
        z = (z ^ (z >> 30)).wrapping_mul(0xBF58_476D_1CE4_E5B9);
        z = (z ^ (z >> 27)).wrapping_mul(0x94D0_49BB_1331_11EB);
        z ^ (z >> 31)
    }

    /// 0..n (0 when n is 0).
    pub fn below(&mut self, n: u64) -> u64 {
        if n == 0 {
            0
        } else {
            self.next() % n
        }
    }

    /// True `percent` times in a hundred.
    pub fn chance(&mut self, percent: u64) -> bool {
        self.below(100) < percent
    }

    pub fn pick<T: Copy>(&mut self, from: &[T]) -> T {
        from[self.below(from.len() as u64) as usize]
    }
}

/// A generated recipe and what a reader of a failure wants to know about it.
pub struct Generated {
    pub yaml: String,
    /// The recipe's name (unique per seed: how its record is found in the store).
    pub name: String,
}

/// What the generator knows of the drive as the steps go.
struct Drive {
    enabled: bool,
    /// The setpoint written last, rpm.
    setpoint: u32,
    /// The speed the last wait reached (so a sample can check its mean), rpm.
    reached: Option<u32>,
}

/// A recipe for `target` from `rng`.
pub fn recipe(seed: u64, target: &Target, rng: &mut Rng) -> Generated {
    let name = format!("campaign seed {seed} ({})", target.name);
    let mut y = format!("name: {name}\n{}steps:\n", target.header);
    if target.controlled {
        controlled_steps(target, rng, &mut y);
    } else {
        plain_steps(target, rng, &mut y);
    }
    if rng.chance(30) {
        y.push_str(&format!("on_fault:\n  - read: [{}]\n", target.fault_object));
    }
    if target.controlled {
        match rng.below(10) {
            0 | 1 => y.push_str("finally:\n  - disable_operation\n  - shutdown\n"),
            2 => y.push_str(
                "finally:\n  - set: { speed_setpoint: 0 rpm }\n  - wait_until: { speed_actual: { below: 20 rpm }, timeout: 20 s }\n  - disable_operation\n  - shutdown\n",
            ),
            _ => {}
        }
    }
    guards(seed, target, &mut y);
    Generated { yaml: y, name }
}

/// Sometimes `on_failure: stop` for the whole recipe or on a repeat or attempts block, and
/// a `watch:` on the speed (at a speed the steps may pass: then it ends the run), from a
/// generator of its own, so every seed's steps and fault stay what they were
/// before guards existed (the kept cases replay them).
fn guards(seed: u64, target: &Target, y: &mut String) {
    let mut rng = Rng::new(seed ^ 0x6775_6172_6473);
    if target.controlled && rng.chance(25) {
        let limit = speed(target, &mut rng);
        let watch =
            format!("watch:\n  speed_actual: {{ below: {limit} rpm, for: 1 s }}\n  every: 500 ms\nsteps:\n");
        *y = y.replacen("steps:\n", &watch, 1);
    }
    if rng.chance(25) {
        *y = y.replacen("steps:\n", "on_failure: stop\nsteps:\n", 1);
    }
    for block in ["repeat:\n", "attempts:\n"] {
        if y.contains(block) && rng.chance(30) {
            *y = y.replace(block, &format!("{block}      on_failure: stop\n"));
        }
    }
}

fn step(y: &mut String, text: &str) {
    y.push_str("  - ");
    y.push_str(text);
    y.push('\n');
}

fn speed(target: &Target, rng: &mut Rng) -> u32 {
    // Multiples of 60 rpm: whole tenths of a hertz on an inverter.
    let steps = (target.top_rpm / 60).max(11);
    60 * (10 + rng.below(u64::from(steps - 9)) as u32)
}

fn reach(y: &mut String, drive: &mut Drive, rpm: u32) {
    step(y, &format!("set: {{ speed_setpoint: {rpm} rpm }}"));
    step(
        y,
        &format!("wait_until: {{ speed_actual: {{ near: {rpm} rpm, within: 1 % }}, timeout: 15 s }}"),
    );
    drive.setpoint = rpm;
    drive.reached = Some(rpm);
}

fn enable(y: &mut String, drive: &mut Drive) {
    step(y, "go_to: { state: operation_enabled, timeout: 2 s }");
    drive.enabled = true;
}

fn controlled_steps(target: &Target, rng: &mut Rng, y: &mut String) {
    let mut drive = Drive {
        enabled: false,
        setpoint: 0,
        reached: None,
    };
    step(y, "set: { speed_setpoint: 0 rpm }");
    enable(y, &mut drive);
    let count = 1 + rng.below(5);
    for _ in 0..count {
        if !drive.enabled {
            // After a coast-down: sometimes the old setpoint still stands as it enables.
            if rng.chance(50) {
                step(y, "set: { speed_setpoint: 0 rpm }");
                drive.setpoint = 0;
            }
            enable(y, &mut drive);
            drive.reached = None;
        }
        match rng.below(10) {
            9 => {
                // The power stage off by the recipe itself; the stop finds the drive there.
                step(
                    y,
                    &format!("go_to: {{ state: {}, timeout: 2 s }}", target.off_state),
                );
                drive.enabled = false;
                drive.reached = None;
            }
            0 | 1 => {
                let rpm = speed(target, rng);
                reach(y, &mut drive, rpm);
            }
            2 => step(y, &format!("dwell: {} s", 1 + rng.below(20))),
            3 => {
                let Some(rpm) = drive.reached else {
                    let rpm = speed(target, rng);
                    reach(y, &mut drive, rpm);
                    continue;
                };
                // Half the samples of a drive that names its status word read it too: the
                // fault watch then judges the sample's own reply instead of polling.
                let objects = if target.reads.contains(&"status_word") && rng.chance(50) {
                    "speed_actual, status_word"
                } else {
                    "speed_actual"
                };
                step(
                    y,
                    &format!("sample: {{ objects: [{objects}], every: 100 ms, for: 2 s }}"),
                );
                // One in five checks a speed the drive is not at: a failed check.
                let want = if rng.chance(20) { rpm + 300 } else { rpm };
                step(
                    y,
                    &format!("expect: {{ speed_actual: {{ mean: {{ near: {want} rpm, within: 2 % }} }} }}"),
                );
            }
            4 => {
                let to = speed(target, rng);
                step(
                    y,
                    &format!(
                        "ramp: {{ object: speed_setpoint, from: {} rpm, to: {to} rpm, rate: 2000 rpm/s, every: 500 ms }}",
                        drive.setpoint
                    ),
                );
                drive.setpoint = to;
                drive.reached = None;
            }
            5 => step(y, &format!("read: [{}]", rng.pick(target.reads))),
            6 => step(
                y,
                &format!(
                    "repeat:\n      times: 2\n      steps:\n        - dwell: {} s\n        - read: [{}]",
                    1 + rng.below(3),
                    rng.pick(target.reads)
                ),
            ),
            7 => {
                let rpm = match drive.reached {
                    Some(rpm) => rpm,
                    None => {
                        let rpm = speed(target, rng);
                        step(y, &format!("set: {{ speed_setpoint: {rpm} rpm }}"));
                        drive.setpoint = rpm;
                        rpm
                    }
                };
                step(
                    y,
                    &format!(
                        "attempts:\n      times: 2\n      steps:\n        - wait_until: {{ speed_actual: {{ near: {rpm} rpm, within: 1 % }}, timeout: 5 s }}"
                    ),
                );
                drive.reached = Some(rpm);
            }
            _ => coast_down(target, rng, y, &mut drive),
        }
    }
    // One in ten ends in ready to switch on, one in five with a coast-down: the stop
    // then finds the power stage off, the spindle coasting.
    if rng.chance(10) {
        step(
            y,
            &format!("go_to: {{ state: {}, timeout: 2 s }}", target.off_state),
        );
    } else if rng.chance(20) {
        if !drive.enabled {
            enable(y, &mut drive);
        }
        coast_down(target, rng, y, &mut drive);
    }
}

/// A coast-down from a speed the drive first reaches (the power stage goes off).
fn coast_down(target: &Target, rng: &mut Rng, y: &mut String, drive: &mut Drive) {
    let rpm = match drive.reached {
        Some(rpm) if rpm >= 600 => rpm,
        _ => {
            let rpm = speed(target, rng).max(600);
            reach(y, drive, rpm);
            rpm
        }
    };
    step(
        y,
        &format!(
            "coast_down: {{ from: {} rpm, below: {} rpm, expect: {{ above: 100 ms }} }}",
            rpm * 9 / 10,
            rpm / 2
        ),
    );
    drive.enabled = false;
    drive.reached = None;
}

/// Steps for a drive without a device-control profile: reads, dwells, checks of values.
fn plain_steps(target: &Target, rng: &mut Rng, y: &mut String) {
    let count = 1 + rng.below(5);
    for _ in 0..count {
        match rng.below(6) {
            0 => step(y, &format!("read: [{}]", rng.pick(target.reads))),
            1 => step(y, &format!("dwell: {} s", 1 + rng.below(20))),
            2 => match (target.text_check, target.sampled) {
                (Some((object, value)), _) => {
                    let want = if rng.chance(20) { "BOOTLOADER" } else { value };
                    step(y, &format!("expect: {{ {object}: {{ equals: \"{want}\" }} }}"));
                }
                (None, Some(object)) => {
                    step(
                        y,
                        &format!("sample: {{ objects: [{object}], every: 200 ms, for: 2 s }}"),
                    );
                    let check = if rng.chance(20) {
                        "above: 200"
                    } else {
                        "below: 200"
                    };
                    step(y, &format!("expect: {{ {object}: {{ mean: {{ {check} }} }} }}"));
                }
                (None, None) => step(y, "dwell: 1 s"),
            },
            3 => step(
                y,
                &format!(
                    "repeat:\n      times: 3\n      steps:\n        - dwell: 1 s\n        - read: [{}]",
                    rng.pick(target.reads)
                ),
            ),
            4 => step(
                y,
                &format!(
                    "attempts:\n      times: 2\n      steps:\n        - read: [{}]\n        - dwell: 500 ms",
                    rng.pick(target.reads)
                ),
            ),
            _ => step(y, &format!("dwell: {} ms", 100 + rng.below(2000))),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn the_same_seed_gives_the_same_recipe_and_others_differ() {
        let t = super::super::target::TARGETS[0];
        let a = recipe(7, &t, &mut Rng::new(7)).yaml;
        assert_eq!(a, recipe(7, &t, &mut Rng::new(7)).yaml);
        let differ = (8..40)
            .filter(|s| recipe(*s, &t, &mut Rng::new(*s)).yaml != a)
            .count();
        assert!(differ > 25, "{differ}");
    }

    #[test]
    fn some_recipes_stop_on_failure_for_the_whole_run_or_a_block_or_watch_the_speed() {
        let t = super::super::target::TARGETS[0];
        let all: Vec<String> = (0..200).map(|s| recipe(s, &t, &mut Rng::new(s)).yaml).collect();
        let top = all
            .iter()
            .filter(|y| y.contains("\non_failure: stop\nsteps:"))
            .count();
        let block = all
            .iter()
            .filter(|y| y.contains("      on_failure: stop"))
            .count();
        let watched = all.iter().filter(|y| y.contains("\nwatch:\n")).count();
        assert!(
            top > 20 && block > 10 && watched > 20,
            "{top} recipe(s), {block} block(s), {watched} watch(es)"
        );
    }
}

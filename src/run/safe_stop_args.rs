//! The command line's choices for the safe stop at the end of every run, over a recipe's
//! (or a script's) own and the defaults. Only settings; the stop itself is the session's.

use crate::dictionary::Quantity;
use crate::recipe::SafeStopChoice;
use crate::run::connection_args::parse_duration;
use crate::run::BadValue;
use crate::session::SafeStopSettings;
use clap::Args;

/// How the safe stop at the end of every run behaves.
#[derive(Debug, Clone, Default, Args)]
#[command(next_help_heading = "Safe stop")]
pub struct SafeStopArgs {
    /// How long the safe stop waits for standstill, setpoint at 0, before it disables
    /// the drive (also before a recipe's own finally) [default: 60s].
    #[arg(long, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub stop_timeout: Option<std::time::Duration>,
    /// Speeds within ± this count as standstill [default: 10rpm].
    #[arg(long, value_name = "SPEED", value_parser = parse_speed)]
    pub standstill: Option<Quantity>,
    /// How long to keep trying to reopen a lost port to deliver the safe stop [default: 10s].
    #[arg(long, hide_short_help = true, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub reconnect_timeout: Option<std::time::Duration>,
    /// Read the status word for fault watching at most this often [default: 250ms].
    #[arg(long, hide_short_help = true, value_name = "DURATION", value_parser = parse_stop_duration)]
    pub fault_poll: Option<std::time::Duration>,
    /// End the run through the safe stop at the first failed check (as `on_failure: stop`
    /// everywhere in the recipe; a failed attempt counts once the attempts are used up);
    /// the steps after it are reported as not run.
    #[arg(short = 'x', long)]
    pub stop_on_failure: bool,
}

impl SafeStopArgs {
    /// The command line's choices on top of the recipe's, on top of the defaults.
    pub fn settings(&self, recipe: &SafeStopChoice) -> SafeStopSettings {
        let d = SafeStopSettings::default();
        SafeStopSettings {
            standstill_timeout: self
                .stop_timeout
                .or(recipe.timeout)
                .unwrap_or(d.standstill_timeout),
            standstill: self.standstill.or(recipe.standstill).unwrap_or(d.standstill),
            brake_to_standstill: recipe.no_brake_at.is_none(),
            reconnect_timeout: self.reconnect_timeout.unwrap_or(d.reconnect_timeout),
            fault_poll: self.fault_poll.unwrap_or(d.fault_poll),
            stop_on_failure: self.stop_on_failure,
        }
    }
}

/// A safe-stop wait from the command line: at least a millisecond, at most a day.
fn parse_stop_duration(text: &str) -> Result<std::time::Duration, BadValue> {
    let d = parse_duration(text)?;
    if d.is_zero() || d > std::time::Duration::from_secs(24 * 3600) {
        return Err(BadValue(format!("`{text}`: give a duration between 1ms and 24h")));
    }
    Ok(d)
}

fn parse_speed(text: &str) -> Result<Quantity, BadValue> {
    let q = Quantity::parse(text).map_err(|e| BadValue(e.to_string()))?;
    match q.unit {
        Some(u) if u.dimension() == crate::dictionary::Dimension::Speed && q.value >= 0.0 => Ok(q),
        _ => Err(BadValue(format!(
            "`{text}`: give a speed with its unit, e.g. 10rpm"
        ))),
    }
}

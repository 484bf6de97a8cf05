//! Opening the named drives of a file (a recipe's `drives:`, a script's `//! drives:`): each drive's dictionary, then one bus
//! per connection — the drives on the command line's connection share ONE bus (one
//! `SharedTransport` or frame bus), so its link serialises their requests; a drive with
//! its own `port:`/`tcp:`/`can:` gets its own. Without a port every drive on the command
//! line's connection is simulated: the drives of one family together on one in-memory
//! line, each answering at its own address, all on one clock. Must not send anything.

use super::connection_args::{CanSpec, ConnectionArgs};
use super::drive_args::DictionaryArgs;
use super::not_run::silent_drive_of;
use super::run_setup::{telegram_outputs, trace_header, SharedTelegrams};
use super::{RunError, RunRequest};
use crate::bus::{
    Bus, BusKind, FramePeer, FramePeerLine, MemoryFrameBus, MemoryTransport, Peer, PeerLine, SharedFrameBus,
    SharedTransport,
};
use crate::clock::{RealClock, SharedClock, VirtualClock};
use crate::dictionary::Dictionary;
use crate::drive::Drive;
use crate::family::{DriveAddress, Family, LinkContext, Registry, SimPeer};
use crate::link::TelegramObserver;
use crate::recipe::DriveDecl;
use crate::sim::SimulatedDrive;
use crate::stop_request::StopRequests;
use std::path::Path;
use std::sync::{Arc, Mutex};

/// The dictionary of every drive a recipe declares, by name; on failure the rendered
/// problem (exit code 2).
pub fn drive_dictionaries(
    args: &DictionaryArgs,
    registry: &Registry,
    recipe: &Path,
    declared: &[(String, String)],
) -> Result<Vec<(String, Arc<Dictionary>)>, RunError> {
    let pole_pairs = crate::recipe::declared_pole_pairs(recipe);
    declared
        .iter()
        .map(|(name, drive)| {
            let dictionary = registry
                .dictionary_for_drive(drive)
                .map_err(|e| RunError::Invalid(format!("error: drive `{name}`: {e}\n")))?;
            // The command line's pole pairs win over the drive's own `pole_pairs:`.
            let own = pole_pairs
                .iter()
                .find(|(n, _)| n == name)
                .map(|(_, p)| (p.clone(), format!("drive `{name}`'s `pole_pairs: {p}`")));
            let one = DictionaryArgs {
                name: dictionary.to_string(),
                pole_pairs: args.pole_pairs.clone().or(own),
                ..args.clone()
            };
            let loaded = one
                .load_for(registry, Some(recipe))
                .map_err(|e| e.of_drive(name))?;
            Ok((name.clone(), loaded))
        })
        .collect()
}

/// The drives of a run, opened, with the simulated ones behind them.
pub struct OpenDrives {
    pub drives: Vec<(String, Drive)>,
    pub simulators: Vec<(String, Arc<Mutex<dyn SimulatedDrive>>)>,
    /// One line per bus for the first line of output.
    pub description: String,
    pub clock: SharedClock,
}

/// Where a drive is: the command line's connection, or its own.
pub(super) fn connection_of(decl: &DriveDecl, line: &ConnectionArgs) -> Result<ConnectionArgs, RunError> {
    let mut args = line.clone();
    if decl.on_command_line_connection() {
        return Ok(args);
    }
    (args.port, args.tcp, args.can) = (decl.port.clone(), decl.tcp.clone(), None);
    if let Some(can) = &decl.can {
        args.can = Some(match can.split_once(':') {
            Some(("slcan", path)) if !path.is_empty() => CanSpec::Slcan(path.to_string()),
            Some(("socketcan", interface)) if !interface.is_empty() => {
                CanSpec::SocketCan(interface.to_string())
            }
            _ => {
                return Err(RunError::Invalid(format!(
                    "drive `{}`: can: {can}: write slcan:PATH or socketcan:IF",
                    decl.name
                )))
            }
        });
    }
    Ok(args)
}

/// The key of the bus a drive is on: drives with equal keys share one bus. Simulated
/// drives of different families cannot share a line (each simulator would read the
/// other's telegrams as noise), so the family is part of a simulated line's key.
fn bus_key(args: &ConnectionArgs, family: &str) -> String {
    match (&args.port, &args.tcp, &args.can) {
        (Some(p), _, _) => format!("port {p}"),
        (_, Some(t), _) => format!("tcp {t}"),
        (_, _, Some(CanSpec::Slcan(p))) => format!("slcan {p}"),
        (_, _, Some(CanSpec::SocketCan(i))) => format!("socketcan {i}"),
        _ => format!("simulated {family}"),
    }
}

/// Opens every declared drive (see the module's contract). `observer` gives each drive's
/// telegram observer. On failure, the message to print (exit code 3; 2 for a wrong
/// address or link setting, which the caller checked before with [`check_drives`]).
#[allow(clippy::too_many_arguments)]
pub fn open_drives(
    registry: &Registry,
    line: &ConnectionArgs,
    decls: &[DriveDecl],
    dictionaries: &[(String, Arc<Dictionary>)],
    virtual_time: bool,
    observer: &mut dyn FnMut(&str) -> Option<Box<dyn TelegramObserver>>,
    stop: Option<Arc<StopRequests>>,
) -> Result<OpenDrives, RunError> {
    let all_simulated = decls.iter().all(|d| d.on_command_line_connection()) && line.is_simulated();
    let clock: SharedClock = if all_simulated && virtual_time {
        Arc::new(VirtualClock::new())
    } else {
        RealClock::shared()
    };
    // (key, bus, simulated peers still to put on it, description)
    let mut buses: Vec<(String, Option<Bus>, Vec<SimPeer>, String)> = Vec::new();
    let mut planned = Vec::new();
    let mut simulators = Vec::new();
    for decl in decls {
        let (dictionary, family, args, address) = placed(registry, line, decl, dictionaries)?;
        let key = bus_key(&args, family.id());
        let index = match buses.iter().position(|b| b.0 == key) {
            Some(i) => i,
            None => {
                let (bus, description) = if args.is_simulated() {
                    (None, String::new())
                } else {
                    let opened = args
                        .open(registry, family.as_ref(), false)
                        .map_err(|e| RunError::Unreachable(format!("error: drive `{}`: {e}", decl.name)))?;
                    let d = opened.bus.name().to_string();
                    (Some(opened.bus), d)
                };
                buses.push((key.clone(), bus, Vec::new(), description));
                buses.len() - 1
            }
        };
        if args.is_simulated() {
            let device = family.simulator(&address, args.sim_config());
            simulators.push((decl.name.clone(), device.drive));
            buses[index].2.push(device.peer);
            let shown = format!("{} {} ({})", decl.name, family.id().to_uppercase(), address.shown);
            let d = &mut buses[index].3;
            d.push_str(if d.is_empty() { "" } else { ", " });
            d.push_str(&shown);
        }
        planned.push((decl.name.clone(), dictionary, family, args, address, index));
    }
    // The simulated lines, now that every simulated drive is known.
    let time = if virtual_time && all_simulated {
        "virtual time"
    } else {
        "real time"
    };
    for (key, bus, peers, description) in &mut buses {
        if bus.is_some() {
            continue;
        }
        let name = format!("built-in simulated line ({key})");
        let mut bytes: Vec<Arc<Mutex<dyn Peer>>> = Vec::new();
        let mut frames: Vec<Arc<Mutex<dyn FramePeer>>> = Vec::new();
        for peer in peers.drain(..) {
            match peer {
                SimPeer::Bytes(p) => bytes.push(p),
                SimPeer::Frames(p) => frames.push(p),
            }
        }
        *bus = Some(if frames.is_empty() {
            let line: Arc<Mutex<dyn Peer>> = Arc::new(Mutex::new(PeerLine(bytes)));
            Bus::Bytes(SharedTransport::new(Box::new(MemoryTransport::new(
                name,
                line,
                clock.clone(),
            ))))
        } else {
            let line: Arc<Mutex<dyn FramePeer>> = Arc::new(Mutex::new(FramePeerLine(frames)));
            Bus::Frames(SharedFrameBus::new(Box::new(MemoryFrameBus::new(
                name,
                line,
                clock.clone(),
            ))))
        });
        *description =
            format!("the built-in simulated drives {description} on one line ({time}; no hardware is moved)");
    }
    let mut drives = Vec::new();
    for (name, dictionary, family, args, address, index) in planned {
        let Some(bus) = buses[index].1.clone() else {
            return Err(RunError::Invalid(format!(
                "error: drive `{name}`: its bus could not be opened"
            )));
        };
        check_bus_kind(family.as_ref(), &bus, &name)?;
        let context = LinkContext {
            clock: clock.clone(),
            observer: observer(&name),
            stop: stop.clone(),
        };
        let access = family
            .open(&bus, &address, &args.link_options(), context)
            .map_err(|e| RunError::Unreachable(format!("error: drive `{name}`: {e}")))?;
        drives.push((name, Drive::new(access, dictionary)));
    }
    let description = buses.iter().map(|b| b.3.clone()).collect::<Vec<_>>().join("; ");
    Ok(OpenDrives {
        drives,
        simulators,
        description,
        clock,
    })
}

/// Where a declared drive is: its dictionary, family, connection (its link settings
/// checked) and address.
type Placed = (Arc<Dictionary>, Arc<dyn Family>, ConnectionArgs, DriveAddress);

/// [`Placed`] for `decl`.
fn placed(
    registry: &Registry,
    line: &ConnectionArgs,
    decl: &DriveDecl,
    dictionaries: &[(String, Arc<Dictionary>)],
) -> Result<Placed, RunError> {
    let dictionary = dictionary_of(dictionaries, &decl.name)?;
    let family = registry
        .family(dictionary.family())
        .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
    let args = connection_of(decl, line)?;
    family
        .check_link_options(&args.link_options().extra)
        .map_err(|e| RunError::Invalid(format!("error: drive `{}`: {e}", decl.name)))?;
    let address = family
        .parse_drive_address(decl.address.as_deref())
        .map_err(|e| RunError::Invalid(format!("error: drive `{}`: {e}", decl.name)))?;
    Ok((dictionary, family, args, address))
}

pub(super) fn dictionary_of(
    dictionaries: &[(String, Arc<Dictionary>)],
    name: &str,
) -> Result<Arc<Dictionary>, RunError> {
    dictionaries
        .iter()
        .find(|(n, _)| n == name)
        .map(|(_, d)| d.clone())
        .ok_or_else(|| RunError::Invalid(format!("error: no dictionary was loaded for drive `{name}`")))
}

fn check_bus_kind(family: &dyn Family, bus: &Bus, name: &str) -> Result<(), RunError> {
    if family.bus_kind() == bus.kind() {
        return Ok(());
    }
    let wanted = match family.bus_kind() {
        BusKind::Frames => "a CAN bus (can: slcan:PATH or socketcan:IF)",
        BusKind::Bytes => "a serial line (port: or tcp:)",
    };
    Err(RunError::Invalid(format!(
        "error: drive `{name}` ({}) needs {wanted}, and its connection {} is not one; give it its own",
        family.id(),
        bus.name()
    )))
}

/// Checks every drive's address and link settings, and that no two drives on one line
/// answer at one address, before anything opens (exit code 2 on a problem).
pub fn check_drives(
    registry: &Registry,
    line: &ConnectionArgs,
    decls: &[DriveDecl],
    dictionaries: &[(String, Arc<Dictionary>)],
) -> Result<(), RunError> {
    let mut seen: Vec<(String, u32, String)> = Vec::new();
    for decl in decls {
        let (_, family, args, address) = placed(registry, line, decl, dictionaries)?;
        let key = bus_key(&args, family.id());
        if let Some((other, _, _)) = seen.iter().find(|(_, n, k)| *n == address.number && *k == key) {
            return Err(RunError::Invalid(format!(
                "error: drives `{other}` and `{}` are both at {} on one line; give each its own `address:`",
                decl.name, address.shown
            )));
        }
        seen.push((decl.name.clone(), address.number, key));
    }
    Ok(())
}

/// Before anything opens, for a run (recipe or script) with several drives: `--fast` only
/// with every drive simulated, each drive's address and link settings, and the one trace
/// for all of them (its telegrams are explained with the first drive's family, so drives
/// of different families are not traced together). On failure, the message (exit code 2).
pub fn named_drives_checked(
    request: &RunRequest,
    connection: &ConnectionArgs,
    decls: &[DriveDecl],
    dictionaries: &[(String, Arc<Dictionary>)],
) -> Result<SharedTelegrams, RunError> {
    let outputs = request.outputs;
    if request.fast && decls.iter().any(|d| !d.on_command_line_connection()) {
        return Err(RunError::Invalid("error: --fast (virtual time) works only when every drive is simulated; a drive with its own port runs in real time".into()));
    }
    if let Some(address) = connection.address_given() {
        return Err(RunError::Invalid(format!(
            "error: {address} names one drive; with several drives each gives its own `address:` (drives: {})",
            decls.iter().map(|d| d.name.as_str()).collect::<Vec<_>>().join(", ")
        )));
    }
    check_drives(request.registry, connection, decls, dictionaries)?;
    let (first, first_dict) = (&dictionaries[0].0, dictionaries[0].1.clone());
    let families: std::collections::BTreeSet<&str> = dictionaries.iter().map(|(_, d)| d.family()).collect();
    if families.len() > 1 && (outputs.trace.is_some() || outputs.verbose) {
        return Err(RunError::Invalid(format!(
            "error: --trace and -v explain the telegrams of one drive family; these drives are of {} (drive `{first}` first)",
            families.into_iter().collect::<Vec<_>>().join(" and ")
        )));
    }
    let family = request
        .registry
        .family(first_dict.family())
        .map_err(|e| RunError::Invalid(format!("error: {e}")))?;
    let addresses = decls
        .iter()
        .map(|d| format!("{} {}", d.name, d.address.as_deref().unwrap_or("(default)")));
    let address = addresses.collect::<Vec<_>>().join(", ");
    let header = trace_header(
        family.as_ref(),
        &first_dict,
        &request.dictionary.extra,
        connection,
        address,
    );
    telegram_outputs(outputs, family.as_ref(), &first_dict, &header).map(SharedTelegrams::new)
}

/// Opens the drives checked by [`named_drives_checked`], says early when one never answers,
/// and hands every simulated drive, in the order declared, to the run's
/// `prepare_simulator`. On failure, the message (exit code 3).
pub fn named_drives_opened(
    request: &RunRequest,
    connection: &ConnectionArgs,
    decls: &[DriveDecl],
    dictionaries: &[(String, Arc<Dictionary>)],
    telegrams: &SharedTelegrams,
) -> Result<OpenDrives, RunError> {
    let mut open = open_drives(
        request.registry,
        connection,
        decls,
        dictionaries,
        request.fast,
        &mut |name| telegrams.tap(name),
        Some(request.stop.clone()),
    )?;
    // A drive that never answers is said once, early, as for one drive.
    for (name, drive) in &mut open.drives {
        if let Err(crate::drive::DriveError::Access(e)) = drive.state() {
            if e.is_no_reply() {
                return Err(RunError::Unreachable(format!(
                    "drive `{name}`: {}",
                    silent_drive_of(request, drive.dictionary(), &e.to_string())
                )));
            }
        }
    }
    if let Some(prepare) = request.prepare_simulator {
        for (_, sim) in &open.simulators {
            prepare(sim, &open.clock);
        }
    }
    Ok(open)
}

//! Run-in benchmark: what a long run costs, each figure as a ratio against its limit.
//!
//! A measurement, not a test (DESIGN: benchmarks report ratios against a stated limit,
//! never a timed assertion in a test). Run with `cargo bench --bench run_in`. It runs the
//! release binary as a user would:
//! - reads/s of `sample` (every 4 ms, faster than the line) and of `repeat` + `read`
//!   through a real pseudo-terminal served by
//!   `drivescript simulate --pty --wire-time` at 57600 bit/s, against the wire limit
//!   `(request + reply bytes) × 10 bit / 57600 bit/s + the simulated drive's 100 µs`
//!   (goal ≥ 97 %). Each rate is taken over the step's own time, as the step reports it.
//!   Beside them: what a bare write/poll/read loop (no engine) reaches through the same
//!   pty, which is the most this rig allows, and how busy the simulator saw the line
//!   (reads, the fault watch's status polls and the run's start and end together);
//! - 24 h of sampling two objects at 100 Hz with `--fast`, without and with `--csv`: the
//!   speed-up over real time (goal ≥ 10 000× without CSV, ≥ 5 000× with it), the peak
//!   resident memory (goal < 30 MB), from `wait4`'s resource usage of the child, and the
//!   CSV's cost: the CPU time with it over the CPU time without (goal ≤ 1.3);
//! - the same day sampling the speed and the motor temperature with a slope check over its
//!   last 10 min, then a `wait_until` stable polled every 10 ms, and the same day measuring
//!   the speed's step response: each one's CPU per second of virtual time over the plain
//!   day's (goal ≤ 1.15: the measures stream), ≥ 10 000× and < 30 MB (bounded buckets);
//!   the day-long runs take turns, three rounds, medians;
//! - values per second of four process values sampled over object access and over the
//!   SD2 cyclic channel, each against its physical maximum (goal ≥ 97 %), over the sample
//!   step's own time, beside what a bare loop reached of its own limit in the same rounds
//!   (the rig's ceiling at the time: a loaded machine lowers both alike);
//! - CPU time per read telegram of `repeat` + `read` against the CPU time of a 20-line
//!   Python/pyserial loop doing the same reads against the same simulated drive (goal
//!   ≤ 1/5), each the median of three runs, split into user space (the program's own
//!   work) and the kernel (the pty's work, the same for any program: a bare loop shows
//!   it). Needs `pip install pyserial`; says so and skips the figure without it.

#[path = "support/child_cost.rs"]
mod child_cost;
#[path = "support/goal.rs"]
mod goal;

use child_cost::{measure_child, Cost};
use drivescript::family::sd2::codec::{Body, Cyclic, Data, ErrorCode, Telegram, WriteLength};
use goal::verdict;
use std::io::{BufRead, BufReader};
use std::path::{Path, PathBuf};
use std::process::{Command, ExitCode, Stdio};
use std::time::{Duration, Instant};

const BAUD: f64 = 57_600.0;
const BITS_PER_BYTE: f64 = 10.0;
/// The simulated drive's reply latency as `simulate` serves it.
const DRIVE_LATENCY: f64 = 100e-6;
/// How long each wire measurement samples or repeats, and how many rounds of them.
const WIRE_SECONDS: u64 = 5;
const WIRE_ROUNDS: usize = 3;

/// The middle value (of an odd count; the upper middle of an even one).
fn median(values: &mut [f64]) -> f64 {
    values.sort_by(f64::total_cmp);
    values.get(values.len() / 2).copied().unwrap_or(f64::NAN)
}

fn binary() -> &'static str {
    env!("CARGO_BIN_EXE_drivescript")
}

fn scratch() -> PathBuf {
    let dir = std::env::temp_dir().join(format!("drivescript-bench-run-in-{}", std::process::id()));
    let _ = std::fs::create_dir_all(&dir);
    dir
}

/// Bytes of the reply to a read of a 4-byte object.
fn read_reply_len() -> usize {
    Telegram {
        dest: 1,
        source: 2,
        body: Body::ReadReply {
            error: ErrorCode::OK,
            data: Data::new(&[0; 4]).unwrap_or_default(),
        },
    }
    .encode(WriteLength::Captured)
    .len()
}

/// The wire limit of one read of a 4-byte object, in reads per second.
fn read_limit() -> f64 {
    let request = Telegram::read_request(2, 1, 398, 0)
        .encode(WriteLength::Captured)
        .len();
    1.0 / ((request + read_reply_len()) as f64 * BITS_PER_BYTE / BAUD + DRIVE_LATENCY)
}

/// Runs `recipe` with `args`; returns its standard output and what it cost.
fn run(recipe: &Path, args: &[&str]) -> Result<(String, Cost), String> {
    let mut command = Command::new(binary());
    // The measurements are of the run, not of a results store in the user's data directory.
    command
        .arg("run")
        .arg(recipe)
        .args(args)
        .args(["--no-progress", "--no-results"]);
    measure_child(command)
}

/// The number before `word` in the first line that has it: `4321 samples`.
fn count_before(text: &str, word: &str) -> Option<f64> {
    text.lines().find_map(|l| {
        let i = l.find(word)?;
        l[..i]
            .split_whitespace()
            .last()?
            .trim_start_matches('(')
            .parse()
            .ok()
    })
}

/// The seconds a step says it took: `… in 10.00 s` (repeat) or `… the step took 10.43 s`
/// (a sample slower than asked).
fn step_seconds(text: &str) -> Option<f64> {
    count_before(text, " s: the line is too slow").or_else(|| {
        text.lines().find_map(|l| {
            let rest = &l[l.find(" iteration(s) in ")? + " iteration(s) in ".len()..];
            rest.split_whitespace().next()?.parse().ok()
        })
    })
}

/// A `drivescript simulate --pty --wire-time`, killed when dropped.
struct Simulator {
    child: std::process::Child,
    path: String,
}

/// CPUs for the CPU comparison: the simulator on one, the program measured on another.
/// Where the scheduler puts two processes that wake each other changes the cost of every
/// wake-up (another CPU's caches, an interrupt between CPUs), and it changes from run to
/// run; fixed places make the three programs' figures comparable. `None` on a machine
/// with one CPU.
fn cpu_places() -> Option<(usize, usize)> {
    (std::thread::available_parallelism().map_or(1, |n| n.get()) >= 2).then_some((0, 1))
}

/// Makes `command` run on `cpu` only.
fn pin(command: &mut Command, cpu: usize) {
    use std::os::unix::process::CommandExt;
    // SAFETY: only sched_setaffinity, which is async-signal-safe, runs in the child
    // between fork and exec.
    unsafe {
        command.pre_exec(move || {
            set_cpu(cpu);
            Ok(())
        });
    }
}

/// Keeps the calling thread (or the process after fork) on `cpu`; returns whether it could.
fn set_cpu(cpu: usize) -> bool {
    // SAFETY: a zeroed cpu_set_t is empty; CPU_SET and sched_setaffinity get valid pointers.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        libc::CPU_SET(cpu, &mut set);
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set) == 0
    }
}

/// Lets the calling thread run on every CPU again.
fn unpin() {
    let n = std::thread::available_parallelism().map_or(1, |n| n.get());
    // SAFETY: as in `set_cpu`.
    unsafe {
        let mut set: libc::cpu_set_t = std::mem::zeroed();
        for cpu in 0..n {
            libc::CPU_SET(cpu, &mut set);
        }
        libc::sched_setaffinity(0, std::mem::size_of::<libc::cpu_set_t>(), &set);
    }
}

/// What the simulator served, from its last line: `stopped after N replies (B bytes
/// received, C bytes sent)`.
struct Served {
    replies: f64,
    bytes: f64,
}

impl Simulator {
    fn start(wire_time: bool) -> Result<Simulator, String> {
        Self::start_on(wire_time, None)
    }

    /// A simulator that runs on `cpu` only (see [`pin`]).
    fn start_on(wire_time: bool, cpu: Option<usize>) -> Result<Simulator, String> {
        let mut command = Command::new(binary());
        if let Some(cpu) = cpu {
            pin(&mut command, cpu);
        }
        let mut child = command
            .args(["simulate", "--pty"])
            .args(wire_time.then_some("--wire-time"))
            .stdout(Stdio::piped())
            .stderr(Stdio::piped())
            .spawn()
            .map_err(|e| format!("cannot start the simulator: {e}"))?;
        let mut line = String::new();
        let out = child.stdout.take().ok_or("no stdout")?;
        BufReader::new(out)
            .read_line(&mut line)
            .map_err(|e| e.to_string())?;
        Ok(Simulator {
            child,
            path: line.trim().to_string(),
        })
    }

    /// Stops the simulator as Ctrl-C would and reads what it says it served.
    fn stop(mut self) -> Result<Served, String> {
        // SAFETY: signalling our own child, which has not been waited for yet.
        unsafe {
            libc::kill(self.child.id() as libc::pid_t, libc::SIGTERM);
        }
        let err = self.child.stderr.take().ok_or("no stderr")?;
        let text: String = BufReader::new(err)
            .lines()
            .map_while(Result::ok)
            .collect::<Vec<_>>()
            .join("\n");
        let replies = count_before(&text, " replies").ok_or_else(|| format!("no reply count in:\n{text}"))?;
        let received = count_before(&text, " bytes received").ok_or("no byte count")?;
        let sent = count_before(&text, " bytes sent").ok_or("no byte count")?;
        Ok(Served {
            replies,
            bytes: received + sent,
        })
    }
}

impl Drop for Simulator {
    fn drop(&mut self) {
        let _ = self.child.kill();
        let _ = self.child.wait();
    }
}

fn main() -> ExitCode {
    goal::exit_of(measure())
}

fn measure() -> Result<(), String> {
    // `cargo bench --bench run_in -- wire cpu` runs only those parts (wire, long,
    // channels, cpu); cargo's own `--bench` flag is not a part.
    let parts: Vec<String> = std::env::args()
        .skip(1)
        .filter(|a| !a.starts_with("--"))
        .collect();
    let wanted = |part: &str| parts.is_empty() || parts.iter().any(|p| p == part);
    let dir = scratch();
    println!("drivescript run-in benchmark (release binary, 2 cores)\n");
    if wanted("wire") {
        wire_rate(&dir)?;
    }
    if wanted("long") {
        long_run(&dir)?;
    }
    if wanted("drift") {
        drift_run(&dir)?;
    }
    if wanted("channels") {
        channels(&dir)?;
    }
    if wanted("cpu") {
        cpu_per_telegram(&dir)?;
    }
    let _ = std::fs::remove_dir_all(&dir);
    Ok(())
}

/// Seconds one telegram exchange takes on the wire with `data` bytes of reply data.
fn exchange_time(request: &Telegram, reply: &Telegram) -> f64 {
    let bytes = request.encode(WriteLength::Captured).len() + reply.encode(WriteLength::Captured).len();
    bytes as f64 * BITS_PER_BYTE / BAUD + DRIVE_LATENCY
}

/// Values per second of the four process values (status word, actual speed, drive error,
/// actual current) sampled over object access (four telegrams per sample) and over the
/// cyclic channel (one), each against its own physical maximum.
fn channels(dir: &Path) -> Result<(), String> {
    let read = |index: u16, size: usize| {
        let reply = Telegram {
            dest: 1,
            source: 2,
            body: Body::ReadReply {
                error: ErrorCode::OK,
                data: Data::new(&vec![0; size]).unwrap_or_default(),
            },
        };
        exchange_time(&Telegram::read_request(2, 1, index, 0), &reply)
    };
    // status_word u16, speed_actual i32, drive_error u16, current_actual i32.
    let object_max = 4.0 / (read(67, 2) + read(398, 4) + read(401, 2) + read(400, 4));
    let cyclic = Telegram {
        dest: 2,
        source: 1,
        body: Body::CyclicRequest(Cyclic::request(0, 0, false)),
    };
    let cyclic_reply = Telegram {
        dest: 1,
        source: 2,
        body: Body::CyclicReply(Cyclic::reply([1, 0], 0, 0, 0, 0)),
    };
    let cyclic_max = 4.0 / exchange_time(&cyclic, &cyclic_reply);
    println!(
        "\nchannels: status word, actual speed, drive error and current sampled through a pty at 57600 bit/s"
    );
    // Every 2 ms asks for more than either channel carries: each of the 1001 samples is
    // taken as soon as the line allows, so the rate is samples over the run's time.
    let recipe = write_recipe(
        dir,
        "four.yaml",
        "name: Four values as fast as the line allows\nsteps:\n  - sample: { objects: [status_word, speed_actual, drive_error, current_actual], every: 2 ms, for: 2 s }\nfinally: []\n",
    )?;
    // The simulator counts the cyclic current in 0.01 A (its own choice; the sources do
    // not give the drive's scaling, so the user states it).
    let cyclic_args = [
        "--channel",
        "cyclic",
        "--velocity-scaling",
        "24000rpm",
        "--link-option",
        "current-scaling=0.01A",
    ];
    let kinds = [
        ("object access", &[][..], object_max),
        ("cyclic channel", &cyclic_args[..], cyclic_max),
    ];
    // The two take turns, so a busy spell of the machine falls on both alike.
    let mut rates: [Vec<f64>; 2] = [Vec::new(), Vec::new()];
    // What the rig allows at the time, beside them: a bare loop's reads against their limit.
    let mut ceilings = Vec::new();
    for _ in 0..WIRE_ROUNDS {
        let sim = Simulator::start(true)?;
        ceilings.push(bare_loop(&sim.path, Load::For(Duration::from_secs(2)))?.rate / read_limit());
        drop(sim);
        for (k, (_, extra, _)) in kinds.iter().enumerate() {
            let sim = Simulator::start(true)?;
            let mut args = vec!["--port", sim.path.as_str()];
            args.extend_from_slice(extra);
            let (out, cost) = run(&recipe, &args)?;
            let n = count_before(&out, " samples").ok_or_else(|| format!("no count in:\n{out}"))?;
            // Over the step's own time, as it reports it (every sample is late: the line
            // is slower than every 2 ms), like the wire rates: the program's start, the
            // dictionary and the safe stop are no channel's time.
            let seconds = step_seconds(&out).unwrap_or(cost.wall.as_secs_f64());
            rates[k].push(4.0 * n / seconds);
        }
    }
    let ceiling = median(&mut ceilings);
    for ((what, _, max), rounds) in kinds.iter().zip(rates.iter_mut()) {
        let rate = median(rounds);
        let ratio = rate / max;
        println!(
            "  {what:<15} {rate:>7.1} values/s = {:>5.1} % of its maximum {max:.0} values/s (goal 97 %)  {}",
            ratio * 100.0,
            verdict(ratio >= 0.97)
        );
        println!(
            "  {:<15} = {:>5.1} % of what the rig allowed meanwhile (below)",
            "",
            ratio / ceiling * 100.0
        );
    }
    println!(
        "  the rig: a bare write/poll/read loop (no engine) reached {:.1} % of its wire limit in the same rounds;",
        ceiling * 100.0
    );
    println!("  a channel short of 97 % by as much as the bare loop is short of 100 % lost it to the machine, not the engine");
    println!("  (median of {WIRE_ROUNDS} rounds over each sample step's own time)");
    println!(
        "  (the cyclic channel's maximum is {:.1}× object access's)",
        cyclic_max / object_max
    );
    Ok(())
}

/// The Python loop the CPU figure compares with: reads one object `n` times.
const PYSERIAL_LOOP: &str = r#"
import serial, sys
port, request, n, reply_len = sys.argv[1], bytes.fromhex(sys.argv[2]), int(sys.argv[3]), int(sys.argv[4])
line = serial.Serial(port, 57600, timeout=1)
for _ in range(n):
    line.reset_input_buffer()
    line.write(request)
    if len(line.read(reply_len)) != reply_len:
        sys.exit("no reply")
"#;

/// How long the bare loop runs.
enum Load {
    For(Duration),
    Reads(u32),
}

/// What the bare loop did.
struct Bare {
    rate: f64,
    user: Duration,
    system: Duration,
}

/// Reads of `speed_actual` by a bare loop in this process, the way a ten-line C program
/// would: write the request, poll, read until the whole reply is there. No engine and no
/// fault watching, so its rate is the most the rig (pty, simulator, scheduler) allows and
/// its CPU the least any program pays for the same system calls.
#[cfg(target_os = "linux")]
fn bare_loop(path: &str, load: Load) -> Result<Bare, String> {
    use std::os::fd::{AsRawFd, FromRawFd, OwnedFd};
    let c_path = std::ffi::CString::new(path).map_err(|e| e.to_string())?;
    // SAFETY: opening a path given as a valid C string.
    let fd = unsafe { libc::open(c_path.as_ptr(), libc::O_RDWR | libc::O_NOCTTY) };
    if fd < 0 {
        return Err(format!("cannot open {path}: {}", std::io::Error::last_os_error()));
    }
    // SAFETY: `fd` was just opened and is owned here alone.
    let fd = unsafe { OwnedFd::from_raw_fd(fd) };
    let raw = fd.as_raw_fd();
    // SAFETY: termios calls on an open descriptor with a zeroed, then filled structure.
    unsafe {
        let mut t: libc::termios = std::mem::zeroed();
        libc::tcgetattr(raw, &mut t);
        libc::cfmakeraw(&mut t);
        libc::cfsetspeed(&mut t, libc::B57600);
        libc::tcsetattr(raw, libc::TCSANOW, &t);
    }
    let request = Telegram::read_request(2, 1, 398, 0).encode(WriteLength::Captured);
    let reply_len = read_reply_len();
    let usage = || {
        // SAFETY: an all-zero rusage is a valid value for getrusage to fill in.
        let mut u: libc::rusage = unsafe { std::mem::zeroed() };
        // SAFETY: this thread's own usage into a valid pointer.
        unsafe { libc::getrusage(libc::RUSAGE_THREAD, &mut u) };
        let time = |t: libc::timeval| Duration::new(t.tv_sec as u64, t.tv_usec as u32 * 1000);
        (time(u.ru_utime), time(u.ru_stime))
    };
    let (user0, system0) = usage();
    let started = Instant::now();
    let mut reads = 0u32;
    let mut buf = [0u8; 64];
    loop {
        match load {
            Load::For(d) if started.elapsed() >= d => break,
            Load::Reads(n) if reads >= n => break,
            _ => {}
        }
        // SAFETY: writing a buffer of its own length to an open descriptor.
        let n = unsafe { libc::write(raw, request.as_ptr().cast(), request.len()) };
        if n != request.len() as isize {
            return Err("the bare loop could not write its request".into());
        }
        let mut got = 0;
        while got < reply_len {
            let mut p = libc::pollfd {
                fd: raw,
                events: libc::POLLIN,
                revents: 0,
            };
            // SAFETY: one valid pollfd.
            if unsafe { libc::poll(&mut p, 1, 1000) } <= 0 {
                return Err("the simulator did not answer the bare loop".into());
            }
            // SAFETY: reading into the rest of a buffer we own.
            let r = unsafe { libc::read(raw, buf[got..].as_mut_ptr().cast(), buf.len() - got) };
            if r > 0 {
                got += r as usize;
            }
        }
        reads += 1;
    }
    let seconds = started.elapsed().as_secs_f64();
    let (user1, system1) = usage();
    Ok(Bare {
        rate: f64::from(reads) / seconds,
        user: user1.saturating_sub(user0),
        system: system1.saturating_sub(system0),
    })
}

#[cfg(not(target_os = "linux"))]
fn bare_loop(_path: &str, _load: Load) -> Result<Bare, String> {
    Err("the bare loop is written for Linux".into())
}

/// The run whose total CPU is the median.
fn median_cost(mut costs: Vec<Cost>) -> Cost {
    costs.sort_by_key(|c| c.user + c.system);
    let middle = costs.len() / 2;
    costs.swap_remove(middle)
}

/// CPU per read telegram of drivescript's `repeat` + `read`, of a pyserial loop and of the
/// bare loop, all against `simulate --pty` without wire time (CPU is what is compared,
/// not the line). Each program's start-up is part of its figure.
fn cpu_per_telegram(dir: &Path) -> Result<(), String> {
    const READS: u32 = 5000;
    const RUNS: usize = 5;
    println!(
        "\nCPU per read telegram, {READS} reads of speed_actual against the same simulated drive (median of {RUNS} runs;"
    );
    println!("the simulator on CPU 0 and the program measured on CPU 1, so that each wake-up costs the same for all)");
    let have_pyserial = Command::new("python3")
        .args(["-c", "import serial"])
        .stderr(Stdio::null())
        .status()
        .is_ok_and(|s| s.success());
    if !have_pyserial {
        println!("  skipped: python3 with pyserial is not installed (pip install pyserial)");
        return Ok(());
    }
    let recipe = write_recipe(
        dir,
        "reads.yaml",
        format!(
            "name: Reads\nsteps:\n  - repeat: {{ times: {READS}, steps: [ {{ read: speed_actual }} ] }}\nfinally: []\n"
        ),
    )?;
    let request = Telegram::read_request(2, 1, 398, 0).encode(WriteLength::Captured);
    let hex: String = request.iter().map(|b| format!("{b:02x}")).collect();
    let reply_len = read_reply_len().to_string();
    let reads = READS.to_string();
    // The three take turns, so a busy spell of the machine falls on all of them alike.
    let (mut ours, mut theirs, mut bares) = (Vec::new(), Vec::new(), Vec::new());
    let places = cpu_places();
    let (sim_cpu, program_cpu) = (places.map(|p| p.0), places.map(|p| p.1));
    for _ in 0..RUNS {
        let sim = Simulator::start_on(false, sim_cpu)?;
        let mut ds = Command::new(binary());
        ds.arg("run")
            .arg(&recipe)
            .args(["--port", &sim.path, "--no-progress", "--no-results"]);
        if let Some(cpu) = program_cpu {
            pin(&mut ds, cpu);
        }
        ours.push(measure_child(ds)?.1);
        drop(sim);
        let sim = Simulator::start_on(false, sim_cpu)?;
        let mut python = Command::new("python3");
        python.args(["-c", PYSERIAL_LOOP, &sim.path, &hex, &reads, &reply_len]);
        if let Some(cpu) = program_cpu {
            pin(&mut python, cpu);
        }
        theirs.push(measure_child(python)?.1);
        drop(sim);
        let sim = Simulator::start_on(false, sim_cpu)?;
        let pinned = program_cpu.is_some_and(set_cpu);
        let bare = bare_loop(&sim.path, Load::Reads(READS));
        if pinned {
            unpin();
        }
        let bare = bare?;
        drop(sim);
        bares.push(Cost {
            wall: Duration::ZERO,
            user: bare.user,
            system: bare.system,
            peak_rss_kb: 0,
        });
    }
    let (ours, theirs, bare) = (median_cost(ours), median_cost(theirs), median_cost(bares));
    let per = |d: Duration| d.as_secs_f64() / f64::from(READS) * 1e6;
    let floor = per(bare.user + bare.system);
    println!("                       all   own work (above the bare loop)   user space / kernel");
    for (what, user, system) in [
        ("drivescript", ours.user, ours.system),
        ("pyserial loop", theirs.user, theirs.system),
        ("bare loop", bare.user, bare.system),
    ] {
        println!(
            "  {what:<14} {:>7.1} µs {:>10.1} µs {:>25.1} / {:.1} µs",
            per(user + system),
            per(user + system) - floor,
            per(user),
            per(system)
        );
    }
    let own = (per(ours.user + ours.system) - floor) / (per(theirs.user + theirs.system) - floor);
    let all = per(ours.user + ours.system) / per(theirs.user + theirs.system);
    println!(
        "  engine CPU per telegram, drivescript / pyserial: {own:.2} of their own work (goal ≤ 0.20)  {}",
        verdict(own <= 0.2)
    );
    println!(
        "  all CPU: {all:.2}. The bare loop's {floor:.1} µs are the pty's system calls and the wake-up for each reply, which every program pays;"
    );
    println!(
        "  own work is what a program spends beyond them. Each figure includes its program's start-up (drivescript's dictionary and"
    );
    println!(
        "  recipe loading, Python's interpreter) and drivescript's fault polls. The user/kernel split is the kernel's tick sampling, rough."
    );
    Ok(())
}

/// Reads per second of `sample` and of `repeat` + `read` through a pty with wire time.
fn wire_rate(dir: &Path) -> Result<(), String> {
    let limit = read_limit();
    println!("wire: reads of a 4-byte object through a pty at 57600 bit/s, limit {limit:.1} reads/s");
    let sample = write_recipe(
        dir,
        "sample.yaml",
        format!(
            "name: Sample as fast as the line allows\nsteps:\n  - sample: {{ objects: [speed_actual], every: 4 ms, for: {WIRE_SECONDS} s }}\nfinally: []\n"
        ),
    )?;
    let repeat = write_recipe(
        dir,
        "repeat.yaml",
        format!(
            "name: Read in a loop\nsteps:\n  - repeat: {{ for: {WIRE_SECONDS} s, steps: [ {{ read: speed_actual }} ] }}\nfinally: []\n"
        ),
    )?;
    // The three measurements take turns, so a busy spell of the machine falls on all of
    // them alike; each figure is the median of its rounds.
    let mut bare_rates = Vec::new();
    let mut runs: [Vec<(f64, f64)>; 2] = [Vec::new(), Vec::new()];
    let kinds = [
        ("sample", &sample, " samples"),
        ("repeat + read", &repeat, " iteration(s)"),
    ];
    for _ in 0..WIRE_ROUNDS {
        let sim = Simulator::start(true)?;
        bare_rates.push(bare_loop(&sim.path, Load::For(Duration::from_secs(WIRE_SECONDS)))?.rate);
        drop(sim);
        for (k, (_, recipe, word)) in kinds.iter().enumerate() {
            let sim = Simulator::start(true)?;
            let (out, cost) = run(recipe, &["--port", &sim.path])?;
            let served = sim.stop()?;
            let n = count_before(&out, word).ok_or_else(|| format!("no count in:\n{out}"))?;
            // Sampling every 4 ms asks for more than the line carries, so the step takes
            // as long as the reads do; its own time leaves out the program's start and end.
            let seconds = step_seconds(&out).unwrap_or(cost.wall.as_secs_f64());
            let busy = (served.bytes * BITS_PER_BYTE / BAUD + served.replies * DRIVE_LATENCY)
                / cost.wall.as_secs_f64();
            runs[k].push((n / seconds, busy));
        }
    }
    let bare = median(&mut bare_rates);
    println!(
        "  bare loop      {bare:>7.1} reads/s = {:>5.1} % of the limit: write, poll, read, no engine; the most this rig allows",
        bare / limit * 100.0
    );
    for ((what, _, _), rounds) in kinds.iter().zip(runs.iter_mut()) {
        let rate = median(&mut rounds.iter().map(|r| r.0).collect::<Vec<_>>());
        let busy = median(&mut rounds.iter().map(|r| r.1).collect::<Vec<_>>());
        let ratio = rate / limit;
        println!(
            "  {what:<14} {rate:>7.1} reads/s = {:>5.1} % of the limit (goal 97 %)  {}",
            ratio * 100.0,
            verdict(ratio >= 0.97)
        );
        println!(
            "  {:<14} = {:>5.1} % of the bare loop; the line was busy {:.1} % of the whole run (reads, status polls, start and end)",
            "",
            rate / bare * 100.0,
            busy * 100.0
        );
    }
    println!("  (median of {WIRE_ROUNDS} rounds of {WIRE_SECONDS} s each)");
    Ok(())
}

/// How many times each day-long variant runs; the variants take turns (A B A B…), so a
/// busy spell of the machine falls on all of them alike, and each figure is a median.
const DAY_ROUNDS: usize = 3;

/// The day at 100 Hz every cost is compared with: two objects, nothing but the run.
const PLAIN_DAY: &str = "name: A day at 100 Hz\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  - sample: { objects: [speed_actual, current_actual], every: 10 ms, for: 24 h }\n";

/// 24 h at 100 Hz in virtual time, without and with CSV; the CSV's cost as the ratio of
/// the two runs' CPU time (goal ≤ 1.3: formatting and buffering once per row).
fn long_run(dir: &Path) -> Result<(), String> {
    println!("\nlong run: 24 h sampling speed_actual and current_actual every 10 ms, --fast");
    let long = write_recipe(dir, "long.yaml", PLAIN_DAY)?;
    let csv = dir.join("long.csv");
    let csv_arg = csv.to_string_lossy().to_string();
    let days = day_figures(&[
        ("without CSV", &long, vec!["--fast"], 10_000.0),
        (
            "with --csv",
            &long,
            vec!["--fast", "--csv", csv_arg.as_str()],
            5_000.0,
        ),
    ])?;
    cost_ratio("CSV", "with --csv / without", &days[1], &days[0], 1.3);
    let _ = std::fs::remove_file(&csv);
    Ok(())
}

/// 24 h at 100 Hz with a drift check over the last 10 min of the day, then a wait until
/// the temperature is stable polled every 10 ms (10 min more: the stretch it needs); and
/// the same day measuring the step response of the speed. Each against the plain day, per
/// second of virtual time (goal ≤ 1.15: the measures stream in constant memory).
fn drift_run(dir: &Path) -> Result<(), String> {
    println!(
        "\ndrift and step response: 24 h sampling speed_actual and motor_temperature every 10 ms, --fast"
    );
    let plain = write_recipe(dir, "plain.yaml", PLAIN_DAY)?;
    let drift = write_recipe(
        dir,
        "drift.yaml",
        "name: A day with a drift check\ndrive: sd2\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  \
         - sample: { objects: [speed_actual, motor_temperature], every: 10 ms, for: 24 h }\n  \
         - expect: { motor_temperature: { slope: { below: 0.5 K/min, over: 10 min } } }\n  \
         - wait_until: { motor_temperature: { slope: { below: 0.5 K/min, over: 10 min } }, timeout: 1 h, every: 10 ms }\n",
    )?;
    let step = write_recipe(
        dir,
        "step.yaml",
        "name: A day with a step response\ndrive: sd2\nsteps:\n  - go_to: operation_enabled\n  - set: { speed_setpoint: 6000 rpm }\n  \
         - sample: { objects: [speed_actual, motor_temperature], every: 10 ms, for: 24 h, step: { speed_actual: { from: 0 rpm, to: 6000 rpm } } }\n  \
         - expect: { speed_actual: { rise_time: { below: 1 min } } }\n  \
         - expect: { speed_actual: { overshoot: { below: 15 % } } }\n  \
         - expect: { speed_actual: { settling_time: { below: 1 min } } }\n",
    )?;
    let days = day_figures(&[
        ("plain day", &plain, vec!["--fast"], 10_000.0),
        ("drift check", &drift, vec!["--fast"], 10_000.0),
        ("step response", &step, vec!["--fast"], 10_000.0),
    ])?;
    cost_ratio("drift", "drift check / plain day", &days[1], &days[0], 1.15);
    cost_ratio(
        "step response",
        "step response / plain day",
        &days[2],
        &days[0],
        1.15,
    );
    Ok(())
}

/// The runs of one variant of a day: CPU time per second of virtual time, each round.
struct Day {
    cpu_per_virtual: Vec<f64>,
}

/// Prints the median ratio of `a`'s CPU per virtual second to `b`'s, round by round
/// (the runs of one round ran side by side in time), against `limit`.
fn cost_ratio(what: &str, label: &str, a: &Day, b: &Day, limit: f64) {
    let mut ratios: Vec<f64> = a
        .cpu_per_virtual
        .iter()
        .zip(&b.cpu_per_virtual)
        .map(|(a, b)| a / b)
        .collect();
    let ratio = median(&mut ratios);
    println!(
        "  {what} cost: CPU per virtual second {label} = {ratio:.3} (goal ≤ {limit:.2}, median of {} pairs)  {}",
        ratios.len(),
        verdict(ratio <= limit)
    );
}

/// The virtual time a run reports on its last line: `… 24h 3s 5ms of virtual time, …`.
fn virtual_seconds(out: &str) -> Option<f64> {
    let line = out.lines().find(|l| l.contains(" of virtual time"))?;
    let before = &line[..line.find(" of virtual time")?];
    let text = before.rsplit(", ").next()?;
    humantime::parse_duration(text.trim())
        .ok()
        .map(|d| d.as_secs_f64())
}

/// Runs each variant `DAY_ROUNDS` times, taking turns, and prints its median speed-up over
/// real time and peak memory against their goals (the speed-up counts the day-long step's
/// 24 h only).
fn day_figures(variants: &[(&str, &Path, Vec<&str>, f64)]) -> Result<Vec<Day>, String> {
    let mut costs: Vec<Vec<Cost>> = variants.iter().map(|_| Vec::new()).collect();
    let mut days: Vec<Day> = variants
        .iter()
        .map(|_| Day {
            cpu_per_virtual: Vec::new(),
        })
        .collect();
    for _ in 0..DAY_ROUNDS {
        for (k, (_, recipe, args, _)) in variants.iter().enumerate() {
            let (out, cost) = run(recipe, args)?;
            if !out.contains("PASSED") {
                return Err(format!("the run did not pass:\n{out}"));
            }
            let seconds = virtual_seconds(&out).ok_or_else(|| format!("no virtual time in:\n{out}"))?;
            days[k]
                .cpu_per_virtual
                .push((cost.user + cost.system).as_secs_f64() / seconds);
            costs[k].push(cost);
        }
    }
    for ((what, _, _, goal), runs) in variants.iter().zip(costs) {
        let mut walls: Vec<f64> = runs.iter().map(|c| c.wall.as_secs_f64()).collect();
        let wall = median(&mut walls);
        let rss_kb = runs.iter().map(|c| c.peak_rss_kb).max().unwrap_or(0);
        let cost = median_cost(runs);
        let speed_up = 24.0 * 3600.0 / wall;
        let rss_mb = rss_kb as f64 / 1024.0;
        println!(
            "  {what:<13} {wall:>7.1} s wall = {speed_up:>7.0}× real time ({:>5.1} % of goal {goal:.0}×)  {}",
            speed_up / goal * 100.0,
            verdict(speed_up >= *goal)
        );
        // On a shared machine the wall clock counts other programs' time too; the CPU time
        // is what the run itself took (a core of its own gets this figure).
        let cpu = (cost.user + cost.system).as_secs_f64().max(1e-6);
        println!(
            "  {what:<13} {cpu:>7.1} s CPU  = {:>7.0}× real time on a core of its own ({:>5.1} % of goal)  {}",
            24.0 * 3600.0 / cpu,
            24.0 * 3600.0 / cpu / goal * 100.0,
            verdict(24.0 * 3600.0 / cpu >= *goal)
        );
        println!(
            "  {what:<13} peak RSS {rss_mb:>6.1} MB ({:>5.1} % of the 30 MB limit)  {}",
            rss_mb / 30.0 * 100.0,
            verdict(rss_mb < 30.0)
        );
    }
    println!("  (median of {DAY_ROUNDS} runs each, the variants taking turns)");
    Ok(days)
}

/// Writes a recipe for a measurement into the scratch folder.
fn write_recipe(dir: &Path, name: &str, text: impl AsRef<str>) -> Result<PathBuf, String> {
    let path = dir.join(name);
    std::fs::write(&path, text.as_ref()).map_err(|e| e.to_string())?;
    Ok(path)
}

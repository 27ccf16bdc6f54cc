//! Loopback fakes of a UR controller and a Robotiq URCap gripper socket, speaking the same protocols as
//! the real ones on `127.0.0.1`, with scripted faults. They record everything they receive so tests can
//! check a run step by step, and so can a user trying a configuration without a robot.
//!
//! - [`FakeController`]: accepts URScript programs on a script port (as the secondary interface does)
//!   and serves RTDE on another (protocol version 2, one output recipe, data at ~250 Hz). A program
//!   "runs" for a short time, then the tool pose becomes the target of its last `movel` and the done
//!   register the value its `write_output_integer_register` writes.
//! - [`FakeGripper`]: answers `SET … → ack` and `GET VAR → VAR n` like the URCap socket: activation
//!   (`STA` 3), requested position echoed in `PRE`, `OBJ` 0 while moving then 3 (or 2 when closing on
//!   an object), `FLT`.
//!
//! What they do not model: the real controller's secondary-interface state stream, program
//! interruption rules, what raises a protective stop (one can only be scripted), and the gripper's
//! timing and object detection physics.

use std::io::{BufRead, BufReader, Read, Write};
use std::net::{TcpListener, TcpStream};
use std::sync::atomic::{AtomicBool, AtomicUsize, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::rtde::{self, RobotState};

/// Faults a [`FakeController`] acts out.
#[derive(Clone, Debug, Default)]
pub struct ControllerFaults {
    /// After receiving this many programs, drop every connection and accept no more (the last one
    /// received never finishes).
    pub disconnect_after_programs: Option<usize>,
    /// The n-th program (1-based) ends in a protective stop (safety mode 3) instead of finishing.
    pub protective_stop_at_program: Option<usize>,
}

#[derive(Debug)]
struct ControllerShared {
    programs: Mutex<Vec<String>>,
    state: Mutex<RobotState>,
    disconnected: AtomicBool,
    shutdown: AtomicBool,
}

/// A fake UR controller on loopback ports.
#[derive(Debug)]
pub struct FakeController {
    script_port: u16,
    rtde_port: u16,
    shared: Arc<ControllerShared>,
}

/// How long a fake program or gripper move takes.
const MOTION_TIME: Duration = Duration::from_millis(5);

fn lock<T>(m: &Mutex<T>) -> std::sync::MutexGuard<'_, T> {
    m.lock().unwrap_or_else(std::sync::PoisonError::into_inner)
}

/// Accepts connections until `stop` says otherwise, handing each to `handle`.
fn accept_loop(
    listener: TcpListener,
    stop: impl Fn() -> bool + Send + 'static,
    mut handle: impl FnMut(TcpStream) + Send + 'static,
) {
    std::thread::spawn(move || {
        let _ = listener.set_nonblocking(true);
        while !stop() {
            match listener.accept() {
                Ok((stream, _)) => {
                    let _ = stream.set_nonblocking(false);
                    handle(stream);
                }
                Err(_) => std::thread::sleep(Duration::from_millis(1)),
            }
        }
    });
}

/// The target of the last `movel(p[…]` in a program, and the token its done-register write sends.
fn parse_program(program: &str) -> (Option<[f64; 6]>, Option<i32>) {
    let target = program.rfind("movel(p[").and_then(|at| {
        let rest = &program[at + "movel(p[".len()..];
        let values: Vec<f64> = rest[..rest.find(']')?]
            .split(',')
            .filter_map(|v| v.trim().parse().ok())
            .collect();
        values.try_into().ok()
    });
    let token = program
        .rfind("write_output_integer_register(")
        .and_then(|at| {
            let rest = &program[at..];
            let inside = &rest[rest.find(',')? + 1..rest.find(')')?];
            inside.trim().parse().ok()
        });
    (target, token)
}

impl FakeController {
    /// Starts the fake on two free loopback ports.
    ///
    /// # Errors
    /// When a port cannot be bound.
    pub fn start(faults: ControllerFaults) -> std::io::Result<Self> {
        let script = TcpListener::bind("127.0.0.1:0")?;
        let rtde_listener = TcpListener::bind("127.0.0.1:0")?;
        let shared = Arc::new(ControllerShared {
            programs: Mutex::new(Vec::new()),
            state: Mutex::new(RobotState {
                runtime_state: 1,
                robot_mode: 7,
                safety_mode: 1,
                ..RobotState::default()
            }),
            disconnected: AtomicBool::new(false),
            shutdown: AtomicBool::new(false),
        });
        let fake = Self {
            script_port: script.local_addr()?.port(),
            rtde_port: rtde_listener.local_addr()?.port(),
            shared: Arc::clone(&shared),
        };

        let stop = {
            let shared = Arc::clone(&shared);
            move || {
                shared.shutdown.load(Ordering::Relaxed)
                    || shared.disconnected.load(Ordering::Relaxed)
            }
        };
        let s = Arc::clone(&shared);
        accept_loop(script, stop.clone(), move |mut stream| {
            let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
            let mut program = String::new();
            let _ = stream.read_to_string(&mut program);
            let count = {
                let mut programs = lock(&s.programs);
                programs.push(program.clone());
                programs.len()
            };
            if faults.disconnect_after_programs == Some(count) {
                s.disconnected.store(true, Ordering::Relaxed);
                return;
            }
            lock(&s.state).runtime_state = 2;
            std::thread::sleep(MOTION_TIME);
            if faults.protective_stop_at_program == Some(count) {
                let mut state = lock(&s.state);
                state.safety_mode = 3;
                state.runtime_state = 4;
                return;
            }
            let (target, token) = parse_program(&program);
            let mut state = lock(&s.state);
            if let Some(pose) = target {
                state.tcp_pose = pose;
            }
            if let Some(token) = token {
                state.done_register = token;
            }
            state.runtime_state = 1;
        });

        let s = Arc::clone(&shared);
        accept_loop(rtde_listener, stop, move |stream| {
            let s = Arc::clone(&s);
            std::thread::spawn(move || serve_rtde(stream, &s));
        });
        Ok(fake)
    }

    /// The script port (stands for 30002).
    pub fn script_port(&self) -> u16 {
        self.script_port
    }

    /// The RTDE port (stands for 30004).
    pub fn rtde_port(&self) -> u16 {
        self.rtde_port
    }

    /// Every program received, in order.
    pub fn programs(&self) -> Vec<String> {
        lock(&self.shared.programs).clone()
    }

    /// The state the fake reports now.
    pub fn state(&self) -> RobotState {
        *lock(&self.shared.state)
    }

    /// Sets the done register as if an earlier session had left a value in it.
    pub fn set_done_register(&self, value: i32) {
        lock(&self.shared.state).done_register = value;
    }
}

impl Drop for FakeController {
    fn drop(&mut self) {
        self.shared.shutdown.store(true, Ordering::Relaxed);
    }
}

fn serve_rtde(mut stream: TcpStream, shared: &ControllerShared) {
    let _ = stream.set_read_timeout(Some(Duration::from_secs(2)));
    let mut recipe_ok = false;
    loop {
        let Ok((kind, payload)) = rtde::read_package(&mut stream) else {
            return;
        };
        let reply = match kind {
            rtde::kind::REQUEST_PROTOCOL_VERSION => {
                vec![u8::from(payload == 2u16.to_be_bytes())]
            }
            rtde::kind::SETUP_OUTPUTS => {
                let names =
                    String::from_utf8_lossy(payload.get(8..).unwrap_or_default()).to_string();
                let known = [
                    "timestamp",
                    "runtime_state",
                    "robot_mode",
                    "safety_mode",
                    "actual_TCP_pose",
                ];
                let types: Vec<String> = names
                    .split(',')
                    .enumerate()
                    .map(|(i, name)| match name {
                        "timestamp" => "DOUBLE".to_string(),
                        "runtime_state" => "UINT32".to_string(),
                        "robot_mode" | "safety_mode" => "INT32".to_string(),
                        "actual_TCP_pose" => "VECTOR6D".to_string(),
                        n if n.starts_with("output_int_register_") && i == known.len() => {
                            "INT32".to_string()
                        }
                        _ => "NOT_FOUND".to_string(),
                    })
                    .collect();
                recipe_ok = names.split(',').count() == known.len() + 1
                    && types.iter().all(|t| t != "NOT_FOUND");
                let mut reply = vec![1u8];
                reply.extend(types.join(",").as_bytes());
                reply
            }
            rtde::kind::START => vec![u8::from(recipe_ok)],
            _ => return,
        };
        if rtde::write_package(&mut stream, kind, &reply).is_err() {
            return;
        }
        if kind == rtde::kind::START && recipe_ok {
            break;
        }
    }
    let started = Instant::now();
    while !shared.shutdown.load(Ordering::Relaxed) && !shared.disconnected.load(Ordering::Relaxed) {
        let mut state = *lock(&shared.state);
        state.timestamp = started.elapsed().as_secs_f64();
        if rtde::write_package(&mut stream, rtde::kind::DATA, &state.encode(1)).is_err() {
            return;
        }
        std::thread::sleep(Duration::from_millis(4));
    }
    let _ = stream.shutdown(std::net::Shutdown::Both);
}

/// Faults a [`FakeGripper`] acts out.
#[derive(Clone, Debug, Default)]
pub struct GripperFaults {
    /// The fingers never report stopping (`OBJ` stays 0).
    pub never_done: bool,
    /// From the n-th move command on (1-based), report this fault code in `FLT`.
    pub fault_at_move: Option<(usize, u8)>,
    /// Closing stops at this position on an object (`OBJ` 2) instead of reaching the request.
    pub object_at: Option<u8>,
}

#[derive(Debug, Default)]
struct GripperState {
    active: bool,
    requested: u8,
    position: u8,
    moving_since: Option<Instant>,
    fault: u8,
    moves: usize,
}

/// A fake Robotiq URCap socket on a loopback port.
#[derive(Debug)]
pub struct FakeGripper {
    port: u16,
    lines: Arc<Mutex<Vec<String>>>,
    shutdown: Arc<AtomicBool>,
    connections: Arc<AtomicUsize>,
}

impl FakeGripper {
    /// Starts the fake on a free loopback port.
    ///
    /// # Errors
    /// When the port cannot be bound.
    pub fn start(faults: GripperFaults) -> std::io::Result<Self> {
        let listener = TcpListener::bind("127.0.0.1:0")?;
        let port = listener.local_addr()?.port();
        let lines = Arc::new(Mutex::new(Vec::new()));
        let shutdown = Arc::new(AtomicBool::new(false));
        let connections = Arc::new(AtomicUsize::new(0));
        let state = Arc::new(Mutex::new(GripperState::default()));
        let (l, s, c) = (
            Arc::clone(&lines),
            Arc::clone(&shutdown),
            Arc::clone(&connections),
        );
        let stop = Arc::clone(&shutdown);
        accept_loop(
            listener,
            move || stop.load(Ordering::Relaxed),
            move |stream| {
                c.fetch_add(1, Ordering::Relaxed);
                let (l, s, state, faults) = (
                    Arc::clone(&l),
                    Arc::clone(&s),
                    Arc::clone(&state),
                    faults.clone(),
                );
                std::thread::spawn(move || serve_gripper(stream, &l, &s, &state, &faults));
            },
        );
        Ok(Self {
            port,
            lines,
            shutdown,
            connections,
        })
    }

    /// The port (stands for 63352).
    pub fn port(&self) -> u16 {
        self.port
    }

    /// Every line received, in order.
    pub fn lines(&self) -> Vec<String> {
        lock(&self.lines).clone()
    }

    /// The `SET` lines received, in order.
    pub fn commands(&self) -> Vec<String> {
        self.lines()
            .into_iter()
            .filter(|l| l.starts_with("SET "))
            .collect()
    }

    /// Connections accepted so far.
    pub fn connections(&self) -> usize {
        self.connections.load(Ordering::Relaxed)
    }
}

impl Drop for FakeGripper {
    fn drop(&mut self) {
        self.shutdown.store(true, Ordering::Relaxed);
    }
}

fn serve_gripper(
    stream: TcpStream,
    lines: &Mutex<Vec<String>>,
    shutdown: &AtomicBool,
    state: &Mutex<GripperState>,
    faults: &GripperFaults,
) {
    let _ = stream.set_read_timeout(Some(Duration::from_millis(50)));
    let Ok(mut writer) = stream.try_clone() else {
        return;
    };
    let mut reader = BufReader::new(stream);
    let mut line = String::new();
    while !shutdown.load(Ordering::Relaxed) {
        line.clear();
        match reader.read_line(&mut line) {
            Ok(0) => return,
            Ok(_) => {}
            Err(_) => continue,
        }
        let request = line.trim().to_string();
        lock(lines).push(request.clone());
        let answer = answer(&request, &mut lock(state), faults);
        if writer.write_all(format!("{answer}\n").as_bytes()).is_err() {
            return;
        }
    }
}

fn answer(request: &str, g: &mut GripperState, faults: &GripperFaults) -> String {
    let words: Vec<&str> = request.split_whitespace().collect();
    match words.as_slice() {
        ["SET", pairs @ ..] if pairs.len() % 2 == 0 && !pairs.is_empty() => {
            let mut go = false;
            for pair in pairs.chunks(2) {
                let Ok(value) = pair[1].parse::<u8>() else {
                    return "?".to_string();
                };
                match pair[0] {
                    "ACT" => g.active = value == 1,
                    "POS" => g.requested = value,
                    "GTO" => go = value == 1,
                    "SPE" | "FOR" | "ATR" | "ADR" => {}
                    _ => return "?".to_string(),
                }
            }
            if go && g.active {
                g.moves += 1;
                g.moving_since = Some(Instant::now());
                if let Some((n, code)) = faults.fault_at_move
                    && g.moves >= n
                {
                    g.fault = code;
                }
            }
            "ack".to_string()
        }
        ["GET", variable] => {
            let done =
                !faults.never_done && g.moving_since.is_some_and(|t| t.elapsed() >= MOTION_TIME);
            let on_object = faults.object_at.filter(|at| g.requested > *at);
            if done {
                g.position = on_object.unwrap_or(g.requested);
            }
            let value = match *variable {
                "STA" => {
                    if g.active {
                        3
                    } else {
                        0
                    }
                }
                "PRE" => u32::from(g.requested),
                "POS" => u32::from(g.position),
                "FLT" => u32::from(g.fault),
                "OBJ" => match (g.moving_since.is_some(), done, on_object.is_some()) {
                    (false, _, _) => 3,
                    (true, false, _) => 0,
                    (true, true, true) => 2,
                    (true, true, false) => 3,
                },
                _ => return "?".to_string(),
            };
            format!("{variable} {value}")
        }
        _ => "?".to_string(),
    }
}

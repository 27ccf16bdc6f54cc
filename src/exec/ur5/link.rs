//! Links that carry robot steps out: [`DryRun`] records them; [`Live`] talks to the controller and the
//! gripper over their documented interfaces.
//!
//! [`Live`] sends each motion program to the secondary interface (a fresh connection per program), reads
//! the robot's state over RTDE on a background thread, and waits until the program's token appears in
//! the done register (also watching the safety mode and the connection). The gripper is driven through
//! the Robotiq URCap socket: `SET POS p SPE s FOR f GTO 1`, then `GET PRE` until it echoes `p` (the
//! request was taken) and `GET OBJ` until the fingers stop (1, 2 or 3), reading `GET FLT` on every poll.
//! Any fault returns at once; the executor sends nothing after it.

use std::io::{BufRead, BufReader, Write};
use std::net::{TcpStream, ToSocketAddrs};
use std::sync::atomic::{AtomicBool, Ordering};
use std::sync::{Arc, Mutex};
use std::time::{Duration, Instant};

use super::config::RobotConfig;
use super::rtde::{self, RobotState};

/// What went wrong on a link, in words for the report.
pub type Fault = String;

/// Something that carries out motion programs and gripper commands.
pub trait RobotLink {
    /// Runs one motion program and waits until it ends: it writes `token` to the done register last.
    /// `expected` is its expected duration, seconds.
    ///
    /// # Errors
    /// A [`Fault`] for a lost connection, a protective stop or a timeout.
    fn run_program(&mut self, program: &str, token: i32, expected: f64) -> Result<(), Fault>;

    /// Sends a gripper command line and waits until the fingers stop; returns the object status
    /// (`OBJ`: 1 or 2 stopped on an object, 3 at the requested position).
    ///
    /// # Errors
    /// A [`Fault`] for a lost connection, a gripper fault (`FLT` ≠ 0) or a timeout.
    fn run_gripper(&mut self, command: &str, position: u8) -> Result<u8, Fault>;

    /// The first token to use: one that cannot be mistaken for the done register's current value.
    fn first_token(&mut self) -> i32 {
        1
    }

    /// The last known state of the robot and gripper, for reports.
    fn last_state(&self) -> String;
}

/// A link that moves nothing: it records the programs and gripper commands it is given.
#[derive(Debug, Default)]
pub struct DryRun {
    /// Programs in the order given.
    pub programs: Vec<String>,
    /// Gripper command lines in the order given.
    pub gripper_commands: Vec<String>,
}

impl RobotLink for DryRun {
    fn run_program(&mut self, program: &str, _token: i32, _expected: f64) -> Result<(), Fault> {
        self.programs.push(program.to_string());
        Ok(())
    }

    fn run_gripper(&mut self, command: &str, _position: u8) -> Result<u8, Fault> {
        self.gripper_commands.push(command.to_string());
        Ok(3)
    }

    fn last_state(&self) -> String {
        "dry run: nothing moved".to_string()
    }
}

/// The live link to a UR controller and a Robotiq gripper.
#[derive(Debug)]
pub struct Live {
    config: RobotConfig,
    state: Arc<Mutex<Option<RobotState>>>,
    rtde_alive: Arc<AtomicBool>,
    stop_reader: Arc<AtomicBool>,
    rtde_stream: TcpStream,
    gripper: BufReader<TcpStream>,
    gripper_state: String,
}

fn seconds(s: f64) -> Duration {
    Duration::from_secs_f64(s.max(1e-3))
}

fn connect(host: &str, port: u16, timeout: f64) -> Result<TcpStream, Fault> {
    let addresses = (host, port)
        .to_socket_addrs()
        .map_err(|e| format!("cannot resolve {host}:{port}: {e}"))?;
    let mut last = format!("no address for {host}:{port}");
    for address in addresses {
        match TcpStream::connect_timeout(&address, seconds(timeout)) {
            Ok(stream) => return Ok(stream),
            Err(e) => last = format!("cannot connect to {address}: {e}"),
        }
    }
    Err(last)
}

impl Live {
    /// Connects to RTDE and the gripper socket, starts the state stream and activates the gripper.
    /// Nothing moves.
    ///
    /// # Errors
    /// A [`Fault`] when a connection, the RTDE handshake or the gripper's activation fails.
    pub fn connect(config: &RobotConfig) -> Result<Self, Fault> {
        let c = &config.controller;
        let t = &config.timeouts;
        let mut rtde_stream = connect(&c.host, c.rtde_port, t.connect)?;
        rtde_stream
            .set_read_timeout(Some(seconds(t.reply)))
            .map_err(|e| e.to_string())?;
        rtde_handshake(&mut rtde_stream, config)?;
        let rtde_handle = rtde_stream.try_clone().map_err(|e| e.to_string())?;

        let state = Arc::new(Mutex::new(None));
        let rtde_alive = Arc::new(AtomicBool::new(true));
        let stop_reader = Arc::new(AtomicBool::new(false));
        {
            let state = Arc::clone(&state);
            let alive = Arc::clone(&rtde_alive);
            let stop = Arc::clone(&stop_reader);
            std::thread::spawn(move || {
                while !stop.load(Ordering::Relaxed) {
                    match rtde::read_package(&mut rtde_stream) {
                        Ok((rtde::kind::DATA, payload)) => {
                            if let Some(s) = RobotState::decode(&payload)
                                && let Ok(mut slot) = state.lock()
                            {
                                *slot = Some(s);
                            }
                        }
                        Ok(_) => {}
                        Err(_) => break,
                    }
                }
                alive.store(false, Ordering::Relaxed);
            });
        }

        let gripper_stream = match connect(&c.host, c.gripper_port, t.connect) {
            Ok(stream) => stream,
            Err(fault) => {
                stop_reader.store(true, Ordering::Relaxed);
                let _ = rtde_handle.shutdown(std::net::Shutdown::Both);
                return Err(fault);
            }
        };
        gripper_stream
            .set_read_timeout(Some(seconds(t.reply)))
            .map_err(|e| e.to_string())?;
        let mut link = Self {
            config: config.clone(),
            state,
            rtde_alive,
            stop_reader,
            rtde_stream: rtde_handle,
            gripper: BufReader::new(gripper_stream),
            gripper_state: "gripper not yet read".to_string(),
        };
        link.activate_gripper()?;
        Ok(link)
    }

    fn latest(&self) -> Option<RobotState> {
        self.state.lock().ok().and_then(|s| *s)
    }

    /// Sends one line to the gripper socket and reads its one-line answer.
    fn gripper_request(&mut self, line: &str) -> Result<String, Fault> {
        let stream = self.gripper.get_mut();
        stream
            .write_all(format!("{line}\n").as_bytes())
            .map_err(|e| format!("gripper socket: sending `{line}` failed: {e}"))?;
        let mut answer = String::new();
        match self.gripper.read_line(&mut answer) {
            Ok(0) => Err(format!("gripper socket closed after `{line}`")),
            Ok(_) => Ok(answer.trim().to_string()),
            Err(e) => Err(format!("gripper socket: no answer to `{line}`: {e}")),
        }
    }

    fn gripper_get(&mut self, variable: &str) -> Result<i64, Fault> {
        let answer = self.gripper_request(&format!("GET {variable}"))?;
        answer
            .strip_prefix(variable)
            .and_then(|rest| rest.trim().parse().ok())
            .ok_or_else(|| format!("gripper socket: `GET {variable}` answered `{answer}`"))
    }

    fn gripper_set(&mut self, command: &str) -> Result<(), Fault> {
        let answer = self.gripper_request(command)?;
        if answer == "ack" {
            Ok(())
        } else {
            Err(format!(
                "gripper socket: `{command}` answered `{answer}`, not `ack`"
            ))
        }
    }

    fn check_fault(&mut self) -> Result<(), Fault> {
        let fault = self.gripper_get("FLT")?;
        if fault != 0 {
            return Err(format!("gripper fault FLT {fault}"));
        }
        Ok(())
    }

    fn activate_gripper(&mut self) -> Result<(), Fault> {
        if self.gripper_get("STA")? == 3 {
            return Ok(());
        }
        self.gripper_set("SET ACT 1")?;
        let deadline = Instant::now() + seconds(self.config.timeouts.gripper);
        loop {
            self.check_fault()?;
            let status = self.gripper_get("STA")?;
            self.gripper_state = format!("gripper STA {status}");
            if status == 3 {
                return Ok(());
            }
            if Instant::now() > deadline {
                return Err(format!(
                    "gripper did not activate within {} s (STA {status})",
                    self.config.timeouts.gripper
                ));
            }
            std::thread::sleep(Duration::from_millis(10));
        }
    }
}

impl Drop for Live {
    fn drop(&mut self) {
        self.stop_reader.store(true, Ordering::Relaxed);
        let _ = self.rtde_stream.shutdown(std::net::Shutdown::Both);
        let _ = self.gripper.get_ref().shutdown(std::net::Shutdown::Both);
    }
}

fn rtde_handshake(stream: &mut TcpStream, config: &RobotConfig) -> Result<(), Fault> {
    let io = |e: std::io::Error| format!("RTDE handshake: {e}");
    let expect = |stream: &mut TcpStream, kind: u8| -> Result<Vec<u8>, Fault> {
        loop {
            let (k, payload) = rtde::read_package(stream).map_err(io)?;
            if k == kind {
                return Ok(payload);
            }
            if k != rtde::kind::TEXT_MESSAGE {
                return Err(format!(
                    "RTDE handshake: expected package `{}`, got `{}`",
                    kind as char, k as char
                ));
            }
        }
    };
    rtde::write_package(
        stream,
        rtde::kind::REQUEST_PROTOCOL_VERSION,
        &2u16.to_be_bytes(),
    )
    .map_err(io)?;
    if expect(stream, rtde::kind::REQUEST_PROTOCOL_VERSION)?.first() != Some(&1) {
        return Err("RTDE: the controller refused protocol version 2".to_string());
    }
    let outputs = rtde::outputs(config.controller.done_register);
    let names: Vec<String> = outputs.iter().map(|(n, _)| n.clone()).collect();
    rtde::write_package(
        stream,
        rtde::kind::SETUP_OUTPUTS,
        &rtde::setup_outputs_payload(config.controller.rtde_frequency, &names),
    )
    .map_err(io)?;
    let answer = expect(stream, rtde::kind::SETUP_OUTPUTS)?;
    let types = String::from_utf8_lossy(answer.get(1..).unwrap_or_default()).to_string();
    let expected: Vec<&str> = outputs.iter().map(|(_, t)| *t).collect();
    if types.split(',').collect::<Vec<_>>() != expected {
        return Err(format!(
            "RTDE: output recipe {names:?} answered types `{types}`, expected {expected:?} (an \
             `IN_USE` register is taken by another client or a URCap)"
        ));
    }
    rtde::write_package(stream, rtde::kind::START, &[]).map_err(io)?;
    if expect(stream, rtde::kind::START)?.first() != Some(&1) {
        return Err("RTDE: the controller refused to start the stream".to_string());
    }
    Ok(())
}

impl RobotLink for Live {
    fn first_token(&mut self) -> i32 {
        let deadline = Instant::now() + seconds(self.config.timeouts.reply);
        while Instant::now() < deadline {
            if let Some(state) = self.latest() {
                return state.done_register.wrapping_add(1).max(1);
            }
            std::thread::sleep(Duration::from_millis(2));
        }
        1
    }

    fn run_program(&mut self, program: &str, token: i32, expected: f64) -> Result<(), Fault> {
        let c = &self.config.controller;
        if !self.rtde_alive.load(Ordering::Relaxed) {
            return Err("RTDE connection lost before sending".to_string());
        }
        let mut script = connect(&c.host, c.script_port, self.config.timeouts.connect)?;
        script
            .write_all(program.as_bytes())
            .and_then(|()| script.flush())
            .map_err(|e| format!("secondary interface: sending the program failed: {e}"))?;
        drop(script);
        let limit = expected + self.config.timeouts.motion_margin;
        let deadline = Instant::now() + seconds(limit);
        loop {
            if let Some(state) = self.latest() {
                // 1 normal, 2 reduced; anything else is a stop of some kind (3 protective,
                // 5 safeguard, 6 and 7 emergency, 8 violation, 9 fault).
                if !matches!(state.safety_mode, 1 | 2) {
                    return Err(format!(
                        "safety mode {} (a protective, safeguard or emergency stop)",
                        state.safety_mode
                    ));
                }
                if state.done_register == token {
                    return Ok(());
                }
            }
            if !self.rtde_alive.load(Ordering::Relaxed) {
                return Err("RTDE connection lost while waiting for the motion".to_string());
            }
            if Instant::now() > deadline {
                return Err(format!(
                    "motion not finished within {limit:.1} s (token {token} never appeared)"
                ));
            }
            std::thread::sleep(Duration::from_millis(2));
        }
    }

    fn run_gripper(&mut self, command: &str, position: u8) -> Result<u8, Fault> {
        self.gripper_set(command)?;
        let deadline = Instant::now() + seconds(self.config.timeouts.gripper);
        let mut taken = false;
        loop {
            self.check_fault()?;
            if !taken {
                taken = self.gripper_get("PRE")? == i64::from(position);
            }
            if taken {
                let object = self.gripper_get("OBJ")?;
                self.gripper_state = format!("gripper requested {position}, OBJ {object}");
                if (1..=3).contains(&object) {
                    return u8::try_from(object).map_err(|e| e.to_string());
                }
            }
            if Instant::now() > deadline {
                return Err(format!(
                    "gripper did not finish `{command}` within {} s ({})",
                    self.config.timeouts.gripper, self.gripper_state
                ));
            }
            std::thread::sleep(Duration::from_millis(5));
        }
    }

    fn last_state(&self) -> String {
        let robot = self
            .latest()
            .map_or_else(|| "no RTDE data yet".to_string(), |s| s.describe());
        format!("{robot}; {}", self.gripper_state)
    }
}

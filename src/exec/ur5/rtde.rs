//! The parts of Universal Robots' RTDE protocol (port 30004, protocol version 2) the executor uses,
//! for both ends: the client here and the loopback fake in `fake.rs`.
//!
//! A package is `u16 size` (whole package, big-endian) · `u8 type` · payload. The client asks for
//! protocol version 2 (`V`), sets up an output recipe (`O`: `f64` frequency and comma-separated
//! variable names; the answer is a recipe id and the comma-separated types), starts (`S`), and then
//! receives data packages (`U`: recipe id, then each variable big-endian in recipe order).
//!
//! Why RTDE and not the real-time stream on 30003: RTDE's packages are declared by name and type in the
//! handshake, so they do not change with the controller's software version, while the 30003 packet is a
//! fixed byte layout that Universal Robots has changed between versions.

use std::io::{Read, Write};

/// Package types used.
pub mod kind {
    /// Request protocol version.
    pub const REQUEST_PROTOCOL_VERSION: u8 = b'V';
    /// Set up the output recipe.
    pub const SETUP_OUTPUTS: u8 = b'O';
    /// Start the data stream.
    pub const START: u8 = b'S';
    /// A data package.
    pub const DATA: u8 = b'U';
    /// A text message from the controller.
    pub const TEXT_MESSAGE: u8 = b'M';
}

/// The variables the executor reads, in recipe order, with their RTDE types.
pub fn outputs(done_register: u8) -> Vec<(String, &'static str)> {
    vec![
        ("timestamp".to_string(), "DOUBLE"),
        ("runtime_state".to_string(), "UINT32"),
        ("robot_mode".to_string(), "INT32"),
        ("safety_mode".to_string(), "INT32"),
        ("actual_TCP_pose".to_string(), "VECTOR6D"),
        (format!("output_int_register_{done_register}"), "INT32"),
    ]
}

/// The robot's state as the executor reads it.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
pub struct RobotState {
    /// Controller time, seconds.
    pub timestamp: f64,
    /// Program state: 1 stopped, 2 playing, 4 paused (others are transitions).
    pub runtime_state: u32,
    /// Robot mode: 7 running.
    pub robot_mode: i32,
    /// Safety mode: 1 normal, 3 protective stop, 6/7 emergency stops.
    pub safety_mode: i32,
    /// Tool centre point pose `[x, y, z, rx, ry, rz]`, base frame.
    pub tcp_pose: [f64; 6],
    /// The done register.
    pub done_register: i32,
}

impl RobotState {
    /// Encodes the state as a data package payload for output recipe `recipe`, for the fake
    /// controller.
    pub fn encode(&self, recipe: u8) -> Vec<u8> {
        let mut payload = vec![recipe];
        payload.extend(self.timestamp.to_be_bytes());
        payload.extend(self.runtime_state.to_be_bytes());
        payload.extend(self.robot_mode.to_be_bytes());
        payload.extend(self.safety_mode.to_be_bytes());
        for v in self.tcp_pose {
            payload.extend(v.to_be_bytes());
        }
        payload.extend(self.done_register.to_be_bytes());
        payload
    }

    /// Decodes a data package payload laid out by [`outputs`].
    pub fn decode(payload: &[u8]) -> Option<Self> {
        let mut at = 1;
        let mut take = |n: usize| {
            let bytes = payload.get(at..at + n)?;
            at += n;
            Some(bytes)
        };
        let f64_at = |b: &[u8]| b.try_into().ok().map(f64::from_be_bytes);
        let timestamp = f64_at(take(8)?)?;
        let runtime_state = u32::from_be_bytes(take(4)?.try_into().ok()?);
        let robot_mode = i32::from_be_bytes(take(4)?.try_into().ok()?);
        let safety_mode = i32::from_be_bytes(take(4)?.try_into().ok()?);
        let mut tcp_pose = [0.0; 6];
        for v in &mut tcp_pose {
            *v = f64_at(take(8)?)?;
        }
        let done_register = i32::from_be_bytes(take(4)?.try_into().ok()?);
        Some(Self {
            timestamp,
            runtime_state,
            robot_mode,
            safety_mode,
            tcp_pose,
            done_register,
        })
    }

    /// One line for error reports.
    pub fn describe(&self) -> String {
        let p = self.tcp_pose;
        format!(
            "runtime_state {}, robot_mode {}, safety_mode {}, tcp ({:.4}, {:.4}, {:.4}) m, done register {}",
            self.runtime_state,
            self.robot_mode,
            self.safety_mode,
            p[0],
            p[1],
            p[2],
            self.done_register
        )
    }
}

/// Writes one package.
///
/// # Errors
/// The stream's error.
pub fn write_package(stream: &mut impl Write, kind: u8, payload: &[u8]) -> std::io::Result<()> {
    let size = u16::try_from(payload.len() + 3)
        .map_err(|_| std::io::Error::other("RTDE package too large"))?;
    let mut bytes = Vec::with_capacity(payload.len() + 3);
    bytes.extend(size.to_be_bytes());
    bytes.push(kind);
    bytes.extend_from_slice(payload);
    stream.write_all(&bytes)
}

/// Reads one package: its type and payload.
///
/// # Errors
/// The stream's error; `UnexpectedEof` when the peer closed the connection.
pub fn read_package(stream: &mut impl Read) -> std::io::Result<(u8, Vec<u8>)> {
    let mut header = [0u8; 3];
    stream.read_exact(&mut header)?;
    let size = usize::from(u16::from_be_bytes([header[0], header[1]]));
    if size < 3 {
        return Err(std::io::Error::other(format!(
            "RTDE package of size {size} < 3"
        )));
    }
    let mut payload = vec![0u8; size - 3];
    stream.read_exact(&mut payload)?;
    Ok((header[2], payload))
}

/// The payload of an output setup request: frequency and comma-separated names.
pub fn setup_outputs_payload(frequency: f64, names: &[String]) -> Vec<u8> {
    let mut payload = frequency.to_be_bytes().to_vec();
    payload.extend(names.join(",").as_bytes());
    payload
}

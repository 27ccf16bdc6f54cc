//! URScript for motion steps, and the readable listings of a dry run.
//!
//! Each motion step is one program sent to the secondary interface: it sets the tool centre point,
//! runs its `movel`s (each blocks until the move ends) and last writes a token to an output integer
//! register, which the executor reads over RTDE to know the step is done. Numbers are printed with
//! fixed decimals so a program is the same bytes on every machine (the golden-file test relies on it).

use std::fmt::Write;

use super::config::RobotConfig;
use super::motion::{Action, LinearMove, Step};

/// A UR pose literal with five decimals (10 µm, 10 µrad); values that round to zero print as `0.00000`,
/// never `-0.00000`.
fn pose_literal(values: [f64; 6]) -> String {
    let parts: Vec<String> = values
        .iter()
        .map(|v| {
            let v = if v.abs() < 5e-6 { 0.0 } else { *v };
            format!("{v:.5}")
        })
        .collect();
    format!("p[{}]", parts.join(", "))
}

/// The URScript program of a motion step (`None` for a gripper step): `index` names the program and
/// `token` is written to the done register at its end.
pub fn program(config: &RobotConfig, step: &Step, index: usize, token: i32) -> Option<String> {
    match &step.action {
        Action::Move { moves } => Some(motion_program(config, &step.label, moves, index, token)),
        Action::Gripper { .. } => None,
    }
}

/// The URScript program that runs `moves` and then writes `token` to the done register.
pub fn motion_program(
    config: &RobotConfig,
    label: &str,
    moves: &[LinearMove],
    index: usize,
    token: i32,
) -> String {
    let mut text = String::new();
    let _ = writeln!(text, "def pushmog_step_{index:04}():");
    let _ = writeln!(text, "  # {label}");
    let _ = writeln!(text, "  set_tcp({})", pose_literal(config.tcp));
    for m in moves {
        let [x, y, z] = m.to.position;
        let [rx, ry, rz] = m.to.rotation;
        let blend = if m.blend > 0.0 {
            format!(", r={:.4}", m.blend)
        } else {
            String::new()
        };
        let _ = writeln!(
            text,
            "  movel({}, a={:.3}, v={:.3}{blend})",
            pose_literal([x, y, z, rx, ry, rz]),
            m.acceleration,
            m.speed
        );
    }
    let _ = writeln!(
        text,
        "  write_output_integer_register({}, {token})",
        config.controller.done_register
    );
    let _ = writeln!(text, "end");
    text
}

/// The URCap socket line of a gripper step (`None` for a motion step).
pub fn gripper_command(step: &Step) -> Option<String> {
    match step.action {
        Action::Gripper {
            position,
            speed,
            force,
        } => Some(gripper_line(position, speed, force)),
        Action::Move { .. } => None,
    }
}

/// The URCap socket line that moves the fingers to `position` with `speed` and `force`.
pub fn gripper_line(position: u8, speed: u8, force: u8) -> String {
    format!("SET POS {position} SPE {speed} FOR {force} GTO 1")
}

/// Every step of a run as one listing: the motion programs in order (tokens 1, 2, …) with each
/// gripper command as a comment where it is sent. This is what a dry run writes as `program.script`.
pub fn listing(config: &RobotConfig, steps: &[Step]) -> String {
    let mut text = String::from(
        "# pushmog: URScript of every motion step, in order. Each `def` is sent alone to the secondary\n\
         # interface; gripper commands go to the Robotiq URCap socket and are shown as comments.\n",
    );
    let mut token = 0;
    for (index, step) in steps.iter().enumerate() {
        text.push('\n');
        if let Some(command) = gripper_command(step) {
            let _ = writeln!(text, "# step {index}: {}", step.label);
            let _ = writeln!(text, "# gripper: {command}");
        } else {
            token += 1;
            let _ = writeln!(text, "# step {index}");
            if let Some(program) = program(config, step, index, token) {
                text.push_str(&program);
            }
        }
    }
    text
}

/// A readable list of the steps: index, label and what is commanded.
pub fn step_list(steps: &[Step]) -> String {
    let mut text = String::new();
    for (index, step) in steps.iter().enumerate() {
        match &step.action {
            Action::Gripper {
                position,
                speed,
                force,
            } => {
                let _ = writeln!(
                    text,
                    "{index:4}  {}\n      gripper position {position}, speed {speed}, force {force}",
                    step.label
                );
            }
            Action::Move { moves } => {
                let _ = writeln!(text, "{index:4}  {}", step.label);
                for m in moves {
                    let [x, y, z] = m.to.position;
                    let blend = if m.blend > 0.0 {
                        format!(", on through a {:.1} mm blend", m.blend * 1e3)
                    } else {
                        String::new()
                    };
                    let _ = writeln!(
                        text,
                        "      movel to ({:.1}, {:.1}, {:.1}) mm at {:.0} mm/s{blend}",
                        x * 1e3,
                        y * 1e3,
                        z * 1e3,
                        m.speed * 1e3
                    );
                }
            }
        }
    }
    text
}

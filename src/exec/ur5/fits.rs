//! Whether a planned trip fits the gripper the robot file describes.
//!
//! A plan is made for the gripper of its scenes (`scene.gripper`); the robot drives the one measured
//! in `[gripper]` of the robot file. With `t` the configured plate thickness and `g_open`, `g_closed`
//! the measured gaps between the pads fully open and fully closed, the jaws can stand with their
//! plate centres `o ∈ [g_closed + t, g_open + t]` apart. A trip fits when
//! - the plan's plates are the configured ones, `|t_plan − t| ≤ ε`;
//! - the plan's stroke (the widest opening it may assume) is at most `g_open + t + ε`;
//! - every fork push's opening and the grasp's opening lie in that range, widened by `ε`;
//! - the grasp closes on a row at least `g_closed − ε` wide (the pads cannot close further).
//!
//! `ε` is [`FIT_TOLERANCE`]. Anything else would drive the robot to openings the plan did not assume.

use super::config::GripperConfig;
use crate::error::{Error, Result};
use crate::grasp::Grasp;
use crate::push::Push;
use crate::scene::Gripper;

/// Slack of the comparison, metres: a position count of the 2F-85 moves the pads about 0.4 mm
/// (its position resolution), and calibration readings are good to about a millimetre.
pub const FIT_TOLERANCE: f64 = 0.001;

/// Checks trip `trip` (1-based, for the message): `planned` is its scene's gripper; `grasp` is `None`
/// when only pushes are to be checked (the closed loop checks each push before it is sent).
///
/// # Errors
/// [`Error::InvalidField`] naming the trip and the robot file's field that does not fit.
pub fn check_trip_fits(
    config: &GripperConfig,
    planned: &Gripper,
    pushes: &[Push],
    grasp: Option<&Grasp>,
    trip: usize,
) -> Result<()> {
    let refuse = |field: &str, reason: String| {
        Err(Error::field(
            "robot config",
            format!("gripper.{field}"),
            format!("trip {trip}: {reason}"),
        ))
    };
    let widest = config.open_gap + config.plate_thickness;
    let narrowest = config.closed_gap + config.plate_thickness;
    let mm = |v: f64| v * 1e3;
    if (planned.plate_thickness - config.plate_thickness).abs() > FIT_TOLERANCE {
        return refuse(
            "plate_thickness",
            format!(
                "the plan's plates are {:.1} mm thick, the robot's {:.1} mm",
                mm(planned.plate_thickness),
                mm(config.plate_thickness)
            ),
        );
    }
    if planned.stroke > widest + FIT_TOLERANCE {
        return refuse(
            "open_gap",
            format!(
                "the plan assumes jaws that open {:.1} mm between plate centres; the robot's open \
                 to {:.1} mm (open_gap + plate_thickness)",
                mm(planned.stroke),
                mm(widest)
            ),
        );
    }
    let openings = pushes
        .iter()
        .enumerate()
        .map(|(k, p)| (format!("push {}", k + 1), p.fork.opening))
        .chain(grasp.map(|g| ("the grasp".to_string(), g.jaws.opening)));
    for (what, opening) in openings {
        if opening > widest + FIT_TOLERANCE {
            return refuse(
                "open_gap",
                format!(
                    "{what} opens the jaws {:.1} mm between plate centres; the robot's open to \
                     {:.1} mm",
                    mm(opening),
                    mm(widest)
                ),
            );
        }
        if opening < narrowest - FIT_TOLERANCE {
            return refuse(
                "closed_gap",
                format!(
                    "{what} sets the jaws {:.1} mm apart between plate centres; the robot's close \
                     no further than {:.1} mm",
                    mm(opening),
                    mm(narrowest)
                ),
            );
        }
    }
    if let Some(grasp) = grasp
        && grasp.width < config.closed_gap - FIT_TOLERANCE
    {
        return refuse(
            "closed_gap",
            format!(
                "the grasp closes on a row {:.1} mm wide; the robot's pads stop {:.1} mm apart",
                mm(grasp.width),
                mm(config.closed_gap)
            ),
        );
    }
    Ok(())
}

//! The crate's error type. `Err` means misuse or an environment fault (invalid input, I/O); a planner
//! that finds no answer reports that as a status inside `Ok`.

use std::path::PathBuf;

use crate::id::ObjectId;

/// Everything that can go wrong in pushmog, each variant naming the culprit.
#[derive(Debug, thiserror::Error)]
#[non_exhaustive]
pub enum Error {
    /// One field of one object is invalid.
    #[error("object {id} (entry {index} of `objects`): field `{field}`: {reason}")]
    InvalidObject {
        /// The object's id.
        id: ObjectId,
        /// Its position in the `objects` list.
        index: usize,
        /// The offending field (`vertices`, `pose`, `height`, `mass`).
        field: &'static str,
        /// What is wrong with it.
        reason: String,
    },
    /// Two objects share an id.
    #[error("object id {id} is used twice: entries {first} and {second} of `objects`")]
    DuplicateId {
        /// The repeated id.
        id: ObjectId,
        /// Position of the first use.
        first: usize,
        /// Position of the second use.
        second: usize,
    },
    /// Two objects overlap at their poses.
    #[error(
        "objects {first} and {second} overlap: they interpenetrate by {:.3} mm (field `pose`)",
        depth * 1e3
    )]
    Overlap {
        /// One object.
        first: ObjectId,
        /// The other.
        second: ObjectId,
        /// Penetration depth in metres.
        depth: f64,
    },
    /// A field of a component other than an object (workspace, gripper, a settings struct) is invalid.
    #[error("{component}: field `{field}`: {reason}")]
    InvalidField {
        /// The component (`workspace`, `gripper`, `generator`, …).
        component: String,
        /// The offending field.
        field: String,
        /// What is wrong with it.
        reason: String,
    },
    /// A setting asks for a part this build left out: a Cargo feature it was not compiled with.
    #[error("{component}: field `{field}`: {reason}")]
    NotCompiled {
        /// The component whose setting asks for it.
        component: String,
        /// The setting.
        field: String,
        /// The Cargo feature that would provide it.
        feature: &'static str,
        /// What is missing and how to build it in.
        reason: String,
    },
    /// A call out of order: an executor asked to act before it was given a table (`reset`).
    #[error("{component}: {reason}")]
    Misuse {
        /// What was misused.
        component: String,
        /// Which call was missing or out of order.
        reason: String,
    },
    /// A JSON document could not be read into the expected type.
    #[error("{source_name}: invalid JSON at line {line}, column {column}{}: {message}",
        if path.is_empty() || path == "." { String::new() } else { format!(" (at `{path}`)") })]
    Json {
        /// Where the document came from (a file path or `<stdin>`).
        source_name: String,
        /// 1-based line of the error.
        line: usize,
        /// 1-based column of the error.
        column: usize,
        /// Path of the offending field inside the document, e.g. `objects[3].vertices[1]`.
        path: String,
        /// What the parser says.
        message: String,
    },
    /// The scene generator could not place all objects.
    #[error(
        "scene generator: placed only {placed} of {requested} objects after {samples} samples: circles \
         of radius {:.1} mm do not fit the {:.3} m × {:.3} m workspace; use a larger workspace or fewer \
         objects",
        radius * 1e3, width, depth
    )]
    Placement {
        /// Objects asked for.
        requested: usize,
        /// Objects placed before giving up.
        placed: usize,
        /// Position samples drawn in total.
        samples: usize,
        /// Radius in metres of the circle kept clear around each object.
        radius: f64,
        /// Workspace width (x extent) in metres.
        width: f64,
        /// Workspace depth (y extent) in metres.
        depth: f64,
    },
    /// A robot motion was refused before anything was sent: it leaves the safety envelope or exceeds
    /// the speed limit.
    #[error("step {step} ({label}) refused before sending anything: {reason}")]
    UnsafeMotion {
        /// Index of the refused step in the step list (0-based).
        step: usize,
        /// The step's description.
        label: String,
        /// What limit it breaks.
        reason: String,
    },
    /// The robot link stopped mid-run: a lost connection, a gripper fault or a timeout. Nothing was
    /// sent after the failing step.
    #[error(
        "robot stopped at step {step} ({label}): {reason}; {completed} step(s) completed; last known \
         state: {last_state}"
    )]
    RobotStopped {
        /// Index of the failing step (0-based).
        step: usize,
        /// The step's description.
        label: String,
        /// What went wrong.
        reason: String,
        /// Steps completed before it.
        completed: usize,
        /// The last state read from the controller and the gripper.
        last_state: String,
    },
    /// A trip was refused before anything of it was sent: the independent verifier found it wrong
    /// (`Run::verify_before_acting`).
    #[error("trip {trip}: refused before acting: the verifier says {reason}")]
    Refused {
        /// The trip (0-based).
        trip: usize,
        /// The verifier's first finding.
        reason: String,
    },
    /// A file is held by another process (an experiment log another `pushmog experiment` writes).
    #[error("{}: {reason}", path.display())]
    Busy {
        /// The file.
        path: PathBuf,
        /// Who holds it and what to do.
        reason: String,
    },
    /// Reading or writing a file failed.
    #[error("{}: {source}", path.display())]
    Io {
        /// The file.
        path: PathBuf,
        /// The operating system's error.
        source: std::io::Error,
    },
}

/// `Result` with the crate's [`Error`].
pub type Result<T> = std::result::Result<T, Error>;

/// Checks that `value` is a finite number in `[low, high]`; otherwise an [`Error::InvalidField`]
/// naming the component, the field, the range and `why` it is bounded.
///
/// # Errors
/// As described.
pub fn in_range(
    component: &str,
    field: &str,
    value: f64,
    range: (f64, f64),
    why: &str,
) -> Result<()> {
    if value.is_finite() && value >= range.0 && value <= range.1 {
        return Ok(());
    }
    Err(Error::field(
        component,
        field,
        format!(
            "must be between {} and {} ({why}), got {}",
            number(range.0),
            number(range.1),
            number(value)
        ),
    ))
}

/// A number as a message shows it: plainly between 10⁻⁴ and 10⁹ (and 0), else in scientific
/// notation, so `1e300` is not printed as three hundred digits.
pub fn number(value: f64) -> String {
    let size = value.abs();
    if size == 0.0 || !size.is_finite() || (1e-4..1e9).contains(&size) {
        format!("{value}")
    } else {
        format!("{value:e}")
    }
}

/// Checks that a count lies in `[low, high]`; otherwise an [`Error::InvalidField`] worded as
/// [`in_range`]'s.
///
/// # Errors
/// As described.
pub fn count_in_range(
    component: &str,
    field: &str,
    value: usize,
    range: (usize, usize),
    why: &str,
) -> Result<()> {
    bounded(component, field, value, true, range, why)
}

/// `Ok` when `value` is `valid` and within `[low, high]`, else the error of [`in_range`].
fn bounded<T: PartialOrd + std::fmt::Display>(
    component: &str,
    field: &str,
    value: T,
    valid: bool,
    (low, high): (T, T),
    why: &str,
) -> Result<()> {
    if valid && value >= low && value <= high {
        Ok(())
    } else {
        Err(Error::field(
            component,
            field,
            format!("must be between {low} and {high} ({why}), got {value}"),
        ))
    }
}

impl Error {
    /// An [`Error::Misuse`]: `reason` says which call was missing or out of order.
    pub fn misuse(component: impl Into<String>, reason: impl Into<String>) -> Self {
        Self::Misuse {
            component: component.into(),
            reason: reason.into(),
        }
    }

    /// An [`Error::InvalidField`] for a component other than an object.
    pub fn field(
        component: impl Into<String>,
        field: impl Into<String>,
        reason: impl Into<String>,
    ) -> Self {
        Self::InvalidField {
            component: component.into(),
            field: field.into(),
            reason: reason.into(),
        }
    }
}

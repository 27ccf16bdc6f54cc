//! What one solve of the clustering model returned: shared by the solver (`milp/`) and the
//! merging of independent parts (`decompose.rs`), so neither depends on the other's internals.

use crate::outcome::Status;

/// What one solver call (or the merge of several) returned.
pub(super) struct Solved {
    /// The solver's status.
    pub status: Status,
    /// Positions of the chosen candidates, ascending.
    pub chosen: Vec<usize>,
    /// Positions of the chosen rides among the model's rides (`riders.rs`), ascending.
    pub riding: Vec<usize>,
    /// Best bound on the objective, when known.
    pub bound: Option<f64>,
    /// Relative gap, when known.
    pub gap: Option<f64>,
    /// Branch-and-bound nodes, when known.
    pub nodes: Option<u64>,
    /// LP iterations, when known.
    pub iterations: Option<u64>,
    /// The backend's own words.
    pub backend_status: String,
}

impl Solved {
    /// The answer for a table with nothing on it: no clusters, proven optimal at cost 0.
    pub fn empty() -> Self {
        Self {
            status: Status::Optimal,
            chosen: Vec::new(),
            riding: Vec::new(),
            bound: Some(0.0),
            gap: Some(0.0),
            nodes: Some(0),
            iterations: Some(0),
            backend_status: "empty scene".to_string(),
        }
    }
}

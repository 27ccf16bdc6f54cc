//! A planner's answer together with how it was obtained.

use serde::{Deserialize, Serialize};

/// How good an answer is, in the planner's own terms.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
pub enum Status {
    /// A heuristic answer: valid, with no optimality claim.
    Heuristic,
    /// Proven optimal for the stated model.
    Optimal,
    /// The best of a search over a sampled set of choices (axes, orders), each solved to its own
    /// optimum: no claim over the choices not sampled.
    BestFound,
    /// Valid, with a gap to the best bound.
    Feasible,
    /// The time limit ended the search; the answer is the best found.
    TimeLimit,
    /// The node limit ended the search; the answer is the best found.
    NodeLimit,
    /// No valid answer exists for the stated model.
    Infeasible,
    /// The planner could not produce an answer; the reason says why.
    Failed {
        /// Why.
        reason: String,
    },
}

/// Measurements of one planner call.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize)]
pub struct Stats {
    /// Wall-clock time, seconds.
    pub seconds: f64,
    /// Objective value, when the planner has one.
    pub objective: Option<f64>,
    /// Best bound on the objective, when known.
    pub bound: Option<f64>,
    /// Relative gap between the objective and the bound, when known.
    pub gap: Option<f64>,
    /// The backend's own status string, kept verbatim.
    pub backend_status: Option<String>,
    /// Named counts (splits, candidates evaluated, iterations, …).
    pub counters: Vec<(String, f64)>,
}

impl Stats {
    /// The value of a named counter, if recorded.
    pub fn counter(&self, name: &str) -> Option<f64> {
        self.counters
            .iter()
            .find(|(key, _)| key == name)
            .map(|(_, value)| *value)
    }
}

/// A planner's answer with its status and measurements.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Outcome<T> {
    /// The answer.
    pub value: T,
    /// How good it is.
    pub status: Status,
    /// How it was obtained.
    pub stats: Stats,
}

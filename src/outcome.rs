//! A planner's answer together with how it was obtained.

use serde::{Deserialize, Serialize};

/// How good an answer is, in the planner's own terms. More statuses may come: match with a wildcard
/// arm, or ask [`Status::is_proven`] and [`Status::has_answer`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(rename_all = "snake_case")]
#[non_exhaustive]
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

impl Status {
    /// Whether the answer is proven optimal for the stated model: only [`Status::Optimal`]. An
    /// answer cut short by a time or node limit, a heuristic one, or the best of a sampled search
    /// is not.
    pub fn is_proven(&self) -> bool {
        matches!(self, Self::Optimal)
    }

    /// The name in files (`optimal`, `best_found`, `time_limit`, …), as serde writes it.
    pub fn name(&self) -> &'static str {
        match self {
            Self::Heuristic => "heuristic",
            Self::Optimal => "optimal",
            Self::BestFound => "best_found",
            Self::Feasible => "feasible",
            Self::TimeLimit => "time_limit",
            Self::NodeLimit => "node_limit",
            Self::Infeasible => "infeasible",
            Self::Failed { .. } => "failed",
        }
    }

    /// Whether the planner gave a valid answer (every status but [`Status::Infeasible`] and
    /// [`Status::Failed`]).
    pub fn has_answer(&self) -> bool {
        !matches!(self, Self::Infeasible | Self::Failed { .. })
    }
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

/// What a planner can claim of its answers: whether one can be proven optimal, and the time after
/// which it answers with the best found so far. Experiment logs write the abilities of each policy's
/// planners in their header, so that a reader of a table knows which statuses its runs could have.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct Abilities {
    /// The planner's name, as its `name()` gives it (`milp`, `socp`, `multi-object`, …).
    pub name: String,
    /// Whether an answer can carry [`Status::Optimal`].
    pub proves_optimality: bool,
    /// Seconds of search after which the planner answers with the best found
    /// ([`Status::TimeLimit`]); `None`: every search runs to its end.
    pub time_limit: Option<f64>,
}

impl Abilities {
    /// A planner that claims no optimum and has no time limit, as heuristics.
    pub fn heuristic(name: &str) -> Self {
        Self {
            name: name.to_string(),
            proves_optimality: false,
            time_limit: None,
        }
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

#[cfg(test)]
mod tests {
    use super::Status;

    #[test]
    fn only_optimal_is_proven_and_only_failures_have_no_answer() {
        let all = [
            Status::Heuristic,
            Status::Optimal,
            Status::BestFound,
            Status::Feasible,
            Status::TimeLimit,
            Status::NodeLimit,
            Status::Infeasible,
            Status::Failed {
                reason: "why".to_string(),
            },
        ];
        let proven: Vec<bool> = all.iter().map(Status::is_proven).collect();
        assert_eq!(
            proven,
            [false, true, false, false, false, false, false, false]
        );
        let answered: Vec<bool> = all.iter().map(Status::has_answer).collect();
        assert_eq!(answered, [true, true, true, true, true, true, false, false]);
        for status in &all {
            let written = serde_json::to_value(status).unwrap();
            let key = match &written {
                serde_json::Value::String(name) => name.clone(),
                serde_json::Value::Object(map) => map.keys().next().unwrap().clone(),
                other => panic!("{other}"),
            };
            assert_eq!(status.name(), key);
        }
    }
}

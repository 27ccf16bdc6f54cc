//! The clustering model split into independent parts (`formulations/clustering.md`, "Independent
//! parts").
//!
//! Two objects are tied when one candidate holds both, when a candidate holding one clashes with
//! a candidate holding the other, or when one may ride on a row that holds the other. The classes
//! of the ties (connected components, by union–find) are independent: no row of the model holds
//! variables of two classes, so the model's optimum is the union of the classes' optima, its
//! objective their sum, and it is proven optimal when every part is. Branch and bound on the whole
//! model multiplies the parts' search trees together; solved one by one, a table of 1000 objects
//! is hundreds of small models.

use super::riders::RideVar;
use super::solved::Solved;
use crate::outcome::Status;

/// One independent part of the model, with its candidates renumbered from 0.
#[derive(Clone, Debug)]
pub(super) struct Part {
    /// Scene indices of the part's objects, ascending.
    pub objects: Vec<usize>,
    /// Positions of the part's candidates in the whole model, ascending.
    pub global: Vec<usize>,
    /// The candidates (scene indices of their members).
    pub candidates: Vec<Vec<usize>>,
    /// Their costs.
    pub costs: Vec<f64>,
    /// For each of the part's objects, the part's candidates that hold it.
    pub covering: Vec<Vec<usize>>,
    /// Clashing pairs of the part's candidates.
    pub clashes: Vec<(usize, usize)>,
    /// The warm start's candidates in the part.
    pub warm: Vec<usize>,
    /// The part's rides, their row and single renumbered as the part's candidates.
    pub rides: Vec<RideVar>,
    /// Positions of the part's rides in the whole model, ascending.
    pub rides_global: Vec<usize>,
}

fn root(parent: &mut [usize], mut i: usize) -> usize {
    while parent[i] != i {
        parent[i] = parent[parent[i]];
        i = parent[i];
    }
    i
}

fn join(parent: &mut [usize], a: usize, b: usize) {
    let (a, b) = (root(parent, a), root(parent, b));
    if a != b {
        parent[a.max(b)] = a.min(b);
    }
}

/// The independent parts of the model over `objects` objects, in order of their first object.
/// With one part, its candidates, costs, clashes and warm start equal the whole model's.
pub(super) fn parts(
    objects: usize,
    candidates: &[Vec<usize>],
    costs: &[f64],
    clashes: &[(usize, usize)],
    warm: &[usize],
    rides: &[RideVar],
) -> Vec<Part> {
    let mut parent: Vec<usize> = (0..objects).collect();
    for candidate in candidates {
        for pair in candidate.windows(2) {
            join(&mut parent, pair[0], pair[1]);
        }
    }
    for &(a, b) in clashes {
        if let (Some(&x), Some(&y)) = (candidates[a].first(), candidates[b].first()) {
            join(&mut parent, x, y);
        }
    }
    for ride in rides {
        if let (Some(&x), Some(&y)) = (
            candidates[ride.row].first(),
            candidates[ride.single].first(),
        ) {
            join(&mut parent, x, y);
        }
    }
    let roots: Vec<usize> = (0..objects).map(|i| root(&mut parent, i)).collect();
    // Parts numbered by their first object.
    let mut number = vec![usize::MAX; objects];
    let mut parts: Vec<Part> = Vec::new();
    for (i, &r) in roots.iter().enumerate() {
        if number[r] == usize::MAX {
            number[r] = parts.len();
            parts.push(Part {
                objects: Vec::new(),
                global: Vec::new(),
                candidates: Vec::new(),
                costs: Vec::new(),
                covering: Vec::new(),
                clashes: Vec::new(),
                warm: Vec::new(),
                rides: Vec::new(),
                rides_global: Vec::new(),
            });
        }
        parts[number[r]].objects.push(i);
    }
    let mut local = vec![0usize; candidates.len()];
    let mut part_of = vec![usize::MAX; candidates.len()];
    for (k, candidate) in candidates.iter().enumerate() {
        let Some(&first) = candidate.first() else {
            continue;
        };
        let p = number[roots[first]];
        part_of[k] = p;
        local[k] = parts[p].candidates.len();
        parts[p].global.push(k);
        parts[p].candidates.push(candidate.clone());
        parts[p].costs.push(costs[k]);
    }
    for &(a, b) in clashes {
        if part_of[a] != usize::MAX {
            parts[part_of[a]].clashes.push((local[a], local[b]));
        }
    }
    for &k in warm {
        if part_of[k] != usize::MAX {
            parts[part_of[k]].warm.push(local[k]);
        }
    }
    for (global, ride) in rides.iter().enumerate() {
        let p = part_of[ride.row];
        if p != usize::MAX {
            parts[p].rides.push(RideVar {
                row: local[ride.row],
                single: local[ride.single],
                ..*ride
            });
            parts[p].rides_global.push(global);
        }
    }
    for part in &mut parts {
        let row: std::collections::HashMap<usize, usize> = part
            .objects
            .iter()
            .enumerate()
            .map(|(r, &o)| (o, r))
            .collect();
        part.covering = vec![Vec::new(); part.objects.len()];
        for (k, candidate) in part.candidates.iter().enumerate() {
            for o in candidate {
                part.covering[row[o]].push(k);
            }
        }
    }
    parts
}

impl Part {
    /// The answer without a solve when the part has one candidate holding all its objects (the only
    /// partition there is).
    pub fn trivial(&self) -> Option<Solved> {
        (self.candidates.len() == 1 && self.candidates[0].len() == self.objects.len()).then(|| {
            Solved {
                status: Status::Optimal,
                chosen: vec![0],
                riding: Vec::new(),
                bound: Some(self.costs[0]),
                gap: Some(0.0),
                nodes: Some(0),
                iterations: Some(0),
                backend_status: "one candidate".to_string(),
            }
        })
    }
}

/// How far a status is from a proof, for reporting the weakest part.
fn weakness(status: &Status) -> u8 {
    match status {
        Status::Optimal => 0,
        Status::BestFound => 1,
        Status::Feasible => 2,
        Status::Heuristic => 3,
        Status::NodeLimit => 4,
        Status::TimeLimit => 5,
        Status::Infeasible => 6,
        Status::Failed { .. } => 7,
    }
}

/// The whole model's answer from its parts' (chosen positions in the whole model), and how many
/// parts fell back to their warm start. With one part, that part's answer unchanged (an empty choice
/// stays empty, and the caller falls back as a whole); with several, a part whose solve chose nothing
/// keeps its warm start (the heuristic's clusters there); with none (an empty table), the empty
/// clustering.
pub(super) fn merge(solved: Vec<(Part, Solved)>) -> (Solved, usize) {
    if solved.is_empty() {
        return (Solved::empty(), 0);
    }
    if solved.len() == 1 {
        let (part, mut answer) = solved.into_iter().next().expect("one part");
        answer.chosen = answer.chosen.iter().map(|&k| part.global[k]).collect();
        answer.riding = answer
            .riding
            .iter()
            .map(|&k| part.rides_global[k])
            .collect();
        return (answer, 0);
    }
    let count = solved.len();
    let proven = solved
        .iter()
        .filter(|(_, s)| s.status == Status::Optimal)
        .count();
    let weakest = solved
        .iter()
        .max_by_key(|(_, s)| weakness(&s.status))
        .map(|(_, s)| (s.status.clone(), s.backend_status.clone()));
    let sum = |values: Vec<Option<f64>>| values.into_iter().sum::<Option<f64>>();
    let bound = sum(solved.iter().map(|(_, s)| s.bound).collect());
    // The largest relative gap of a part bounds the relative gap of the sum.
    let gap = solved
        .iter()
        .map(|(_, s)| s.gap)
        .try_fold(0.0f64, |worst, g| g.map(|g| worst.max(g)));
    let nodes = solved.iter().map(|(_, s)| s.nodes).sum::<Option<u64>>();
    let iterations = solved
        .iter()
        .map(|(_, s)| s.iterations)
        .sum::<Option<u64>>();
    let mut chosen: Vec<usize> = Vec::new();
    let mut riding: Vec<usize> = Vec::new();
    let mut fell_back = 0;
    for (part, answer) in &solved {
        let local = if answer.chosen.is_empty() {
            fell_back += 1;
            &part.warm
        } else {
            riding.extend(answer.riding.iter().map(|&k| part.rides_global[k]));
            &answer.chosen
        };
        chosen.extend(local.iter().map(|&k| part.global[k]));
    }
    chosen.sort_unstable();
    riding.sort_unstable();
    let (status, weakest_backend) = weakest.expect("at least two parts");
    let merged = Solved {
        backend_status: if status == Status::Optimal {
            format!("{count} independent parts, each proven optimal")
        } else {
            format!(
                "{count} independent parts, {proven} proven optimal; weakest: {weakest_backend}"
            )
        },
        status,
        chosen,
        riding,
        bound,
        gap,
        nodes,
        iterations,
    };
    (merged, fell_back)
}

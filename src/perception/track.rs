//! Ids kept across looks: each object seen takes the id of the prior's object whose centroid is
//! nearest, within a gate, pairs taken shortest first (greedy matching; with objects further apart
//! than twice the gate it is the optimal assignment). The prior is the last look or, better, the
//! scene the planner predicted after the trip's pushes: a pushed object moves further than the gate,
//! but its predicted place does not.

use nalgebra::Point2;

use crate::id::ObjectId;
use crate::scene::Scene;

/// For each of `seen`, the prior's id it takes, if any; and the prior's ids that nothing took.
pub fn match_prior(
    seen: &[Point2<f64>],
    prior: &Scene,
    gate: f64,
) -> (Vec<Option<ObjectId>>, Vec<ObjectId>) {
    let mut pairs: Vec<(f64, usize, usize)> = Vec::new();
    for (i, p) in seen.iter().enumerate() {
        for k in prior.near(p, gate) {
            let d = nalgebra::distance(p, &prior.centroid(k));
            if d <= gate {
                pairs.push((d, i, k));
            }
        }
    }
    pairs.sort_by(|a, b| a.0.total_cmp(&b.0));
    let mut taken = vec![None; seen.len()];
    let mut used = vec![false; prior.len()];
    for (_, i, k) in pairs {
        if taken[i].is_none() && !used[k] {
            taken[i] = Some(prior.objects()[k].id);
            used[k] = true;
        }
    }
    let gone = prior
        .objects()
        .iter()
        .zip(&used)
        .filter(|(_, u)| !**u)
        .map(|(o, _)| o.id)
        .collect();
    (taken, gone)
}

//! Pushing ahead (`pricing.push_ahead`): a trip grasps one cluster as it lies and, before that grasp,
//! pushes another cluster into a row for a later trip. The look before the next trip, which every
//! trip makes anyway, shows how the pushed row came out, so the pushes need no look of their own:
//! by the time model a one-push pair then costs its push alone (about 7.9 s) instead of the push and a
//! look (about 9.6 s), and the pushes of a second cluster in the same trip would find the jaws at the
//! fork opening already (`formulations/picks-per-hour.md`).
//!
//! Each trip, in order:
//! 1. the grasp: the row the last trip pushed ahead, grasped as it now lies when the multi-object
//!    planner finds a grasp of two or more of it; otherwise a cluster chosen at random, grasped as
//!    it lies (two or more together, else one by itself), and the row that did not come out is the
//!    first tried for pushes ahead again;
//! 2. the pushes ahead: other clusters of two or more, nearest the grasp first (at most
//!    [`AHEAD_TRIES`] tried), the first whose pushes are planned with a multi-object grasp after
//!    them, pay by the price without a look and with the travel from them to the trip's grasp
//!    (under the expected-time objective), move nothing the trip's grasp takes, and leave that grasp
//!    standing on the table predicted after them (it is planned again there).
//!
//! When the cluster chosen in step 1 cannot be grasped as it lies, the trip is planned as without
//! pushing ahead.

use super::trip::TripContext;
use super::{Policy, PolicyPusher, TripPlan};
use crate::cluster::Clustering;
use crate::error::Result;
use crate::grasp::Grasp;
use crate::push::predict;
use crate::scene::{ObjectId, Scene};

/// A trip's grasp and the position of its cluster in the clustering.
type ChosenGrasp = (Option<usize>, Grasp);

/// Clusters tried for pushes ahead in one trip: each try plans pushes (an SOCP per axis and order
/// for push-mog-opt) and a multi-object grasp, so the number bounds a trip's planning time.
pub const AHEAD_TRIES: usize = 4;

impl Policy {
    /// The trip described in the module docs; `None` when the chosen cluster cannot be grasped as it
    /// lies.
    pub(super) fn draft_ahead(
        &self,
        pusher: &dyn PolicyPusher,
        observed: &Scene,
        clustering: &Clustering,
        candidates: &[usize],
        context: &mut TripContext,
    ) -> Result<Option<TripPlan>> {
        let (chosen, unformed) =
            self.grasp_as_it_lies(observed, clustering, candidates, context)?;
        let Some((cluster, grasp)) = chosen else {
            return Ok(None);
        };
        let mut others: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&k| {
                let members = &clustering.clusters[k];
                members.len() >= 2 && members.iter().all(|id| !grasp.objects.contains(id))
            })
            .collect();
        // Nearest first: the arm travels from the pushes to the grasp.
        let centre = |k: usize| {
            let members = &clustering.clusters[k];
            let sum: nalgebra::Vector2<f64> = members
                .iter()
                .filter_map(|&id| observed.index_of(id))
                .map(|i| observed.centroid(i).coords)
                .sum();
            nalgebra::Point2::from(sum / members.len() as f64)
        };
        let mut by_distance: Vec<(f64, usize)> = others
            .iter()
            .map(|&k| (nalgebra::distance(&centre(k), &grasp.jaws.center), k))
            .collect();
        by_distance.sort_by(|a, b| a.0.total_cmp(&b.0));
        others = by_distance.into_iter().map(|(_, k)| k).collect();
        // A row pushed ahead that did not come out graspable is pushed again first.
        let again = (unformed.len() >= 2 && unformed.iter().all(|id| !grasp.objects.contains(id)))
            .then_some(unformed);
        let tries: Vec<Vec<ObjectId>> = again
            .into_iter()
            .chain(others.into_iter().map(|k| clustering.clusters[k].clone()))
            .take(AHEAD_TRIES)
            .collect();
        let mut skipped = Vec::new();
        for members in &tries {
            let (pushed, why_not) =
                self.push_draft(pusher, observed, members, context, (1, false, Some(&grasp)))?;
            skipped.extend(why_not);
            let Some((pushes, later, judged)) = pushed else {
                continue;
            };
            let touches = |id: &ObjectId| grasp.objects.contains(id);
            if pushes.iter().any(|p| touches(&p.object)) || later.objects.iter().any(touches) {
                continue;
            }
            let predicted = predict(observed, &pushes)?;
            let Some(standing) = self.grasp_again(&predicted, &grasp, context)? else {
                continue;
            };
            context.ahead.clone_from(&later.objects);
            return Ok(Some(TripPlan {
                clustering: clustering.clone(),
                cluster,
                pushes,
                skipped_pushes: skipped,
                grasp: standing,
                judged: Some(judged),
                ahead: later.objects,
            }));
        }
        Ok(Some(TripPlan {
            clustering: clustering.clone(),
            cluster,
            pushes: Vec::new(),
            skipped_pushes: skipped,
            grasp,
            judged: None,
            ahead: Vec::new(),
        }))
    }

    /// Step 1 of the module docs: the row pushed ahead, else a random cluster, grasped as it lies;
    /// with the position of its cluster in `clustering`, and the row pushed ahead when it could
    /// not be grasped together (else empty).
    fn grasp_as_it_lies(
        &self,
        observed: &Scene,
        clustering: &Clustering,
        candidates: &[usize],
        context: &mut TripContext,
    ) -> Result<(Option<ChosenGrasp>, Vec<ObjectId>)> {
        let avoid = context.failed.clone();
        let waiting: Vec<ObjectId> = std::mem::take(&mut context.ahead)
            .into_iter()
            .filter(|&id| observed.index_of(id).is_some())
            .collect();
        if waiting.len() >= 2 {
            let outcome = self
                .multi
                .plan_several(observed, &waiting, &[], &[], &avoid)?;
            if let Some(grasp) = outcome.value.filter(|g| context.together(g)) {
                let cluster = clustering
                    .clusters
                    .iter()
                    .position(|c| grasp.objects.iter().any(|id| c.contains(id)));
                return Ok((Some((cluster, grasp)), Vec::new()));
            }
        }
        let chosen = candidates[context.rng.index(candidates.len())];
        let members = &clustering.clusters[chosen];
        let together = self
            .multi
            .plan_several(observed, members, &[], &[], &avoid)?
            .value
            .filter(|g| context.together(g));
        let grasp = match together {
            Some(grasp) => Some(grasp),
            None => self.single.plan_avoiding(observed, members, &avoid)?.value,
        };
        Ok((grasp.map(|grasp| (Some(chosen), grasp)), waiting))
    }

    /// `grasp` planned again on `predicted` (the table after pushes elsewhere), its jaws offered
    /// first: the same objects, or `None`.
    fn grasp_again(
        &self,
        predicted: &Scene,
        grasp: &Grasp,
        context: &TripContext,
    ) -> Result<Option<Grasp>> {
        let avoid = &context.failed;
        let same = |g: &Grasp| {
            let (mut a, mut b) = (g.objects.clone(), grasp.objects.clone());
            a.sort_unstable();
            b.sort_unstable();
            a == b
        };
        let again = if grasp.objects.len() >= 2 {
            self.multi
                .plan_several(predicted, &grasp.objects, &[grasp.jaws], &[], avoid)?
                .value
        } else {
            self.single
                .plan_avoiding(predicted, &grasp.objects, avoid)?
                .value
        };
        Ok(again.filter(same))
    }
}

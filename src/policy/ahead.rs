//! Pushing ahead (`pricing.push_ahead`): a trip grasps one cluster as it lies and, before that grasp,
//! pushes other clusters into rows for later trips. The look before the next trip, which every
//! trip makes anyway, shows how the pushed rows came out, so the pushes need no look of their own:
//! by the time model a one-push pair then costs its push alone instead of the push and a look, and
//! rows pushed in the same trip share its jaw commands: a second row adds about 8 s where the first
//! adds about 9.5 s (`formulations/picks-per-hour.md`).
//!
//! Each trip, in order:
//! 1. the grasp: a row pushed ahead before, grasped as it now lies when the multi-object planner
//!    finds a grasp of two or more of it (the rows in the order they were pushed; those tried and
//!    refused did not come out); otherwise a single object chosen at random (a cluster chosen at
//!    random when none is left), grasped as it lies (two or more together, else one by itself);
//! 2. the pushes ahead, only when no row pushed before still waits for its grasp: other clusters of
//!    two or more, the rows that did not come out first, then the rest along a chain from the
//!    trip's grasp (the nearest cluster to it, the nearest to that, and so on), at most
//!    [`AHEAD_TRIES`] + `ahead_rows` − 1 tried. Each is planned on the table predicted after the
//!    pushes kept before it and kept when its pushes are planned with a multi-object grasp after
//!    them, pay by the price for what they add to the trip (no look, the travel through them to the
//!    trip's grasp, under the expected-time objective), move nothing the trip's grasp or a row kept
//!    before takes, and leave that grasp and every row kept before graspable on the table predicted
//!    after them; at most `ahead_rows` rows. When two or more are kept, the same rows are planned
//!    again from the chain's far end, and that order is made when the trip is then shorter.
//!
//! When the cluster chosen in step 1 cannot be grasped as it lies, the trip is planned as without
//! pushing ahead.

use super::context::TripContext;
use super::{Policy, PolicyPusher, TripPlan};
use super::{grasp_path, push_paths};
use crate::cluster::Clustering;
use crate::error::Result;
use crate::grasp::{Grasp, GraspRequest};
use crate::outcome::Status;
use crate::plan::AheadRow;
use crate::push::{Push, SkippedPush, predict};
use crate::scene::{ObjectId, Scene};

/// A trip's grasp and the position of its cluster in the clustering.
type ChosenGrasp = (Option<usize>, Grasp);

/// The rows one trip pushes ahead: its pushes in order, each row's objects and the cluster members
/// it was planned from, the judged probability of each row's grasp, the trip's own grasp planned
/// again on the table predicted after the pushes, and the pushes planned and not made.
struct Batch {
    pushes: Vec<Push>,
    rows: Vec<Vec<ObjectId>>,
    members: Vec<Vec<ObjectId>>,
    judged: Vec<f64>,
    statuses: Vec<Status>,
    standing: Grasp,
    skipped: Vec<SkippedPush>,
}

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
        let plain = |grasp: Grasp, skipped| TripPlan {
            skipped_pushes: skipped,
            ..TripPlan::grasping(clustering.clone(), cluster, grasp)
        };
        // Rows pushed before still wait for their grasps: the next rows are pushed together once
        // none waits.
        if !context.ahead.is_empty() {
            return Ok(Some(plain(grasp, Vec::new())));
        }
        let others: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&k| {
                let members = &clustering.clusters[k];
                members.len() >= 2 && members.iter().all(|id| !grasp.objects.contains(id))
            })
            .collect();
        // Nearest first: the arm travels from the pushes to the grasp.
        let others = nearest_chain(others, clustering, observed, grasp.jaws.center);
        // Rows pushed ahead that did not come out graspable are pushed again first.
        let rows = self.settings.pricing.ahead_rows;
        let tries: Vec<Vec<ObjectId>> = unformed
            .into_iter()
            .filter(|row| row.len() >= 2 && row.iter().all(|id| !grasp.objects.contains(id)))
            .chain(others.into_iter().map(|k| clustering.clusters[k].clone()))
            .take(AHEAD_TRIES + rows - 1)
            .collect();
        let forward = self.plan_batch(pusher, observed, &tries, &grasp, context)?;
        // Rows are tried nearest the grasp first; made in that order the arm would go out and back.
        // The same rows planned again farthest first are kept when that trip is shorter.
        let batch = if forward.rows.len() >= 2 {
            let reversed: Vec<Vec<ObjectId>> = forward.members.iter().rev().cloned().collect();
            let backward = self.plan_batch(pusher, observed, &reversed, &grasp, context)?;
            let seconds = |batch: &Batch| {
                let model = self.problem.time_model();
                let jaws = grasp_path(&batch.standing, observed.gripper());
                model.trip_seconds(observed.gripper(), &push_paths(&batch.pushes), &jaws)
            };
            if backward.rows.len() == forward.rows.len() && seconds(&backward) < seconds(&forward) {
                Batch {
                    skipped: forward.skipped,
                    ..backward
                }
            } else {
                forward
            }
        } else {
            forward
        };
        if batch.rows.is_empty() {
            return Ok(Some(plain(grasp, batch.skipped)));
        }
        let ahead = batch.rows.iter().flatten().copied().collect();
        let ahead_rows = batch
            .rows
            .iter()
            .zip(&batch.judged)
            .map(|(objects, &judged)| AheadRow {
                objects: objects.clone(),
                judged,
            })
            .collect();
        context.ahead = batch.rows;
        Ok(Some(TripPlan {
            clustering: clustering.clone(),
            cluster,
            pushes: batch.pushes,
            skipped_pushes: batch.skipped,
            grasp: batch.standing,
            judged: batch.judged.first().copied(),
            ahead,
            ahead_rows,
            push_statuses: batch.statuses,
            riders: Vec::new(),
        }))
    }

    /// Rows pushed ahead in one trip whose grasp is `grasp`: `tries` in order, each planned on the
    /// table predicted after the pushes of those before it and kept when its pushes pay for what
    /// they add to the trip, move nothing already taken, and leave the trip's grasp and every row
    /// kept before graspable; at most `pricing.ahead_rows` rows.
    fn plan_batch(
        &self,
        pusher: &dyn PolicyPusher,
        observed: &Scene,
        tries: &[Vec<ObjectId>],
        grasp: &Grasp,
        context: &TripContext,
    ) -> Result<Batch> {
        let most = self.settings.pricing.ahead_rows;
        let mut batch = Batch {
            pushes: Vec::new(),
            rows: Vec::new(),
            members: Vec::new(),
            judged: Vec::new(),
            statuses: Vec::new(),
            standing: grasp.clone(),
            skipped: Vec::new(),
        };
        let mut table = observed.clone();
        for members in tries {
            if batch.rows.len() >= most {
                break;
            }
            let taken: Vec<ObjectId> = batch
                .standing
                .objects
                .iter()
                .chain(batch.rows.iter().flatten())
                .copied()
                .collect();
            if members.iter().any(|id| taken.contains(id)) {
                continue;
            }
            let (pushed, why_not) = self.push_draft(
                pusher,
                &table,
                members,
                context,
                (1, false, Some((&batch.pushes, &batch.standing))),
            )?;
            batch.skipped.extend(why_not);
            let Some((more, later, judged, status)) = pushed else {
                continue;
            };
            let touches = |id: &ObjectId| taken.contains(id);
            if more.iter().any(|p| touches(&p.object)) || later.objects.iter().any(touches) {
                continue;
            }
            let mut all = batch.pushes.clone();
            all.extend(more);
            let predicted = predict(observed, &all)?;
            let Some(again) = self.grasp_again(&predicted, grasp, context)? else {
                continue;
            };
            // The rows pushed before in this trip must still be graspable after these pushes.
            if !self.rows_stand(&predicted, &batch.rows, context)? {
                continue;
            }
            (batch.pushes, table, batch.standing) = (all, predicted, again);
            batch.rows.push(later.objects);
            batch.members.push(members.clone());
            batch.judged.push(judged);
            batch.statuses.push(status);
        }
        Ok(batch)
    }

    /// Whether each of `rows` still has a multi-object grasp of all its objects on `predicted`.
    fn rows_stand(
        &self,
        predicted: &Scene,
        rows: &[Vec<ObjectId>],
        context: &TripContext,
    ) -> Result<bool> {
        for row in rows {
            let grasp = self
                .multi
                .plan_request(
                    &GraspRequest::new(predicted, row)
                        .avoiding(&context.failed)
                        .several(),
                )?
                .value;
            if !grasp.is_some_and(|g| g.objects.len() >= row.len() && context.together(&g)) {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Step 1 of the module docs: a row pushed ahead, else a single object (a cluster when none is
    /// left) chosen at random, grasped as it lies; with the position of its cluster in
    /// `clustering`, and the rows pushed ahead that were tried and could not be grasped together.
    /// The rows not tried stay waiting in `context`.
    fn grasp_as_it_lies(
        &self,
        observed: &Scene,
        clustering: &Clustering,
        candidates: &[usize],
        context: &mut TripContext,
    ) -> Result<(Option<ChosenGrasp>, Vec<Vec<ObjectId>>)> {
        let avoid = context.failed.clone();
        let mut waiting: Vec<Vec<ObjectId>> = std::mem::take(&mut context.ahead)
            .into_iter()
            .map(|row| {
                row.into_iter()
                    .filter(|&id| observed.index_of(id).is_some())
                    .collect::<Vec<_>>()
            })
            .filter(|row| row.len() >= 2)
            .collect();
        let mut unformed = Vec::new();
        while !waiting.is_empty() {
            let row = waiting.remove(0);
            let outcome = self
                .multi
                .plan_request(&GraspRequest::new(observed, &row).avoiding(&avoid).several())?;
            if let Some(grasp) = outcome.value.filter(|g| context.together(g)) {
                let cluster = clustering
                    .clusters
                    .iter()
                    .position(|c| grasp.objects.iter().any(|id| c.contains(id)));
                // Rows that share no object with this grasp keep waiting.
                context.ahead = waiting
                    .into_iter()
                    .filter(|r| r.iter().all(|id| !grasp.objects.contains(id)))
                    .collect();
                return Ok((Some((cluster, grasp)), unformed));
            }
            unformed.push(row);
        }
        // A single object when one is left: a pair is worth more pushed ahead than taken as it
        // lies, and every later trip grasps the row the trip before pushed.
        let singles: Vec<usize> = candidates
            .iter()
            .copied()
            .filter(|&k| clustering.clusters[k].len() == 1)
            .collect();
        let pool = if singles.is_empty() {
            candidates
        } else {
            &singles
        };
        let chosen = pool[context.rng.index(pool.len())];
        let members = &clustering.clusters[chosen];
        let together = self
            .multi
            .plan_request(
                &GraspRequest::new(observed, members)
                    .avoiding(&avoid)
                    .several(),
            )?
            .value
            .filter(|g| context.together(g));
        let grasp = match together {
            Some(grasp) => Some(grasp),
            None => {
                self.single
                    .plan_request(&GraspRequest::new(observed, members).avoiding(&avoid))?
                    .value
            }
        };
        Ok((grasp.map(|grasp| (Some(chosen), grasp)), unformed))
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
                .plan_request(
                    &GraspRequest::new(predicted, &grasp.objects)
                        .hints(&[grasp.jaws])
                        .avoiding(avoid)
                        .several(),
                )?
                .value
        } else {
            self.single
                .plan_request(&GraspRequest::new(predicted, &grasp.objects).avoiding(avoid))?
                .value
        };
        Ok(again.filter(same))
    }
}

/// `clusters` (indices into `clustering`) as a chain: the one whose centroid is nearest `from`,
/// then the one nearest that, and so on, so that rows pushed together and made from the chain's
/// far end lie along a short path.
fn nearest_chain(
    mut clusters: Vec<usize>,
    clustering: &Clustering,
    observed: &Scene,
    from: nalgebra::Point2<f64>,
) -> Vec<usize> {
    let centre = |k: usize| {
        let members = &clustering.clusters[k];
        let sum: nalgebra::Vector2<f64> = members
            .iter()
            .filter_map(|&id| observed.index_of(id))
            .map(|i| observed.centroid(i).coords)
            .sum();
        nalgebra::Point2::from(sum / members.len() as f64)
    };
    let mut chain = Vec::with_capacity(clusters.len());
    let mut at = from;
    while !clusters.is_empty() {
        let (k, _) = clusters
            .iter()
            .enumerate()
            .map(|(k, &c)| (k, nalgebra::distance(&centre(c), &at)))
            .min_by(|a, b| a.1.total_cmp(&b.1))
            .unwrap_or((0, 0.0));
        let next = clusters.remove(k);
        at = centre(next);
        chain.push(next);
    }
    chain
}

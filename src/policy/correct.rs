//! The rest of a trip once its pushes are made, planned on a new look at the table
//! ([`Policy::correct_trip`]): the closed loop (`run.rs`) calls it after every round of pushes, and
//! so can a robot stack that owns its loop.

use super::trip::Drafted;
use super::{Policy, TripContext, TripPlan};
use crate::error::Result;
use crate::grasp::GraspRequest;
use crate::push::{SkippedPush, predict};
use crate::scene::{ObjectId, Scene};

impl Policy {
    /// What to do next in a trip whose pushes have been made, planned on `observed`, a new look at
    /// the table. Pushes shift and turn objects away from their planned targets (in the simulator a
    /// median 2.4 mm and 4.5°, a 90th percentile 6.1 mm and 19°: `formulations/grasping.md`), so
    /// jaws planned on the prediction can come down on a pushed object or catch a broken row; here
    /// they are planned on where the objects are. In order:
    /// - the trip's cluster (its objects still seen) grasped together as it lies, when the
    ///   multi-object planner finds a grasp of as many objects as the cluster has (the planned jaws
    ///   offered as a candidate; a grasp may also catch an object outside the cluster);
    /// - with `may_push`, corrective pushes of the cluster planned afresh, when a multi-object grasp
    ///   follows them (as in the trip's first plan) that takes more objects than the best grasp of
    ///   the cluster as it lies;
    /// - that grasp as it lies, when it takes two or more;
    /// - one of the cluster's objects by itself; else any object by itself.
    ///
    /// The returned plan's clustering and cluster are the trip's. `None` when no object on the table
    /// can be grasped. Jaws where a grasp failed before are never proposed.
    ///
    /// # Errors
    /// Misuse only.
    pub fn correct_trip(
        &self,
        observed: &Scene,
        trip: &TripPlan,
        context: &TripContext,
        may_push: bool,
    ) -> Result<Option<TripPlan>> {
        let Some(mut corrected) = self.correct_draft(observed, trip, context, may_push)? else {
            return Ok(None);
        };
        if self.settings.riders.enabled {
            let predicted = predict(observed, &corrected.pushes)?;
            corrected.riders = self.riders_for(&predicted, &corrected, context)?;
        }
        Ok(Some(corrected))
    }

    /// [`Policy::correct_trip`] without its riders.
    fn correct_draft(
        &self,
        observed: &Scene,
        trip: &TripPlan,
        context: &TripContext,
        may_push: bool,
    ) -> Result<Option<TripPlan>> {
        let avoid = &context.failed;
        let planned: &[ObjectId] = match trip.cluster {
            Some(k) if k < trip.clustering.clusters.len() => &trip.clustering.clusters[k],
            _ => &trip.grasp.objects,
        };
        let members: Vec<ObjectId> = planned
            .iter()
            .copied()
            .filter(|&id| observed.index_of(id).is_some())
            .collect();
        let next =
            |(pushes, grasp, judged, status): Drafted, skipped_pushes: Vec<SkippedPush>| TripPlan {
                clustering: trip.clustering.clone(),
                cluster: trip.cluster,
                pushes,
                skipped_pushes,
                grasp,
                judged,
                ahead: Vec::new(),
                ahead_rows: Vec::new(),
                push_statuses: status.into_iter().collect(),
                riders: Vec::new(),
            };
        let mut skipped = Vec::new();
        if members.len() >= 2 {
            let outcome = self.multi.plan_request(
                &GraspRequest::new(observed, &members)
                    .hints(&[trip.grasp.jaws])
                    .avoiding(avoid)
                    .several(),
            )?;
            let as_it_lies = outcome.value.filter(|g| context.together(g));
            let taken = as_it_lies.as_ref().map_or(0, |g| g.objects.len());
            if taken == members.len() {
                return Ok(as_it_lies.map(|grasp| next((Vec::new(), grasp, None, None), skipped)));
            }
            // Fewer objects than the cluster has can be taken as it lies (a row of three or more
            // broken by the pushes): corrective pushes come first when their grasp takes more.
            if let Some(pusher) = self.pusher.as_deref().filter(|_| may_push) {
                let (pushed, why_not) = self.push_draft(
                    pusher,
                    observed,
                    &members,
                    context,
                    (taken.max(1), true, None),
                )?;
                skipped = why_not;
                if let Some((pushes, grasp, judged, status)) =
                    pushed.filter(|(_, g, ..)| g.objects.len() > taken)
                {
                    return Ok(Some(next(
                        (pushes, grasp, Some(judged), Some(status)),
                        skipped,
                    )));
                }
            }
            if let Some(grasp) = as_it_lies {
                return Ok(Some(next((Vec::new(), grasp, None, None), skipped)));
            }
        }
        if let Some(grasp) = self
            .single
            .plan_request(&GraspRequest::new(observed, &members).avoiding(avoid))?
            .value
        {
            return Ok(Some(next((Vec::new(), grasp, None, None), skipped)));
        }
        let everything: Vec<ObjectId> = observed.objects().iter().map(|o| o.id).collect();
        Ok(self
            .single
            .plan_request(&GraspRequest::new(observed, &everything).avoiding(avoid))?
            .value
            .map(|grasp| next((Vec::new(), grasp, None, None), skipped)))
    }
}

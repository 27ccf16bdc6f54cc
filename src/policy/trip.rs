//! Planning one trip: the paper's Algorithm 1 without its loop. [`Policy::plan_trip`] plans from the
//! scene it is given and nothing else, so a robot stack, a Python loop or another simulator can drive
//! it; [`Policy::plan_trip_with`] also carries what a run remembers between trips ([`TripContext`]:
//! the random stream that picks the next object or cluster, and where grasps failed).
//!
//! - `sog`: a graspable object at random, grasped alone ([`SingleObject`]); if its grasps all failed
//!   before, the next one.
//! - the clustering policies: cluster, pick a cluster at random; with pushes, plan them and predict the
//!   table after them; push only if a multi-object grasp follows there and no pushed object is
//!   stranded; otherwise grasp the cluster as it lies (several objects, else one by itself).
//!
//! [`Policy::correct_trip`] plans the rest of a trip once its pushes are made, on a new look at the
//! table: the closed loop (`run.rs`) calls it after every round of pushes, and so can a robot stack
//! that owns its loop.

use std::time::Instant;

use nalgebra::Vector2;

use super::context::{Landing, TripContext};
use super::{NoTrip, Policy, PolicyClusterer, PolicyPusher, TripAnswer};
use crate::cluster::Clustering;
use crate::error::Result;
use crate::geometry::distance;
use crate::grasp::{Grasp, GraspRequest, JawPose};
use crate::outcome::{Stats, Status};
use crate::plan::TripPlan;
use crate::push::fork::finger_footprints;
use crate::push::{Push, PushPlan, SkipReason, SkippedPush, predict};
use crate::random::SeededRng;
use crate::scene::{ObjectId, Scene};

/// Pushes to make, in order, the grasp planned on the table predicted after them, the grasp
/// planner's estimate of its probability, and the push planner's status for those pushes.
type PushesThenGrasp = (Vec<Push>, Grasp, f64, Status);

/// What a trip plan is drafted from: its pushes, its grasp, the grasp's judged probability and
/// the push planner's status (both `None` without pushes).
pub(super) type Drafted = (Vec<Push>, Grasp, Option<f64>, Option<Status>);

impl Policy {
    /// Plans the next trip on `scene` as it is, with a fresh [`TripContext`] of seed 0: the pushes
    /// and the grasp, or why there is none ([`NoTrip`]).
    ///
    /// # Errors
    /// Misuse only (invalid settings are refused when the policy is built).
    pub fn plan_trip(&self, scene: &Scene) -> Result<TripAnswer> {
        self.plan_trip_with(scene, &mut TripContext::new(0))
    }

    /// As [`Policy::plan_trip`], drawing the random choice from `context` and avoiding the grasps
    /// that failed in it. Clustering time is in the counter `clustering_seconds`.
    ///
    /// # Errors
    /// As [`Policy::plan_trip`].
    pub fn plan_trip_with(&self, scene: &Scene, context: &mut TripContext) -> Result<TripAnswer> {
        let started = Instant::now();
        let mut clustering_seconds = None;
        let drafted = if scene.is_empty() {
            Err(NoTrip::EmptyTable)
        } else {
            match &self.clusterer {
                None => self.draft_single(scene, &mut context.rng, &context.failed)?,
                Some(clusterer) => match self.perched_trip(scene, context)? {
                    Some(trip) => Ok(trip),
                    None => self.draft_clustered(
                        scene,
                        clusterer.as_ref(),
                        context,
                        &mut clustering_seconds,
                    )?,
                },
            }
        };
        let mut counters = Vec::new();
        if let Some(seconds) = clustering_seconds {
            counters.push(("clustering_seconds".to_string(), seconds));
        }
        let trip = match drafted {
            Ok(mut trip) => {
                if self.settings.riders.enabled {
                    let predicted = predict(scene, &trip.pushes)?;
                    trip.riders = self.riders_for(&predicted, &trip, context)?;
                }
                Ok(trip)
            }
            Err(no_trip) => Err(no_trip),
        };
        let stats = Stats {
            seconds: started.elapsed().as_secs_f64(),
            counters,
            ..Stats::default()
        };
        Ok(TripAnswer { trip, stats })
    }

    fn draft_single(
        &self,
        observed: &Scene,
        rng: &mut SeededRng,
        avoid: &[JawPose],
    ) -> Result<std::result::Result<TripPlan, NoTrip>> {
        let graspable: Vec<usize> = (0..observed.len())
            .filter(|&i| observed.is_graspable(i))
            .collect();
        if graspable.is_empty() {
            return Ok(Err(NoTrip::NothingFitsTheJaws));
        }
        // A random object first, then the others in turn if its grasps all failed before.
        let first = rng.index(graspable.len());
        let order = graspable[first..].iter().chain(&graspable[..first]);
        let mut first_failure = None;
        for &index in order {
            let target = observed.objects()[index].id;
            let outcome = self
                .single
                .plan_request(&GraspRequest::new(observed, &[target]).avoiding(avoid))?;
            match outcome.value {
                Some(grasp) => {
                    return Ok(Ok(TripPlan::grasping(Clustering::default(), None, grasp)));
                }
                None if first_failure.is_none() => {
                    first_failure = Some(NoTrip::NoGraspOfObject {
                        object: target,
                        grasp: outcome.status,
                    });
                }
                None => {}
            }
            if avoid.is_empty() {
                break;
            }
        }
        // At least one graspable object was tried, so a failure was recorded.
        Ok(Err(first_failure.unwrap_or(NoTrip::NothingFitsTheJaws)))
    }

    /// A draft for a chosen cluster. With pushes, the cluster is pushed only when the table predicted
    /// after the pushes offers a multi-object grasp, and every pushed object that grasp does not
    /// take could still be taken by itself there (no object is stranded); otherwise nothing is pushed
    /// and the cluster is grasped as it lies. Jaws where a grasp failed before are never proposed
    /// again, nor pushes whose fingers would come down near an unseen object they landed on before.
    fn draft_clustered(
        &self,
        observed: &Scene,
        clusterer: &dyn PolicyClusterer,
        context: &mut TripContext,
        clustering_seconds: &mut Option<f64>,
    ) -> Result<std::result::Result<TripPlan, NoTrip>> {
        let started = Instant::now();
        context.clusterings.hold(context.ahead.clone());
        let clustered = clusterer.cluster_remembering(observed, &mut context.clusterings)?;
        *clustering_seconds = Some(started.elapsed().as_secs_f64());
        // The status goes with the clustering into the trip and the record.
        let clustering = Clustering {
            status: Some(clustered.status),
            ..clustered.value
        };
        let mut candidates: Vec<usize> = (0..clustering.len())
            .filter(|&k| {
                clustering.clusters[k]
                    .iter()
                    .filter_map(|&id| observed.index_of(id))
                    .any(|i| observed.is_graspable(i))
            })
            .collect();
        // A rider the clustering put on a row rides that row's trip and takes none of its own,
        // unless nothing else is left to take.
        let rides = |k: &usize| match clustering.clusters[*k][..] {
            [only] => clustering.is_rider(only),
            _ => false,
        };
        if candidates.iter().any(|k| !rides(k)) {
            candidates.retain(|k| !rides(k));
        }
        if candidates.is_empty() {
            return Ok(Err(NoTrip::NoClusterFitsTheJaws));
        }
        if self.settings.pricing.push_ahead
            && let Some(pusher) = self.pusher.as_deref()
            && let Some(trip) =
                self.draft_ahead(pusher, observed, &clustering, &candidates, context)?
        {
            return Ok(Ok(trip));
        }
        let chosen = candidates[context.rng.index(candidates.len())];
        let avoid = &context.failed;
        let members = clustering.clusters[chosen].clone();
        let draft =
            |(pushes, grasp, judged, status): Drafted, skipped: Vec<SkippedPush>| TripPlan {
                clustering: clustering.clone(),
                cluster: Some(chosen),
                pushes,
                skipped_pushes: skipped,
                grasp,
                judged,
                ahead: Vec::new(),
                ahead_rows: Vec::new(),
                push_statuses: status.into_iter().collect(),
                riders: Vec::new(),
            };
        let mut skipped = Vec::new();
        if let Some(pusher) = self.pusher.as_deref()
            && members.len() > 1
        {
            let look = self.settings.run.observe_after_pushes;
            let (pushed, why_not) =
                self.push_draft(pusher, observed, &members, context, (1, look, None))?;
            skipped = why_not;
            if let Some((pushes, grasp, judged, status)) = pushed {
                return Ok(Ok(draft(
                    (pushes, grasp, Some(judged), Some(status)),
                    skipped,
                )));
            }
        }
        // As the cluster lies: a multi-object grasp of two or more, else one object by itself (jaws
        // opened just wider than the object, flush on an edge, not fully around it).
        let outcome = self.multi.plan_request(
            &GraspRequest::new(observed, &members)
                .avoiding(avoid)
                .several(),
        )?;
        if let Some(grasp) = outcome.value.filter(|g| context.together(g)) {
            return Ok(Ok(draft((Vec::new(), grasp, None, None), skipped)));
        }
        let single = self
            .single
            .plan_request(&GraspRequest::new(observed, &members).avoiding(avoid))?;
        if let Some(grasp) = single.value {
            return Ok(Ok(draft((Vec::new(), grasp, None, None), skipped)));
        }
        // Members too close to be taken alone or together: push one clear of its neighbour.
        if self.pusher.is_some()
            && let Some((push, grasp)) = self.separate(observed, &members, avoid)?
        {
            let separating = (vec![push], grasp, None, Some(Status::Heuristic));
            return Ok(Ok(draft(separating, skipped)));
        }
        // Pressed together, with no room for the fingers of a parting push either: together with
        // the neighbours in the way, as they lie.
        if let Some(grasp) = self.take_with_neighbours(observed, &members, context)? {
            return Ok(Ok(draft((Vec::new(), grasp, None, None), skipped)));
        }
        Ok(Err(NoTrip::NoGraspOfCluster {
            members,
            grasp: single.status,
        }))
    }

    /// Pushes for `members` and the multi-object grasp planned on the table predicted after them,
    /// when that grasp takes two or more objects and every pushed object it leaves could still be
    /// taken by itself there (no object is stranded), and no push lowers its fingers near an unseen
    /// object a push of the same object `landed` on; under the expected-time objective, also only
    /// when the pushes are expected to save time over taking `taken` objects as they lie, with a
    /// look after them or not (`look`), the trip then making `then` (pushing ahead: the pushes of
    /// rows already planned for the trip, made after these, and the trip's grasp) or the grasp
    /// after the pushes ([`super::Pricing::saving`]). With the pushes that were planned and not
    /// made, and why.
    pub(super) fn push_draft(
        &self,
        pusher: &dyn PolicyPusher,
        observed: &Scene,
        members: &[ObjectId],
        context: &TripContext,
        (taken, look, then): (usize, bool, Option<(&[Push], &Grasp)>),
    ) -> Result<(Option<PushesThenGrasp>, Vec<SkippedPush>)> {
        let (avoid, landed) = (&context.failed, &context.landed);
        let (plan, status) = self.plan_pushes(pusher, observed, members)?;
        let mut skipped = plan.skipped;
        if plan.pushes.is_empty() {
            return Ok((None, skipped));
        }
        let repeated = plan
            .pushes
            .iter()
            .find_map(|push| landed.iter().find(|l| lands_again(observed, push, l)));
        if let Some(landing) = repeated {
            skipped.extend(plan.pushes.iter().map(|p| SkippedPush {
                object: p.object,
                reason: SkipReason::LandedBefore { object: landing.on },
            }));
            return Ok((None, skipped));
        }
        let predicted = predict(observed, &plan.pushes)?;
        let hints: Vec<JawPose> = plan.intended_grasp.into_iter().collect();
        let pushed: Vec<ObjectId> = plan.pushes.iter().map(|p| p.object).collect();
        let outcome = self.multi.plan_request(
            &GraspRequest::new(&predicted, members)
                .hints(&hints)
                .pushed(&pushed)
                .avoiding(avoid)
                .several(),
        )?;
        let reason = match outcome.value.filter(|g| context.together(g)) {
            Some(grasp) => {
                let left: Vec<ObjectId> = pushed
                    .iter()
                    .copied()
                    .filter(|id| !grasp.objects.contains(id))
                    .collect();
                let (earlier, then): (&[Push], _) = match then {
                    Some((earlier, grasp)) => (earlier, Some(grasp)),
                    None => (&[], None),
                };
                let saving = self.saving(
                    observed,
                    (&plan.pushes, earlier, &grasp, then),
                    &outcome.stats,
                    (taken, look),
                );
                if !self.each_has_a_fallback(&predicted, &left)? {
                    SkipReason::DeadEnd
                } else if saving.is_some_and(|saving| saving <= 0.0) {
                    SkipReason::DoesNotPay {
                        saving: saving.unwrap_or(0.0),
                    }
                } else {
                    let judged = outcome.stats.counter("probability").unwrap_or(0.0);
                    return Ok((Some((plan.pushes, grasp, judged, status)), skipped));
                }
            }
            None => SkipReason::NoGraspAfter,
        };
        skipped.extend(pushed.iter().map(|&object| SkippedPush {
            object,
            reason: reason.clone(),
        }));
        Ok((None, skipped))
    }

    /// Under the expected-time objective, the expected seconds saved by `pushes` and then `grasp`
    /// (judged as `judged` says, the grasp planner's counter `probability`) over taking `taken`
    /// objects as they lie, with a look after the pushes or not; `None` under the objects-per-trip
    /// objective.
    fn saving(
        &self,
        observed: &Scene,
        planned: (&[Push], &[Push], &Grasp, Option<&Grasp>),
        judged: &Stats,
        (taken, look): (usize, bool),
    ) -> Option<f64> {
        let settings = &self.settings;
        (settings.pricing.objective == super::TripObjective::ExpectedTime).then(|| {
            settings.pricing.saving(
                self.problem.time_model(),
                observed.gripper(),
                planned,
                judged.counter("probability").unwrap_or(0.0),
                taken,
                look,
            )
        })
    }

    /// Whether every pushed object could still be grasped by itself on the predicted table.
    fn each_has_a_fallback(&self, predicted: &Scene, pushed: &[ObjectId]) -> Result<bool> {
        for &object in pushed {
            if self.single.plan(predicted, &[object])?.value.is_none() {
                return Ok(false);
            }
        }
        Ok(true)
    }

    /// Pushes for a cluster. When no row of the whole cluster can be planned (the SOCP proves it
    /// infeasible, or no push sequence exists), or the planned row is not predicted held while a
    /// smaller one is, the largest sub-clusters are tried, cheapest first, and the object left out is
    /// reported as skipped to wait for a later trip. With the push planner's status for the plan
    /// chosen.
    fn plan_pushes(
        &self,
        pusher: &dyn PolicyPusher,
        observed: &Scene,
        members: &[ObjectId],
    ) -> Result<(PushPlan, Status)> {
        let usable = Status::has_answer;
        // Planners that do not judge their rows (the paper's) count as held.
        let held = |plan: &PushPlan| plan.row_held != Some(false);
        let whole = pusher.plan(observed, members)?;
        if members.len() < 3 || (usable(&whole.status) && held(&whole.value)) {
            return Ok((whole.value, whole.status));
        }
        let mut best: Option<(bool, f64, PushPlan, Status)> = None;
        for left_out in members {
            let part: Vec<ObjectId> = members
                .iter()
                .copied()
                .filter(|id| id != left_out)
                .collect();
            let sub = pusher.plan(observed, &part)?;
            if !usable(&sub.status) {
                continue;
            }
            let (is_held, cost) = (
                held(&sub.value),
                sub.stats.objective.unwrap_or(f64::INFINITY),
            );
            let better = best
                .as_ref()
                .is_none_or(|(h, c, ..)| (is_held && !*h) || (is_held == *h && cost < *c));
            if better {
                let mut plan = sub.value;
                plan.skipped.push(SkippedPush {
                    object: *left_out,
                    reason: SkipReason::NoRow,
                });
                best = Some((is_held, cost, plan, sub.status));
            }
        }
        Ok(match best {
            Some((true, _, plan, status)) => (plan, status),
            Some((false, _, plan, status)) if !usable(&whole.status) => (plan, status),
            _ => (whole.value, whole.status),
        })
    }
}

/// After a finger came down on an object the camera does not see (outside the workspace), later
/// pushes of the same object keep their lowered fingers this far from where the fingers came down,
/// metres: three standard deviations of where a finger comes down under the simulator's noise (2 mm
/// perception and 1 mm actuation, 2.2 mm per axis together). Plans of the same push differ by a
/// few millimetres from look to look, since each look sees the objects anew.
const LANDED_CLEARANCE: f64 = 0.007;

/// Whether `push` pushes the object of `landing` with its fingers lowered within
/// [`LANDED_CLEARANCE`] of where they came down then, on an object that `observed` does not show.
/// An object that is seen is kept clear as any other (`ForkSettings::finger_clearance`).
fn lands_again(observed: &Scene, push: &Push, landing: &Landing) -> bool {
    if push.object != landing.push.object || observed.index_of(landing.on).is_some() {
        return false;
    }
    let gripper = observed.gripper();
    let fingers = |push: &Push| {
        let jaw = push.fork.jaw_angle;
        finger_footprints(
            gripper,
            push.fork.opening,
            &push.fork.approach,
            &Vector2::new(jaw.sin(), -jaw.cos()),
        )
    };
    let before = fingers(&landing.push);
    fingers(push).iter().any(|finger| {
        before
            .iter()
            .any(|landed| distance(finger, landed) < LANDED_CLEARANCE)
    })
}

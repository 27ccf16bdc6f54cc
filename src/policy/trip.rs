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
use serde::{Deserialize, Serialize};

use super::{Policy, PolicyClusterer, PolicyPusher};
use crate::cluster::{ClusterMemory, Clustering};
use crate::error::Result;
use crate::geometry::distance;
use crate::grasp::{Grasp, GraspPlanner, JawPose};
use crate::outcome::{Outcome, Stats, Status};
use crate::plan::AheadRow;
use crate::push::fork::finger_footprints;
use crate::push::{Push, PushPlan, SkipReason, SkippedPush, predict, separating_push};
use crate::random::SeededRng;
use crate::scene::{ObjectId, Scene};

/// The next trip: what to push, then where to grasp. Its fields are those of a trip in a run record
/// (`pushmog plan`), without what the executor reports.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
pub struct TripPlan {
    /// The clustering of the scene (empty for policies that do not cluster).
    pub clustering: Clustering,
    /// Position in `clustering.clusters` of the cluster this trip works on (`None` when not clustered).
    pub cluster: Option<usize>,
    /// The fork pushes, in execution order.
    pub pushes: Vec<Push>,
    /// Pushes that were not planned or not made, with their reasons.
    pub skipped_pushes: Vec<SkippedPush>,
    /// The grasp, planned on the scene predicted after the pushes.
    pub grasp: Grasp,
    /// With pushes, the grasp planner's estimate of the probability that the grasp they prepare
    /// carries every object it is planned for, on the table predicted after them (the `p` of the
    /// expected-time price): this trip's grasp, or, for pushes ahead (`pricing.push_ahead`), the
    /// grasp of the pushed row a later trip is to make. `None` without pushes.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub judged: Option<f64>,
    /// When pushing ahead (`pricing.push_ahead`): the objects this trip's pushes arrange into rows
    /// for later trips' grasps, none of them taken by this trip's grasp. Empty otherwise.
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ahead: Vec<ObjectId>,
    /// Those objects row by row, in the order the rows are pushed, each with the grasp judge's
    /// probability for the grasp a later trip is to make of it (the first row's is `judged`).
    #[serde(default, skip_serializing_if = "Vec::is_empty")]
    pub ahead_rows: Vec<AheadRow>,
}

/// Pushes to make, in order, the grasp planned on the table predicted after them, and the grasp
/// planner's estimate of its probability.
type PushesThenGrasp = (Vec<Push>, Grasp, f64);

/// Lengths tried, shortest first, for a push that separates an object from the neighbour it is stuck
/// against, metres: a 10 mm plate and the single-object planner's clearance on either side need
/// about 20 mm; longer ones for neighbours that are not square to the push.
const SEPARATIONS: [f64; 3] = [0.02, 0.03, 0.045];

/// Directions tried for a separating push: this many around the full turn, of which those that do not
/// run into the neighbour are used.
const SEPARATION_DIRECTIONS: usize = 16;

/// Least room left between a separated object and the workspace's edge, metres (the SOCP's default
/// edge margin).
const SEPARATION_EDGE_MARGIN: f64 = 0.005;

/// What a run remembers from trip to trip: the random stream that picks the next object or cluster,
/// the jaw poses where grasps carried nothing (not tried again in practically the same place), the
/// sets of objects whose multi-object grasps carried nothing (after [`GIVE_UP_AFTER`] such grasps,
/// those objects are taken one at a time), and the pushes whose fingers came down on an object (if
/// the camera cannot see it, the pushed object is not pushed again with the fingers lowered near
/// there), and what the clusterer remembers (the MILP's last optimum). A policy keeps no state
/// between calls: a trip's plan depends on the table and this context only.
#[derive(Clone, Debug)]
pub struct TripContext {
    pub(super) rng: SeededRng,
    /// Jaw poses of grasps that carried nothing.
    pub failed: Vec<JawPose>,
    /// The objects (sorted) of each multi-object grasp that carried nothing.
    pub failed_together: Vec<Vec<ObjectId>>,
    /// Pushes during whose descent a finger came down on an object.
    pub landed: Vec<Landing>,
    /// The rows trips pushed ahead for later trips' grasps (`pricing.push_ahead`), each its
    /// objects, in the order they were pushed; empty when none waits.
    pub ahead: Vec<Vec<ObjectId>>,
    /// What the clusterer remembers from earlier trips (the MILP's last proven optimum).
    pub clusterings: ClusterMemory,
}

/// Multi-object grasps of one set of objects that may carry nothing before those objects are no
/// longer grasped together in the run. A failed grasp is not tried again in the same place, but a
/// grasp model that misjudges a set (an object toppled onto a side face, say, seen from above as an
/// upright prism of its outline) may hold it in every other place too: on a held-out scene the
/// pair 12/31 (a triangular prism lying on its side and a pentagon) was grasped together eleven
/// times, each carrying nothing, until the run stopped. One failure can be bad luck (objects move,
/// and the next look sees them anew), so the set is given up after the second.
pub const GIVE_UP_AFTER: usize = 2;

/// A push during whose descent a finger came down on an object.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct Landing {
    /// The push.
    pub push: Push,
    /// The object the finger came down on.
    pub on: ObjectId,
}

impl TripContext {
    /// A fresh context; `seed` drives the random choices.
    pub fn new(seed: u64) -> Self {
        Self {
            rng: SeededRng::new(seed),
            failed: Vec::new(),
            failed_together: Vec::new(),
            landed: Vec::new(),
            ahead: Vec::new(),
            clusterings: ClusterMemory::default(),
        }
    }

    /// Notes a grasp that carried nothing: its jaws, and its objects when there were several.
    pub fn record_failure(&mut self, grasp: &Grasp) {
        self.failed.push(grasp.jaws);
        if grasp.objects.len() >= 2 {
            let mut objects = grasp.objects.clone();
            objects.sort_unstable();
            self.failed_together.push(objects);
        }
    }

    /// Whether `grasp` takes two or more objects that are still to be grasped together.
    pub(super) fn together(&self, grasp: &Grasp) -> bool {
        grasp.objects.len() >= 2 && !self.given_up(&grasp.objects)
    }

    /// Whether these objects are no longer to be grasped together: [`GIVE_UP_AFTER`] grasps of
    /// exactly them carried nothing.
    pub fn given_up(&self, objects: &[ObjectId]) -> bool {
        let mut objects = objects.to_vec();
        objects.sort_unstable();
        self.failed_together
            .iter()
            .filter(|set| **set == objects)
            .count()
            >= GIVE_UP_AFTER
    }
}

impl Policy {
    /// Plans the next trip on `scene` as it is, with a fresh [`TripContext`] of seed 0: the pushes
    /// and the grasp, or (value `None`, status [`Status::Failed`]) why there is none.
    ///
    /// # Errors
    /// Misuse only (invalid settings are refused when the policy is built).
    pub fn plan_trip(&self, scene: &Scene) -> Result<Outcome<Option<TripPlan>>> {
        self.plan_trip_with(scene, &mut TripContext::new(0))
    }

    /// As [`Policy::plan_trip`], drawing the random choice from `context` and avoiding the grasps
    /// that failed in it. Clustering time is in the counter `clustering_seconds`.
    ///
    /// # Errors
    /// As [`Policy::plan_trip`].
    pub fn plan_trip_with(
        &self,
        scene: &Scene,
        context: &mut TripContext,
    ) -> Result<Outcome<Option<TripPlan>>> {
        let started = Instant::now();
        let mut clustering_seconds = None;
        let drafted = if scene.is_empty() {
            Err("the table is empty".to_string())
        } else {
            match &self.clusterer {
                None => self.draft_single(scene, &mut context.rng, &context.failed)?,
                Some(clusterer) => self.draft_clustered(
                    scene,
                    clusterer.as_ref(),
                    context,
                    &mut clustering_seconds,
                )?,
            }
        };
        let mut counters = Vec::new();
        if let Some(seconds) = clustering_seconds {
            counters.push(("clustering_seconds".to_string(), seconds));
        }
        let stats = Stats {
            seconds: started.elapsed().as_secs_f64(),
            counters,
            ..Stats::default()
        };
        Ok(match drafted {
            Ok(trip) => Outcome {
                value: Some(trip),
                status: Status::Heuristic,
                stats,
            },
            Err(reason) => Outcome {
                value: None,
                status: Status::Failed { reason },
                stats,
            },
        })
    }

    fn draft_single(
        &self,
        observed: &Scene,
        rng: &mut SeededRng,
        avoid: &[JawPose],
    ) -> Result<std::result::Result<TripPlan, String>> {
        let graspable: Vec<usize> = (0..observed.len())
            .filter(|&i| observed.is_graspable(i))
            .collect();
        if graspable.is_empty() {
            return Ok(Err("no object narrower than the jaw gap".to_string()));
        }
        // A random object first, then the others in turn if its grasps all failed before.
        let first = rng.index(graspable.len());
        let order = graspable[first..].iter().chain(&graspable[..first]);
        let mut reason = String::new();
        for &index in order {
            let target = observed.objects()[index].id;
            let outcome = self.single.plan_avoiding(observed, &[target], avoid)?;
            match outcome.value {
                Some(grasp) => {
                    return Ok(Ok(TripPlan {
                        clustering: Clustering::default(),
                        cluster: None,
                        pushes: Vec::new(),
                        skipped_pushes: Vec::new(),
                        grasp,
                        judged: None,
                        ahead: Vec::new(),
                        ahead_rows: Vec::new(),
                    }));
                }
                None if reason.is_empty() => {
                    reason = format!("object {target}: {}", failure_reason(&outcome.status));
                }
                None => {}
            }
            if avoid.is_empty() {
                break;
            }
        }
        Ok(Err(reason))
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
    ) -> Result<std::result::Result<TripPlan, String>> {
        let started = Instant::now();
        let clustered = clusterer.cluster_remembering(observed, &mut context.clusterings)?;
        *clustering_seconds = Some(started.elapsed().as_secs_f64());
        // The status goes with the clustering into the trip and the record.
        let clustering = Clustering {
            status: Some(clustered.status),
            ..clustered.value
        };
        let candidates: Vec<usize> = (0..clustering.len())
            .filter(|&k| {
                clustering.clusters[k]
                    .iter()
                    .filter_map(|&id| observed.index_of(id))
                    .any(|i| observed.is_graspable(i))
            })
            .collect();
        if candidates.is_empty() {
            return Ok(Err(
                "no cluster with an object narrower than the jaw gap".to_string()
            ));
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
        let draft = |pushes: Vec<Push>, skipped: Vec<SkippedPush>, grasp: Grasp, judged| TripPlan {
            clustering: clustering.clone(),
            cluster: Some(chosen),
            pushes,
            skipped_pushes: skipped,
            grasp,
            judged,
            ahead: Vec::new(),
            ahead_rows: Vec::new(),
        };
        let mut skipped = Vec::new();
        if let Some(pusher) = self.pusher.as_deref()
            && members.len() > 1
        {
            let look = self.settings.run.observe_after_pushes;
            let (pushed, why_not) =
                self.push_draft(pusher, observed, &members, context, (1, look, None))?;
            skipped = why_not;
            if let Some((pushes, grasp, judged)) = pushed {
                return Ok(Ok(draft(pushes, skipped, grasp, Some(judged))));
            }
        }
        // As the cluster lies: a multi-object grasp of two or more, else one object by itself (jaws
        // opened just wider than the object, flush on an edge, not fully around it).
        let outcome = self
            .multi
            .plan_several(observed, &members, &[], &[], avoid)?;
        if let Some(grasp) = outcome.value.filter(|g| context.together(g)) {
            return Ok(Ok(draft(Vec::new(), skipped, grasp, None)));
        }
        let single = self.single.plan_avoiding(observed, &members, avoid)?;
        if let Some(grasp) = single.value {
            return Ok(Ok(draft(Vec::new(), skipped, grasp, None)));
        }
        // Members too close to be taken alone or together: push one clear of its neighbour.
        if self.pusher.is_some()
            && let Some((push, grasp)) = self.separate(observed, &members, avoid)?
        {
            return Ok(Ok(draft(vec![push], skipped, grasp, None)));
        }
        Ok(Err(format!(
            "cluster {:?}: {}",
            members.iter().map(|id| id.0).collect::<Vec<_>>(),
            failure_reason(&single.status)
        )))
    }

    /// A push that moves one of `members` away from the object nearest it ([`separating_push`], the
    /// shortest of [`SEPARATIONS`] that works, in the first of the directions that do not point into
    /// that object, nearest straight away first), and a grasp of that object
    /// or its neighbour by itself on the table predicted after the push; `None` when no member can
    /// be freed so. The way out when objects stand too close for a plate between them and the grasp
    /// model refuses them together (a dead end the paper's pushes, which end with objects touching,
    /// can leave).
    fn separate(
        &self,
        observed: &Scene,
        members: &[ObjectId],
        avoid: &[JawPose],
    ) -> Result<Option<(Push, Grasp)>> {
        for &id in members {
            let Some(index) = observed.index_of(id) else {
                continue;
            };
            let outline = observed.world_polygon(index);
            let Some(neighbour) = (0..observed.len())
                .filter(|&j| j != index)
                .min_by(|&a, &b| {
                    distance(outline, observed.world_polygon(a))
                        .total_cmp(&distance(outline, observed.world_polygon(b)))
                })
            else {
                continue;
            };
            let freed = [id, observed.objects()[neighbour].id];
            let away = (observed.centroid(index) - observed.centroid(neighbour)).normalize();
            // Directions that do not run into the neighbour, nearest straight away first.
            let mut directions: Vec<(f64, Vector2<f64>)> = (0..SEPARATION_DIRECTIONS)
                .map(|k| {
                    let turn = std::f64::consts::TAU * k as f64 / SEPARATION_DIRECTIONS as f64;
                    let (sin, cos) = turn.sin_cos();
                    let direction =
                        Vector2::new(away.x * cos - away.y * sin, away.x * sin + away.y * cos);
                    (-cos, direction)
                })
                .filter(|(_, direction)| direction.dot(&away) >= -1e-9)
                .collect();
            directions.sort_by(|a, b| a.0.total_cmp(&b.0));
            for travel in SEPARATIONS {
                for (_, direction) in &directions {
                    let Ok(push) = separating_push(
                        observed,
                        self.problem.fork(),
                        (index, neighbour),
                        direction,
                        travel,
                        SEPARATION_EDGE_MARGIN,
                    ) else {
                        continue;
                    };
                    let predicted = predict(observed, std::slice::from_ref(&push))?;
                    if let Some(grasp) = self.single.plan_avoiding(&predicted, &freed, avoid)?.value
                    {
                        return Ok(Some((push, grasp)));
                    }
                }
            }
        }
        Ok(None)
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
        let plan = self.plan_pushes(pusher, observed, members)?;
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
        let outcome = self
            .multi
            .plan_several(&predicted, members, &hints, &pushed, avoid)?;
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
                    return Ok((Some((plan.pushes, grasp, judged)), skipped));
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
            |pushes: Vec<Push>, skipped_pushes: Vec<SkippedPush>, grasp: Grasp, judged| TripPlan {
                clustering: trip.clustering.clone(),
                cluster: trip.cluster,
                pushes,
                skipped_pushes,
                grasp,
                judged,
                ahead: Vec::new(),
                ahead_rows: Vec::new(),
            };
        let mut skipped = Vec::new();
        if members.len() >= 2 {
            let outcome =
                self.multi
                    .plan_several(observed, &members, &[trip.grasp.jaws], &[], avoid)?;
            let as_it_lies = outcome.value.filter(|g| context.together(g));
            let taken = as_it_lies.as_ref().map_or(0, |g| g.objects.len());
            if taken == members.len() {
                return Ok(as_it_lies.map(|grasp| next(Vec::new(), skipped, grasp, None)));
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
                if let Some((pushes, grasp, judged)) =
                    pushed.filter(|(_, g, _)| g.objects.len() > taken)
                {
                    return Ok(Some(next(pushes, skipped, grasp, Some(judged))));
                }
            }
            if let Some(grasp) = as_it_lies {
                return Ok(Some(next(Vec::new(), skipped, grasp, None)));
            }
        }
        if let Some(grasp) = self.single.plan_avoiding(observed, &members, avoid)?.value {
            return Ok(Some(next(Vec::new(), skipped, grasp, None)));
        }
        let everything: Vec<ObjectId> = observed.objects().iter().map(|o| o.id).collect();
        Ok(self
            .single
            .plan_avoiding(observed, &everything, avoid)?
            .value
            .map(|grasp| next(Vec::new(), skipped, grasp, None)))
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
    /// reported as skipped to wait for a later trip.
    fn plan_pushes(
        &self,
        pusher: &dyn PolicyPusher,
        observed: &Scene,
        members: &[ObjectId],
    ) -> Result<PushPlan> {
        let usable = Status::has_answer;
        // Planners that do not judge their rows (the paper's) count as held.
        let held = |plan: &PushPlan| plan.row_held != Some(false);
        let whole = pusher.plan(observed, members)?;
        if members.len() < 3 || (usable(&whole.status) && held(&whole.value)) {
            return Ok(whole.value);
        }
        let mut best: Option<(bool, f64, PushPlan)> = None;
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
                .is_none_or(|(h, c, _)| (is_held && !*h) || (is_held == *h && cost < *c));
            if better {
                let mut plan = sub.value;
                plan.skipped.push(SkippedPush {
                    object: *left_out,
                    reason: SkipReason::NoRow,
                });
                best = Some((is_held, cost, plan));
            }
        }
        Ok(match best {
            Some((true, _, plan)) => plan,
            Some((false, _, plan)) if !usable(&whole.status) => plan,
            _ => whole.value,
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

pub(super) fn failure_reason(status: &Status) -> String {
    match status {
        Status::Failed { reason } => reason.clone(),
        other => format!("{other:?}"),
    }
}

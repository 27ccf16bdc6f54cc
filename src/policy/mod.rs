//! Policies and the closed loop that runs them (the Push-MOG paper's Algorithm 1).
//!
//! Each trip: observe the table, plan, execute, count the trip, until the table is clear:
//! - `sog`: pick a graspable object at random (seeded), grasp it alone ([`SingleObject`]).
//! - `mog`: cluster ([`Hierarchical`]), pick a cluster at random, grasp with [`MultiObject`] on the
//!   table as it is: multi-object grasps without pushes.
//! - `push-mog`: cluster, pick a cluster at random, plan fork pushes toward its central object
//!   ([`TowardCentral`]), predict the table after them, plan the multi-object grasp on the
//!   prediction, then execute pushes and grasp (the paper's method).
//! - `push-mog-opt`: the same loop with optimal clustering ([`Milp`]) and SOCP push targets
//!   ([`Socp`]); `push-mog-milp` (MILP clustering, the paper's pushes) and `push-mog-socp` (the
//!   paper's clustering, SOCP pushes) separate the two effects. The push planner's intended grasp is
//!   offered to the grasp planner as a candidate.
//!
//! When the push planner finds no row for a whole cluster of three or more, its largest sub-clusters
//! are tried and the object left out waits for a later trip. When the multi-object planner finds nothing
//! for a cluster, a single-object grasp of one of its
//! objects is tried. An attempt that yields no grasp is recorded with its reason and costs no trip; a
//! grasp that carries nothing is a trip (a failed grasp). The run stops when the table is clear, when
//! every object left is wider than the jaw gap, after `max_failed_attempts` fruitless attempts in a
//! row, or at the trip limit; it never loops forever.

use std::str::FromStr;
use std::sync::Arc;
use std::time::Instant;

use serde::{Deserialize, Serialize};

use crate::cluster::{
    Clusterer, Clustering, Hierarchical, HierarchicalSettings, Milp, MilpSettings,
};
use crate::error::{Error, Result};
use crate::exec::{Executor, Rollout, SimSettings};
use crate::grasp::{
    Grasp, GraspPlanner, JawPose, MultiObject, MultiObjectSettings, SingleObject,
    SingleObjectSettings,
};
use crate::plan::{Fault, Plan, RunStatus, Status, Trip};
use crate::push::{
    Push, PushPlan, PushPlanner, SkipReason, SkippedPush, Socp, SocpSettings, TowardCentral,
    TowardCentralSettings, predict,
};
use crate::random::SeededRng;
use crate::scene::{Gripper, ObjectId, Scene};
use crate::time_model::{GraspPath, PushPath, TimeModel};

/// Which policy.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Serialize, Deserialize, schemars::JsonSchema)]
pub enum PolicyKind {
    /// Single-object grasps in random order.
    #[serde(rename = "sog")]
    Sog,
    /// Multi-object grasps of clusters, no pushes.
    #[serde(rename = "mog")]
    Mog,
    /// Fork pushes toward each cluster's central object, then a multi-object grasp (the paper).
    #[serde(rename = "push-mog")]
    PushMog,
    /// Optimal (MILP) clustering, the paper's pushes toward the central object.
    #[serde(rename = "push-mog-milp")]
    PushMogMilp,
    /// The paper's hierarchical clustering, push targets from the SOCP.
    #[serde(rename = "push-mog-socp")]
    PushMogSocp,
    /// Optimal clustering and SOCP push targets.
    #[serde(rename = "push-mog-opt")]
    PushMogOpt,
}

impl PolicyKind {
    /// Every policy, in table order.
    pub const ALL: [PolicyKind; 6] = [
        PolicyKind::Sog,
        PolicyKind::Mog,
        PolicyKind::PushMog,
        PolicyKind::PushMogMilp,
        PolicyKind::PushMogSocp,
        PolicyKind::PushMogOpt,
    ];

    /// The policy's name (`sog`, `mog`, `push-mog`, `push-mog-milp`, `push-mog-socp`,
    /// `push-mog-opt`).
    pub fn name(self) -> &'static str {
        match self {
            Self::Sog => "sog",
            Self::Mog => "mog",
            Self::PushMog => "push-mog",
            Self::PushMogMilp => "push-mog-milp",
            Self::PushMogSocp => "push-mog-socp",
            Self::PushMogOpt => "push-mog-opt",
        }
    }

    /// Whether the policy clusters with the MILP (rather than the paper's hierarchical clustering).
    pub fn optimal_clustering(self) -> bool {
        matches!(self, Self::PushMogMilp | Self::PushMogOpt)
    }

    /// Whether the policy places push targets with the SOCP (rather than toward the central object).
    pub fn optimal_pushing(self) -> bool {
        matches!(self, Self::PushMogSocp | Self::PushMogOpt)
    }

    /// Whether the policy pushes at all.
    pub fn pushes(self) -> bool {
        !matches!(self, Self::Sog | Self::Mog)
    }
}

impl std::fmt::Display for PolicyKind {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(self.name())
    }
}

impl FromStr for PolicyKind {
    type Err = Error;
    fn from_str(text: &str) -> Result<Self> {
        Self::ALL
            .into_iter()
            .find(|kind| kind.name() == text)
            .ok_or_else(|| {
                Error::field(
                    "policy",
                    "name",
                    format!(
                        "unknown policy `{text}`; choose one of {}",
                        Self::ALL.map(|k| k.name()).join(", ")
                    ),
                )
            })
    }
}

/// Settings of every stage of a policy and of the loop.
#[derive(Clone, Debug, Default, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct PolicySettings {
    /// Hierarchical clustering (`mog`, `push-mog`, `push-mog-socp`).
    pub clustering: HierarchicalSettings,
    /// Optimal clustering (`push-mog-milp`, `push-mog-opt`).
    pub milp: MilpSettings,
    /// Pushes toward the central object (`push-mog`, `push-mog-milp`).
    pub pushing: TowardCentralSettings,
    /// SOCP push targets (`push-mog-socp`, `push-mog-opt`).
    pub socp: SocpSettings,
    /// Single-object grasps (`sog`, and the fallback of the others).
    pub single: SingleObjectSettings,
    /// Multi-object grasps (`mog`, `push-mog`).
    pub multi: MultiObjectSettings,
    /// Limits of the loop.
    pub run: LoopSettings,
    /// Judge multi-object candidates by rolling each sample out in the rapier simulator (default
    /// settings) instead of with the grasp model: slower by two orders of magnitude, for comparison.
    /// Default false.
    pub rollout: bool,
    /// Seconds per trip and per push: the time each run reports, and the time the MILP clustering
    /// minimises (it replaces `milp.time_model`).
    pub time_model: TimeModel,
}

/// Limits that keep the closed loop finite.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct LoopSettings {
    /// Attempts in a row that find no grasp or carry nothing before the run stops. Default 10.
    pub max_failed_attempts: usize,
    /// Trips allowed per object on the table at the start (at least one trip). Default 3.
    pub max_trips_per_object: f64,
}

impl Default for LoopSettings {
    fn default() -> Self {
        Self {
            max_failed_attempts: 10,
            max_trips_per_object: 3.0,
        }
    }
}

impl PolicySettings {
    /// Checks every stage's settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        self.clustering.validate()?;
        self.milp.validate()?;
        self.pushing.validate()?;
        self.socp.validate()?;
        self.single.validate()?;
        self.multi.validate()?;
        self.time_model.validate()?;
        if self.run.max_failed_attempts == 0 {
            return Err(Error::field(
                "run",
                "max_failed_attempts",
                "must be at least 1",
            ));
        }
        if !(self.run.max_trips_per_object.is_finite() && self.run.max_trips_per_object > 0.0) {
            return Err(Error::field(
                "run",
                "max_trips_per_object",
                format!("must be positive, got {}", self.run.max_trips_per_object),
            ));
        }
        Ok(())
    }
}

/// A policy ready to run.
#[derive(Clone, Debug)]
pub struct Policy {
    kind: PolicyKind,
    settings: PolicySettings,
    clusterer: AnyClusterer,
    pusher: AnyPusher,
    single: SingleObject,
    multi: MultiObject,
}

/// Wall-clock planning times of one run, seconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunTiming {
    /// Every planning attempt (clustering, pushes and grasp together).
    pub planning: Vec<f64>,
    /// Every clustering.
    pub clustering: Vec<f64>,
}

/// One of the clusterers, chosen by the settings.
#[derive(Clone, Debug)]
enum AnyClusterer {
    Hierarchical(Hierarchical),
    Milp(Milp),
}

impl AnyClusterer {
    fn get(&self) -> &dyn Clusterer {
        match self {
            Self::Hierarchical(c) => c,
            Self::Milp(c) => c,
        }
    }
}

/// One of the push planners, chosen by the policy.
#[derive(Clone, Debug)]
enum AnyPusher {
    TowardCentral(TowardCentral),
    Socp(Socp),
}

impl AnyPusher {
    fn get(&self) -> &dyn PushPlanner {
        match self {
            Self::TowardCentral(p) => p,
            Self::Socp(p) => p,
        }
    }
}

/// What one planning attempt produced before execution.
struct Draft {
    clustering: Clustering,
    cluster: Option<usize>,
    pushes: Vec<Push>,
    skipped: Vec<SkippedPush>,
    grasp: Grasp,
}

impl Policy {
    /// A policy with these settings.
    ///
    /// # Errors
    /// [`Error::InvalidField`] when a setting is out of range.
    pub fn new(kind: PolicyKind, settings: PolicySettings) -> Result<Self> {
        settings.validate()?;
        Ok(Self {
            kind,
            clusterer: if kind.optimal_clustering() {
                AnyClusterer::Milp(Milp::new(MilpSettings {
                    time_model: settings.time_model.clone(),
                    ..settings.milp.clone()
                })?)
            } else {
                AnyClusterer::Hierarchical(Hierarchical::new(settings.clustering.clone())?)
            },
            pusher: if kind.optimal_pushing() {
                AnyPusher::Socp(Socp::new(settings.socp.clone())?)
            } else {
                AnyPusher::TowardCentral(TowardCentral::new(settings.pushing.clone())?)
            },
            single: SingleObject::new(settings.single.clone())?,
            multi: if settings.rollout {
                MultiObject::with_outcome(
                    settings.multi.clone(),
                    Arc::new(Rollout {
                        settings: SimSettings::default(),
                        samples: settings.multi.samples,
                        noise: settings.multi.noise.clone(),
                    }),
                )?
            } else {
                MultiObject::new(settings.multi.clone())?
            },
            settings,
        })
    }

    /// Which policy this is.
    pub fn kind(&self) -> PolicyKind {
        self.kind
    }

    /// The effective settings.
    pub fn settings(&self) -> &PolicySettings {
        &self.settings
    }

    /// Grasps of `targets` the multi-object planner refuses although they catch two or more objects
    /// and land on nothing, evenly spread over its candidates (see [`MultiObject::refused`]).
    ///
    /// # Errors
    /// An id that is not in the scene.
    pub fn refused_candidates(&self, scene: &Scene, targets: &[ObjectId]) -> Result<Vec<Grasp>> {
        let all = self.multi.refused(scene, targets)?;
        // Every k-th, so a few replays sample the whole list.
        let stride = (all.len() / 8).max(1);
        Ok(all.into_iter().step_by(stride).collect())
    }

    /// Clears `scene` with `executor`, planning after every observation; `seed` drives the random
    /// choices (which object or cluster next).
    ///
    /// # Errors
    /// Misuse or an executor fault; a run that cannot clear the table ends with
    /// [`RunStatus::Stopped`] inside `Ok`.
    pub fn run(&self, scene: &Scene, executor: &mut dyn Executor, seed: u64) -> Result<Plan> {
        self.run_timed(scene, executor, seed).map(|(plan, _)| plan)
    }

    /// As [`Policy::run`], also returning how long planning took (wall-clock, so not reproducible;
    /// kept apart from the plan).
    ///
    /// # Errors
    /// As [`Policy::run`].
    pub fn run_timed(
        &self,
        scene: &Scene,
        executor: &mut dyn Executor,
        seed: u64,
    ) -> Result<(Plan, RunTiming)> {
        let mut timing = RunTiming::default();
        executor.reset(scene)?;
        let mut rng = SeededRng::new(seed);
        let max_trips =
            ((self.settings.run.max_trips_per_object * scene.len() as f64).ceil() as usize).max(1);
        let mut trips: Vec<Trip> = Vec::new();
        let mut failed_attempts: Vec<String> = Vec::new();
        let mut in_a_row = 0;
        // Where grasps carried nothing: never tried again in the same place.
        let mut failed_jaws: Vec<JawPose> = Vec::new();
        let status = loop {
            let observed = executor.observe()?;
            let lost = executor.lost();
            let mut remaining: Vec<ObjectId> = observed.objects().iter().map(|o| o.id).collect();
            remaining.extend(lost.iter().map(|(id, _)| *id));
            if observed.is_empty() {
                if lost.is_empty() {
                    break RunStatus::Cleared;
                }
                let mut reasons: Vec<&str> = lost.iter().map(|(_, why)| *why).collect();
                reasons.sort_unstable();
                reasons.dedup();
                let counts: Vec<String> = reasons
                    .iter()
                    .map(|why| {
                        let n = lost.iter().filter(|(_, w)| w == why).count();
                        format!("{n} {why}")
                    })
                    .collect();
                break RunStatus::Stopped {
                    remaining,
                    reason: format!(
                        "nothing left that can be planned for: {}",
                        counts.join(", ")
                    ),
                };
            }
            let stop = |reason: String| RunStatus::Stopped {
                remaining: remaining.clone(),
                reason,
            };
            if observed.ungraspable().len() == observed.len() {
                break stop("every object left is wider than the jaw gap".to_string());
            }
            if in_a_row >= self.settings.run.max_failed_attempts {
                break stop(format!(
                    "{in_a_row} attempts in a row found no grasp or carried nothing"
                ));
            }
            if trips.len() >= max_trips {
                break stop(format!("trip limit of {max_trips} reached"));
            }
            let started = Instant::now();
            let draft = match self.kind {
                PolicyKind::Sog => self.draft_single(&observed, &mut rng, &failed_jaws)?,
                kind => self.draft_clustered(
                    &observed,
                    &mut rng,
                    kind.pushes(),
                    &failed_jaws,
                    &mut timing,
                )?,
            };
            timing.planning.push(started.elapsed().as_secs_f64());
            let draft = match draft {
                Ok(draft) => draft,
                Err(reason) => {
                    failed_attempts.push(reason);
                    in_a_row += 1;
                    continue;
                }
            };
            let mut fault = None;
            for (k, push) in draft.pushes.iter().enumerate() {
                if let Some(landing) = executor.push(push)? {
                    fault = Some(Fault::Push {
                        push: k,
                        object: landing.object,
                    });
                    break;
                }
            }
            let carried = if fault.is_none() {
                let result = executor.grasp(&draft.grasp)?;
                fault = result.landing.map(|landing| Fault::Grasp {
                    object: landing.object,
                });
                result.carried
            } else {
                Vec::new()
            };
            in_a_row = if carried.is_empty() { in_a_row + 1 } else { 0 };
            if carried.is_empty() {
                failed_jaws.push(draft.grasp.jaws);
            }
            trips.push(Trip {
                scene: observed.to_spec(),
                clustering: draft.clustering,
                cluster: draft.cluster,
                pushes: draft.pushes,
                skipped_pushes: draft.skipped,
                grasp: draft.grasp,
                carried,
                fault,
            });
        };
        let seconds = run_seconds(
            &self.settings.time_model,
            scene.gripper(),
            &trips,
            failed_attempts.len(),
        );
        Ok((
            Plan {
                seconds,
                policy: self.kind.name().to_string(),
                executor: executor.name().to_string(),
                seed,
                settings: serde_json::to_value(&self.settings).unwrap_or_default(),
                trips,
                failed_attempts,
                status,
            },
            timing,
        ))
    }

    fn draft_single(
        &self,
        observed: &Scene,
        rng: &mut SeededRng,
        avoid: &[JawPose],
    ) -> Result<std::result::Result<Draft, String>> {
        let graspable: Vec<usize> = (0..observed.len())
            .filter(|&i| observed.is_graspable(i))
            .collect();
        // A random object first, then the others in turn if its grasps all failed before.
        let first = rng.index(graspable.len());
        let order = graspable[first..].iter().chain(&graspable[..first]);
        let mut reason = String::new();
        for &index in order {
            let target = observed.objects()[index].id;
            let outcome = self.single.plan_avoiding(observed, &[target], avoid)?;
            match outcome.value {
                Some(grasp) => {
                    return Ok(Ok(Draft {
                        clustering: Clustering::default(),
                        cluster: None,
                        pushes: Vec::new(),
                        skipped: Vec::new(),
                        grasp,
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
    /// again.
    fn draft_clustered(
        &self,
        observed: &Scene,
        rng: &mut SeededRng,
        with_pushes: bool,
        avoid: &[JawPose],
        timing: &mut RunTiming,
    ) -> Result<std::result::Result<Draft, String>> {
        let started = Instant::now();
        let clustering = self.clusterer.get().cluster(observed)?.value;
        timing.clustering.push(started.elapsed().as_secs_f64());
        let candidates: Vec<usize> = (0..clustering.len())
            .filter(|&k| {
                clustering.clusters[k]
                    .iter()
                    .filter_map(|&id| observed.index_of(id))
                    .any(|i| observed.is_graspable(i))
            })
            .collect();
        let chosen = candidates[rng.index(candidates.len())];
        let members = clustering.clusters[chosen].clone();
        let draft = |pushes: Vec<Push>, skipped: Vec<SkippedPush>, grasp: Grasp| Draft {
            clustering: clustering.clone(),
            cluster: Some(chosen),
            pushes,
            skipped,
            grasp,
        };
        let mut skipped = Vec::new();
        if with_pushes && members.len() > 1 {
            let plan = self.plan_pushes(observed, &members)?;
            skipped = plan.skipped;
            if !plan.pushes.is_empty() {
                let predicted = predict(observed, &plan.pushes)?;
                let hints: Vec<JawPose> = plan.intended_grasp.into_iter().collect();
                let pushed: Vec<ObjectId> = plan.pushes.iter().map(|p| p.object).collect();
                let outcome = self
                    .multi
                    .plan_after_pushes(&predicted, &members, &hints, &pushed, avoid)?;
                if let Some(grasp) = outcome.value.filter(|g| g.objects.len() >= 2) {
                    let left: Vec<ObjectId> = pushed
                        .iter()
                        .copied()
                        .filter(|id| !grasp.objects.contains(id))
                        .collect();
                    if self.each_has_a_fallback(&predicted, &left)? {
                        return Ok(Ok(draft(plan.pushes, skipped, grasp)));
                    }
                    skipped.extend(pushed.iter().map(|&object| SkippedPush {
                        object,
                        reason: SkipReason::DeadEnd,
                    }));
                } else {
                    skipped.extend(pushed.iter().map(|&object| SkippedPush {
                        object,
                        reason: SkipReason::NoGraspAfter,
                    }));
                }
            }
        }
        // As the cluster lies: a multi-object grasp of two or more, else one object by itself (jaws
        // opened just wider than the object, flush on an edge, not fully around it).
        let outcome = self
            .multi
            .plan_after_pushes(observed, &members, &[], &[], avoid)?;
        if let Some(grasp) = outcome.value.filter(|g| g.objects.len() >= 2) {
            return Ok(Ok(draft(Vec::new(), skipped, grasp)));
        }
        let single = self.single.plan_avoiding(observed, &members, avoid)?;
        Ok(match single.value {
            Some(grasp) => Ok(draft(Vec::new(), skipped, grasp)),
            None => Err(format!(
                "cluster {:?}: {}",
                members.iter().map(|id| id.0).collect::<Vec<_>>(),
                failure_reason(&single.status)
            )),
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
}

impl Policy {
    /// Pushes for a cluster. When no row of the whole cluster can be planned (the SOCP proves it
    /// infeasible, or no push sequence exists), or the planned row is not predicted held while a
    /// smaller one is, the largest sub-clusters are tried, cheapest first, and the object left out is
    /// reported as skipped to wait for a later trip.
    fn plan_pushes(&self, observed: &Scene, members: &[ObjectId]) -> Result<PushPlan> {
        let pusher = self.pusher.get();
        let usable =
            |status: &Status| !matches!(status, Status::Infeasible | Status::Failed { .. });
        // Planners that do not judge their rows (the paper's) count as held.
        let held = |stats: &crate::plan::Stats| stats.counter("row_held").is_none_or(|h| h > 0.5);
        let whole = pusher.plan(observed, members)?;
        if members.len() < 3 || (usable(&whole.status) && held(&whole.stats)) {
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
                held(&sub.stats),
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

/// Robot time of a run by the time model: every trip as planned (a trip stopped by a landing is
/// charged in full, a stand-in for recovering from it) and an observation before every trip and
/// every planning attempt that found nothing, seconds.
pub fn run_seconds(model: &TimeModel, gripper: &Gripper, trips: &[Trip], failed: usize) -> f64 {
    let trips_seconds: f64 = trips
        .iter()
        .map(|trip| {
            let pushes: Vec<PushPath> = trip
                .pushes
                .iter()
                .map(|p| PushPath {
                    approach: p.fork.approach,
                    end: p.fork.end,
                })
                .collect();
            let grasp = GraspPath {
                center: trip.grasp.jaws.center,
                opening: trip.grasp.jaws.opening,
                closed: (trip.grasp.width + gripper.plate_thickness).min(trip.grasp.jaws.opening),
            };
            model.trip_seconds(gripper, &pushes, &grasp)
        })
        .sum();
    trips_seconds + model.observation * (trips.len() + failed) as f64
}

fn failure_reason(status: &Status) -> String {
    match status {
        Status::Failed { reason } => reason.clone(),
        other => format!("{other:?}"),
    }
}

//! The closed loop (the paper's Algorithm 1) as a small driver over [`Policy::plan_trip_with`] and an
//! [`Executor`]: observe, plan one trip, push, grasp, record, until the table is clear or a typed stop
//! reason ends the run. It never loops forever: it stops when the table is clear, when nothing left
//! can be planned for (toppled, outside), when every object left is wider than the jaw gap, after
//! `max_failed_attempts` fruitless attempts in a row, or at the trip limit. With
//! `run.reach_past_edge`, a workspace left empty but for objects the executor sees just past its
//! edge is not the end: those are taken one at a time first (`past_edge.rs`).
//!
//! An attempt that yields no grasp is recorded with its reason and costs no trip; a grasp that
//! carries nothing is a trip (a failed grasp). [`Run::record`] gives the record so far at any moment,
//! so a caller whose executor failed keeps every trip made.

use std::time::Instant;

use super::context::{Landing, TripContext};
use super::fuse::LookFusion;
use super::{NoTrip, Policy, TimeModel, TripPlan};
use crate::error::Result;
use crate::exec::Executor;
use crate::plan::{Fault, Look, LostObject, Plan, RunStatus, SharedScene, StopReason, Trip};
use crate::scene::{Gripper, ObjectId, Scene};

/// Wall-clock planning times of one run, seconds.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct RunTiming {
    /// Every planning attempt (clustering, pushes and grasp together).
    pub planning: Vec<f64>,
    /// Every clustering.
    pub clustering: Vec<f64>,
}

/// A closed-loop run under way.
#[derive(Debug)]
pub struct Run<'a> {
    policy: &'a Policy,
    gripper: Gripper,
    seed: u64,
    executor: &'static str,
    context: TripContext,
    max_trips: usize,
    in_a_row: usize,
    trips: Vec<Trip>,
    failed_attempts: Vec<String>,
    timing: RunTiming,
    status: Option<RunStatus>,
    verify_first: bool,
    /// What the executor reported lost at the last observation.
    lost_before: Vec<ObjectId>,
    /// With `run.fuse_looks`, the poses seen since each object was last touched.
    fusion: Option<LookFusion>,
}

impl<'a> Run<'a> {
    /// Resets `executor` to `scene` and starts a run; `seed` drives the random choices (which object
    /// or cluster next).
    ///
    /// # Errors
    /// An executor fault.
    pub fn start(
        policy: &'a Policy,
        scene: &Scene,
        executor: &mut dyn Executor,
        seed: u64,
    ) -> Result<Self> {
        executor.reset(scene)?;
        let limit = policy.settings().run.max_trips_per_object * scene.len() as f64;
        let noise = &policy.settings().multi.noise;
        let fusion = policy
            .settings()
            .run
            .fuse_looks
            .then(|| LookFusion::new(noise.perception_position, noise.perception_yaw));
        Ok(Self {
            policy,
            gripper: scene.gripper().clone(),
            seed,
            executor: executor.name(),
            context: TripContext::new(seed),
            max_trips: (limit.ceil() as usize).max(1),
            in_a_row: 0,
            trips: Vec::new(),
            failed_attempts: Vec::new(),
            timing: RunTiming::default(),
            status: None,
            verify_first: false,
            lost_before: Vec::new(),
            fusion,
        })
    }

    /// Check every trip's plan with the independent verifier before carrying it out, and stop with
    /// an error, having sent nothing of that trip, if it fails (for a real robot).
    pub fn verify_before_acting(mut self) -> Self {
        self.verify_first = true;
        self
    }

    /// One observation and what follows it: a trip, a planning attempt that found nothing, or the
    /// end of the run. Returns the final status once the run has ended (and then does nothing).
    ///
    /// # Errors
    /// An executor fault, or with [`Run::verify_before_acting`] an [`crate::Error::Refused`] trip;
    /// the record so far stays available through [`Run::record`].
    pub fn step(&mut self, executor: &mut dyn Executor) -> Result<Option<&RunStatus>> {
        if self.status.is_some() {
            return Ok(self.status.as_ref());
        }
        let observed = self.fused(executor.observe()?);
        let lost = executor.lost();
        let newly = self.newly_lost(&lost);
        if let Some(trip) = self.trips.last_mut() {
            trip.lost.extend(newly);
        }
        self.context.note_lost(&lost);
        if observed.is_empty() && !lost.is_empty() && self.may_go_on() {
            let seen = executor.past_edge();
            let gripper = observed.gripper();
            if let Some((table, trip)) = self.policy.past_edge_trip(
                observed.workspace(),
                gripper,
                &seen,
                &self.context.failed,
            )? {
                let record = Trip {
                    scene: SharedScene::sharing(
                        table.to_spec(),
                        self.trips.last().map(|t| &t.scene),
                    ),
                    plan: trip,
                    looks: Vec::new(),
                    carried: Vec::new(),
                    fault: None,
                    lost: Vec::new(),
                };
                self.refuse_unless_verified(&record)?;
                self.grasp_and_record(record, &table, 0, executor)?;
                return Ok(None);
            }
        }
        if let Some(reason) = self.stop_reason(&observed, &lost) {
            let mut remaining: Vec<ObjectId> = observed.objects().iter().map(|o| o.id).collect();
            remaining.extend(lost.iter().map(|(id, _)| *id));
            self.status = Some(match reason {
                None => RunStatus::Cleared,
                Some(reason) => RunStatus::Stopped { remaining, reason },
            });
            return Ok(self.status.as_ref());
        }
        let mut planned = self.plan_trip(&observed)?;
        if planned.is_err() {
            let carried: Vec<ObjectId> =
                self.trips.iter().flat_map(|t| t.carried.clone()).collect();
            if self.context.forget_landings_on(&carried) {
                // Grasps that came down on an object since carried away stopped every plan: their
                // places are tried again.
                planned = self.plan_trip(&observed)?;
            }
        }
        let trip = match planned {
            Ok(trip) => trip,
            Err(no_trip) => {
                self.failed_attempts.push(no_trip.to_string());
                self.in_a_row += 1;
                return Ok(None);
            }
        };
        let run_settings = &self.policy.settings().run;
        let mut record = Trip {
            scene: SharedScene::sharing(observed.to_spec(), self.trips.last().map(|t| &t.scene)),
            plan: trip.clone(),
            looks: Vec::new(),
            carried: Vec::new(),
            fault: None,
            lost: Vec::new(),
        };
        self.refuse_unless_verified(&record)?;
        // Push; then, if anything was pushed, look again and plan the rest of the trip on what is
        // seen: corrective pushes (at most `max_corrections` rounds) and the grasp.
        let mut current = trip;
        let mut from = 0;
        // Pushes already noted for the looks' fusion.
        let mut noted = 0;
        loop {
            for (k, push) in record.plan.pushes.iter().enumerate().skip(from) {
                if let Some(landing) = executor.push(push)? {
                    record.fault = Some(Fault::Push {
                        push: k,
                        object: landing.object,
                    });
                    self.context.landed.push(Landing {
                        push: push.clone(),
                        on: landing.object,
                    });
                    break;
                }
            }
            // Pushes ahead for a later trip's grasp are seen at the next trip's look.
            let ahead = !record.plan.ahead.is_empty();
            if record.fault.is_some()
                || record.plan.pushes.len() == from
                || !run_settings.observe_after_pushes
                || ahead
            {
                break;
            }
            self.note_pushes(&record.plan.pushes[noted..]);
            noted = record.plan.pushes.len();
            let after = self.fused(executor.observe()?);
            let newly = self.newly_lost(&executor.lost());
            record.lost.extend(newly);
            let may_push = record.looks.len() < run_settings.max_corrections;
            // Nothing on the table can be grasped: the grasp planned before is made (as the paper
            // would), on the table it was planned for.
            let Some(next) = self
                .policy
                .correct_trip(&after, &current, &self.context, may_push)?
            else {
                break;
            };
            from = record.plan.pushes.len();
            record.looks.push(Look {
                after_pushes: from,
                scene: SharedScene::sharing(after.to_spec(), Some(&record.scene)),
            });
            record.plan.pushes.extend(next.pushes.iter().cloned());
            record
                .plan
                .push_statuses
                .extend(next.push_statuses.iter().cloned());
            record.plan.grasp = next.grasp.clone();
            record.plan.riders = next.riders.clone();
            current = next;
            self.refuse_unless_verified(&record)?;
        }
        self.grasp_and_record(record, &observed, noted, executor)?;
        Ok(None)
    }

    /// Whether the run may make another attempt: fewer fruitless ones in a row than allowed, and
    /// fewer trips than the limit.
    fn may_go_on(&self) -> bool {
        self.in_a_row < self.policy.settings().run.max_failed_attempts
            && self.trips.len() < self.max_trips
    }

    /// Puts down the riders of `record` and makes its grasp (unless a landing stopped it), then
    /// records the trip: the riders put down on `observed`, the pushes from `noted` on for the
    /// looks' fusion, and a grasp that carried nothing.
    fn grasp_and_record(
        &mut self,
        mut record: Trip,
        observed: &Scene,
        noted: usize,
        executor: &mut dyn Executor,
    ) -> Result<()> {
        place_and_grasp(&mut record, executor)?;
        self.context.note_riders(observed, &record.plan);
        self.context.note_carried(&record.plan, &record.carried);
        self.note_pushes(&record.plan.pushes[noted..]);
        if let Some(fusion) = self.fusion.as_mut() {
            fusion.trip_grasped(&record.plan);
        }
        if record.carried.is_empty() {
            self.in_a_row += 1;
            match record.fault {
                Some(Fault::Grasp { object }) => {
                    self.context.record_landing(&record.plan.grasp, object);
                }
                _ => self.context.record_failure(&record.plan.grasp),
            }
        } else {
            self.in_a_row = 0;
        }
        self.trips.push(record);
        Ok(())
    }

    /// `observed` with the looks fused (`run.fuse_looks`), or as it is.
    fn fused(&mut self, observed: Scene) -> Scene {
        match self.fusion.as_mut() {
            Some(fusion) => fusion.fuse(observed),
            None => observed,
        }
    }

    /// Notes `pushes` as made, for the looks' fusion.
    fn note_pushes(&mut self, pushes: &[crate::push::Push]) {
        if let Some(fusion) = self.fusion.as_mut() {
            for push in pushes {
                fusion.pushed(push);
            }
        }
    }

    /// Plans a trip on `observed`, timing it.
    fn plan_trip(&mut self, observed: &Scene) -> Result<std::result::Result<TripPlan, NoTrip>> {
        let started = Instant::now();
        let planned = self.policy.plan_trip_with(observed, &mut self.context)?;
        self.timing.planning.push(started.elapsed().as_secs_f64());
        if let Some(seconds) = planned.stats.counter("clustering_seconds") {
            self.timing.clustering.push(seconds);
        }
        Ok(planned.trip)
    }

    /// The objects of `lost` (the executor's report at an observation) that the report before did
    /// not have; remembers `lost` for the next observation.
    fn newly_lost(&mut self, lost: &[(ObjectId, &'static str)]) -> Vec<LostObject> {
        let newly = lost
            .iter()
            .filter(|(id, _)| !self.lost_before.contains(id))
            .map(|&(object, why)| LostObject {
                object,
                reason: why.to_string(),
            })
            .collect();
        self.lost_before = lost.iter().map(|(id, _)| *id).collect();
        newly
    }

    /// With [`Run::verify_before_acting`], an error unless the verifier passes the trip as planned
    /// so far (nothing of what it finds wrong has been sent).
    fn refuse_unless_verified(&self, record: &Trip) -> Result<()> {
        if !self.verify_first {
            return Ok(());
        }
        match crate::plan::verify_trip(record).first() {
            None => Ok(()),
            Some(problem) => Err(crate::error::Error::Refused {
                trip: self.trips.len(),
                reason: problem.clone(),
            }),
        }
    }

    /// `Some(None)` when the table is clear, `Some(Some(reason))` when the run must stop, `None` to
    /// go on.
    fn stop_reason(
        &self,
        observed: &Scene,
        lost: &[(ObjectId, &'static str)],
    ) -> Option<Option<StopReason>> {
        if observed.is_empty() {
            if lost.is_empty() {
                return Some(None);
            }
            let mut reasons: Vec<&str> = lost.iter().map(|(_, why)| *why).collect();
            reasons.sort_unstable();
            reasons.dedup();
            let lost = reasons
                .iter()
                .map(|why| {
                    (
                        why.to_string(),
                        lost.iter().filter(|(_, w)| w == why).count(),
                    )
                })
                .collect();
            return Some(Some(StopReason::NothingPlannable { lost }));
        }
        if observed.ungraspable().len() == observed.len() {
            return Some(Some(StopReason::AllTooWide));
        }
        if self.in_a_row >= self.policy.settings().run.max_failed_attempts {
            return Some(Some(StopReason::FailedAttempts {
                count: self.in_a_row,
            }));
        }
        if self.trips.len() >= self.max_trips {
            return Some(Some(StopReason::TripLimit {
                limit: self.max_trips,
            }));
        }
        None
    }

    /// The record so far: every trip made and every fruitless attempt, with the final status once
    /// the run has ended (until then, stopped as interrupted).
    pub fn record(&self) -> Plan {
        self.plan(self.trips.clone())
    }

    /// The status after `trips` (the run's own): the final one, or stopped as interrupted with
    /// every object seen and not carried still somewhere.
    fn status_after(&self, trips: &[Trip]) -> RunStatus {
        self.status.clone().unwrap_or_else(|| {
            let carried: std::collections::HashSet<ObjectId> = trips
                .iter()
                .flat_map(|t| t.carried.iter().copied())
                .collect();
            let mut seen = std::collections::HashSet::new();
            let remaining = trips
                .iter()
                .flat_map(|trip| trip.scene.ids())
                .filter(|id| !carried.contains(id) && seen.insert(*id))
                .collect();
            RunStatus::Stopped {
                remaining,
                reason: StopReason::Interrupted,
            }
        })
    }

    /// The record with these trips (the run's own).
    fn plan(&self, trips: Vec<Trip>) -> Plan {
        let settings = self.policy.settings();
        Plan {
            seconds: run_seconds(
                self.policy.problem().time_model(),
                &self.gripper,
                &trips,
                self.failed_attempts.len(),
            ),
            policy: self.policy.kind().name().to_string(),
            executor: self.executor.to_string(),
            seed: self.seed,
            settings: serde_json::to_value(settings).unwrap_or_default(),
            status: self.status_after(&trips),
            failed_attempts: self.failed_attempts.clone(),
            trips,
        }
    }

    /// The wall-clock planning times so far.
    pub fn timing(&self) -> &RunTiming {
        &self.timing
    }

    /// The record and the planning times, ending the run.
    pub fn finish(mut self) -> (Plan, RunTiming) {
        let trips = std::mem::take(&mut self.trips);
        (self.plan(trips), self.timing)
    }
}

/// The end of a trip not stopped before: its riders put on the row, then the grasp, with what it
/// carried or the landing that stopped it.
fn place_and_grasp(record: &mut Trip, executor: &mut dyn Executor) -> Result<()> {
    if record.fault.is_some() {
        return Ok(());
    }
    for (k, rider) in record.plan.riders.iter().enumerate() {
        if let Some(landing) = executor.place(rider)? {
            record.fault = Some(Fault::Place {
                rider: k,
                object: landing.object,
            });
            return Ok(());
        }
    }
    let result = executor.grasp(&record.plan.grasp)?;
    record.fault = result.landing.map(|landing| Fault::Grasp {
        object: landing.object,
    });
    record.carried = result.carried;
    Ok(())
}

/// Robot time of a run by the time model: every trip as planned (a trip stopped by a landing is
/// charged in full, a stand-in for recovering from it), an observation before every trip and every
/// planning attempt that found nothing, and one for every look during a trip, seconds.
pub fn run_seconds(model: &TimeModel, gripper: &Gripper, trips: &[Trip], failed: usize) -> f64 {
    let trips_seconds: f64 = trips
        .iter()
        .map(|trip| {
            let mut pushes = super::push_paths(&trip.plan.pushes);
            for look in &trip.looks {
                if let Some(push) = look
                    .after_pushes
                    .checked_sub(1)
                    .and_then(|k| pushes.get_mut(k))
                {
                    push.look_after = true;
                }
            }
            model.trip_seconds_with_riders(
                gripper,
                &pushes,
                &super::rider_paths(&trip.plan.riders, gripper),
                &super::grasp_path(&trip.plan.grasp, gripper),
            )
        })
        .sum();
    let looks: usize = trips.iter().map(|trip| trip.looks.len()).sum();
    trips_seconds + model.look_seconds() * (trips.len() + failed + looks) as f64
}

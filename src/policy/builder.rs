//! Builds a [`Policy`] from a preset and its settings, with any stage replaced: the shared problem,
//! each stage's planner, and the multi-object planner without the edge margin that the last way out
//! of a dead end uses (`separate.rs`).

use std::sync::Arc;

use super::{
    ClustererKind, Policy, PolicyClusterer, PolicyGraspPlanner, PolicyKind, PolicyPusher,
    PolicySettings, PusherKind,
};
use crate::cluster::{Hierarchical, RowTest};
use crate::error::Result;
use crate::grasp::{MultiObject, MultiObjectSettings, SingleObject};
use crate::problem::Problem;
use crate::push::{Socp, TowardCentral};

/// Builds a [`Policy`] from a preset, replacing any of its parts.
///
/// ```
/// use pushmog::cluster::Hierarchical;
/// use pushmog::policy::{Policy, PolicyKind};
/// // The paper's pushes with the paper's clustering, however push-mog-opt would cluster.
/// let policy = Policy::builder(PolicyKind::PushMogOpt)
///     .clusterer(Hierarchical::default())
///     .build()
///     .unwrap();
/// assert_eq!(policy.kind(), PolicyKind::PushMogOpt);
/// ```
#[derive(Debug)]
pub struct PolicyBuilder {
    pub(super) kind: PolicyKind,
    pub(super) settings: PolicySettings,
    pub(super) clusterer: Option<Option<Arc<dyn PolicyClusterer>>>,
    pub(super) pusher: Option<Option<Arc<dyn PolicyPusher>>>,
    pub(super) single: Option<Arc<dyn PolicyGraspPlanner>>,
    pub(super) multi: Option<Arc<dyn PolicyGraspPlanner>>,
    pub(super) parts: (Option<Option<ClustererKind>>, Option<PusherKind>),
}

impl PolicyBuilder {
    /// Settings of every stage (defaults otherwise).
    pub fn settings(mut self, settings: PolicySettings) -> Self {
        self.settings = settings;
        self
    }

    /// Cluster with this clusterer.
    pub fn clusterer(mut self, clusterer: impl PolicyClusterer + 'static) -> Self {
        self.clusterer = Some(Some(Arc::new(clusterer)));
        self
    }

    /// Push with this push planner.
    pub fn pusher(mut self, pusher: impl PolicyPusher + 'static) -> Self {
        self.pusher = Some(Some(Arc::new(pusher)));
        self
    }

    /// Grasp one object at a time with this planner (its requests ask for one object).
    pub fn single_object_planner(mut self, planner: impl PolicyGraspPlanner + 'static) -> Self {
        self.single = Some(Arc::new(planner));
        self
    }

    /// Grasp several objects at once with this planner: every multi-object grasp the policy makes,
    /// after pushes or as the objects lie, is its answer to a [`GraspRequest`](crate::grasp::GraspRequest) for two or more
    /// objects. The SOCP still judges its rows with the built-in planner of the settings
    /// (`socp.robust_rows`). `examples/custom_grasp_planner.rs` plugs one into push-mog-opt.
    pub fn multi_object_planner(mut self, planner: impl PolicyGraspPlanner + 'static) -> Self {
        self.multi = Some(Arc::new(planner));
        self
    }

    /// Use a named clusterer, built from the settings (`None`: single-object grasps, no clustering).
    pub fn clusterer_kind(mut self, kind: Option<ClustererKind>) -> Self {
        self.parts.0 = Some(kind);
        self
    }

    /// Use a named push planner, built from the settings.
    pub fn pusher_kind(mut self, kind: PusherKind) -> Self {
        self.parts.1 = Some(kind);
        self
    }

    /// The policy.
    ///
    /// # Errors
    /// [`crate::error::Error::InvalidField`] when a setting is out of range.
    pub fn build(self) -> Result<Policy> {
        let settings = self.settings;
        // Checked once: the shared problem, then each stage's own settings.
        let problem = settings.problem()?;
        settings.validate_stages()?;
        // The clustering's pair test follows flush pushes only when the SOCP makes the pushes.
        let pusher_kind = self.parts.1.unwrap_or(self.kind.pusher());
        let rows = if self.pusher.is_some() || pusher_kind != PusherKind::Socp {
            RowTest {
                flush_pairs: None,
                ..settings.row_test()
            }
        } else {
            settings.row_test()
        };
        let judge = multi_object(&settings, &problem)?;
        let at_edges = if self.multi.is_none() && settings.multi.edge_margin > 0.0 {
            let without_margin = PolicySettings {
                multi: MultiObjectSettings {
                    edge_margin: 0.0,
                    ..settings.multi.clone()
                },
                ..settings.clone()
            };
            Some(Arc::new(multi_object(&without_margin, &problem)?) as Arc<dyn PolicyGraspPlanner>)
        } else {
            None
        };
        let clusterer = match self.clusterer {
            Some(chosen) => chosen,
            None => match self.parts.0.unwrap_or(self.kind.clusterer()) {
                None => None,
                Some(ClustererKind::Hierarchical) => {
                    Some(Arc::new(Hierarchical::new(settings.clustering.clone())?)
                        as Arc<dyn PolicyClusterer>)
                }
                Some(ClustererKind::Milp) => {
                    Some(Arc::new(settings.milp_clusterer(problem.clone(), rows)?) as _)
                }
            },
        };
        let pusher = match self.pusher {
            Some(chosen) => chosen,
            None => match self.parts.1.unwrap_or(self.kind.pusher()) {
                PusherKind::None => None,
                PusherKind::TowardCentral => Some(Arc::new(TowardCentral::new(
                    settings.pushing.clone(),
                    problem.clone(),
                )?) as Arc<dyn PolicyPusher>),
                PusherKind::Socp => Some(Arc::new(
                    Socp::new(settings.socp.clone(), problem.clone())?.with_judge(judge.clone()),
                ) as _),
            },
        };
        Ok(Policy {
            kind: self.kind,
            clusterer,
            pusher,
            single: match self.single {
                Some(chosen) => chosen,
                None => Arc::new(SingleObject::new(settings.single.clone(), problem.clone())?),
            },
            at_edges,
            multi: self.multi.unwrap_or_else(|| Arc::new(judge.clone())),
            judge,
            problem,
            settings,
        })
    }
}

/// The multi-object planner: judged by the grasp model, or by rollouts in the simulator.
fn multi_object(settings: &PolicySettings, problem: &Arc<Problem>) -> Result<MultiObject> {
    if !settings.rollout {
        return MultiObject::new(settings.multi.clone(), problem.clone());
    }
    #[cfg(feature = "sim")]
    {
        MultiObject::with_outcome(
            settings.multi.clone(),
            problem.clone(),
            Arc::new(crate::exec::Rollout {
                settings: crate::exec::SimSettings::default(),
                samples: settings.multi.samples,
                noise: settings.multi.noise.clone(),
            }),
        )
    }
    #[cfg(not(feature = "sim"))]
    Err(crate::error::Error::NotCompiled {
        component: "policy".to_string(),
        field: "rollout".to_string(),
        feature: "sim",
        reason: "rollouts need the simulator: build with the `sim` feature".to_string(),
    })
}

//! Settings of the SOCP push planner ([`super::Socp`]).

use serde::{Deserialize, Serialize};

use crate::error::Result;

/// Settings of [`Socp`].
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, schemars::JsonSchema)]
#[serde(default, deny_unknown_fields)]
pub struct SocpSettings {
    /// Evenly spaced closing axes tried over `[0, π)`. Default 12 (15° apart).
    pub axes: usize,
    /// Orders tried along the chosen axis, the natural one included, for clusters of three or more.
    /// Default 6 (every order of three objects).
    pub max_orders: usize,

    /// Room left between the row and the usable jaw gap, metres. Default 0.010: on each side, the
    /// 4.5 mm the grasp planner keeps between an open plate and a pushed object, rounded up.
    pub margin: f64,
    /// Gap kept between neighbours in the row, metres. Default 0.001.
    pub gap: f64,
    /// How far every object must reach past the plates' centre line on each side, metres. Default
    /// 0.003: every object is caught by the plates and touches its neighbours when squeezed.
    pub straddle: f64,
    /// How far a target centroid may lie from the plates' centre line, metres. Default 0.002: in
    /// the simulator, rows whose centroids lie near that line are held far more often than rows
    /// whose centroids lie 10 mm or more off it (`pushmog grasp-agreement`). Against 0.004 (the
    /// default before), push-mog-opt carried 0.020 more objects per trip in the simulator on
    /// paper-100 and on 60 held-out scenes, and in MuJoCo (30 scenes, with noise) lost objects in
    /// 21 multi-object grasps instead of 35, at up to 5.5 % more push distance
    /// (`formulations/pushing.md`).
    pub centring: f64,
    /// How far inside the workspace's edges targets stay (or their start's distance from the edge,
    /// if smaller), metres. Default 0.005: pushes end a median 2.4 mm and a 90th percentile 6.1 mm
    /// from their targets in the simulator, and an object whose outline leaves the workspace can no
    /// longer be planned for (targets 1 µm inside left one object outside in 5 of 100 paper-100
    /// runs of push-mog-opt).
    pub edge_margin: f64,
    /// Gap kept to objects outside the cluster (or the current gap, if smaller), metres. Default 0.002.
    pub clearance: f64,
    /// Outside objects further than this from every member are ignored, metres. Default 0.15.
    pub neighbourhood: f64,
    /// Among rows that can be pushed into place, take the cheapest one the grasp model predicts held
    /// (the cheapest of all when none is). Default true.
    pub prefer_held_rows: bool,
    /// Judge a row's intended grasp as the policy's multi-object planner judges its grasps: on the
    /// table predicted after the pushes and on copies moved by the noise the run assumes (a pushed
    /// object's push error included), held when at least its `min_probability` of the samples
    /// carry every member. Default true. False, or a planner built without that judge
    /// ([`Socp::with_judge`]): the grasp model's prediction alone.
    pub robust_rows: bool,
    /// Push every object flush (`push::flush`): the jaws closed to one block that meets one face
    /// of the object flat and pushes within `flush_cone` of that face's inward normal, so the
    /// object slides without turning. A pair lines up along the line through both centroids once
    /// the pushed one stops, tight against the other (`flush_gap`); in larger clusters each moving
    /// member's push is turned to its nearest face normal. The clustering then proposes only pairs
    /// a flush push lines up. Default false (the paper's fork, jaw line across the push, any
    /// direction). In the simulator, pushes within 5° of a face normal turned their object a
    /// median 3.8° and the pair was carried together 91 % of the time, against 12–15° and 73–76 %
    /// for pushes 10–30° off; flush pushes turned it a median 1.5° (`formulations/pushing.md`).
    pub flush: bool,
    /// How far the face a flush push meets must reach past the line of the push through the
    /// centroid on each side, beyond 2 mm of placement error, metres. Default 0.002.
    pub flush_margin: f64,
    /// Largest angle between a flush push and its face's normal, radians. Default 0.19 (10.9°): half
    /// the friction cone of the pads on the objects at μ 0.4 (atan 0.4 = 21.8°), within which the
    /// contact holds the object without slipping along the face. In the simulator, pushes 10° off
    /// the normal turned their object a median 1.4–2.0° (p90 3.7–4.4°), as pushes along it; 20°
    /// off, a p90 of 16°. 0: along the normal only.
    pub flush_cone: f64,
    /// How far from its neighbour a flush push of a pair leaves the pushed object along the row,
    /// at most, metres (and at least `gap`). Default 0.003, about 1.4 standard deviations of where
    /// flush pushes end along the push (2.2 mm in the simulator): the row is then as short as
    /// the two allow and the jaws have room on both sides, instead of the row just fitting the
    /// jaws less the margin, as the least push would leave it.
    pub flush_gap: f64,
    /// Least room, metres, along each push of a row between the workspace's edge and a member held
    /// in place ahead of the pushed one. A push that ends a little past its target (or against a
    /// neighbour seen a little off its place) shoves the held member on, out of the workspace if
    /// it lies at the edge; rows that would are refused (the other member may be pushed instead).
    /// In the simulator a held member moved 5 mm along the push at the 95th percentile and 23 mm
    /// at most in 1663 (push-mog-time, training scenes 7001–7150). Default 0 (no such check);
    /// push-mog-time sets 0.02 (`formulations/picks-per-hour.md`, "The margins").
    #[serde(default, skip_serializing_if = "is_zero")]
    pub held_edge_margin: f64,
    /// Longest a search for one cluster may run, seconds, checked before each row is solved. When
    /// it ends the search, the cheapest row found so far is the answer with status `time_limit`
    /// (and none found: a failed status saying so). Default none: every axis and order is tried,
    /// so answers do not depend on the machine's speed.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub time_limit: Option<f64>,
}

impl Default for SocpSettings {
    fn default() -> Self {
        Self {
            axes: 12,
            max_orders: 6,
            margin: 0.010,
            gap: 0.001,
            straddle: 0.003,
            centring: 0.002,
            edge_margin: 0.005,
            clearance: 0.002,
            neighbourhood: 0.15,
            prefer_held_rows: true,
            robust_rows: true,
            flush: false,
            flush_margin: 0.002,
            flush_cone: 0.19,
            flush_gap: 0.003,
            held_edge_margin: 0.0,
            time_limit: None,
        }
    }
}

impl SocpSettings {
    /// Checks every field.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the field.
    pub fn validate(&self) -> Result<()> {
        let counts: [(&str, usize, (usize, usize), &str); 2] = [
            ("axes", self.axes, (1, 360), "each axis is a solve"),
            (
                "max_orders",
                self.max_orders,
                (1, 720),
                "each order is a solve (720 = every order of six)",
            ),
        ];
        for (field, value, range, why) in counts {
            crate::error::count_in_range("socp", field, value, range, why)?;
        }
        let lengths: [(&str, f64, (f64, f64)); 10] = [
            ("margin", self.margin, (0.0, 0.05)),
            ("gap", self.gap, (0.0, 0.02)),
            ("straddle", self.straddle, (0.0, 0.05)),
            ("centring", self.centring, (0.0, 0.05)),
            ("edge_margin", self.edge_margin, (0.0, 0.05)),
            ("clearance", self.clearance, (0.0, 0.05)),
            ("neighbourhood", self.neighbourhood, (0.0, 2.0)),
            ("flush_margin", self.flush_margin, (0.0, 0.02)),
            ("flush_gap", self.flush_gap, (0.0, 0.05)),
            ("held_edge_margin", self.held_edge_margin, (0.0, 0.05)),
        ];
        for (field, value, range) in lengths {
            crate::error::in_range("socp", field, value, range, "metres, within a jaw's reach")?;
        }
        if let Some(limit) = self.time_limit {
            crate::error::in_range(
                "socp",
                "time_limit",
                limit,
                (0.001, 3600.0),
                "seconds of search per cluster",
            )?;
        }
        crate::error::in_range(
            "socp",
            "flush_cone",
            self.flush_cone,
            (0.0, 0.6),
            "radians off a face's normal; beyond atan 0.6 (31°) the pads slip on any known surface",
        )
    }
}

/// Whether a length is zero: such settings are left out of written settings, so logs and plans
/// written before them read and hash as they did.
fn is_zero(value: &f64) -> bool {
    *value == 0.0
}

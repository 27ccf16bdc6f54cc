#!/usr/bin/env python3
"""pushmog as the planner of a MuJoCo simulation: a second, independent physics engine.

MuJoCo holds the table, the objects (each a prism: the convex hull of its outline at the table and
at its height) and a two-finger gripper. Every trip, pushmog plans from the poses MuJoCo reports; the
gripper here carries out the fork pushes and the grasp; what the lift takes clear of the table goes
to the bin. The loop repeats until the table is clear, then prints the objects of every trip, the
objects per trip (OpT), and how often MuJoCo carried exactly what pushmog predicted, beside the same
figure from pushmog's own rapier simulator on the same scene.

The physical settings are pushmog's simulator defaults (``pushmog.default_settings("sim")``):
friction pad-object, object-object and object-table, object density, finger mass, pad height, the
gripper's plate thickness and pad width from the scene, a grip of at most ``grip_force`` per finger
from one motor driving both fingers symmetrically, and the jaw, push and vertical speeds.

Choices of MuJoCo's own: elliptic friction cones with ``impratio`` 10 and the noslip solver (20
passes), because MuJoCo's soft contacts otherwise let a squeezed row creep out while the contact force
is still inside the friction cone, which Coulomb friction does not allow (measured on scene seed 3,
push-mog-opt: 2-object grasps held 5 of 10 without noslip, 7 of 9 with it). MuJoCo rests a prism's
base on at most 4 contact points (a hexagon and an octagon rest on 4), so turning under a push is
resisted at those corners rather than over the whole base.

The camera sees what pushmog's simulator's camera sees: upright objects inside the workspace, and a
toppled object lying flat on a face as a new, lower prism (its outline from above); a toppled object
leaning on something, or one outside the workspace, is lost.

Riders (policy setting ``riders``, ``formulations/stacking.md``) are put down as pushmog's simulator
puts them: picked by their single-object grasp with the pads at half their height, lifted 1 cm clear
of everything, carried and turned over the row, lowered until their base is 2 mm above the row's
top, let go, and the hand rises. A grasp with riders aboard then carries the row sideways along the
plates (0.3 m at the simulator's ``carry_speed`` and ``carry_acceleration``, a trapezoidal profile)
before counting what is held. A placed rider still standing upright 5 mm or more above the table
when the camera looks is reported lost, "a rider left on another object", as in pushmog's
simulator; the loop tells the planner (``TripContext.record_riders`` and ``record_lost``), which
grasps that row again with the rider aboard, as pushmog's own loop does.

With the policy setting ``run.reach_past_edge`` (metres, off by default), once the workspace is empty
but for objects lost outside it, those the camera sees there (upright or lying flat, with the same
error as inside) are taken one at a time by themselves (``Planner.past_edge_trip``), as pushmog's own
loop takes them; MuJoCo's table goes on past the workspace.

    python examples/mujoco_loop.py --objects 34 --seed 1 --policy push-mog-opt
    python examples/mujoco_loop.py --seed 1 --policy push-mog-time-riders
"""

from __future__ import annotations

import argparse
import json
import math
import sys
from collections import Counter
from dataclasses import dataclass, field
from typing import Optional

import numpy as np

try:
    import mujoco
except ImportError:  # pragma: no cover - reported to the user
    sys.exit("mujoco_loop.py needs MuJoCo: pip install mujoco")

import pushmog

GRIP_STIFFNESS = 5000.0  # N/m, the pads' servo: the 20 N cap is reached 4 mm behind the target
NOSLIP = 20  # noslip solver passes: Coulomb friction without the soft-contact creep (see the docstring)
TIMESTEP = 0.0005  # s; at 1 ms the stiff, no-slip contacts of a squeezed row sometimes blew up and threw objects at metres per second
TRANSFER_SPEED = 0.25  # m/s, moves through the air (not timed: only what happens on the table matters)
BIN = np.array([3.0, 3.0])  # carried objects are put down here, far from the table
STRAIGHT = 1e-7  # sine of the smallest turn a hull keeps at a vertex (pushmog refuses below 1e-9)
RIDING = 0.005  # m: a placed rider whose base stands this high is still on another object (as pushmog's simulator)
RIDER_LEFT = pushmog.RIDER_LEFT  # pushmog's simulator's reason, word for word
PAST_EDGE_STREAM = 0x7061737445646765  # mixed into the seed of the past-the-edge error stream


def prism_mesh(vertices: np.ndarray, height: float) -> str:
    """Mesh vertices of a prism: the outline at z = 0 and at z = height."""
    points = [(x, y, z) for z in (0.0, height) for x, y in vertices]
    return " ".join(f"{x:.9g} {y:.9g} {z:.9g}" for x, y, z in points)


def model_xml(scene: pushmog.Scene, sim: dict) -> str:
    """An MJCF model of the scene: table plane, prisms on free joints, a gripper on four servoed joints
    (x, y, z, yaw) with two pads on slide joints along its closing axis (local x)."""
    gripper = scene.gripper
    thickness = gripper["plate_thickness"]
    pad_width = gripper["plate_length"]
    pad_height = sim["finger_height"]
    half_stroke = gripper["stroke"] / 2 + thickness / 2
    assets, bodies = [], []
    for obj in scene.objects:
        name = f"object{obj.id}"
        assets.append(f'<mesh name="{name}" vertex="{prism_mesh(obj.vertices, obj.height)}"/>')
        c, s = math.cos(obj.pose.yaw / 2), math.sin(obj.pose.yaw / 2)
        mass = "" if obj.mass is None else f' mass="{obj.mass}"'
        bodies.append(
            f'<body name="{name}" pos="{obj.pose.x} {obj.pose.y} 0" quat="{c} 0 0 {s}">'
            f'<freejoint/><geom type="mesh" mesh="{name}" class="object"{mass}/></body>'
        )
    grip = sim["grip_force"]
    finger_mass = sim["finger_mass"]
    # Servo gains: the hand (1 kg) and pads follow their targets closely (natural frequencies
    # ~140 rad/s and ~300 rad/s, critically damped); the pads' squeeze is capped at the grip force.
    return f"""
<mujoco model="pushmog-table">
  <option timestep="{TIMESTEP}" integrator="implicitfast" cone="elliptic" impratio="10" noslip_iterations="{NOSLIP}">
    <flag multiccd="enable"/>
  </option>
  <default>
    <geom solref="0.004 1" solimp="0.95 0.99 0.0005"/>
    <default class="object">
      <geom friction="{sim['friction_object']}" density="{sim['density']}"/>
    </default>
    <default class="pad">
      <geom type="box" size="{thickness / 2} {pad_width / 2} {pad_height / 2}" mass="{finger_mass}"
            friction="{sim['friction_finger']}" priority="1"/>
    </default>
  </default>
  <asset>{''.join(assets)}</asset>
  <worldbody>
    <geom name="table" type="plane" size="0 0 0.01" friction="{sim['friction_table']}"
          priority="2"/>
    <body name="hand" pos="0 0 0" gravcomp="1">
      <joint name="x" type="slide" axis="1 0 0"/>
      <joint name="y" type="slide" axis="0 1 0"/>
      <joint name="z" type="slide" axis="0 0 1"/>
      <joint name="yaw" type="hinge" axis="0 0 1"/>
      <inertial pos="0 0 0.1" mass="1" diaginertia="0.01 0.01 0.01"/>
      <body name="left" gravcomp="1">
        <joint name="left" type="slide" axis="1 0 0" range="{-half_stroke} 0"/>
        <geom name="left" class="pad" pos="0 0 {pad_height / 2}"/>
      </body>
      <body name="right" gravcomp="1">
        <joint name="right" type="slide" axis="1 0 0" range="0 {half_stroke}"/>
        <geom name="right" class="pad" pos="0 0 {pad_height / 2}"/>
      </body>
    </body>
    {''.join(bodies)}
  </worldbody>
  <tendon>
    <fixed name="closing"><joint joint="left" coef="1"/><joint joint="right" coef="-1"/></fixed>
  </tendon>
  <equality>
    <joint joint1="left" joint2="right" polycoef="0 -1 0 0 0"/>
  </equality>
  <actuator>
    <position name="x" joint="x" kp="20000" kv="283"/>
    <position name="y" joint="y" kp="20000" kv="283"/>
    <position name="z" joint="z" kp="20000" kv="283"/>
    <position name="yaw" joint="yaw" kp="200" kv="2.83"/>
    <position name="grip" tendon="closing" kp="{GRIP_STIFFNESS}" kv="{2 * math.sqrt(GRIP_STIFFNESS * finger_mass):.3g}" forcelimited="true"
              forcerange="{-grip} {grip}"/>
  </actuator>
</mujoco>"""


@dataclass
class Record:
    """What happened in one trip."""

    predicted: list
    carried: list
    pushes: int
    landed: bool = False
    riders: list = field(default_factory=list)  # riders put down on the row before its grasp
    past_edge: bool = False  # an object taken from past the workspace's edge (run.reach_past_edge)


@dataclass
class World:
    """The MuJoCo model and data, and which object is which body."""

    scene: pushmog.Scene
    sim: dict
    seed: int = 0  # of the stream that draws the camera's error past the workspace's edge
    model: "mujoco.MjModel" = field(init=False)
    data: "mujoco.MjData" = field(init=False)

    def __post_init__(self) -> None:
        self.model = mujoco.MjModel.from_xml_string(model_xml(self.scene, self.sim))
        self.data = mujoco.MjData(self.model)
        self.closing = False  # whether the grip servo is closing (`follow`)
        self.pad_address = [self.model.jnt_qposadr[self.model.joint(side).id] for side in ("left", "right")]
        self.closed_target = -self.scene.gripper["plate_thickness"]  # the grip servo's target, fully closed
        self.lead_at_cap = self.sim["grip_force"] / GRIP_STIFFNESS  # the servo's lead at the force cap
        self.objects = {o.id: o for o in self.scene.objects}
        self.body = {o.id: self.model.body(f"object{o.id}").id for o in self.scene.objects}
        self.qpos = {i: self.model.jnt_qposadr[self.model.body_jntadr[b]] for i, b in self.body.items()}
        self.qvel = {i: self.model.jnt_dofadr[self.model.body_jntadr[b]] for i, b in self.body.items()}
        self.pads = {self.model.geom("left").id, self.model.geom("right").id}
        self.geom_object = {g: i for i, b in self.body.items() for g in range(self.model.ngeom) if self.model.geom_bodyid[g] == b}
        self.landed_on: Optional[int] = None  # the object a pad last came down on
        self.binned: list = []
        self.placed: list = []  # riders put down and not yet carried
        # Objects lost outside the workspace as the last look saw them there; their error comes from
        # a stream of their own, so that seeing them changes no other draw of a run.
        self.past_edge: list = []
        self.past_edge_rng = np.random.default_rng([self.seed, PAST_EDGE_STREAM])
        half = self.scene.gripper["stroke"] / 2
        # Park the gripper high above the table, jaws fully open.
        self.target = np.array([0.3, 0.2, 0.3, 0.0, -2 * half])
        for name, value in zip(("x", "y", "z", "yaw"), self.target[:4]):
            self.data.qpos[self.model.jnt_qposadr[self.model.joint(name).id]] = value
        self.data.qpos[self.pad_address[0]] = -half
        self.data.qpos[self.pad_address[1]] = half
        self.data.ctrl[:] = self.target
        mujoco.mj_forward(self.model, self.data)
        self.wait(0.3)

    # -- motion --------------------------------------------------------------------------------
    def step(self) -> None:
        if self.closing:
            self.follow()
        self.data.ctrl[:] = self.target
        mujoco.mj_step(self.model, self.data)

    def follow(self) -> None:
        """One step of closing: the grip servo's target moves toward fully closed at no more than the
        jaw speed, and never leads the pads by more than the squeeze that gives the grip force. The
        force so stays at its cap while the pads are blocked, and pads whose object slips away follow
        at the jaw speed, as the 2F-85's speed-limited motor does, instead of snapping shut."""
        pads = -self.opening()
        self.target[4] = min(self.closed_target, self.target[4] + self.sim["jaw_speed"] * TIMESTEP, pads + (self.lead_at_cap + 0.001))

    def wait(self, seconds: float) -> None:
        for _ in range(int(round(seconds / TIMESTEP))):
            self.step()

    def move(self, goal: np.ndarray, speed: float, watch_landing: bool = False) -> bool:
        """Moves the hand target (x, y, z, yaw) in a straight line at `speed` (m/s; yaw turns along).
        With `watch_landing`, stops and returns True as soon as a pad rests on top of an object."""
        start = self.target[:4].copy()
        distance = float(np.linalg.norm(goal[:3] - start[:3]))
        steps = max(1, int(math.ceil(distance / speed / TIMESTEP)))
        for k in range(1, steps + 1):
            self.target[:4] = start + (goal - start) * (k / steps)
            self.step()
            if watch_landing and self.pad_on_top():
                return True
        self.wait(0.02)
        return watch_landing and self.pad_on_top()

    def carry(self, offset: np.ndarray, speed: float, acceleration: float) -> None:
        """Moves the hand target by `offset` (x, y, z) with a trapezoidal speed profile: up to
        `acceleration` and at most `speed`, as an arm's linear move (what may slide or tip a
        rider)."""
        start = self.target[:3].copy()
        distance = float(np.linalg.norm(offset))
        if distance <= 0:
            return
        top = min(speed, math.sqrt(distance * acceleration))
        ramp = top / acceleration
        duration = 2 * ramp + (distance - top * ramp) / top
        steps = max(1, int(math.ceil(duration / TIMESTEP)))
        for k in range(1, steps + 1):
            t = k * duration / steps
            if t < ramp:
                travelled = 0.5 * acceleration * t * t
            elif t > duration - ramp:
                left = duration - t
                travelled = distance - 0.5 * acceleration * left * left
            else:
                travelled = 0.5 * top * ramp + top * (t - ramp)
            self.target[:3] = start + offset * (travelled / distance)
            self.step()

    def set_opening(self, opening: float) -> None:
        """Opens the jaws to `opening` between the plate centres, and waits until they are there."""
        self.closing = False
        self.target[4] = -opening
        self.wait(0.15)

    def close(self) -> None:
        """Closes at the jaw speed with at most the grip force per pad (`follow`), until the pads
        have stopped (under a tenth of the jaw speed for 0.05 s) squeezing with the whole grip force,
        or have had time to close fully. The drive stays on through the lift, as pushmog's
        simulator's does, until the jaws open again."""
        speed = self.sim["jaw_speed"]
        self.closing = True
        last, still = self.opening(), 0
        for _ in range(int(math.ceil((last / speed + 0.5) / TIMESTEP))):
            self.step()
            now = self.opening()
            still = still + 1 if abs(last - now) < 0.1 * speed * TIMESTEP else 0
            last = now
            if still * TIMESTEP >= 0.05 and (self.target[4] + now >= self.lead_at_cap or self.target[4] >= self.closed_target):
                break

    def opening(self) -> float:
        """Distance between the pads' centres, metres."""
        return float(self.data.qpos[self.pad_address[1]] - self.data.qpos[self.pad_address[0]])

    def pad_on_top(self) -> bool:
        """Whether a pad touches an object with a mostly vertical contact normal (it came down on it)."""
        for contact in self.data.contact[: self.data.ncon]:
            pair = {contact.geom1, contact.geom2}
            if pair & self.pads and any(g in self.geom_object for g in pair) and contact.dist < 0:
                if abs(contact.frame[2]) > 0.5:
                    self.landed_on = next(self.geom_object[g] for g in pair if g in self.geom_object)
                    return True
        return False

    # -- what the camera sees --------------------------------------------------------------------
    def corners(self, object_id: int) -> np.ndarray:
        """The prism's corners in the world, ``(2n, 3)``: each outline vertex at its base and its top."""
        body = self.body[object_id]
        rotation = self.data.xmat[body].reshape(3, 3)
        obj = self.objects[object_id]
        local = np.array([[vx, vy, vz] for vx, vy in obj.vertices for vz in (0.0, obj.height)])
        return local @ rotation.T + self.data.xpos[body]

    def pose(self, object_id: int) -> tuple:
        """(x, y, yaw, tilt, lowest point) of an object's body frame."""
        body = self.body[object_id]
        rotation = self.data.xmat[body].reshape(3, 3)
        x, y, _ = self.data.xpos[body]
        yaw = math.atan2(rotation[1, 0], rotation[0, 0])
        tilt = math.acos(max(-1.0, min(1.0, rotation[2, 2])))
        return x, y, yaw, tilt, float(self.corners(object_id)[:, 2].min())

    def lying_flat(self, object_id: int) -> Optional[tuple]:
        """A toppled prism as an overhead camera sees it when it lies flat on a face (three or more
        corners on the table), as pushmog's simulator sees it: the outline of all its corners from
        above (about its centroid), that centroid, and how tall it stands now. None when it leans on
        something."""
        corners = self.corners(object_id)
        low, top = corners[:, 2].min(), corners[:, 2].max()
        resting = convex_hull(corners[corners[:, 2] < low + 1e-3, :2])
        if len(resting) < 3 or polygon_area(resting) < 1e-6:
            return None
        footprint = convex_hull(corners[:, :2])
        centre = polygon_centroid(footprint)
        return footprint - centre, centre, float(top - low)

    def observe(self, noise: float, rng: np.random.Generator) -> tuple:
        """The table as seen from above: a pushmog scene of the objects inside the workspace (a
        toppled one lying flat seen as a new, lower prism, as in pushmog's simulator), and the ids
        lost (toppled and leaning on something, or off the workspace). Objects lost off the workspace
        that stand upright or lie flat are kept in ``past_edge`` as seen there (with the same
        error), as pushmog's simulator reports them."""
        low, high = self.scene.workspace
        objects, lost = [], {}
        self.past_edge = []
        for object_id, obj in self.objects.items():
            if object_id in self.binned:
                continue
            x, y, yaw, tilt, lowest = self.pose(object_id)
            vertices, height = obj.vertices, obj.height
            if object_id in self.placed and tilt <= self.sim["topple_angle"] and lowest > RIDING:
                lost[object_id] = RIDER_LEFT
                continue
            if tilt > self.sim["topple_angle"]:
                flat = self.lying_flat(object_id)
                if flat is None:
                    lost[object_id] = "toppled"
                    continue
                vertices, (x, y), height = [[float(u), float(v)] for u, v in flat[0]], flat[1], flat[2]
                yaw = 0.0
            # Whether an object has left the workspace is decided by where it is, not by the noise
            # of the camera's estimate, as in pushmog's simulator; an estimate that noise put past
            # an edge is not reported, the true pose is.
            actual = pushmog.Object(object_id, vertices, pushmog.Pose(x, y, yaw), height, obj.name, obj.mass)
            if outside(actual.world_vertices(), low, high):
                lost[object_id] = "outside the workspace"
                there = actual
                if noise > 0:
                    draw = self.past_edge_rng
                    there = pushmog.Object(object_id, vertices, pushmog.Pose(x + draw.normal(0, noise), y + draw.normal(0, noise), yaw + draw.normal(0, self.sim["perception_yaw"])), height, obj.name, obj.mass)
                self.past_edge.append(there)
                continue
            seen = actual
            if noise > 0:
                noisy = pushmog.Pose(x + rng.normal(0, noise), y + rng.normal(0, noise), yaw + rng.normal(0, self.sim["perception_yaw"]))
                seen = pushmog.Object(object_id, vertices, noisy, height, obj.name, obj.mass)
                if outside(seen.world_vertices(), low, high):
                    seen = actual
            objects.append(seen)
        return separated(objects, self.scene), lost

    # -- actions ---------------------------------------------------------------------------------
    def tallest(self) -> float:
        return max((o.height for i, o in self.objects.items() if i not in self.binned), default=0.0)

    def push(self, push: pushmog.Push, offset: np.ndarray) -> bool:
        """A fork push; True when a pad came down on an object (the action stops there)."""
        above = self.tallest() + 0.01
        tip = push.height if push.height is not None else self.sim["push_height_fraction"] * self.objects[push.object].height
        approach, end = push.path[0] + offset[:2], push.path[2] + offset[:2]
        yaw = push.jaw_angle + offset[2]
        self.move(np.array([*self.target[:2], above, self.target[3]]), TRANSFER_SPEED)
        self.set_opening(push.opening)
        self.move(np.array([*approach, above, yaw]), TRANSFER_SPEED)
        if self.move(np.array([*approach, tip, yaw]), self.sim["vertical_speed"], watch_landing=True):
            self.move(np.array([*approach, above, yaw]), self.sim["vertical_speed"])
            return True
        self.move(np.array([*end, tip, yaw]), self.sim["push_speed"])
        self.move(np.array([*end, above, yaw]), self.sim["vertical_speed"])
        return False

    def grasp(self, grasp: pushmog.Grasp, offset: np.ndarray) -> tuple:
        """Lower, close, lift, settle; the objects lifted clear of the table go to the bin. Returns
        (carried ids, whether a pad came down on an object)."""
        above = self.tallest() + 0.01
        center = grasp.jaws.center + offset[:2]
        yaw = grasp.jaws.angle + offset[2]
        self.move(np.array([*self.target[:2], above, self.target[3]]), TRANSFER_SPEED)
        self.set_opening(grasp.jaws.opening)
        self.move(np.array([*center, above, yaw]), TRANSFER_SPEED)
        if self.move(np.array([*center, self.sim["grasp_height"], yaw]), self.sim["vertical_speed"], watch_landing=True):
            self.move(np.array([*center, above, yaw]), self.sim["vertical_speed"])
            return [], True
        self.close()
        lift = self.sim["lift"]
        self.move(np.array([*center, self.sim["grasp_height"] + lift, yaw]), self.sim["vertical_speed"])
        self.wait(self.sim["settle"])
        aboard = [i for i in self.placed if self.pose(i)[4] > 0.5 * lift]
        if aboard and self.sim["carry"] > 0:
            # With riders aboard the row goes sideways toward the bin, along the plates.
            along = yaw + math.pi / 2
            way = np.array([math.cos(along), math.sin(along), 0.0]) * self.sim["carry"]
            self.carry(way, self.sim["carry_speed"], self.sim["carry_acceleration"])
            self.wait(self.sim["settle"])
        carried = [i for i in self.objects if i not in self.binned and self.pose(i)[4] > 0.5 * lift]
        for object_id in carried:
            self.to_bin(object_id)
        self.placed = [i for i in self.placed if i not in carried]
        self.set_opening(grasp.jaws.opening)
        self.wait(0.2)  # whatever dropped settles before the next observation
        return carried, False

    def place(self, rider: dict, offset: np.ndarray) -> bool:
        """Puts a rider down on its row's top (see the module docstring); True when the pick's
        descent came down on an object (the action stops there). Actuation noise (`offset`) moves
        the pick and the release alike."""
        object_id = rider["object"]
        height = self.objects[object_id].height
        jaws = rider["pick"]["jaws"]
        grip = max(0.5 * height, self.sim["grasp_height"])
        above = self.tallest() + 0.01
        center = np.array(jaws["center"]) + offset[:2]
        yaw = jaws["angle"] + offset[2]
        self.move(np.array([*self.target[:2], above, self.target[3]]), TRANSFER_SPEED)
        self.set_opening(jaws["opening"])
        self.move(np.array([*center, above, yaw]), TRANSFER_SPEED)
        if self.move(np.array([*center, grip, yaw]), self.sim["vertical_speed"], watch_landing=True):
            self.move(np.array([*center, above, yaw]), self.sim["vertical_speed"])
            return True
        self.close()
        self.wait(0.05)
        # Base 1 cm above everything, then over the release, turned as it says.
        high = self.tallest() + 0.01 + grip
        self.move(np.array([*center, high, yaw]), self.sim["vertical_speed"])
        release = np.array(rider["release"]["center"]) + offset[:2]
        turned = yaw + wrap(rider["release"]["angle"] - jaws["angle"])
        self.move(np.array([*release, high, turned]), TRANSFER_SPEED)
        self.move(np.array([*release, rider["base"] + 0.002 + grip, turned]), self.sim["vertical_speed"])
        self.set_opening(jaws["opening"])
        self.wait(0.1)
        self.move(np.array([*release, rider["base"] + height + 0.01, turned]), self.sim["vertical_speed"])
        self.wait(0.05)
        self.placed.append(object_id)
        return False

    def to_bin(self, object_id: int) -> None:
        spot = BIN + np.array([0.1 * len(self.binned), 0.0])
        address, dof = self.qpos[object_id], self.qvel[object_id]
        self.data.qpos[address : address + 7] = [spot[0], spot[1], 0.0, 1, 0, 0, 0]
        self.data.qvel[dof : dof + 6] = 0
        self.binned.append(object_id)
        mujoco.mj_forward(self.model, self.data)


def wrap(angle: float) -> float:
    """`angle` in (-π, π]."""
    return math.atan2(math.sin(angle), math.cos(angle))


def outside(outline: np.ndarray, low, high) -> bool:
    """Whether any vertex of a world outline lies past the workspace's edges."""
    return bool((outline < low).any() or (outline > high).any())


def convex_hull(points: np.ndarray) -> np.ndarray:
    """The convex hull of 2-D points, counter-clockwise, without repeated or collinear points. A
    point where the hull turns by less than `STRAIGHT` (the sine of the angle between its edges) is
    dropped: pushmog refuses an outline with a vertex that straight, as it would a collinear one."""
    pts = sorted({(round(float(x), 9), round(float(y), 9)) for x, y in points})
    if len(pts) < 3:
        return np.array(pts)

    def turn(o, a, b):
        cross = (a[0] - o[0]) * (b[1] - o[1]) - (a[1] - o[1]) * (b[0] - o[0])
        return cross / max(math.dist(o, a) * math.dist(a, b), 1e-300)

    def half(sequence):
        chain: list = []
        for p in sequence:
            while len(chain) >= 2 and turn(chain[-2], chain[-1], p) <= STRAIGHT:
                chain.pop()
            chain.append(p)
        return chain[:-1]

    return np.array(half(pts) + half(reversed(pts)))


def polygon_area(vertices: np.ndarray) -> float:
    """Signed area of a polygon (shoelace formula), positive when counter-clockwise."""
    x, y = vertices[:, 0], vertices[:, 1]
    return 0.5 * float(np.dot(x, np.roll(y, -1)) - np.dot(np.roll(x, -1), y))


def polygon_centroid(vertices: np.ndarray) -> np.ndarray:
    """Area centroid of a simple polygon."""
    x, y = vertices[:, 0], vertices[:, 1]
    cross = x * np.roll(y, -1) - np.roll(x, -1) * y
    area = 0.5 * cross.sum()
    return np.array([((x + np.roll(x, -1)) * cross).sum(), ((y + np.roll(y, -1)) * cross).sum()]) / (6.0 * area)


def separated(objects: list, scene: pushmog.Scene) -> pushmog.Scene:
    """A pushmog scene of `objects`. Soft contacts let touching objects interpenetrate by a fraction of
    a millimetre, which a scene refuses (as a camera's segmentation would never report it): each
    reported overlap is undone by moving the second object straight away from the first (or the first
    away from the second, when the second would leave the workspace)."""
    poses = {o.id: o for o in objects}
    for _ in range(10 * len(objects) + 10):
        try:
            return pushmog.Scene.from_objects(poses.values(), gripper=scene.gripper, workspace=scene.workspace)
        except ValueError as error:
            if getattr(error, "field", None) != "pose" or not hasattr(error, "other"):
                raise
            first, second = poses[error.object], poses[error.other]
            away = second.world_vertices().mean(axis=0) - first.world_vertices().mean(axis=0)
            away /= max(float(np.linalg.norm(away)), 1e-9)
            shift = away * (error.depth + 1e-4)
            # The second goes; when that would put it past the workspace's edge, the first goes the
            # other way instead (a scene refuses an outline outside the workspace too).
            low, high = scene.workspace
            for obj, sign in ((second, 1.0), (first, -1.0)):
                moved = pushmog.Pose(obj.pose.x + sign * shift[0], obj.pose.y + sign * shift[1], obj.pose.yaw)
                candidate = pushmog.Object(obj.id, obj.vertices, moved, obj.height, obj.name, obj.mass)
                if not outside(candidate.world_vertices(), low, high) or sign < 0:
                    poses[obj.id] = candidate
                    break
    raise RuntimeError("could not separate the observed outlines")


def agreement(pairs: list) -> dict:
    """For each predicted count k: grasps, and how many carried exactly the predicted objects."""
    table: dict = {}
    for predicted, carried in pairs:
        k = len(predicted)
        row = table.setdefault(k, [0, 0])
        row[0] += 1
        row[1] += int(sorted(predicted) == sorted(carried))
    return dict(sorted(table.items()))


def actuation(sim: dict, rng: np.random.Generator) -> np.ndarray:
    """An actuation error as pushmog's simulator draws one: planar offset (x, y) and yaw."""
    position, yaw = sim["actuation_position"], sim["actuation_yaw"]
    return np.array([rng.normal(0, position), rng.normal(0, position), rng.normal(0, yaw)])


def clear_table(scene: pushmog.Scene, planner: pushmog.Planner, seed: int, noise: bool, log=print) -> dict:
    """Runs the loop on one scene; returns the trips and figures."""
    sim = pushmog.default_settings("sim")
    world = World(scene, sim, seed)
    rng = np.random.default_rng(seed)
    context = pushmog.TripContext(seed)
    records: list = []
    in_a_row, status = 0, "cleared"
    perception = sim["perception_position"] if noise else 0.0
    # With run.fuse_looks, still objects are planned at the mean of their looks, as pushmog's loop.
    fusion = pushmog.LookFusion.for_planner(planner) if planner.settings["run"].get("fuse_looks") else None
    while True:
        observed, lost = world.observe(perception, rng)
        context.record_lost(lost)
        if fusion is not None:
            observed = fusion.fuse(observed)
        may_go_on = in_a_row < planner.settings["run"]["max_failed_attempts"] and len(records) < 3 * len(scene)
        if len(observed) == 0 and lost and may_go_on:
            # As pushmog's own loop: with run.reach_past_edge, objects seen just past the
            # workspace's edge are taken one at a time by themselves once the workspace is empty.
            taken = planner.past_edge_trip(observed, world.past_edge, context)
            if taken is not None:
                trip = taken[1]
                carried, landed = world.grasp(trip.grasp, actuation(sim, rng) if noise else np.zeros(3))
                records.append(Record(trip.grasp.objects, carried, 0, landed, past_edge=True))
                log(f"trip {len(records):2d}: from past the workspace's edge, predicted {trip.grasp.objects}, carried {sorted(carried)}" + (" (landed on an object)" if landed else ""))
                if carried:
                    in_a_row = 0
                else:
                    in_a_row += 1
                    context.record_failure(trip)
                continue
        if len(observed) == 0:
            status = "cleared" if not lost else f"stopped: {len(lost)} lost ({', '.join(sorted(set(lost.values())))})"
            break
        if not may_go_on:
            status = f"stopped: {len(observed)} left after {in_a_row} fruitless attempts"
            break
        trip = planner.plan_trip(observed, context)
        if trip is None:
            in_a_row += 1
            continue
        offset = np.zeros(3)
        if noise:
            offset = actuation(sim, rng)
        # As pushmog's own loop: push; after any pushes look again and plan the rest of the trip
        # on what is seen (corrective pushes for at most run.max_corrections rounds, the grasp).
        run = planner.settings["run"]
        landed, pushes, looks, current = False, 0, 0, trip
        while True:
            for index, push in enumerate(current.pushes):
                if world.push(push, offset):
                    landed = True
                    context.record_landing(current, index, world.landed_on)
                    break
                pushes += 1
            if fusion is not None:
                fusion.record_pushes(current)
            # Pushes ahead, for later trips' grasps, are seen at the next trip's look.
            if landed or not current.pushes or not run["observe_after_pushes"] or current.ahead:
                break
            seen, _ = world.observe(perception, rng)
            if fusion is not None:
                seen = fusion.fuse(seen)
            corrected = planner.correct_trip(seen, current, context, may_push=looks < run["max_corrections"])
            looks += 1
            if corrected is None:
                break
            current = corrected
        trip = current
        carried, placed = [], []
        if not landed:
            # Riders go down on the row just before its grasp; a pick that lands stops the trip.
            for rider in trip.riders:
                if world.place(rider, offset):
                    landed = True
                    break
                placed.append(rider["object"])
        if not landed:
            carried, landed = world.grasp(trip.grasp, offset)
        if fusion is not None:
            fusion.record_grasp(trip)
        # A rider the grasp leaves standing on its row is grasped with the row at the next trip;
        # one that fell off its row carried whole is not offered as a rider again.
        context.record_riders(observed, trip)
        context.record_carried(trip, carried)
        records.append(Record(trip.grasp.objects, carried, pushes, landed, placed))
        riders = f", riders {placed}" if placed else ""
        log(f"trip {len(records):2d}: {pushes} pushes, {looks} looks, predicted {trip.grasp.objects}{riders}, carried {sorted(carried)}" + (" (landed on an object)" if landed else ""))
        if carried:
            in_a_row = 0
        else:
            in_a_row += 1
            context.record_failure(trip)
    carried = sum(len(r.carried) for r in records)
    result = {
        "status": status,
        "trips": len(records),
        "carried": carried,
        "objects_per_trip": carried / len(records) if records else 0.0,
        "carried_per_trip": [len(r.carried) for r in records],
        "agreement": agreement([(r.predicted, row_carried(r.carried, r.riders)) for r in records]),
        "multi_misses": misses([(r.predicted, row_carried(r.carried, r.riders), r.landed) for r in records]),
    }
    if any(r.past_edge for r in records):
        result["trips_past_edge"] = sum(r.past_edge for r in records)
    if any(r.riders for r in records):
        result["riders_placed"] = sum(len(r.riders) for r in records)
        result["riders_lost"] = sum(len([i for i in r.riders if i not in r.carried]) for r in records)
    return result


def misses(trips: list) -> dict:
    """Multi-object grasps that did not carry what was predicted, by cause: a pad came down on an
    object (the pushes left the objects elsewhere than predicted), or objects were lost in the
    closing or the lift."""
    out = {"landed": 0, "lost in closing or lift": 0}
    for predicted, carried, landed in trips:
        if len(predicted) >= 2 and sorted(predicted) != sorted(carried):
            out["landed" if landed else "lost in closing or lift"] += 1
    return out


def both_engines(scene: pushmog.Scene, planner: pushmog.Planner, seed: int, noise: bool, log=print) -> dict:
    """The loop in MuJoCo, and pushmog's own closed loop in its rapier simulator on the same scene
    (same policy seed; noise as in MuJoCo)."""
    result = clear_table(scene, planner, seed, noise, log)
    rapier = planner.run(scene, executor="sim", seed=seed, noiseless=not noise)
    trips = rapier.trips
    result["rapier"] = {
        "status": "cleared" if rapier.cleared else json.dumps(rapier.status),
        "trips": len(trips),
        "carried": rapier.objects_carried(),
        "objects_per_trip": rapier.objects_per_trip(),
        "agreement": agreement([(t["grasp"]["objects"], row_carried(t["carried"], [r["object"] for r in placed_riders(t)])) for t in trips]),
        "multi_misses": misses([(t["grasp"]["objects"], row_carried(t["carried"], [r["object"] for r in placed_riders(t)]), t.get("fault") is not None) for t in trips]),
    }
    # A trip from past the edge is planned on another workspace, so its record holds its scene in
    # full (the others may hold only a `scene_change`).
    first = trips[0]["scene"]["workspace"] if trips else None
    past_edge = sum(t.get("scene", {}).get("workspace", first) != first for t in trips)
    if past_edge:
        result["rapier"]["trips_past_edge"] = past_edge
    placed = [(rider["object"], t["carried"]) for t in trips for rider in placed_riders(t)]
    if placed:
        result["rapier"]["riders_placed"] = len(placed)
        result["rapier"]["riders_lost"] = sum(object_id not in carried for object_id, carried in placed)
    return result


def row_carried(carried: list, riders: list) -> list:
    """What a grasp carried of the table, its riders left out: the agreement compares the row with
    the row predicted, and riders are counted apart (``riders_placed``, ``riders_lost``)."""
    return [i for i in carried if i not in riders]


def placed_riders(trip: dict) -> list:
    """The riders a rapier trip put down: all of them unless a push or a rider's pick came down on
    an object first (as pushmog's own count, ``riders_placed``)."""
    riders = trip.get("riders") or []
    fault = trip.get("fault") or {}
    if fault.get("during") == "push":
        return []
    if fault.get("during") == "place":
        return riders[: fault.get("rider", 0)]
    return riders


def percent(table: dict, multi: bool) -> str:
    rows = [v for k, v in table.items() if (k >= 2) == multi]
    n, held = sum(r[0] for r in rows), sum(r[1] for r in rows)
    return f"{held}/{n} ({100.0 * held / n:.0f}%)" if n else "0/0"


def main(argv: Optional[list] = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--objects", type=int, default=34)
    parser.add_argument("--seed", type=int, default=1, help="scene seed (pushmog scene generate --seed)")
    parser.add_argument("--scene", help="a scene JSON file instead of a generated one")
    parser.add_argument("--policy", default="push-mog-opt", choices=[*pushmog.POLICIES, *pushmog.PRESETS])
    parser.add_argument("--settings", help="policy settings, a JSON file (pushmog schema policy), e.g. experiments/push-mog-opt-riders.json")
    parser.add_argument("--noise", action="store_true", help="perception and actuation noise as pushmog's simulator")
    parser.add_argument("--json", help="write the figures to this file")
    parser.add_argument("--quiet", action="store_true")
    args = parser.parse_args(argv)

    scene = pushmog.Scene.from_json(args.scene) if args.scene else pushmog.generate_scene(args.objects, args.seed)
    settings = None
    if args.settings:
        with open(args.settings, encoding="utf-8") as file:
            settings = json.load(file)
    planner = pushmog.Planner(args.policy, settings=settings)
    log = (lambda *_: None) if args.quiet else print
    log(f"MuJoCo {mujoco.__version__}, pushmog {pushmog.__version__}, policy {args.policy}, {len(scene)} objects")
    result = both_engines(scene, planner, args.seed, args.noise, log)
    print(f"MuJoCo: {result['status']}; {result['carried']} objects in {result['trips']} trips; objects per trip {result['objects_per_trip']:.3f}")
    print(f"objects per trip, trip by trip: {result['carried_per_trip']}")
    print("grasps that carried exactly what pushmog predicted:")
    print(f"  predicted k   MuJoCo        rapier (pushmog's simulator, same scene, {'noisy' if args.noise else 'noise-free'})")
    for k in sorted(set(result["agreement"]) | set(result["rapier"]["agreement"])):
        m = result["agreement"].get(k, [0, 0])
        r = result["rapier"]["agreement"].get(k, [0, 0])
        print(f"  {k:>11}   {m[1]:>3}/{m[0]:<3}       {r[1]:>3}/{r[0]:<3}")
    print(f"  single-object  MuJoCo {percent(result['agreement'], False)}, rapier {percent(result['rapier']['agreement'], False)}")
    print(f"  multi-object   MuJoCo {percent(result['agreement'], True)}, rapier {percent(result['rapier']['agreement'], True)}")
    print(f"  multi-object misses: MuJoCo {result['multi_misses']}, rapier {result['rapier']['multi_misses']}")
    print(f"rapier: {result['rapier']['status']}; {result['rapier']['trips']} trips; objects per trip {result['rapier']['objects_per_trip']:.3f}")
    for engine, figures in (("MuJoCo", result), ("rapier", result["rapier"])):
        if "trips_past_edge" in figures:
            print(f"{engine}: {figures['trips_past_edge']} trips took an object from past the workspace's edge")
        if "riders_placed" in figures:
            print(f"{engine} riders: {figures['riders_lost']} of {figures['riders_placed']} placed not carried by their trip")
    if args.json:
        with open(args.json, "w", encoding="utf-8") as out:
            json.dump(result, out, indent=2)
    return 0 if result["status"] == "cleared" else 1


if __name__ == "__main__":
    sys.exit(main())

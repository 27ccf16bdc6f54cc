"""pushmog: plans how a parallel-jaw gripper clears a table of convex prisms in few trips, by pushing
clusters of objects tight and grasping several at once.

>>> import pushmog
>>> scene = pushmog.generate_scene(34, seed=7)
>>> trip = pushmog.Planner("push-mog-opt").plan_trip(scene)
>>> len(trip.grasp.objects) >= 1
True

The planner itself is the Rust crate ``pushmog``; documents here use the command line's JSON formats
(``pushmog.schema(name)`` gives their JSON Schemas).
"""

from __future__ import annotations

import json
from typing import Union

from . import _native
from ._errors import FileError, FormatError, PlanError, PushmogError, SceneError, SettingsError
from ._plan import Grasp, JawPose, Plan, Push, TripPlan
from ._perception import Camera, Perception, labels_from_masks, perceive, render_depth
from ._planner import POLICIES, PRESETS, RIDER_LEFT, LookFusion, NoTrip, Planner, TripContext
from ._scene import Object, Pose, Scene, builtin_object_set, generate_scene

__version__ = _native.version()

__all__ = [
    "POLICIES",
    "PRESETS",
    "RIDER_LEFT",
    "Camera",
    "Perception",
    "FileError",
    "FormatError",
    "Grasp",
    "JawPose",
    "NoTrip",
    "Object",
    "Plan",
    "PlanError",
    "Planner",
    "Pose",
    "Push",
    "PushmogError",
    "Scene",
    "SceneError",
    "SettingsError",
    "TripContext",
    "LookFusion",
    "TripPlan",
    "builtin_object_set",
    "default_settings",
    "generate_scene",
    "labels_from_masks",
    "perceive",
    "render_depth",
    "render_svg",
    "schema",
    "verify",
]


def verify(plan: Plan) -> list:
    """Checks a run record with pushmog's independent verifier (every trip's pushes and grasp
    against its observed table). Returns the violations, each as text; an empty list means none."""
    if not isinstance(plan, Plan):
        raise TypeError(f"expected a pushmog.Plan, got {type(plan).__name__}")
    return list(_native.verify_plan(plan.to_json()))


def render_svg(item: Union[Scene, Plan], title: str = "", pixels_per_metre: float = 1500.0) -> str:
    """An SVG drawing: of a scene (objects, ids, scale bar) or of a plan (clusters, pushes and jaws
    of every trip), as ``pushmog render`` draws it."""
    if isinstance(item, Scene):
        return _native.scene_to_svg(item._native, title or f"{len(item)} objects", float(pixels_per_metre))
    if isinstance(item, Plan):
        return _native.plan_to_svg(item.to_json(), title or f"policy {item.policy}", float(pixels_per_metre))
    raise TypeError(f"expected a pushmog.Scene or pushmog.Plan, got {type(item).__name__}")


def schema(name: str) -> dict:
    """The JSON Schema of a format: ``scene``, ``object-set``, ``policy``, ``sim``, ``plan`` or ``trip``."""
    return json.loads(_native.schema(name))


def default_settings(name: str) -> dict:
    """Default settings: ``"policy"`` (every planner setting), ``"sim"`` (the physical parameters
    of pushmog's rapier simulator: friction, masses, pad size, grip force, speeds, noise),
    ``"perception"`` (the thresholds of :func:`perceive`) or ``"noise"`` (the test camera's depth
    noise of :func:`render_depth`)."""
    return json.loads(_native.defaults(name))

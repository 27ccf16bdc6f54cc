"""Planning: a :class:`Planner` plans one trip from the table it is shown (for a robot stack that owns
its loop) or clears a whole scene with pushmog's own executors."""

from __future__ import annotations

import json
from typing import Any, Iterable, Mapping, Optional, Tuple, Union

from ._errors import PushmogError
from . import _native
from ._plan import Plan, TripPlan
from ._scene import Object, Scene, _plain

RIDER_LEFT: str = _native.RIDER_LEFT
"""The reason an executor gives for a rider still standing on another object (its row's grasp did
not carry it), as :meth:`TripContext.record_lost` expects it."""

__all__ = ["POLICIES", "PRESETS", "RIDER_LEFT", "Planner", "TripContext", "NoTrip", "LookFusion"]

POLICIES = tuple(_native.policies())
"""The six policies."""

PRESETS = {name: (policy, about) for name, policy, about in _native.presets()}
"""The named presets: each a policy with settings of its own (``push-mog-time``,
``push-mog-time-riders``, ``push-mog-opt-riders``), by name: ``(policy, what it is)``. A
:class:`Planner` takes their names too, with ``settings`` laid over the preset's."""


class NoTrip(PushmogError):
    """Raised by :meth:`Planner.plan_trip` with ``strict=True`` when no trip can be planned; the
    reason is the message, and :attr:`reason` is it typed as Rust's ``NoTrip`` writes it: a name
    (``"empty_table"``, ``"nothing_fits_the_jaws"``, ``"no_cluster_fits_the_jaws"``) or a dict
    with one key (``"no_grasp_of_object"``, ``"no_grasp_of_cluster"``)."""

    def __init__(self, message: str, reason: Any = None) -> None:
        super().__init__(message)
        self.reason = reason


class TripContext:
    """What a closed loop carries between trips: the seeded random stream that picks the next cluster,
    the jaw poses whose grasps carried nothing (not tried again in practically the same place), the
    object sets of multi-object grasps that carried nothing (after two such grasps those objects are
    taken one at a time) and the pushes whose fingers came down on an object. A loop that wants the
    command line's choices uses one context, seeded as ``pushmog plan --seed``."""

    __slots__ = ("_native",)

    def __init__(self, seed: int = 0) -> None:
        self._native = _native.TripContext(int(seed))

    def record_failure(self, trip: TripPlan, landed_on: Optional[int] = None) -> None:
        """The grasp of ``trip`` carried nothing: do not propose those jaws again, and after the
        second such grasp of the same objects, do not grasp them together again. ``landed_on``: the
        object a finger came down on, when the grasp stopped on one (see
        :meth:`forget_landings_on`)."""
        self._native.add_failed(
            json.dumps(trip.to_dict()["grasp"]), None if landed_on is None else int(landed_on)
        )

    def forget_landings_on(self, carried: Iterable[int]) -> bool:
        """Forgets the failed grasps that came down on one of ``carried``, the ids of objects carried
        to the bin since, so that their places may be proposed again; whether any was forgotten.
        An object merely no longer seen may still lie where the fingers came down, so pass only
        carried ones. pushmog's own loop calls it only when nothing could be planned: while other
        grasps remain, the place that failed is still passed over."""
        return bool(self._native.forget_landings_on([int(i) for i in carried]))

    @property
    def failed(self) -> list:
        """Jaw poses recorded as failed, as dicts."""
        return json.loads(self._native.failed())

    @property
    def failed_together(self) -> list:
        """Object sets (sorted ids) of the multi-object grasps recorded as failed, one list per grasp."""
        return json.loads(self._native.failed_together())

    def record_landing(self, trip: TripPlan, push: int, on: int) -> None:
        """During push number ``push`` of ``trip`` a finger came down on object ``on``. When that
        object is not on the table the planner is shown (it lies outside the workspace), the pushed
        object is not pushed again with its fingers lowered near there."""
        pushes = trip.to_dict()["pushes"]
        if not 0 <= push < len(pushes):
            raise ValueError(f"push: the trip has {len(pushes)} pushes, got index {push}")
        self._native.add_landed(json.dumps(pushes[push]), int(on))

    @property
    def landed(self) -> list:
        """Pushes recorded as landed on an object, as dicts with ``push`` and ``on``."""
        return json.loads(self._native.landed())

    def record_riders(self, scene: Scene, trip: TripPlan) -> None:
        """The riders of ``trip``, planned on ``scene``, were put down on its row. Call it once the
        trip is made, and :meth:`record_lost` at every look, so that a rider left standing on its
        row is grasped with the row (``formulations/stacking.md``, "Riders left standing")."""
        self._native.note_riders(scene._native, trip.to_json())

    def record_carried(self, trip: TripPlan, carried: Iterable[int]) -> None:
        """The grasp of ``trip`` carried ``carried`` (ids): a rider of the trip that stayed behind
        while its row went to the bin whole fell off a row held in the jaws, and is not offered as
        a rider again (``formulations/stacking.md``, "Riders that fell off")."""
        self._native.note_carried(trip.to_json(), [int(i) for i in carried])

    @property
    def fell_off(self) -> list:
        """The riders that fell off a row carried whole, not offered as riders again."""
        return list(self._native.fell_off())

    def record_lost(self, lost: Mapping[int, str]) -> None:
        """What the last look could not plan for, object id to reason. Riders recorded with
        :meth:`record_riders` and reported as :data:`RIDER_LEFT` are taken, before anything else,
        with their row grasped again as it lies, when the jaws can stay clear of them."""
        self._native.note_lost([(int(k), str(v)) for k, v in lost.items()])


class LookFusion:
    """Looks fused, for a loop run from Python (``pushmog run`` does it with the policy setting
    ``run.fuse_looks``; ``formulations/perception.md``, "Looks fused"): an object that nothing
    touched since the last look is given the mean of its looks since it was last moved, whose error
    shrinks as one over the square root of their number. Call :meth:`fuse` on every look,
    :meth:`record_pushes` once a round of a trip's pushes is made and :meth:`record_grasp` once its
    grasp is. An object within 2 cm of what the robot did, or seen further from its mean than three
    standard deviations of the camera's error, starts again from its newest look."""

    __slots__ = ("_native",)

    def __init__(self, position: float = 0.002, yaw: float = 0.035) -> None:
        """``position`` (metres, per axis) and ``yaw`` (radians): one look's error, each 0 to 0.05;
        a ``SettingsError`` otherwise."""
        self._native = _native.LookFusion(float(position), float(yaw))

    @staticmethod
    def for_planner(planner: "Planner") -> "LookFusion":
        """With the perception noise that ``planner``'s grasp judge assumes (``multi.noise``)."""
        noise = planner.settings["multi"]["noise"]
        return LookFusion(noise["perception_position"], noise["perception_yaw"])

    def fuse(self, scene: Scene) -> Scene:
        """The look ``scene`` with every object that stood still at the mean of its looks."""
        return Scene(self._native.fuse(scene._native))

    def record_pushes(self, trip: TripPlan, start: int = 0) -> None:
        """The pushes of ``trip`` from number ``start`` on were made."""
        for push in trip.to_dict()["pushes"][start:]:
            self._native.pushed(json.dumps(push))

    def record_grasp(self, trip: TripPlan) -> None:
        """The grasp of ``trip`` was made, after its riders' picks."""
        self._native.trip_grasped(json.dumps(trip.to_dict()))


class Planner:
    """A policy with its settings.

    ``policy`` is one of :data:`POLICIES` or a preset of :data:`PRESETS`; ``settings`` overrides
    policy settings (a dict in the format of ``pushmog schema policy``; missing fields keep their
    defaults, or the preset's, laid over key by key). Invalid settings raise
    ``ValueError`` naming the field. Planning releases the GIL, so threads plan in parallel."""

    __slots__ = ("_native", "policy")

    def __init__(self, policy: str = "push-mog-opt", settings: Optional[Mapping[str, Any]] = None) -> None:
        text = None if settings is None else json.dumps(_plain(settings))
        self._native = _native.Planner(policy, text)
        self.policy = policy

    @property
    def settings(self) -> dict:
        """The effective settings."""
        return json.loads(self._native.settings())

    def plan_trip(
        self, scene: Scene, context: Optional[TripContext] = None, strict: bool = False
    ) -> Optional[TripPlan]:
        """Plans the next trip on ``scene`` as it is: pushes, then a grasp. ``context`` carries the
        random stream and failed grasps between calls (default: a fresh one of seed 0, as Rust's
        ``Policy::plan_trip``). Returns ``None`` when nothing can be planned (``strict``: raises
        :class:`NoTrip` with the reason instead)."""
        if not isinstance(scene, Scene):
            raise TypeError(f"expected a pushmog.Scene, got {type(scene).__name__}")
        native_context = None if context is None else context._native
        answer = json.loads(self._native.plan_trip(scene._native, native_context))
        if answer["trip"] is None:
            if strict:
                status = answer["status"]
                reason = status.get("failed", {}).get("reason") if isinstance(status, dict) else status
                raise NoTrip(str(reason), answer.get("no_trip"))
            return None
        return TripPlan(answer["trip"], answer["status"], float(answer["seconds"]))

    def correct_trip(
        self,
        scene: Scene,
        trip: TripPlan,
        context: Optional[TripContext] = None,
        may_push: bool = True,
    ) -> Optional[TripPlan]:
        """The rest of ``trip`` once its pushes are made, planned on ``scene``, a new look at the
        table: pushes turn and shift objects, so the grasp is planned where they are. Returns the
        corrective pushes (only with ``may_push``; often none) and the grasp to make next; ``None``
        when nothing on the table can be grasped. Call it again after corrective pushes, passing
        the plan it returned; ``pushmog run`` allows ``run.max_corrections`` rounds (default 2)."""
        if not isinstance(scene, Scene):
            raise TypeError(f"expected a pushmog.Scene, got {type(scene).__name__}")
        if not isinstance(trip, TripPlan):
            raise TypeError(f"expected a pushmog.TripPlan, got {type(trip).__name__}")
        native_context = None if context is None else context._native
        answer = json.loads(
            self._native.correct_trip(scene._native, trip.to_json(), native_context, bool(may_push))
        )
        if answer["trip"] is None:
            return None
        return TripPlan(answer["trip"], "heuristic", float(answer["seconds"]))

    def past_edge_trip(
        self, scene: Scene, seen: Iterable[Object], context: Optional[TripContext] = None
    ) -> Optional[Tuple[Scene, TripPlan]]:
        """Once ``scene`` (a look at the workspace) holds nothing but objects seen lying just past
        its edge, ``seen``: a single-object grasp of the one nearest the workspace whose every corner
        lies within the policy's ``run.reach_past_edge`` (metres; 0, the default, turns this off),
        as pushmog's own loop takes such objects (``formulations/grasping.md``, "Objects past the
        workspace's edge"). Returns the table it was planned on (the workspace grown by the reach,
        holding the objects seen there) and the trip, no pushes; ``None`` when there is none.
        ``context`` keeps it from jaw poses that failed before."""
        if not isinstance(scene, Scene):
            raise TypeError(f"expected a pushmog.Scene, got {type(scene).__name__}")
        objects = {"objects": [o.to_dict() for o in seen]}
        native_context = None if context is None else context._native
        answer = json.loads(self._native.past_edge_trip(scene._native, json.dumps(objects), native_context))
        if answer["trip"] is None:
            return None
        return Scene.from_dict(answer["scene"]), TripPlan(answer["trip"], "heuristic", float(answer["seconds"]))

    def run(
        self,
        scene: Scene,
        executor: str = "ideal",
        seed: int = 0,
        sim_settings: Optional[Mapping[str, Any]] = None,
        noiseless: bool = False,
    ) -> Plan:
        """Clears ``scene`` in pushmog's closed loop, as ``pushmog run``: ``executor="ideal"``
        applies plans exactly, ``"sim"`` carries them out in the rapier3d simulator (``sim_settings``
        as ``pushmog schema sim``; ``noiseless`` turns off perception and actuation noise)."""
        text = None if sim_settings is None else json.dumps(_plain(sim_settings))
        return Plan(json.loads(self._native.run(scene._native, executor, int(seed), text, bool(noiseless))))

    def __repr__(self) -> str:
        return f"Planner({self.policy!r})"

"""What the planner answers: one trip (:class:`TripPlan`) or a whole run (:class:`Plan`).

Each class is a thin view over the JSON document the command line writes (``to_dict`` gives it back
unchanged): a trip plan has the fields of a trip in ``pushmog plan``'s output, without what the
executor reports (``carried``, ``fault``); a plan is ``pushmog plan``'s document itself.
"""

from __future__ import annotations

import json
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Optional, Union

import numpy as np

from ._scene import Pose

__all__ = ["JawPose", "Grasp", "Push", "TripPlan", "Plan"]


@dataclass(frozen=True)
class JawPose:
    """The open jaws before closing: centre (metres), closing-axis angle (radians), opening between
    the plate centres (metres)."""

    center: np.ndarray
    angle: float
    opening: float

    @staticmethod
    def from_dict(value: dict) -> "JawPose":
        return JawPose(np.array(value["center"], dtype=float), float(value["angle"]), float(value["opening"]))

    def to_dict(self) -> dict:
        return {"center": [float(v) for v in self.center], "angle": self.angle, "opening": self.opening}

    def axis(self) -> np.ndarray:
        """Unit closing direction."""
        return np.array([np.cos(self.angle), np.sin(self.angle)])


@dataclass(frozen=True)
class Grasp:
    """A grasp: the jaws, the objects predicted to be carried, the predicted closed width between the
    plate faces and the clearance of the open plates to the nearest other object (metres)."""

    jaws: JawPose
    objects: list
    width: float
    margin: float

    @staticmethod
    def from_dict(value: dict) -> "Grasp":
        return Grasp(
            JawPose.from_dict(value["jaws"]), [int(i) for i in value["objects"]], float(value["width"]), float(value["margin"])
        )


@dataclass(frozen=True)
class Push:
    """A fork push: the object slides from ``start`` to ``end`` (same yaw). The gripper, jaws open
    to ``opening`` with the jaw line at ``jaw_angle``, comes down at ``path[0]``, touches the object at
    ``path[1]`` and rises at ``path[2]`` (``(3, 2)`` metres), fingertips ``height`` above the table."""

    object: int
    start: Pose
    end: Pose
    direction: np.ndarray
    distance: float
    path: np.ndarray
    jaw_angle: float
    opening: float
    height: Optional[float]

    @staticmethod
    def from_dict(value: dict) -> "Push":
        fork = value["fork"]
        return Push(
            object=int(value["object"]),
            start=Pose.of(value["from"]),
            end=Pose.of(value["to"]),
            direction=np.array(value["direction"], dtype=float),
            distance=float(value["distance"]),
            path=np.array([fork["approach"], fork["contact"], fork["end"]], dtype=float),
            jaw_angle=float(fork["jaw_angle"]),
            opening=float(fork["opening"]),
            height=None if fork.get("height") is None else float(fork["height"]),
        )


class TripPlan:
    """The next trip: fork pushes in order, then a grasp planned on the table predicted after them.

    ``status`` is the planner's own (``"heuristic"``: valid, no optimality claim); ``seconds`` the
    wall-clock planning time."""

    __slots__ = ("_trip", "status", "seconds")

    def __init__(self, trip: dict, status: Any, seconds: float) -> None:
        self._trip = trip
        self.status = status
        self.seconds = seconds

    @property
    def pushes(self) -> list:
        return [Push.from_dict(p) for p in self._trip["pushes"]]

    @property
    def grasp(self) -> Grasp:
        return Grasp.from_dict(self._trip["grasp"])

    @property
    def clusters(self) -> list:
        """The clustering of the observed table: lists of object ids (empty for ``sog``/no clustering)."""
        return [list(c) for c in self._trip["clustering"]["clusters"]]

    @property
    def clustering_status(self) -> Optional[str]:
        """How good the clustering is, as its clusterer said: ``"optimal"`` only when the MILP
        proved it, ``"heuristic"`` for the paper's hierarchical clustering; ``None`` without
        clustering."""
        status = self._trip["clustering"].get("status")
        return status if status is None or isinstance(status, str) else next(iter(status))

    @property
    def cluster(self) -> Optional[int]:
        """Position in ``clusters`` of the cluster this trip works on."""
        return self._trip["cluster"]

    @property
    def skipped_pushes(self) -> list:
        """Pushes not planned or not made, each a dict with the object and the reason."""
        return list(self._trip["skipped_pushes"])

    @property
    def judged(self) -> Optional[float]:
        """With pushes, the grasp planner's estimate that the grasp after them carries every object
        it is planned for (the ``p`` of the expected-time price); ``None`` without pushes."""
        return self._trip.get("judged")

    @property
    def push_statuses(self) -> list:
        """The push planner's status for each answer whose pushes this trip makes, in order:
        ``"best_found"`` for the SOCP's search, ``"time_limit"`` when its time limit cut the search
        short, ``"heuristic"`` for the paper's pushes; empty without pushes."""
        return [s if isinstance(s, str) else next(iter(s)) for s in self._trip.get("push_statuses", [])]

    @property
    def riders(self) -> list:
        """Objects this trip picks by themselves after its pushes and puts down on the top of the
        row its grasp takes (policy setting ``riders``), in order, as dicts: ``object``, ``pick`` (a
        grasp dict), ``place`` (the pose it is put down at), ``release`` (the jaws letting it go),
        ``base`` (the row's top height, metres) and ``on`` (the objects it rests on). Empty without
        riders."""
        return json.loads(json.dumps(self._trip.get("riders", [])))

    @property
    def ahead(self) -> list:
        """Objects this trip pushes into rows for later trips (``pricing.push_ahead``): after such
        pushes no look is made in the trip; the next trip's look shows the rows."""
        return list(self._trip.get("ahead", []))

    def to_dict(self) -> dict:
        """The trip in the run-record format (a trip of ``pushmog plan`` without ``scene``,
        ``carried``, ``fault``)."""
        return json.loads(json.dumps(self._trip))

    def to_json(self) -> str:
        return json.dumps(self._trip, indent=2)

    def __repr__(self) -> str:
        grasp = self._trip["grasp"]
        return f"TripPlan({len(self._trip['pushes'])} pushes, grasp of {grasp['objects']})"


class Plan:
    """A run record: every trip made (its observed table, pushes, grasp, what was carried) and how
    the run ended, exactly as ``pushmog plan`` writes it."""

    __slots__ = ("_document",)

    def __init__(self, document: dict) -> None:
        self._document = document

    @staticmethod
    def from_json(source: Union[str, Path]) -> "Plan":
        """Reads a run record from JSON text or a file path."""
        text = str(source)
        if isinstance(source, Path) or not text.lstrip().startswith("{"):
            text = Path(source).read_text(encoding="utf-8")
        return Plan(json.loads(text))

    @property
    def trips(self) -> list:
        """The trips as dicts, in the run-record format."""
        return list(self._document["trips"])

    @property
    def status(self) -> Any:
        """``{"kind": "cleared"}`` or ``{"kind": "stopped", "remaining": [...], "reason": ...}``."""
        return self._document["status"]

    @property
    def cleared(self) -> bool:
        status = self._document["status"]
        return isinstance(status, dict) and status.get("kind") == "cleared"

    @property
    def policy(self) -> str:
        return self._document["policy"]

    @property
    def executor(self) -> str:
        return self._document["executor"]

    @property
    def seconds(self) -> float:
        """Robot time by the time model, seconds."""
        return float(self._document["seconds"])

    def objects_carried(self) -> int:
        return sum(len(t["carried"]) for t in self._document["trips"])

    def objects_per_trip(self) -> float:
        trips = len(self._document["trips"])
        return self.objects_carried() / trips if trips else 0.0

    def picks_per_hour(self) -> float:
        return 3600.0 * self.objects_carried() / self.seconds if self.seconds > 0 else 0.0

    def carried_per_trip(self) -> list:
        """Objects carried by each trip, in order."""
        return [len(t["carried"]) for t in self._document["trips"]]

    def to_dict(self) -> dict:
        return json.loads(json.dumps(self._document))

    def to_json(self) -> str:
        return json.dumps(self._document, indent=2)

    def save(self, path: Union[str, Path]) -> None:
        """Writes the record, readable by ``pushmog verify`` and ``pushmog render``."""
        Path(path).write_text(self.to_json() + "\n", encoding="utf-8")

    def __repr__(self) -> str:
        return f"Plan({self.policy}, {len(self._document['trips'])} trips, OpT {self.objects_per_trip():.3f})"

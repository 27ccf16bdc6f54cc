"""Scenes: objects (convex outlines extruded to a height) at poses on a table, a gripper and a workspace.

A scene is validated once, in Rust, when it is made; the Python object keeps the validated document
(the JSON format of ``pushmog scene generate``) and offers its parts as numpy arrays.
"""

from __future__ import annotations

import json
import math
import os
from dataclasses import dataclass
from pathlib import Path
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._errors import FileError, SceneError

__all__ = ["Pose", "Object", "Scene", "generate_scene", "builtin_object_set"]

PathOrText = Union[str, "os.PathLike[str]"]


@dataclass(frozen=True)
class Pose:
    """A planar pose on the table: position in metres, yaw in radians."""

    x: float
    y: float
    yaw: float = 0.0

    @staticmethod
    def of(value: Any) -> "Pose":
        """A pose from a ``Pose``, a mapping with ``x``, ``y``, ``yaw`` or a sequence ``(x, y[, yaw])``."""
        if isinstance(value, Pose):
            return value
        if isinstance(value, Mapping):
            return Pose(float(value["x"]), float(value["y"]), float(value.get("yaw", 0.0)))
        values = [float(v) for v in np.asarray(value, dtype=float).ravel()]
        if len(values) not in (2, 3):
            raise SceneError(f"a pose is (x, y) or (x, y, yaw), got {len(values)} numbers")
        return Pose(*values)

    def to_dict(self) -> dict:
        return {"x": self.x, "y": self.y, "yaw": self.yaw}

    def as_array(self) -> np.ndarray:
        """``[x, y, yaw]``."""
        return np.array([self.x, self.y, self.yaw])


@dataclass(frozen=True, eq=False)
class Object:
    """One object: its outline in its own frame (``(k, 2)`` metres, counter-clockwise), pose and height."""

    id: int
    vertices: np.ndarray
    pose: Pose
    height: float
    name: Optional[str] = None
    mass: Optional[float] = None

    def __eq__(self, other: object) -> bool:
        return isinstance(other, Object) and self.to_dict() == other.to_dict()

    __hash__ = None  # type: ignore[assignment]

    def world_vertices(self) -> np.ndarray:
        """The outline on the table, ``(k, 2)`` metres."""
        c, s = math.cos(self.pose.yaw), math.sin(self.pose.yaw)
        rotation = np.array([[c, -s], [s, c]])
        return self.vertices @ rotation.T + np.array([self.pose.x, self.pose.y])

    def to_dict(self) -> dict:
        out: dict = {"id": int(self.id)}
        if self.name is not None:
            out["name"] = self.name
        out["vertices"] = [[float(x), float(y)] for x, y in np.asarray(self.vertices, dtype=float)]
        out["height"] = float(self.height)
        out["pose"] = self.pose.to_dict()
        if self.mass is not None:
            out["mass"] = float(self.mass)
        return out

    @staticmethod
    def from_dict(value: Mapping) -> "Object":
        return Object(
            id=int(value["id"]),
            vertices=np.asarray(value["vertices"], dtype=float).reshape(-1, 2),
            pose=Pose.of(value["pose"]),
            height=float(value["height"]),
            name=value.get("name"),
            mass=value.get("mass"),
        )


def _read(source: PathOrText) -> tuple:
    """The text and a name for errors: a path (``Path`` or a string not starting with ``{``) is read."""
    if isinstance(source, (bytes, bytearray)):
        return source.decode("utf-8"), "<bytes>"
    if isinstance(source, os.PathLike) or not str(source).lstrip().startswith("{"):
        path = Path(source)
        try:
            return path.read_text(encoding="utf-8"), str(path)
        except OSError as error:
            raise FileError(error.errno, error.strerror, str(path)) from error
    return str(source), "<text>"


class Scene:
    """A validated scene. Make one with :meth:`from_json`, :meth:`from_objects`, :meth:`from_dict` or
    :func:`generate_scene`; it does not change (``with_poses`` and ``without`` return new scenes)."""

    __slots__ = ("_native", "_document")

    def __init__(self, native: "_native.Scene") -> None:
        self._native = native
        self._document = json.loads(native.to_json())

    # -- making scenes -------------------------------------------------------------------------
    @staticmethod
    def from_json(source: PathOrText) -> "Scene":
        """Reads a scene from JSON text or a file path. Raises :class:`SceneError` (a ``ValueError``)
        naming the object and field when the scene is invalid, :class:`FileError` (an ``OSError``)
        when the file cannot be read."""
        text, name = _read(source)
        return Scene(_native.Scene.from_json(text, name))

    @staticmethod
    def from_dict(document: Mapping) -> "Scene":
        """A scene from a dict in the JSON format (``to_dict``'s output)."""
        return Scene(_native.Scene.from_json(json.dumps(_plain(document)), "<dict>"))

    @staticmethod
    def from_objects(
        objects: Iterable[Union[Object, Mapping]],
        gripper: Optional[Mapping] = None,
        workspace: Optional[Union[Mapping, Sequence]] = None,
    ) -> "Scene":
        """A scene from objects, each an :class:`Object` or a mapping with ``vertices`` (a ``(k, 2)``
        array in the object's frame, metres), ``pose`` (``(x, y, yaw)`` or a mapping), ``height`` and
        optionally ``id`` (default: its position), ``name`` and ``mass``. ``gripper`` overrides
        fields of the default Robotiq 2F-85; ``workspace`` is ``{"min": [x, y], "max": [x, y]}`` or
        ``((x0, y0), (x1, y1))`` (default: 0.6 m × 0.45 m from the origin)."""
        listed = []
        for index, item in enumerate(objects):
            if isinstance(item, Object):
                listed.append(item.to_dict())
                continue
            if not isinstance(item, Mapping):
                raise TypeError(f"object {index}: expected an Object or a mapping, got {type(item).__name__}")
            for key in ("vertices", "pose", "height"):
                if key not in item:
                    raise SceneError(f"object {index}: missing field `{key}`")
            vertices = np.asarray(item["vertices"], dtype=float)
            if vertices.ndim != 2 or vertices.shape[1] != 2:
                raise SceneError(
                    f"object {item.get('id', index)}: field `vertices` must be a (k, 2) array, got shape {vertices.shape}"
                )
            spec = Object(
                id=int(item.get("id", index)),
                vertices=vertices,
                pose=Pose.of(item["pose"]),
                height=float(item["height"]),
                name=item.get("name"),
                mass=item.get("mass"),
            )
            listed.append(spec.to_dict())
        if workspace is None:
            space = {"min": [0.0, 0.0], "max": [0.6, 0.45]}
        elif isinstance(workspace, Mapping):
            space = {"min": list(map(float, workspace["min"])), "max": list(map(float, workspace["max"]))}
        else:
            low, high = workspace
            space = {"min": [float(v) for v in low], "max": [float(v) for v in high]}
        document = {"workspace": space, "gripper": dict(gripper or {}), "objects": listed}
        return Scene.from_dict(document)

    # -- reading -------------------------------------------------------------------------------
    def __len__(self) -> int:
        return len(self._document["objects"])

    def __repr__(self) -> str:
        return f"Scene({len(self)} objects)"

    @property
    def objects(self) -> list:
        """The objects, in scene order."""
        return [Object.from_dict(o) for o in self._document["objects"]]

    @property
    def ids(self) -> list:
        return [int(o["id"]) for o in self._document["objects"]]

    @property
    def gripper(self) -> dict:
        """Stroke, plate thickness and length, fork-push opening fraction (metres)."""
        return dict(self._document["gripper"])

    @property
    def workspace(self) -> tuple:
        """``(min, max)`` corners, metres, as arrays."""
        space = self._document["workspace"]
        return np.array(space["min"], dtype=float), np.array(space["max"], dtype=float)

    def poses(self) -> np.ndarray:
        """``(n, 3)``: x, y, yaw of every object, in scene order."""
        return np.array([[o["pose"]["x"], o["pose"]["y"], o["pose"]["yaw"]] for o in self._document["objects"]])

    def grasp_diameters(self) -> np.ndarray:
        """The minimum grasp diameter d* of every object, in scene order, metres."""
        return np.array(self._native.grasp_diameters())

    def ungraspable(self) -> list:
        """Ids of objects wider than the jaw gap."""
        return list(self._native.ungraspable())

    def to_dict(self) -> dict:
        """The scene in the JSON format ``pushmog scene generate`` writes."""
        return json.loads(self.to_json())

    def to_json(self) -> str:
        return self._native.to_json()

    # -- new scenes from this one --------------------------------------------------------------
    def with_poses(self, poses: Mapping[int, Any]) -> "Scene":
        """This scene with some objects moved: ``{id: (x, y, yaw)}``. Raises ``KeyError`` for an id
        that is not in the scene."""
        document = self.to_dict()
        by_id = {o["id"]: o for o in document["objects"]}
        for key, pose in poses.items():
            if int(key) not in by_id:
                raise KeyError(f"object {key} is not in the scene")
            by_id[int(key)]["pose"] = Pose.of(pose).to_dict()
        return Scene.from_dict(document)

    def without(self, ids: Iterable[int]) -> "Scene":
        """This scene with some objects taken away."""
        gone = {int(i) for i in ids}
        document = self.to_dict()
        document["objects"] = [o for o in document["objects"] if o["id"] not in gone]
        return Scene.from_dict(document)


def _plain(value: Any) -> Any:
    """numpy arrays and scalars as lists and floats, so ``json`` can write them."""
    if isinstance(value, np.ndarray):
        return value.tolist()
    if isinstance(value, np.generic):
        return value.item()
    if isinstance(value, Mapping):
        return {str(k): _plain(v) for k, v in value.items()}
    if isinstance(value, (list, tuple)):
        return [_plain(v) for v in value]
    return value


def generate_scene(
    n: int = 34,
    seed: int = 0,
    object_set: Optional[Union[PathOrText, Mapping]] = None,
    width: float = 0.6,
    depth: float = 0.45,
) -> Scene:
    """A seeded random scene of ``n`` objects, exactly as ``pushmog scene generate --objects n --seed
    seed`` makes it (same seed, same scene). ``object_set`` is a dict, JSON text or a file (default:
    the built-in 34 objects)."""
    text = None
    if isinstance(object_set, Mapping):
        text = json.dumps(_plain(object_set))
    elif object_set is not None:
        text, _ = _read(object_set)
    return Scene(_native.generate(int(n), int(seed), text, float(width), float(depth)))


def builtin_object_set() -> dict:
    """The built-in object set (``pushmog library --json``)."""
    return json.loads(_native.builtin_objects())

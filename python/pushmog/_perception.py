"""From a camera to a scene: overhead depth images (numpy arrays) and optional instance labels turned
into a validated :class:`~pushmog.Scene`, with a report of every blob (``formulations/perception.md``).

>>> import numpy as np, pushmog
>>> truth = pushmog.generate_scene(34, seed=7)
>>> camera = pushmog.Camera.looking_down(640, 480, fov=1.1, x=0.3, y=0.225, above=0.7)
>>> depth, labels, ids = pushmog.render_depth(truth, camera, noise=True, seed=1)
>>> seen = pushmog.perceive(depth, camera, workspace=truth)
>>> len(seen.scene())
34
"""

from __future__ import annotations

import json
import math
from dataclasses import dataclass, field
from typing import Any, Iterable, Mapping, Optional, Sequence, Union

import numpy as np

from . import _native
from ._errors import SceneError, SettingsError
from ._scene import Scene

__all__ = ["Camera", "Perception", "perceive", "render_depth", "labels_from_masks"]


@dataclass(frozen=True)
class Camera:
    """A calibrated depth camera (OpenCV conventions): pinhole intrinsics in pixels, extrinsics with
    ``p_table = rotation @ p_cam + translation`` in metres, and the metres per unit of 16-bit depth.
    ``pushmog.schema("camera")`` gives the file format."""

    width: int
    height: int
    fx: float
    fy: float
    cx: float
    cy: float
    rotation: tuple = ((1.0, 0.0, 0.0), (0.0, -1.0, 0.0), (0.0, 0.0, -1.0))
    translation: tuple = (0.0, 0.0, 0.7)
    depth_scale: Optional[float] = None

    @staticmethod
    def looking_down(width: int, height: int, fov: float, x: float, y: float, above: float) -> "Camera":
        """A camera ``above`` metres straight over the table point ``(x, y)`` with a horizontal field of
        view of ``fov`` radians, image ``u`` along the table's x and ``v`` against its y."""
        f = 0.5 * width / math.tan(0.5 * fov)
        return Camera(width, height, f, f, 0.5 * width - 0.5, 0.5 * height - 0.5, translation=(x, y, above))

    @staticmethod
    def from_dict(document: Mapping) -> "Camera":
        """A camera from the camera file's form (``{"intrinsics": …, "depth": …, "extrinsics": …}``)."""
        k, e = document["intrinsics"], document["extrinsics"]
        return Camera(
            int(k["width"]), int(k["height"]), float(k["fx"]), float(k["fy"]), float(k["cx"]), float(k["cy"]),
            tuple(tuple(float(v) for v in row) for row in e["rotation"]),
            tuple(float(v) for v in e["translation"]),
            document.get("depth", {}).get("scale"),
        )

    def to_dict(self) -> dict:
        """The camera file's form."""
        out: dict = {
            "intrinsics": {"width": self.width, "height": self.height, "fx": self.fx, "fy": self.fy,
                           "cx": self.cx, "cy": self.cy},
            "depth": {},
            "extrinsics": {"rotation": [[float(v) for v in row] for row in self.rotation],
                           "translation": [float(v) for v in self.translation]},
        }
        if self.depth_scale is not None:
            out["depth"]["scale"] = float(self.depth_scale)
        return out


@dataclass(frozen=True)
class Perception:
    """What one look found: a report per blob (dicts with ``status``, ``pixel_box``, ``position``,
    ``top_height``, ``solidity``, ``id``, and ``hidden_by``, the indices of taller blobs in front of
    it, when there are any), the fitted table, the prior's ids that are gone and the
    adjustments made. :meth:`scene` gives the objects as a scene. ``past_edge`` lists the blobs
    outside the workspace or over its edge that would be objects otherwise, each a dict with
    ``blob`` (the index of its report in ``blobs``) and ``object`` (its footprint where it lies, in
    the scene file's form); they are not part of the scene."""

    blobs: list
    table: dict
    gone: list
    adjustments: list
    past_edge: list = field(default_factory=list)
    _scene: Optional[Scene] = field(default=None, repr=False)
    _refusal: Optional[str] = field(default=None, repr=False)

    def blocking(self) -> list:
        """The blobs that keep the look from being planned on."""
        notices = {"object", "new", "too_small", "outside_workspace"}
        return [b for b in self.blobs if b["status"] not in notices]

    def scene(self) -> Scene:
        """The objects seen, as a validated scene; raises :class:`SceneError` listing every blob that
        blocks planning."""
        if self._scene is None:
            raise SceneError(self._refusal or "no scene")
        return self._scene


def _image(array: Any, name: str, camera: Camera, kinds: Sequence[str]) -> np.ndarray:
    values = np.asarray(array)
    if values.shape != (camera.height, camera.width):
        raise SettingsError(f"{name} has shape {values.shape}, the camera's image is ({camera.height}, {camera.width})")
    if values.dtype.kind not in kinds:
        raise SettingsError(f"{name} has dtype {values.dtype}")
    return values


def perceive(
    depth: Optional[Any],
    camera: Camera,
    labels: Optional[Any] = None,
    heights: Optional[Mapping[int, float]] = None,
    workspace: Union[Scene, Sequence[Sequence[float]], None] = None,
    prior: Optional[Scene] = None,
    settings: Optional[Mapping] = None,
    library: Union[str, Mapping, None] = None,
) -> Perception:
    """One look: ``depth`` a ``(height, width)`` array of metres (float) or of ``camera.depth_scale``
    units (uint16), ``labels`` an integer array (0 for none), ``heights`` the top height of each label
    when there is no depth. ``workspace`` is a scene whose workspace and gripper the look is for, or
    the corners ``((x0, y0), (x1, y1))``; by default the prior's. ``prior`` is the last look or the
    scene predicted after the pushes; its ids are kept. ``library`` (an object set as a mapping, as
    ``pushmog library`` writes it, or ``"builtin"``) names the objects seen without a prior: each
    takes the name, mass and frame (so the yaw) of the set's shape that fits its outline best, when
    one fits; the adjustments say which. The GIL is released while Rust works."""
    if not isinstance(camera, Camera):
        raise TypeError(f"expected a pushmog.Camera, got {type(camera).__name__}")
    if isinstance(workspace, Scene):
        state = workspace
    elif workspace is not None:
        (x0, y0), (x1, y1) = workspace
        state = Scene.from_dict({"workspace": {"min": [x0, y0], "max": [x1, y1]}, "objects": []})
    elif prior is not None:
        state = prior
    else:
        state = Scene.from_dict({"workspace": {"min": [0.0, 0.0], "max": [0.5, 0.4]}, "objects": []})
    depth_bytes, kind = None, "f32"
    if depth is not None:
        values = _image(depth, "depth", camera, "fu")
        if values.dtype.kind == "u":
            depth_bytes, kind = values.astype("<u2").tobytes(), "u16"
        else:
            depth_bytes = values.astype("<f4").tobytes()
    label_bytes = None
    if labels is not None:
        values = _image(labels, "labels", camera, "iub")
        if values.min(initial=0) < 0:
            raise SettingsError("labels must not be negative")
        label_bytes = values.astype("<u4").tobytes()
    report, scene, refusal = _native.perceive(
        json.dumps(camera.to_dict()),
        depth_bytes,
        kind,
        label_bytes,
        None if heights is None else json.dumps({str(int(k)): float(v) for k, v in heights.items()}),
        state._native,
        None if prior is None else prior._native,
        None if settings is None else json.dumps(dict(settings)),
        None if library is None else library if isinstance(library, str) else json.dumps(dict(library)),
    )
    document = json.loads(report)
    return Perception(
        document["blobs"], document["table"], document["gone"], document["adjustments"],
        document.get("past_edge", []), None if scene is None else Scene(scene), refusal,
    )


def render_depth(scene: Scene, camera: Camera, noise: Union[bool, Mapping] = False, seed: int = 0) -> tuple:
    """The exact depth (float32 metres, NaN for nothing) and labels (uint32, ``k + 1`` for the k-th of
    the returned ids) that ``camera`` sees of ``scene``; with ``noise`` (``True`` for the defaults, or
    a mapping of ``pushmog.default_settings("noise")``'s fields) the test camera's depth noise."""
    noise_text = None
    if noise is True:
        noise_text = "{}"
    elif isinstance(noise, Mapping):
        noise_text = json.dumps(dict(noise))
    depth, labels, ids = _native.render(scene._native, json.dumps(camera.to_dict()), noise_text, int(seed))
    shape = (camera.height, camera.width)
    return (np.frombuffer(depth, dtype="<f4").reshape(shape).copy(),
            np.frombuffer(labels, dtype="<u4").reshape(shape).copy(), list(ids))


def labels_from_masks(masks: Union[np.ndarray, Iterable[Any]]) -> np.ndarray:
    """One label image from instance masks: a ``(n, height, width)`` boolean array, or a list of boolean
    arrays or of segment-anything style dicts (``{"segmentation": array}``). Mask ``k`` gets label
    ``k + 1``; masks that overlap are refused, naming both."""
    arrays = []
    for mask in masks:
        if isinstance(mask, Mapping):
            mask = mask["segmentation"]
        arrays.append(np.asarray(mask, dtype=bool))
    if not arrays:
        raise SettingsError("no masks")
    shape = arrays[0].shape
    labels = np.zeros(shape, dtype=np.uint32)
    for k, mask in enumerate(arrays):
        if mask.shape != shape:
            raise SettingsError(f"mask {k} has shape {mask.shape}, mask 0 has {shape}")
        taken = labels[mask]
        if taken.any():
            other = int(taken[taken > 0][0]) - 1
            raise SettingsError(f"masks {other} and {k} overlap in {int((taken > 0).sum())} pixels")
        labels[mask] = k + 1
    return labels

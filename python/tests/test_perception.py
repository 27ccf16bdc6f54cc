"""Perception from Python: numpy depth and labels to a scene, ids kept, bad input refused by name."""

import numpy as np
import pytest

import pushmog

CAMERA = pushmog.Camera.looking_down(640, 480, fov=1.1, x=0.3, y=0.225, above=0.7)


def _centroid(vertices):
    """The area centroid of a polygon, ``(k, 2)``."""
    x, y = vertices[:, 0], vertices[:, 1]
    xn, yn = np.roll(x, -1), np.roll(y, -1)
    cross = x * yn - xn * y
    area = cross.sum() / 2.0
    return np.array([((x + xn) * cross).sum(), ((y + yn) * cross).sum()]) / (6.0 * area)


def _worst_centroid_error(truth, seen):
    """The largest distance from a true object's centroid to the nearest seen one, metres."""
    found = np.array([_centroid(o.world_vertices()) for o in seen.objects])
    return max(float(np.min(np.linalg.norm(found - _centroid(o.world_vertices()), axis=1))) for o in truth.objects)


def test_objects_seen_without_a_prior_are_named_from_a_library(scene):
    # Exact depth: at this camera's 1.3 mm per pixel the noise makes a regular hexagon of the set look
    # like its regular octagon now and then (the noisy case at 1 mm per pixel is a Rust test).
    depth, _, _ = pushmog.render_depth(scene, CAMERA)
    named = pushmog.perceive(depth, CAMERA, workspace=scene, library="builtin").scene()
    assert len(named) == len(scene)
    for truth in scene.objects:
        centre = _centroid(truth.world_vertices())
        seen = min(named.objects, key=lambda o: float(np.linalg.norm(_centroid(o.world_vertices()) - centre)))
        assert seen.name == truth.name
    # A set whose only shape fits nothing leaves every object unnamed, and says so.
    bar = {"name": "bars", "objects": [{"name": "bar", "height": 0.03,
                                        "vertices": [[-0.05, -0.004], [0.05, -0.004], [0.05, 0.004], [-0.05, 0.004]]}]}
    look = pushmog.perceive(depth, CAMERA, workspace=scene, library=bar)
    assert all(o.name is None for o in look.scene().objects)
    assert sum("no shape of the set bars" in a for a in look.adjustments) == len(scene)


def test_a_noisy_depth_image_gives_every_object(scene):
    depth, labels, ids = pushmog.render_depth(scene, CAMERA, noise=True, seed=3)
    assert depth.shape == (480, 640) and depth.dtype == np.float32
    assert sorted(set(np.unique(labels)) - {0}) == list(range(1, len(ids) + 1))
    look = pushmog.perceive(depth, CAMERA, workspace=scene)
    seen = look.scene()
    assert len(seen) == len(scene)
    assert look.blocking() == []
    assert _worst_centroid_error(scene, seen) < 0.002
    # The next look keeps the ids of the first.
    again = pushmog.perceive(depth, CAMERA, prior=seen)
    assert again.scene().ids == seen.ids
    assert again.gone == []


def test_uint16_depth_uses_the_camera_scale_and_a_wrong_scale_is_named(scene):
    depth, _, _ = pushmog.render_depth(scene, CAMERA)
    units = np.nan_to_num(depth / 0.00025).round().astype(np.uint16)
    right = pushmog.Camera(**{**CAMERA.__dict__, "depth_scale": 0.00025})
    assert len(pushmog.perceive(units, right, workspace=scene).scene()) == len(scene)
    wrong = pushmog.Camera(**{**CAMERA.__dict__, "depth_scale": 0.001})
    with pytest.raises(pushmog.SettingsError, match="L515"):
        pushmog.perceive(units, wrong, workspace=scene)


def test_masks_become_labels_and_labels_with_heights_need_no_depth(scene):
    _, labels, ids = pushmog.render_depth(scene, CAMERA)
    masks = [labels == k + 1 for k in range(len(ids))]
    assert np.array_equal(pushmog.labels_from_masks(masks), labels)
    assert np.array_equal(pushmog.labels_from_masks([{"segmentation": m} for m in masks]), labels)
    heights = {k + 1: 0.03 for k in range(len(ids))}
    look = pushmog.perceive(None, CAMERA, labels=labels, heights=heights, workspace=scene)
    assert len(look.scene()) == len(scene)
    overlapping = [masks[0], masks[0] | masks[1]]
    with pytest.raises(pushmog.SettingsError, match="masks 0 and 1 overlap"):
        pushmog.labels_from_masks(overlapping)


def test_a_blocking_blob_is_listed_and_the_scene_refused(scene):
    depth, _, _ = pushmog.render_depth(scene, CAMERA)
    look = pushmog.perceive(depth, CAMERA, workspace=scene, settings={"max_height": 0.02})
    assert {b["status"] for b in look.blobs} == {"too_tall"}
    with pytest.raises(pushmog.SceneError, match="too_tall"):
        look.scene()
    with pytest.raises(pushmog.SettingsError, match="shape"):
        pushmog.perceive(depth[:, 1:], CAMERA, workspace=scene)


def test_objects_past_the_workspaces_edge_are_listed_where_they_lie(scene):
    depth, _, _ = pushmog.render_depth(scene, CAMERA)
    # The scene's left half as the workspace: the objects of the right half are past its edge.
    look = pushmog.perceive(depth, CAMERA, workspace=((0.0, 0.0), (0.3, 0.45)))
    assert look.past_edge
    truths = np.array([_centroid(o.world_vertices()) for o in scene.objects])
    for past in look.past_edge:
        assert look.blobs[past["blob"]]["status"] in {"outside_workspace", "straddles_workspace_edge"}
        # Its outline is about its centroid, yaw 0: the pose is where it lies, near a true object.
        pose = past["object"]["pose"]
        assert pose["x"] > 0.29 and pose["yaw"] == 0.0
        assert float(np.min(np.linalg.norm(truths - [pose["x"], pose["y"]], axis=1))) < 0.002
    # The whole table as the workspace: nothing past its edge.
    assert pushmog.perceive(depth, CAMERA, workspace=scene).past_edge == []


def test_a_taller_object_in_front_is_listed_and_the_hidden_one_cut_at_its_edge():
    # A 100 mm box turned 45°, 180 mm from the nadir, and a 20 mm box against its far corner: the
    # tall box's top is seen over half of the low one (as in the Rust test of the same rule).
    square = [[-0.02, -0.02], [0.02, -0.02], [0.02, 0.02], [-0.02, 0.02]]
    low_x = 0.07 - 0.02 * np.sqrt(2.0) - 0.0205
    scene = pushmog.Scene.from_dict({
        "workspace": {"min": [0.0, 0.0], "max": [0.5, 0.4]},
        "objects": [
            {"id": 0, "vertices": square, "height": 0.1, "pose": {"x": 0.07, "y": 0.2, "yaw": np.pi / 4}},
            {"id": 1, "vertices": square, "height": 0.02, "pose": {"x": low_x, "y": 0.2, "yaw": 0.0}},
        ],
    })
    camera = pushmog.Camera.looking_down(640, 480, fov=1.0, x=0.25, y=0.2, above=0.7)
    depth, labels, _ = pushmog.render_depth(scene, camera)
    look = pushmog.perceive(depth, camera, labels=labels, workspace=scene)
    assert [b["status"] for b in look.blobs] == ["object", "object"]
    assert [b.get("hidden_by", []) for b in look.blobs] == [[], [0]]
    assert any("cut where a taller blob" in a for a in look.adjustments)
    assert len(look.scene()) == 2

"""Scenes: construction from JSON, dicts and numpy arrays, round trips, and errors that name the culprit."""

import json
import math

import numpy as np
import pytest

import pushmog

SQUARE = np.array([[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]])


def test_generated_scene_matches_the_documented_default(scene):
    assert len(scene) == 34
    assert scene.poses().shape == (34, 3)
    assert scene.grasp_diameters().shape == (34,)
    assert all(d > 0 for d in scene.grasp_diameters())
    low, high = scene.workspace
    assert np.allclose(low, [0, 0]) and np.allclose(high, [0.6, 0.45])


def test_same_seed_same_scene_different_seed_different_scene():
    assert pushmog.generate_scene(10, seed=5).to_json() == pushmog.generate_scene(10, seed=5).to_json()
    assert pushmog.generate_scene(10, seed=5).to_json() != pushmog.generate_scene(10, seed=6).to_json()


def test_json_round_trip_is_exact(scene, tmp_path):
    text = scene.to_json()
    assert pushmog.Scene.from_json(text).to_json() == text
    path = tmp_path / "scene.json"
    path.write_text(text)
    assert pushmog.Scene.from_json(path).to_json() == text
    assert pushmog.Scene.from_json(str(path)).to_json() == text
    assert pushmog.Scene.from_dict(scene.to_dict()).to_json() == text


def test_objects_round_trip_through_numpy(scene):
    rebuilt = pushmog.Scene.from_objects(scene.objects, gripper=scene.gripper, workspace=scene.workspace)
    assert rebuilt.to_json() == scene.to_json()
    assert rebuilt.objects == scene.objects
    assert scene.objects[0] != scene.objects[1]
    obj = scene.objects[0]
    assert isinstance(obj.vertices, np.ndarray) and obj.vertices.shape[1] == 2
    # World vertices: the outline turned by the yaw and moved to the position.
    c, s = math.cos(obj.pose.yaw), math.sin(obj.pose.yaw)
    x, y = obj.vertices[0]
    assert np.allclose(obj.world_vertices()[0], [obj.pose.x + c * x - s * y, obj.pose.y + s * x + c * y])


def test_from_objects_takes_arrays_tuples_and_defaults():
    scene = pushmog.Scene.from_objects(
        [
            {"vertices": SQUARE, "pose": (0.1, 0.1, 0.0), "height": 0.03},
            {"vertices": SQUARE.tolist(), "pose": {"x": 0.2, "y": 0.1}, "height": 0.03, "id": 7, "name": "cube"},
        ]
    )
    assert scene.ids == [0, 7]
    assert scene.objects[1].name == "cube"
    assert scene.gripper["stroke"] == pytest.approx(0.085)


def test_with_poses_and_without():
    scene = pushmog.Scene.from_objects(
        [
            {"vertices": SQUARE, "pose": (0.1, 0.1, 0.0), "height": 0.03, "id": 1},
            {"vertices": SQUARE, "pose": (0.3, 0.1, 0.0), "height": 0.03, "id": 2},
        ]
    )
    moved = scene.with_poses({2: (0.3, 0.2, 0.5)})
    assert moved.objects[1].pose == pushmog.Pose(0.3, 0.2, 0.5)
    assert moved.objects[0].pose == scene.objects[0].pose
    assert scene.objects[1].pose == pushmog.Pose(0.3, 0.1, 0.0)  # the original is unchanged
    assert moved.without([1]).ids == [2]
    with pytest.raises(KeyError):
        scene.with_poses({9999: (0.1, 0.1, 0.0)})
    with pytest.raises(ValueError) as raised:
        scene.with_poses({2: (0.11, 0.1, 0.0)})
    assert raised.value.field == "pose"


def test_invalid_object_names_object_and_field():
    with pytest.raises(ValueError) as raised:
        pushmog.Scene.from_objects([{"vertices": SQUARE, "pose": (0.1, 0.1, 0.0), "height": -1.0, "id": 4}])
    assert raised.value.object == 4
    assert raised.value.field == "height"
    assert "object 4" in str(raised.value)


def test_overlap_names_both_objects_and_the_depth():
    with pytest.raises(ValueError) as raised:
        pushmog.Scene.from_objects(
            [
                {"vertices": SQUARE, "pose": (0.1, 0.1, 0.0), "height": 0.03, "id": 1},
                {"vertices": SQUARE, "pose": (0.115, 0.1, 0.0), "height": 0.03, "id": 2},
            ]
        )
    error = raised.value
    assert {error.object, error.other} == {1, 2}
    assert error.field == "pose"
    assert error.depth == pytest.approx(0.005, abs=1e-6)


def test_non_convex_outline_is_refused():
    arrow = np.array([[0, 0], [0.02, 0.0], [0.005, 0.005], [0.0, 0.02]])
    with pytest.raises(ValueError) as raised:
        pushmog.Scene.from_objects([{"vertices": arrow, "pose": (0.1, 0.1, 0.0), "height": 0.03}])
    assert raised.value.field == "vertices"


def test_bad_shapes_and_missing_fields():
    with pytest.raises(ValueError, match=r"\(k, 2\)"):
        pushmog.Scene.from_objects([{"vertices": np.zeros((4, 3)), "pose": (0.1, 0.1), "height": 0.03}])
    with pytest.raises(ValueError, match="missing field `height`"):
        pushmog.Scene.from_objects([{"vertices": SQUARE, "pose": (0.1, 0.1)}])


def test_json_errors_carry_line_and_column(tmp_path):
    with pytest.raises(ValueError) as raised:
        pushmog.Scene.from_json('{"workspace": {"min": [0, 0], "max": [0.6, 0.45]},\n "objects": [{"id": "x"}]}')
    assert raised.value.line == 2
    assert raised.value.column > 0
    assert "objects[0]" in raised.value.field


def test_missing_file_is_an_os_error(tmp_path):
    with pytest.raises(OSError):
        pushmog.Scene.from_json(tmp_path / "absent.json")


def test_generator_errors_are_value_errors():
    with pytest.raises(ValueError):
        pushmog.generate_scene(5000, seed=1, width=0.1, depth=0.1)


def test_object_set_from_dict():
    library = pushmog.builtin_object_set()
    scene = pushmog.generate_scene(5, seed=2, object_set=library)
    assert scene.to_json() == pushmog.generate_scene(5, seed=2).to_json()
    assert json.loads(json.dumps(library)) == library


def test_errors_are_pushmog_classes_and_the_builtin_ones():
    assert issubclass(pushmog.SceneError, pushmog.PushmogError)
    assert issubclass(pushmog.SceneError, ValueError)
    assert issubclass(pushmog.FileError, OSError)
    assert issubclass(pushmog.PlanError, RuntimeError)
    # A bad scene, from the native validation or from the Python side, is a SceneError.
    with pytest.raises(pushmog.SceneError) as raised:
        pushmog.Scene.from_objects([{"vertices": SQUARE, "pose": (0.1, 0.1, 0.0), "height": -1.0, "id": 4}])
    assert raised.value.field == "height"
    with pytest.raises(pushmog.SceneError):
        pushmog.Scene.from_objects([{"vertices": SQUARE, "pose": (0.1, 0.1)}])
    with pytest.raises(pushmog.SceneError):
        pushmog.Scene.from_json('{"objects": [{"id": "x"}]}')
    with pytest.raises(pushmog.SceneError):
        pushmog.generate_scene(5000, seed=1, width=0.1, depth=0.1)
    with pytest.raises(pushmog.FileError):
        pushmog.Scene.from_json("/nonexistent/scene.json")
    # Settings are not scenes.
    with pytest.raises(pushmog.SettingsError) as raised:
        pushmog.Planner("push-mog", settings={"run": {"max_failed_attempts": -1}})
    assert not isinstance(raised.value, pushmog.SceneError)
    with pytest.raises(pushmog.SettingsError):
        pushmog.Planner("fastest")

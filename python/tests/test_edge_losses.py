"""The edge-loss measurement script (experiments/calibration/edge_losses.py) on plans small enough
to check by hand: rooms to the edge, scenes rebuilt from their changes, and the two movements."""

import sys
from pathlib import Path

import pytest

sys.path.insert(0, str(Path(__file__).resolve().parents[2] / "experiments" / "calibration"))

import edge_losses  # noqa: E402

WORKSPACE = {"min": [0.0, 0.0], "max": [0.6, 0.45]}
SQUARE = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]


def square(ident, x, y):
    return {"id": ident, "vertices": SQUARE, "height": 0.03, "pose": {"x": x, "y": y, "yaw": 0.0}}


def test_room_along_is_the_distance_to_the_first_edge_crossed():
    outline = edge_losses.outline(square(0, 0.015, 0.2))
    assert edge_losses.room_along(outline, (-1.0, 0.0), WORKSPACE) == pytest.approx(0.005)
    assert edge_losses.room_along(outline, (1.0, 0.0), WORKSPACE) == pytest.approx(0.575)
    assert edge_losses.room_along(outline, (0.0, 1.0), WORKSPACE) == pytest.approx(0.24)


def test_a_pair_left_behind_is_measured_along_the_plates():
    # Jaws closing along x (angle 0): the plates run along y. The grasp carries nothing; object 1
    # moves 12 mm along y and 3 mm along x, object 0 stays.
    first = {
        "scene": {"workspace": WORKSPACE, "objects": [square(0, 0.1, 0.2), square(1, 0.13, 0.2)]},
        "pushes": [],
        "grasp": {"objects": [0, 1], "jaws": {"center": [0.115, 0.2], "angle": 0.0}},
        "carried": [],
    }
    second = {
        "scene_change": [0, {"id": 1, "pose": {"x": 0.133, "y": 0.212, "yaw": 0.0}}],
        "pushes": [],
    }
    rows = list(edge_losses.moves({"trips": [first, second]}))
    assert [kind for kind, _, _ in rows] == ["squeezed out", "squeezed out"]
    assert rows[0][1] == pytest.approx(0.0)
    assert rows[1][1] == pytest.approx(0.012)
    # Room along the plates, either way: object 0 reaches y = 0.19 and 0.21, so 0.19 downward.
    assert rows[0][2] == pytest.approx(0.19)


def test_a_held_member_is_measured_along_the_push_toward_it():
    push = {"object": 1, "direction": [-1.0, 0.0]}
    first = {
        "scene": {"workspace": WORKSPACE, "objects": [square(0, 0.02, 0.2), square(1, 0.08, 0.2)]},
        "pushes": [push],
        "ahead_rows": [{"objects": [0, 1], "judged": 1.0}],
    }
    lost = {"scene_change": [{"id": 1, "pose": {"x": 0.041, "y": 0.2, "yaw": 0.0}}], "pushes": []}
    rows = list(edge_losses.moves({"trips": [first, lost]}))
    # Object 0 is gone from the next observation: lost, with 10 mm of room along the push.
    assert rows == [("shoved", None, pytest.approx(0.01))]

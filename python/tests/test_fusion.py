"""Looks fused from Python (``pushmog.LookFusion``): still objects at the mean of their looks, objects
beside an action started again, the camera's error checked."""

import math

import pytest

import pushmog


def square(object_id, x, y):
    h = 0.015
    return {"id": object_id, "vertices": [[-h, -h], [h, -h], [h, h], [-h, h]], "pose": (x, y, 0.0), "height": 0.03}


def table(first_x, second_x):
    return pushmog.Scene.from_objects([square(0, first_x, 0.1), square(1, second_x, 0.3)])


def x_of(scene, object_id):
    return next(o.pose.x for o in scene.objects if o.id == object_id)


def test_still_objects_are_averaged_and_a_grasp_beside_one_starts_it_again():
    fusion = pushmog.LookFusion(0.002, 0.035)
    for first, second in [(0.101, 0.401), (0.099, 0.399)]:
        seen = fusion.fuse(table(first, second))
    assert math.isclose(x_of(seen, 0), 0.1, abs_tol=1e-12)
    assert math.isclose(x_of(seen, 1), 0.4, abs_tol=1e-12)
    # Jaws open around the first square: it starts again from the next look; the second is far.
    planner = pushmog.Planner("sog")
    trip = planner.plan_trip(seen.without([1]), pushmog.TripContext(1))
    fusion.record_grasp(trip)
    seen = fusion.fuse(table(0.104, 0.402))
    assert math.isclose(x_of(seen, 0), 0.104, abs_tol=1e-12)
    assert math.isclose(x_of(seen, 1), 0.4 + 0.002 / 3, abs_tol=1e-12)


def test_the_camera_error_is_checked():
    with pytest.raises(pushmog.SettingsError):
        pushmog.LookFusion(-0.001, 0.035)
    fusion = pushmog.LookFusion.for_planner(pushmog.Planner("push-mog-opt"))
    assert len(fusion.fuse(pushmog.generate_scene(8, seed=3))) == 8

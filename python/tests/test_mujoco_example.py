"""The MuJoCo example on one small scene (skipped, with the reason, only if MuJoCo is not installed)."""

import importlib.util
import json
import sys
from pathlib import Path

import pytest

EXAMPLE = Path(__file__).resolve().parents[1] / "examples" / "mujoco_loop.py"


def load_example():
    pytest.importorskip("mujoco", reason="MuJoCo is not installed (pip install mujoco); the example is not run")
    spec = importlib.util.spec_from_file_location("mujoco_loop", EXAMPLE)
    module = importlib.util.module_from_spec(spec)
    sys.modules["mujoco_loop"] = module
    spec.loader.exec_module(module)
    return module


def test_mujoco_loop_on_a_small_scene(tmp_path, capsys):
    example = load_example()
    out = tmp_path / "figures.json"
    code = example.main(["--objects", "6", "--seed", "1", "--policy", "push-mog-opt", "--json", str(out), "--quiet"])
    printed = capsys.readouterr().out
    figures = json.loads(out.read_text())
    assert "objects per trip" in printed and "rapier" in printed
    assert figures["trips"] == len(figures["carried_per_trip"]) > 0
    assert figures["carried"] == sum(figures["carried_per_trip"]) > 0
    assert figures["carried"] <= 6
    # Every trip is counted once in the agreement table, under its predicted object count.
    assert sum(n for n, _ in figures["agreement"].values()) == figures["trips"]
    assert code == (0 if figures["status"] == "cleared" else 1)


def test_the_mujoco_model_is_the_scene(tmp_path):
    example = load_example()
    import mujoco
    import pushmog

    scene = pushmog.generate_scene(4, seed=2)
    world = example.World(scene, pushmog.default_settings("sim"))
    for obj in scene.objects:
        x, y, yaw, tilt, lowest = world.pose(obj.id)
        # Resting on the table where the scene puts it, upright.
        assert abs(x - obj.pose.x) < 1e-3 and abs(y - obj.pose.y) < 1e-3
        assert abs((yaw - obj.pose.yaw + 3.14159) % 6.28318 - 3.14159) < 0.01
        assert tilt < 0.01 and abs(lowest) < 1e-3
        # Its mass from the density, as pushmog's simulator takes it.
        body = world.model.body(f"object{obj.id}").id
        area = 0.5 * abs(sum(a[0] * b[1] - b[0] * a[1] for a, b in zip(obj.vertices, list(obj.vertices[1:]) + [obj.vertices[0]])))
        assert world.model.body_mass[body] == pytest.approx(1000 * area * obj.height, rel=1e-3)
    observed, lost = world.observe(0.0, None)
    assert not lost and len(observed) == len(scene)
    assert mujoco.mj_version() > 0


def test_pads_that_lose_their_object_close_on_at_the_jaw_speed_not_at_once():
    # The 2F-85's motor closes at a bounded speed: when the object between the pads goes, they
    # follow at the jaw speed. (The example's servo once jumped to fully closed under the force cap,
    # and pads that lost an object snapped shut and threw its neighbours.)
    example = load_example()
    import numpy as np
    import pushmog

    scene = pushmog.generate_scene(1, seed=3)
    sim = pushmog.default_settings("sim")
    world = example.World(scene, sim)
    obj = scene.objects[0]
    yaw = 0.3
    above = world.tallest() + 0.01
    world.move(np.array([*world.target[:2], above, world.target[3]]), example.TRANSFER_SPEED)
    world.set_opening(scene.gripper["stroke"])
    world.move(np.array([obj.pose.x, obj.pose.y, above, yaw]), example.TRANSFER_SPEED)
    world.move(np.array([obj.pose.x, obj.pose.y, sim["grasp_height"], yaw]), sim["vertical_speed"])
    world.close()
    held = world.opening()
    thickness = scene.gripper["plate_thickness"]
    assert held > thickness + 0.01  # the pads stopped on the object
    world.to_bin(obj.id)
    steps = 0
    while world.opening() > thickness + 0.001 and steps < 10_000:
        world.step()
        steps += 1
    lead = world.lead_at_cap + 0.001
    fastest = (held - thickness - 0.001 - lead) / sim["jaw_speed"]
    assert steps * example.TIMESTEP >= 0.9 * fastest


def test_a_toppled_object_lying_flat_is_seen_as_a_lower_prism_and_one_leaning_is_lost():
    example = load_example()
    import math

    import mujoco
    import numpy as np
    import pushmog

    # A 20 x 40 mm block 30 mm tall, its long sides along y, at the workspace's centre.
    base = pushmog.generate_scene(1, seed=2)
    low, high = base.workspace
    centre = (np.asarray(low) + np.asarray(high)) / 2
    block = pushmog.Object(0, [[-0.01, -0.02], [0.01, -0.02], [0.01, 0.02], [-0.01, 0.02]], pushmog.Pose(centre[0], centre[1], 0.0), 0.03, "block", None)
    scene = pushmog.Scene.from_objects([block], gripper=base.gripper, workspace=base.workspace)
    (obj,) = scene.objects
    world = example.World(scene, pushmog.default_settings("sim"))
    address = world.qpos[obj.id]
    vertices = np.asarray(obj.vertices, dtype=float)

    def turn_about_x(angle):
        # Corners (x, y, z) go to (x, y cos − z sin, y sin + z cos); the prism is set down on its
        # lowest corner, at the workspace's centre.
        c, s = math.cos(angle), math.sin(angle)
        corners = [(y * s + z * c) for y in vertices[:, 1] for z in (0.0, obj.height)]
        world.data.qpos[address : address + 7] = [centre[0], centre[1], -min(corners), math.cos(angle / 2), math.sin(angle / 2), 0, 0]
        mujoco.mj_forward(world.model, world.data)

    # On its side: seen, standing as tall as its outline was deep, its outline from above as wide as
    # before along x and as deep as the prism was tall along y.
    turn_about_x(math.pi / 2)
    observed, lost = world.observe(0.0, None)
    assert not lost and len(observed) == 1
    (seen,) = observed.objects
    outline = seen.world_vertices()
    assert seen.height == pytest.approx(vertices[:, 1].max() - vertices[:, 1].min(), abs=1e-6)
    assert np.ptp(outline[:, 0]) == pytest.approx(np.ptp(vertices[:, 0]), abs=1e-6)
    assert np.ptp(outline[:, 1]) == pytest.approx(obj.height, abs=1e-6)
    # Tipped half way, resting on one edge: leaning, not lying flat, so lost.
    turn_about_x(math.pi / 4)
    observed, lost = world.observe(0.0, None)
    assert len(observed) == 0 and lost == {obj.id: "toppled"}


def test_the_camera_loses_an_object_by_where_it_is_not_by_its_noise():
    example = load_example()
    import mujoco
    import numpy as np
    import pushmog

    # A 20 mm square whose right side is 0.5 mm inside the workspace's right edge.
    base = pushmog.generate_scene(1, seed=2)
    low, high = base.workspace
    square = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]
    at_edge = pushmog.Pose(high[0] - 0.0105, (low[1] + high[1]) / 2, 0.0)
    scene = pushmog.Scene.from_objects([pushmog.Object(0, square, at_edge, 0.03, "square", None)], gripper=base.gripper, workspace=base.workspace)
    world = example.World(scene, pushmog.default_settings("sim"))
    rng = np.random.default_rng(1)
    # Perception noise of 5 mm puts the estimate past the edge about half the time; the object is
    # still seen, every time, inside the workspace.
    for _ in range(20):
        observed, lost = world.observe(0.005, rng)
        assert not lost and len(observed) == 1
        outline = observed.objects[0].world_vertices()
        assert (outline <= np.asarray(high) + 1e-9).all()
    # Slid 1 mm past the edge, it is lost, with noise or without.
    address = world.qpos[0]
    world.data.qpos[address] += 0.0015
    mujoco.mj_forward(world.model, world.data)
    for noise in (0.0, 0.005):
        observed, lost = world.observe(noise, rng)
        assert len(observed) == 0 and lost == {0: "outside the workspace"}


def test_a_footprint_hull_drops_corners_pushmog_would_call_collinear():
    example = load_example()
    import numpy as np
    import pushmog

    # The six corners of a triangular prism lying on a side face, seen from above, as MuJoCo left one
    # in a noisy push-mog-opt run: three of them lie on one line to within rounding. An exact hull
    # kept the middle one, and pushmog refused the outline as collinear there.
    points = np.array([
        [0.09663468979367605, 0.2665804780534378],
        [0.07122893353264634, 0.2825350243899888],
        [0.10673923587560429, 0.2826707904616118],
        [0.08133347961457457, 0.2986253367981627],
        [0.1168437816616266, 0.29876110239859255],
        [0.09143802540059687, 0.31471564873514346],
    ])
    hull = example.convex_hull(points)
    assert len(hull) == 4
    base = pushmog.generate_scene(1, seed=2)
    lying = pushmog.Object(0, (hull - hull.mean(axis=0)).tolist(), pushmog.Pose(0.3, 0.2, 0.0), 0.03, "lying", None)
    assert len(pushmog.Scene.from_objects([lying], gripper=base.gripper, workspace=base.workspace)) == 1


def test_a_rider_put_down_on_a_row_rides_its_grasp_and_the_sideways_carry():
    # Two 30 mm cubes side by side along x (0.5 mm apart) make a row 61 mm wide; a 20 x 20 mm block
    # 15 mm tall is put down across their tops, centred, as pushmog's checks would place it (its
    # centroid 10 mm inside the support, its footprint 20 mm inside the faces the pads close on).
    example = load_example()
    from types import SimpleNamespace

    import numpy as np
    import pushmog

    base = pushmog.generate_scene(1, seed=2)
    low, high = base.workspace
    cx, cy = (np.asarray(low) + np.asarray(high)) / 2
    cube = [[-0.015, -0.015], [0.015, -0.015], [0.015, 0.015], [-0.015, 0.015]]
    block = [[-0.01, -0.01], [0.01, -0.01], [0.01, 0.01], [-0.01, 0.01]]
    objects = [
        pushmog.Object(0, cube, pushmog.Pose(cx - 0.01525, cy, 0.0), 0.03, "cube", None),
        pushmog.Object(1, cube, pushmog.Pose(cx + 0.01525, cy, 0.0), 0.03, "cube", None),
        pushmog.Object(2, block, pushmog.Pose(cx + 0.12, cy, 0.0), 0.015, "block", None),
    ]
    scene = pushmog.Scene.from_objects(objects, gripper=base.gripper, workspace=base.workspace)
    sim = pushmog.default_settings("sim")
    world = example.World(scene, sim)
    rider = {
        "object": 2,
        "pick": {"jaws": {"center": [cx + 0.12, cy], "angle": 0.0, "opening": 0.05}},
        "release": {"center": [cx, cy], "angle": 0.0, "opening": 0.05},
        "base": 0.03,
    }
    assert not world.place(rider, np.zeros(3))
    x, y, _, tilt, lowest = world.pose(2)
    assert abs(x - cx) < 0.003 and abs(y - cy) < 0.003
    assert tilt < 0.05 and lowest == pytest.approx(0.03, abs=0.002)
    # The camera reports it standing on the row, as pushmog's simulator does.
    observed, lost = world.observe(0.0, None)
    assert lost == {2: example.RIDER_LEFT} and len(observed) == 2
    grasp = SimpleNamespace(jaws=SimpleNamespace(center=np.array([cx, cy]), angle=0.0, opening=0.085))
    carried, landed = world.grasp(grasp, np.zeros(3))
    assert not landed and sorted(carried) == [0, 1, 2]
    assert world.placed == []


def test_mujoco_rows_carries_a_rider_that_rapier_turns_off(tmp_path, capsys):
    # The first row of experiments/data/rows-with-riders.json: a row rapier turned in the jaws.
    # MuJoCo, with its no-slip passes, carries the row and its rider, as the quasi-static checks
    # say (formulations/stacking.md, "Rows turning in the jaws").
    load_example()
    path = EXAMPLE.with_name("mujoco_rows.py")
    spec = importlib.util.spec_from_file_location("mujoco_rows", path)
    rows = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(rows)
    entries = json.loads(rows.DEFAULT_FILE.read_text())
    one = tmp_path / "one-row.json"
    one.write_text(json.dumps(entries[:1]))
    assert entries[0]["source"]["rapier_turn_degrees"] >= 4
    assert rows.main(["--file", str(one), "--runs", "1"]) == 0
    printed = capsys.readouterr().out
    assert "All rows: rider carried 1/1, row carried whole 1/1, landed 0" in printed
    assert rows.main(["--file", str(tmp_path / "missing.json")]) == 2


def test_an_object_just_past_the_edge_is_seen_there_and_taken_by_itself():
    """An object lying just past the workspace's edge is lost from the look but kept in
    ``World.past_edge`` where it lies; ``Planner.past_edge_trip`` plans its grasp there, and MuJoCo's
    gripper carries it (the table goes on past the workspace)."""
    example = load_example()
    import mujoco
    import numpy as np
    import pushmog

    base = pushmog.generate_scene(1, seed=2)
    low, high = base.workspace
    square = [[-0.015, -0.015], [0.015, -0.015], [0.015, 0.015], [-0.015, 0.015]]
    box = pushmog.Object(0, square, pushmog.Pose(high[0] - 0.05, 0.2, 0.0), 0.03, "box", None)
    scene = pushmog.Scene.from_objects([box], gripper=base.gripper, workspace=base.workspace)
    world = example.World(scene, pushmog.default_settings("sim"))
    observed, lost = world.observe(0.0, None)
    assert len(observed) == 1 and not lost and world.past_edge == []
    # Moved so that its near side lies 5 mm past the right-hand edge.
    address = world.qpos[0]
    world.data.qpos[address] = high[0] + 0.02
    mujoco.mj_forward(world.model, world.data)
    world.wait(0.2)
    observed, lost = world.observe(0.0, None)
    assert len(observed) == 0 and lost == {0: "outside the workspace"}
    (seen,) = world.past_edge
    assert seen.id == 0 and abs(seen.pose.x - (high[0] + 0.02)) < 1e-3
    planner = pushmog.Planner("sog", {"run": {"reach_past_edge": 0.05}})
    context = pushmog.TripContext(0)
    context.record_lost(lost)
    _, trip = planner.past_edge_trip(observed, world.past_edge, context)
    carried, landed = world.grasp(trip.grasp, np.zeros(3))
    assert carried == [0] and not landed
    observed, lost = world.observe(0.0, None)
    assert len(observed) == 0 and not lost and world.past_edge == []

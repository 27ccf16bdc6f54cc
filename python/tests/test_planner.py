"""Planning through Python: trips equal to the command line's, whole runs that pass the verifier,
errors as exceptions, and the GIL released while Rust plans."""

import json
import subprocess
import threading
import time
from concurrent.futures import ThreadPoolExecutor
from pathlib import Path

import numpy as np
import pytest

import pushmog


def trip_fields(trip: dict) -> dict:
    """A run record's trip without what the executor reports (``judged``, ``ahead``,
    ``ahead_rows``, ``push_statuses`` and ``riders`` only when the plan has them, as in plan
    files)."""
    keys = ("clustering", "cluster", "pushes", "skipped_pushes", "grasp", "judged", "ahead",
            "ahead_rows", "push_statuses", "riders")
    return {k: trip[k] for k in keys if k in trip}


@pytest.mark.parametrize("policy", pushmog.POLICIES)
def test_plan_trip_equals_the_cli_plan(policy, cli, tmp_path):
    scene = pushmog.generate_scene(12, seed=7)
    path = tmp_path / "scene.json"
    path.write_text(scene.to_json())
    for seed in (0, 5):
        written = subprocess.run(
            [str(cli), "plan", str(path), "--policy", policy, "--seed", str(seed)],
            check=True,
            capture_output=True,
            text=True,
        ).stdout
        first = json.loads(written)["trips"][0]
        trip = pushmog.Planner(policy).plan_trip(scene, pushmog.TripContext(seed))
        assert trip is not None
        assert trip.to_dict() == trip_fields(first)


@pytest.mark.parametrize("policy", ["push-mog", "push-mog-opt"])
def test_plan_trip_and_correct_trip_equal_the_first_trip_of_a_run(policy, scene):
    """The run's loop: plan, push, look again and plan the rest on what is seen (here the table
    exactly as pushed), for at most max_corrections rounds of corrective pushes."""
    planner = pushmog.Planner(policy)
    rounds = planner.settings["run"]["max_corrections"]
    plan = planner.run(scene, executor="ideal", seed=3)
    record = plan.trips[0]
    context = pushmog.TripContext(3)
    trip = planner.plan_trip(scene, context)
    first = trip.to_dict()
    assert {k: first[k] for k in ("clustering", "cluster")} == {k: record[k] for k in ("clustering", "cluster")}
    table, current, pushes, afters = scene, trip, list(first["pushes"]), []
    while current.pushes:
        table = table.with_poses({p.object: (p.end.x, p.end.y, p.end.yaw) for p in current.pushes})
        afters.append(len(pushes))
        current = planner.correct_trip(table, current, context, may_push=len(afters) <= rounds)
        pushes += current.to_dict()["pushes"]
    assert pushes == record["pushes"]
    assert current.to_dict()["grasp"] == record["grasp"]
    assert [look["after_pushes"] for look in record.get("looks", [])] == afters


def test_correct_trip_checks_its_arguments(scene):
    planner = pushmog.Planner("push-mog")
    trip = planner.plan_trip(scene, pushmog.TripContext(1))
    with pytest.raises(TypeError):
        planner.correct_trip(scene, trip.to_dict())
    # Without pushes there is nothing to correct: the grasp is planned on the table as it is.
    again = planner.correct_trip(scene, trip, may_push=False)
    assert again is not None and again.pushes == []


def test_trip_parts_are_numpy_friendly(scene):
    trip = pushmog.Planner("push-mog").plan_trip(scene, pushmog.TripContext(1))
    assert trip.grasp.objects and set(trip.grasp.objects) <= set(scene.ids)
    assert trip.grasp.jaws.center.shape == (2,)
    assert trip.grasp.jaws.opening <= scene.gripper["stroke"] + 1e-12
    for push in trip.pushes:
        assert push.path.shape == (3, 2)
        # The object slides along the push direction by the push distance, yaw unchanged.
        moved = np.array([push.end.x - push.start.x, push.end.y - push.start.y])
        assert np.allclose(moved, push.direction * push.distance, atol=1e-9)
        assert push.end.yaw == push.start.yaw
    assert json.loads(trip.to_json()) == trip.to_dict()


def test_closed_loop_through_plan_trip_clears_a_small_table(small_scene):
    """The robot stack owns the loop: it applies each trip exactly as planned (the pushed objects at
    their planned poses, the grasped ones gone), records failures, and asks again."""
    planner = pushmog.Planner("push-mog-opt")
    context = pushmog.TripContext(2)
    table, trips = small_scene, 0
    while len(table) and trips < 3 * len(small_scene):
        trip = planner.plan_trip(table, context, strict=True)
        trips += 1
        if trip.pushes:
            table = table.with_poses({p.object: (p.end.x, p.end.y, p.end.yaw) for p in trip.pushes})
        table = table.without(trip.grasp.objects)
    assert len(table) == 0
    assert trips <= len(small_scene)


def test_a_trip_pushing_ahead_names_the_rows_and_grasps_none_of_them():
    """push-mog-time's settings (``experiments/push-mog-time.json``): the first trip of a full
    table pushes rows for later trips; every pushed object is in ``ahead``, and the trip's own
    grasp takes none of them, so a robot stack knows to skip the look after these pushes."""
    path = Path(__file__).resolve().parents[2] / "experiments" / "push-mog-time.json"
    planner = pushmog.Planner("push-mog-opt", settings=json.loads(path.read_text()))
    trip = planner.plan_trip(pushmog.generate_scene(34, seed=1), pushmog.TripContext(1))
    assert trip is not None and trip.pushes
    ahead = set(trip.ahead)
    assert {p.object for p in trip.pushes} <= ahead
    assert ahead.isdisjoint(trip.grasp.objects)
    rows = trip.to_dict()["ahead_rows"]
    assert sorted(o for row in rows for o in row["objects"]) == sorted(ahead)


@pytest.mark.parametrize("policy", pushmog.POLICIES)
def test_runs_pass_the_verifier(policy, small_scene):
    plan = pushmog.Planner(policy).run(small_scene, executor="ideal", seed=1)
    assert plan.cleared
    assert plan.objects_carried() == len(small_scene)
    assert pushmog.verify(plan) == []


def test_simulated_run_is_reproducible_and_verified(small_scene):
    planner = pushmog.Planner("push-mog")
    first = planner.run(small_scene, executor="sim", seed=4)
    again = planner.run(small_scene, executor="sim", seed=4)
    assert first.to_dict() == again.to_dict()
    assert first.executor == "sim"
    assert pushmog.verify(first) == []
    assert sum(first.carried_per_trip()) == first.objects_carried()


def test_a_simulated_run_can_look_through_the_depth_camera(small_scene):
    # Each look renders the table, adds depth noise and perceives it; the plan still verifies.
    plan = pushmog.Planner("push-mog").run(small_scene, executor="sim", seed=4, sim_settings={"camera": {}})
    assert pushmog.verify(plan) == []
    assert plan.objects_carried() == len(small_scene)


def test_verifier_finds_a_tampered_plan(small_scene):
    plan = pushmog.Planner("push-mog").run(small_scene, seed=1).to_dict()
    plan["trips"][0]["grasp"]["objects"] = [9999]
    assert pushmog.verify(pushmog.Plan(plan)) != []


def test_plans_are_read_by_the_cli(small_scene, cli, tmp_path):
    plan = pushmog.Planner("push-mog-opt").run(small_scene, seed=1)
    path = tmp_path / "plan.json"
    plan.save(path)
    checked = subprocess.run([str(cli), "verify", str(path)], capture_output=True, text=True)
    assert checked.returncode == 0, checked.stderr
    assert pushmog.Plan.from_json(path).to_dict() == plan.to_dict()


def test_settings_are_applied_and_checked(small_scene):
    planner = pushmog.Planner("push-mog", settings={"run": {"max_failed_attempts": 3}})
    assert planner.settings["run"]["max_failed_attempts"] == 3
    with pytest.raises(ValueError) as raised:
        pushmog.Planner("push-mog", settings={"run": {"max_failed_attempts": -1}})
    assert "max_failed_attempts" in str(raised.value)
    with pytest.raises(ValueError) as raised:
        pushmog.Planner("push-mog", settings={"no_such_setting": 1})
    assert "no_such_setting" in str(raised.value)
    with pytest.raises(ValueError, match="unknown policy"):
        pushmog.Planner("fastest")
    with pytest.raises(ValueError, match="unknown executor"):
        pushmog.Planner("sog").run(small_scene, executor="gazebo")
    with pytest.raises(TypeError):
        pushmog.Planner("sog").plan_trip(small_scene.to_dict())


def test_empty_table_has_no_trip():
    empty = pushmog.Scene.from_objects([])
    assert pushmog.Planner("push-mog").plan_trip(empty) is None
    with pytest.raises(pushmog.NoTrip, match="empty") as raised:
        pushmog.Planner("push-mog").plan_trip(empty, strict=True)
    assert raised.value.reason == "empty_table"


def test_failed_grasps_are_not_proposed_again(scene):
    planner = pushmog.Planner("sog")
    context = pushmog.TripContext(0)
    trip = planner.plan_trip(scene, context)
    context.record_failure(trip)
    assert len(context.failed) == 1
    again = planner.plan_trip(scene, context)
    assert again.grasp.jaws.to_dict() != trip.grasp.jaws.to_dict()
    assert context.failed_together == []  # a single-object grasp gives up no set


def test_a_grasp_that_landed_is_forgotten_once_the_object_is_carried(scene):
    """A failed grasp that came down on an object is forgotten once that object is carried, and
    only then; a failure without a landing is kept."""
    planner = pushmog.Planner("sog")
    context = pushmog.TripContext(0)
    trip = planner.plan_trip(scene, context)
    on = next(o["id"] for o in scene.to_dict()["objects"] if o["id"] not in trip.grasp.objects)
    context.record_failure(trip, landed_on=on)
    context.record_failure(trip)
    assert not context.forget_landings_on(trip.grasp.objects)
    assert len(context.failed) == 2
    assert context.forget_landings_on([on])
    assert len(context.failed) == 1
    assert not context.forget_landings_on([on])


def test_objects_that_failed_together_twice_are_taken_apart():
    """Two multi-object grasps of the same objects that carried nothing: the next trip grasps no set
    of exactly those objects."""
    planner = pushmog.Planner("push-mog-opt")

    def first_trip(seed):
        table = pushmog.generate_scene(seed=seed)
        return table, seed, planner.plan_trip(table, pushmog.TripContext(seed))

    table, seed, trip = next(
        found for found in map(first_trip, range(20)) if len(found[2].grasp.objects) >= 2
    )
    together = sorted(trip.grasp.objects)
    context = pushmog.TripContext(seed)
    context.record_failure(trip)
    assert context.failed_together == [together]
    assert sorted(planner.plan_trip(table, pushmog.TripContext(seed)).grasp.objects) == together
    context.record_failure(trip)
    again = planner.plan_trip(table, context)
    assert sorted(again.grasp.objects) != together


def test_a_push_that_landed_is_remembered(scene):
    """A landing during a push is kept in the context (the push and the object landed on); an index
    past the trip's pushes is refused."""
    planner = pushmog.Planner("push-mog-opt")
    trip = next(
        t for seed in range(20) if (t := planner.plan_trip(scene, pushmog.TripContext(seed))).pushes
    )
    context = pushmog.TripContext(0)
    context.record_landing(trip, 0, 99)
    assert len(context.landed) == 1
    assert context.landed[0]["on"] == 99
    assert context.landed[0]["push"]["object"] == trip.pushes[0].object
    with pytest.raises(ValueError, match="push"):
        context.record_landing(trip, len(trip.pushes), 99)


def test_planning_releases_the_gil(scene):
    """While one thread is inside a long Rust call, another thread keeps running Python."""
    planner = pushmog.Planner("push-mog-opt")
    inside = threading.Event()
    done = threading.Event()
    span = {}

    def work():
        inside.set()
        span["start"] = time.perf_counter()
        planner.run(scene, executor="sim", seed=0)
        span["end"] = time.perf_counter()
        done.set()

    worker = threading.Thread(target=work)
    worker.start()
    inside.wait()
    seen = []
    while not done.is_set():
        seen.append(time.perf_counter())
    worker.join()
    during = [t for t in seen if span["start"] <= t <= span["end"]]
    call = span["end"] - span["start"]
    assert call > 0.05
    # With the GIL held, this thread could run only in the few milliseconds around the call.
    assert during and during[-1] - during[0] > 0.5 * call


def test_parallel_planning_gives_the_serial_answers():
    scenes = [pushmog.generate_scene(20, seed=s) for s in range(4)]
    planner = pushmog.Planner("push-mog-opt")
    serial = [planner.run(s, seed=1).to_dict() for s in scenes]
    with ThreadPoolExecutor(max_workers=2) as pool:
        parallel = list(pool.map(lambda s: planner.run(s, seed=1).to_dict(), scenes))
    assert parallel == serial


def test_a_trip_says_whether_its_clustering_was_proven_optimal():
    """The MILP's proof reaches the trip; the paper's hierarchical clustering makes no claim."""
    scene = pushmog.generate_scene(12, seed=7)
    statuses = {
        policy: pushmog.Planner(policy).plan_trip(scene, pushmog.TripContext(0)).clustering_status
        for policy in ("sog", "push-mog", "push-mog-opt")
    }
    assert statuses == {"sog": None, "push-mog": "heuristic", "push-mog-opt": "optimal"}


@pytest.mark.parametrize("policy, allowed", [("push-mog", {"heuristic"}), ("push-mog-opt", {"best_found", "heuristic"})])
def test_a_trip_says_how_its_pushes_were_planned(scene, policy, allowed):
    """One push-planner status per answer whose pushes the trip makes; none without pushes."""
    planner = pushmog.Planner(policy)
    trips = [planner.plan_trip(scene, pushmog.TripContext(seed)) for seed in range(8)]
    pushed = [t for t in trips if t is not None and t.pushes]
    assert pushed
    for trip in trips:
        assert trip is not None
        assert bool(trip.push_statuses) == bool(trip.pushes)
        assert set(trip.push_statuses) <= allowed


def test_riders_are_planned_when_the_setting_is_on(scene):
    """With ``riders.enabled`` some trip puts a single object on its row; each rider rests on
    objects the trip's grasp takes and is not one of them."""
    planner = pushmog.Planner("push-mog-opt", {"riders": {"enabled": True}})
    trips = [planner.plan_trip(scene, pushmog.TripContext(seed)) for seed in range(8)]
    riding = [t for t in trips if t is not None and t.riders]
    assert riding
    for trip in riding:
        for rider in trip.riders:
            assert set(rider["on"]) <= set(trip.grasp.objects)
            assert rider["object"] not in trip.grasp.objects
    plain = pushmog.Planner("push-mog-opt")
    assert all(t is None or not t.riders for t in (plain.plan_trip(scene, pushmog.TripContext(s)) for s in range(3)))


def test_a_rider_left_standing_is_grasped_with_its_row(scene):
    """A rider recorded as put down and then reported left standing on its row (its row's grasp
    carried nothing) makes the next trip grasp that row again as it lies: no pushes, no new rider,
    and every object the rider rests on taken."""
    planner = pushmog.Planner("push-mog-opt", {"riders": {"enabled": True}})
    for seed in range(8):
        context = pushmog.TripContext(seed)
        trip = planner.plan_trip(scene, context)
        if trip is not None and trip.riders:
            break
    else:
        pytest.fail("no trip put a rider down")
    rider = trip.riders[0]
    # The table after the trip's pushes, with the rider standing on the row, out of the camera's view.
    pushed = scene.with_poses({p.object: p.end.as_array() for p in trip.pushes}).without([rider["object"]])
    context.record_riders(scene, trip)
    context.record_lost({rider["object"]: pushmog.RIDER_LEFT})
    again = planner.plan_trip(pushed, context)
    assert again is not None and not again.pushes and not again.riders
    assert set(rider["on"]) <= set(again.grasp.objects)


def test_an_object_just_past_the_edge_is_taken_by_itself_within_the_reach():
    """``Planner.past_edge_trip`` (as pushmog's own loop with ``run.reach_past_edge``): off by
    default; with a 5 cm reach a single grasp of the object, planned on the workspace grown by the
    reach; an object farther out is left; failed jaws are not tried again; a bad outline names its
    field."""
    empty = pushmog.Scene.from_objects([])
    low, high = empty.workspace
    square = [[-0.015, -0.015], [0.015, -0.015], [0.015, 0.015], [-0.015, 0.015]]
    # 5 mm past the right-hand edge, and one 10 cm out.
    near = pushmog.Object(3, square, pushmog.Pose(high[0] + 0.02, 0.2, 0.1), 0.03, "box", 0.05)
    far = pushmog.Object(4, square, pushmog.Pose(high[0] + 0.115, 0.1, 0.0), 0.03)
    assert pushmog.Planner("push-mog-opt").past_edge_trip(empty, [near]) is None
    planner = pushmog.Planner("push-mog-opt", {"run": {"reach_past_edge": 0.05}})
    assert planner.past_edge_trip(empty, [far]) is None
    context = pushmog.TripContext(0)
    table, trip = planner.past_edge_trip(empty, [near, far], context)
    grown_low, grown_high = table.workspace
    assert np.allclose(grown_low, low - 0.05) and np.allclose(grown_high, high + 0.05)
    assert table.ids == [3] and table.objects[0].name == "box"
    assert trip.pushes == [] and trip.grasp.objects == [3]
    assert trip.grasp.jaws.center[0] > high[0]
    # Carried nothing: those jaws are not proposed again.
    context.record_failure(trip)
    again = planner.past_edge_trip(empty, [near], context)
    assert again is None or again[1].grasp.jaws.to_dict() != trip.grasp.jaws.to_dict()
    with pytest.raises(pushmog.SceneError) as raised:
        planner.past_edge_trip(empty, [pushmog.Object(5, [[0, 0], [0.01, 0], [0.02, 0]], pushmog.Pose(0.7, 0.2, 0.0), 0.03)])
    assert raised.value.field == "vertices"


def test_a_named_preset_is_its_policy_with_its_settings():
    """``Planner("push-mog-time-riders")`` plans as push-mog-opt with ``experiments/push-mog-time.json``
    and riders on; settings given are laid over the preset's; an unknown name lists the presets."""
    assert set(pushmog.PRESETS) == {"push-mog-time", "push-mog-time-riders", "push-mog-opt-riders"}
    assert all(policy in pushmog.POLICIES for policy, _ in pushmog.PRESETS.values())
    settings = json.loads((Path(__file__).resolve().parents[2] / "experiments" / "push-mog-time.json").read_text())
    settings["riders"] = {"enabled": True}
    named = pushmog.Planner("push-mog-time-riders")
    written = pushmog.Planner("push-mog-opt", settings)
    assert named.settings == written.settings
    scene = pushmog.generate_scene(16, seed=4)
    assert named.plan_trip(scene).to_dict() == written.plan_trip(scene).to_dict()
    over = pushmog.Planner("push-mog-time-riders", {"run": {"reach_past_edge": 0.05}}).settings
    assert over["run"]["reach_past_edge"] == 0.05 and over["run"]["fuse_looks"] and over["riders"]["enabled"]
    with pytest.raises(pushmog.SettingsError, match="push-mog-time-riders"):
        pushmog.Planner("push-mog-fast")


def test_a_rider_that_fell_off_a_row_carried_whole_is_not_offered_again(scene):
    """``TripContext.record_carried``: a rider left behind by a grasp that carried its whole row is
    not offered as a rider again; one left behind by a row not carried whole may ride again."""
    planner = pushmog.Planner("push-mog-opt-riders")
    for seed in range(8):
        context = pushmog.TripContext(seed)
        trip = planner.plan_trip(scene, context)
        if trip is not None and trip.riders:
            break
    else:
        pytest.fail("no trip with a rider")
    rider = trip.riders[0]["object"]
    row = trip.grasp.objects
    context.record_carried(trip, row[:1])
    assert context.fell_off == []
    context.record_carried(trip, row)
    assert context.fell_off == [rider]
    again = planner.plan_trip(scene, context)
    assert all(r["object"] != rider for r in again.riders)

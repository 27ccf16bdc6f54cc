"""Drawings, schemas and settings."""

import pytest

import pushmog


def test_render_scene_and_plan(small_scene):
    svg = pushmog.render_svg(small_scene)
    assert "<svg" in svg and svg.rstrip().endswith("</svg>")
    plan = pushmog.Planner("push-mog").run(small_scene, seed=1)
    drawing = pushmog.render_svg(plan, title="a run")
    assert "<svg" in drawing and "a run" in drawing
    with pytest.raises(ValueError):
        pushmog.render_svg(small_scene, pixels_per_metre=0)
    with pytest.raises(TypeError):
        pushmog.render_svg("scene.json")


@pytest.mark.parametrize("name", ["scene", "object-set", "policy", "sim", "plan", "trip"])
def test_schemas(name):
    schema = pushmog.schema(name)
    assert isinstance(schema, dict) and schema
    with pytest.raises(ValueError):
        pushmog.schema("everything")


def test_trip_schema_names_the_trip_fields():
    properties = pushmog.schema("trip")["properties"]
    assert {"clustering", "cluster", "pushes", "skipped_pushes", "grasp"} <= set(properties)


def test_default_settings():
    sim = pushmog.default_settings("sim")
    assert sim["grip_force"] > 0 and sim["friction_table"] > 0
    policy = pushmog.default_settings("policy")
    assert pushmog.Planner("push-mog", settings=policy).settings == pushmog.Planner("push-mog").settings
    with pytest.raises(ValueError):
        pushmog.default_settings("robot")


def test_version():
    assert pushmog.__version__.count(".") == 2

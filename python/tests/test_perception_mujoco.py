"""MuJoCo's rendered depth of a scene, an independent camera, perceived as pushmog's own rendering is
(skipped, with the reason, when MuJoCo or an offscreen GL context is missing).

MuJoCo chooses its GL back end when it is first imported, and another test may have imported it
without ``MUJOCO_GL``; so the rendering runs in a fresh interpreter with ``MUJOCO_GL=egl``."""

import math
import os
import subprocess
import sys
from pathlib import Path

import numpy as np
import pytest

import pushmog

WIDTH, HEIGHT, FOVY = 640, 480, 45.0  # pixels, degrees: about 1.2 mm per pixel on the table

RENDER = """
import sys
import mujoco
import numpy as np
xml, out, height, width = sys.argv[1], sys.argv[2], int(sys.argv[3]), int(sys.argv[4])
model = mujoco.MjModel.from_xml_path(xml)
data = mujoco.MjData(model)
mujoco.mj_forward(model, data)
renderer = mujoco.Renderer(model, height, width)
renderer.enable_depth_rendering()
renderer.update_scene(data, camera="top")
np.save(out, np.asarray(renderer.render(), dtype=np.float32))
"""


def mujoco_depth(scene: pushmog.Scene, x: float, y: float, above: float, folder: Path) -> np.ndarray:
    """Camera-z depth, metres, of the scene's prisms as MuJoCo renders them from (x, y, above)."""
    pytest.importorskip("mujoco", reason="MuJoCo is not installed (pip install mujoco)")
    assets, geoms = [], []
    for obj in scene.objects:
        points = [(px, py, pz) for pz in (0.0, obj.height) for px, py in obj.vertices]
        vertex = " ".join(f"{px:.9g} {py:.9g} {pz:.9g}" for px, py, pz in points)
        assets.append(f'<mesh name="m{obj.id}" vertex="{vertex}"/>')
        c, s = math.cos(obj.pose.yaw / 2), math.sin(obj.pose.yaw / 2)
        geoms.append(f'<geom type="mesh" mesh="m{obj.id}" pos="{obj.pose.x} {obj.pose.y} 0" quat="{c} 0 0 {s}"/>')
    xml = f"""<mujoco><asset>{''.join(assets)}</asset><visual><map znear="0.1" zfar="5"/></visual>
      <worldbody><geom type="plane" size="2 2 0.01"/>{''.join(geoms)}
      <camera name="top" pos="{x} {y} {above}" xyaxes="1 0 0 0 1 0" fovy="{FOVY}"/></worldbody></mujoco>"""
    xml_path, out = folder / "scene.xml", folder / "depth.npy"
    xml_path.write_text(xml)
    env = dict(os.environ, MUJOCO_GL="egl")
    done = subprocess.run(
        [sys.executable, "-c", RENDER, str(xml_path), str(out), str(HEIGHT), str(WIDTH)],
        env=env,
        capture_output=True,
        text=True,
    )
    if done.returncode != 0:  # no display, no EGL or OSMesa
        last = (done.stderr.strip().splitlines() or ["no message"])[-1]
        pytest.skip(f"MuJoCo could not render offscreen: {last}")
    return np.load(out)


def test_mujoco_depth_gives_the_objects_pushmog_renders(scene: pushmog.Scene, tmp_path: Path) -> None:
    x, y, above = 0.3, 0.225, 0.7
    # MuJoCo's camera with xyaxes "1 0 0 0 1 0" looks down -z with image rows along -y: in OpenCV's
    # conventions R = diag(1, -1, -1), f = (H/2)/tan(fovy/2), principal point at the image's middle.
    f = 0.5 * HEIGHT / math.tan(math.radians(FOVY) / 2)
    camera = pushmog.Camera(WIDTH, HEIGHT, f, f, (WIDTH - 1) / 2, (HEIGHT - 1) / 2, translation=(x, y, above))
    theirs = mujoco_depth(scene, x, y, above, tmp_path)
    ours, _, _ = pushmog.render_depth(scene, camera)
    agree = np.abs(theirs - ours) < 1e-4
    assert agree.mean() > 0.99, f"{agree.mean():.4f} of pixels within 0.1 mm"
    seen_theirs = pushmog.perceive(theirs, camera, workspace=scene).scene()
    seen_ours = pushmog.perceive(ours, camera, workspace=scene).scene()
    assert len(seen_theirs) == len(seen_ours) == len(scene)
    ours_at = {o.id: o.world_vertices().mean(axis=0) for o in seen_ours.objects}
    for o in seen_theirs.objects:
        nearest = min(np.linalg.norm(c - o.world_vertices().mean(axis=0)) for c in ours_at.values())
        assert nearest < 0.001

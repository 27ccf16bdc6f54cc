#!/usr/bin/env python3
"""Measures how far objects move in the two ways push-mog-time loses them past the workspace's edge
(formulations/picks-per-hour.md, "How objects were lost without the margins").

Runs push-mog-opt with the given settings (default: experiments/push-mog-time.json) in the
simulator with noise on generated scenes, and reads two displacements from the plans, each between
the observation the trip was planned on and the next trip's observation (both noisy):

- **squeezed out**: objects a multi-object grasp was meant to carry and left on the table, moved
  along the plates (either way);
- **shoved**: members of a row pushed ahead that were held in place while another member was pushed
  toward them, moved along that push (signed: positive is the way of the push).

An object lost from the workspace has no next observation; it is counted apart, with its room
(distance from its outline to the edge along the plates, or along the push) before the trip.

    cargo build --release
    python3 experiments/calibration/edge_losses.py --first 7001 --count 150   # push-mog-time
    python3 experiments/calibration/edge_losses.py --settings no-margins.json  # other settings

Standard library only; the plans go to a temporary folder.
"""

import argparse
import json
import math
import os
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

from push_success import run


def outline(obj):
    """The object's outline in the table frame."""
    pose = obj["pose"]
    c, s = math.cos(pose["yaw"]), math.sin(pose["yaw"])
    return [(pose["x"] + c * x - s * y, pose["y"] + s * x + c * y) for x, y in obj["vertices"]]


def room_along(points, direction, workspace):
    """How far the outline may move along `direction` before it leaves the workspace."""
    (x0, y0), (x1, y1) = workspace["min"], workspace["max"]
    best = math.inf
    for x, y in points:
        for p, u, low, high in ((x, direction[0], x0, x1), (y, direction[1], y0, y1)):
            if u > 1e-12:
                best = min(best, (high - p) / u)
            elif u < -1e-12:
                best = min(best, (low - p) / u)
    return best


def changed(previous, change):
    """A scene (objects by id) from the one before and a `scene_change` list."""
    scene = {}
    for entry in change:
        if isinstance(entry, int):
            scene[entry] = previous[entry]
        elif "vertices" in entry:
            scene[entry["id"]] = entry
        else:
            scene[entry["id"]] = dict(previous[entry["id"]], pose=entry["pose"])
    return scene


def scenes(plan):
    """Each trip's observed scene (objects by id), and the workspace."""
    out, scene, workspace = [], None, None
    for trip in plan["trips"]:
        if trip.get("scene"):
            workspace = trip["scene"]["workspace"]
            scene = {o["id"]: o for o in trip["scene"]["objects"]}
        else:
            scene = changed(scene, trip["scene_change"])
        out.append(scene)
    return out, workspace


def moves(plan):
    """(kind, displacement or None if lost, room before) for every object of the two kinds."""
    observed, workspace = scenes(plan)
    for k, trip in enumerate(plan["trips"]):
        before = observed[k]
        for look in trip.get("looks") or []:
            before = changed(observed[k], look["scene_change"])
        after = observed[k + 1] if k + 1 < len(observed) else None
        if after is None:
            continue

        def moved(obj, direction):
            if obj not in after:
                return None
            a, b = after[obj]["pose"], before[obj]["pose"]
            return (a["x"] - b["x"]) * direction[0] + (a["y"] - b["y"]) * direction[1]

        grasp = trip.get("grasp")
        carried = set(trip.get("carried") or [])
        if grasp and len(grasp["objects"]) >= 2 and not set(grasp["objects"]) <= carried:
            angle = grasp["jaws"]["angle"]
            along = (-math.sin(angle), math.cos(angle))
            for obj in grasp["objects"]:
                if obj in carried:
                    continue
                points = outline(before[obj])
                room = min(room_along(points, along, workspace),
                           room_along(points, (-along[0], -along[1]), workspace))
                d = moved(obj, along)
                yield "squeezed out", None if d is None else abs(d), room
        pushed = {p["object"]: p for p in trip["pushes"]}
        for row in trip.get("ahead_rows") or []:
            for held in (o for o in row["objects"] if o not in pushed):
                for other in (o for o in row["objects"] if o in pushed):
                    direction = pushed[other]["direction"]
                    points = outline(before[held])
                    yield "shoved", moved(held, direction), room_along(points, direction, workspace)


def quantile(values, q):
    ordered = sorted(values)
    return ordered[min(len(ordered) - 1, int(q * len(ordered)))]


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--first", type=int, default=7001, help="first scene seed")
    parser.add_argument("--count", type=int, default=150, help="scenes")
    parser.add_argument("--pushmog", default="target/release/pushmog", help="the command line")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--settings", default="experiments/push-mog-time.json",
                        help="the policy's settings, a JSON file")
    args = parser.parse_args()
    with tempfile.TemporaryDirectory() as folder:
        seeds = range(args.first, args.first + args.count)
        with ThreadPoolExecutor(args.jobs) as pool:
            plans = list(pool.map(lambda s: run(args.pushmog, folder, s, args.settings), seeds))
    rows = [row for plan in plans for row in moves(plan)]
    print(f"scenes {args.first}-{args.first + args.count - 1}, settings {args.settings}")
    print()
    print("| objects | count | lost | median (mm) | p90 | p95 | p99 | largest | lost: room before (mm) |")
    print("|---|---:|---:|---:|---:|---:|---:|---:|---|")
    for kind in ("squeezed out", "shoved"):
        seen = [d * 1000 for k, d, _ in rows if k == kind and d is not None]
        lost = sorted(r * 1000 for k, d, r in rows if k == kind and d is None)
        if not seen:
            continue
        cells = " | ".join(f"{quantile(seen, q):.1f}" for q in (0.5, 0.9, 0.95, 0.99))
        rooms = ", ".join(f"{r:.1f}" for r in lost) or "–"
        print(f"| {kind} | {len(seen) + len(lost)} | {len(lost)} | {cells} | {max(seen):.1f} | "
              f"{rooms} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

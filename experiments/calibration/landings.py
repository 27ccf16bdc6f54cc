#!/usr/bin/env python3
"""Replays one policy's runs of an experiment log and counts the multi-object grasps whose plates
came down on a row member, by how far the nearer plate stood from the row on the observed table
(formulations/grasping.md, "Grasps that come down on a row").

Each run is replayed with `pushmog run` on its scene and logged run seed, with the given settings
(push-mog-opt is the base policy, as in the logs); it prints how many replays gave the log's trip
count (all 400 push-mog-time runs of stacking-unseen did, with the settings they ran). Replays
with other settings (for example `multi.centre_along_axis`) pair with those, run for run
(`--paired-with`).

For every multi-object grasp planned on an observed table (not after pushes in the same trip), the
gap is the least distance between an open plate and a member of the row, on the table the grasp was
planned on. A grasp came down on a member when its trip records a fault during the grasp on one of
the row's objects.

    cargo build --release
    # riders.json: experiments/push-mog-time.json with "riders": {"enabled": true};
    # centred.json: the same with "multi": {..., "centre_along_axis": true}
    python3 experiments/calibration/landings.py --log experiments/results/stacking-unseen.jsonl \\
        --policy push-mog-time-riders --settings riders.json --out base.json
    python3 experiments/calibration/landings.py ... --settings centred.json --out centred.json \\
        --paired-with base.json

Standard library only; the plans go to a temporary folder.
"""

import argparse
import json
import math
import os
import re
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

from edge_losses import changed, outline

BANDS_MM = [3, 4, 5, 6, 8, 100]


def separated(a, b):
    """Whether a separating axis among the edges of the two convex outlines exists."""
    for poly in (a, b):
        for (x0, y0), (x1, y1) in zip(poly, poly[1:] + poly[:1]):
            nx, ny = y1 - y0, x0 - x1
            pa = [nx * x + ny * y for x, y in a]
            pb = [nx * x + ny * y for x, y in b]
            if max(pa) < min(pb) or max(pb) < min(pa):
                return True
    return False


def point_segment(p, a, b):
    (px, py), (ax, ay), (bx, by) = p, a, b
    dx, dy = bx - ax, by - ay
    t = max(0.0, min(1.0, ((px - ax) * dx + (py - ay) * dy) / (dx * dx + dy * dy)))
    return math.hypot(px - ax - t * dx, py - ay - t * dy)


def distance(a, b):
    """Least distance between two convex outlines (0 when they overlap)."""
    if not separated(a, b):
        return 0.0
    return min(point_segment(p, q, r)
               for first, second in ((a, b), (b, a))
               for p in first
               for q, r in zip(second, second[1:] + second[:1]))


def plates(jaws, gripper):
    """The two open plates' outlines."""
    ax = (math.cos(jaws["angle"]), math.sin(jaws["angle"]))
    al = (-ax[1], ax[0])
    ht, hl = gripper["plate_thickness"] / 2, gripper["plate_length"] / 2
    out = []
    for side in (1, -1):
        cx = jaws["center"][0] + ax[0] * side * jaws["opening"] / 2
        cy = jaws["center"][1] + ax[1] * side * jaws["opening"] / 2
        out.append([(cx + ax[0] * u + al[0] * v, cy + ax[1] * u + al[1] * v)
                    for u, v in ((-ht, -hl), (ht, -hl), (ht, hl), (-ht, hl))])
    return out


def grasps(plan):
    """(nearer plate's gap to the row in metres, landed, with a rider) of each multi-object grasp
    planned on an observed table."""
    scene, gripper = None, None
    for trip in plan["trips"]:
        if "scene" in trip:
            scene = {o["id"]: o for o in trip["scene"]["objects"]}
            gripper = trip["scene"]["gripper"]
        else:
            scene = changed(scene, trip["scene_change"])
        grasp, fault = trip.get("grasp"), trip.get("fault")
        if not grasp or len(grasp["objects"]) < 2 or trip.get("pushes"):
            continue
        if fault and fault["during"] != "grasp":
            continue
        members = [outline(scene[i]) for i in grasp["objects"] if i in scene]
        gap = min(distance(p, m) for p in plates(grasp["jaws"], gripper) for m in members)
        on_member = fault is not None and fault.get("object") in grasp["objects"]
        yield gap, on_member, bool(trip.get("riders"))


def summary(plan, printed):
    """What one run did: trips, objects, robot seconds, riders placed and not carried by their
    trip, and its grasps."""
    placed = lost = 0
    for trip in plan["trips"]:
        fault = trip.get("fault")
        riders = trip.get("riders") or []
        if riders and not (fault and fault["during"] in ("push", "place")):
            placed += len(riders)
            lost += sum(r["object"] not in trip["carried"] for r in riders)
    return {
        "trips": len(plan["trips"]),
        "carried": int(re.search(r"(\d+) carried", printed).group(1)),
        "seconds": float(re.search(r"robot time\s+([\d.]+) s", printed).group(1)),
        "cleared": plan["status"]["kind"] == "cleared",
        "riders_placed": placed,
        "riders_lost": lost,
        "grasps": list(grasps(plan)),
    }


def replay(pushmog, folder, settings, entry):
    scene = os.path.join(folder, f"scene-{entry['scene_seed']}.json")
    plan = os.path.join(folder, f"plan-{entry['scene_seed']}-{entry['run_seed']}.json")
    subprocess.run([pushmog, "scene", "generate", "--objects", str(entry["objects"]), "--seed",
                    str(entry["scene_seed"]), "-o", scene], check=True, stdout=subprocess.DEVNULL)
    printed = subprocess.run([pushmog, "run", scene, "--policy", "push-mog-opt", "--executor", "sim",
                              "--seed", str(entry["run_seed"]), "--settings", settings, "--plan",
                              plan], check=True, capture_output=True, text=True).stdout
    with open(plan) as f:
        return summary(json.load(f), printed)


def mean_interval(values):
    n = len(values)
    mean = sum(values) / n
    sd = math.sqrt(sum((v - mean) ** 2 for v in values) / (n - 1)) if n > 1 else 0.0
    return mean, 1.96 * sd / math.sqrt(n)


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--log", required=True, help="experiment log (.jsonl)")
    parser.add_argument("--policy", required=True, help="the log's policy name whose runs to replay")
    parser.add_argument("--settings", required=True, help="settings file for push-mog-opt")
    parser.add_argument("--pushmog", default="target/release/pushmog")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--count", type=int, help="only the first COUNT runs")
    parser.add_argument("--out", help="write each run's summary here (JSON)")
    parser.add_argument("--paired-with", help="another --out file of the same runs to compare with")
    args = parser.parse_args()

    with open(args.log) as f:
        entries = [json.loads(line) for line in f][1:]
    runs = [e for e in entries if e["policy"] == args.policy][: args.count]
    if not runs:
        sys.exit(f"no runs of {args.policy} in {args.log}")
    with tempfile.TemporaryDirectory() as folder, ThreadPoolExecutor(args.jobs) as pool:
        done = list(pool.map(lambda e: replay(args.pushmog, folder, args.settings, e), runs))
    same = sum(d["trips"] == e["trips"] for d, e in zip(done, runs))
    print(f"{len(runs)} runs of {args.policy} replayed; {same} gave the log's trip count")

    print("\n| nearer plate's gap to the row | grasps | came down on a member |")
    print("|---|---:|---:|")
    everything = [g for d in done for g in d["grasps"]]
    low = 0
    for high in BANDS_MM:
        band = [g for g in everything if low <= g[0] * 1000 < high]
        landed = sum(g[1] for g in band)
        share = f"{100 * landed / len(band):.1f} %" if band else "-"
        print(f"| {low}-{high} mm | {len(band)} | {landed} ({share}) |")
        low = high
    for rider, name in ((True, "with a rider"), (False, "without a rider")):
        part = [g for g in everything if g[2] == rider]
        if part:
            print(f"{name}: {sum(g[1] for g in part)} of {len(part)} came down")

    total = {k: sum(d[k] for d in done) for k in ("trips", "carried", "riders_placed", "riders_lost")}
    cleared = sum(d["cleared"] for d in done)
    print(f"\nobjects per trip {total['carried'] / total['trips']:.3f}, cleared {cleared}/{len(done)}, "
          f"riders not carried {total['riders_lost']}/{total['riders_placed']}")
    if args.out:
        with open(args.out, "w") as f:
            json.dump(done, f)
    if args.paired_with:
        with open(args.paired_with) as f:
            other = json.load(f)
        ratio = [(d["carried"] / d["seconds"]) / (o["carried"] / o["seconds"])
                 for d, o in zip(done, other)]
        per_trip = [d["carried"] / d["trips"] - o["carried"] / o["trips"] for d, o in zip(done, other)]
        m, h = mean_interval(ratio)
        a, b = mean_interval(per_trip)
        print(f"paired with {args.paired_with}: picks per hour x{m:.4f} ± {h:.4f}, "
              f"objects per trip {a:+.4f} ± {b:.4f} a run")


if __name__ == "__main__":
    main()

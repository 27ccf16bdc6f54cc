#!/usr/bin/env python3
"""Fits and checks the calibration of the expected-time price (formulations/picks-per-hour.md).

Runs push-mog-opt under the objects-per-trip objective (so that every cluster the grasp judge
accepts after pushes is pushed) in the simulator with noise on generated scenes, and tabulates, by
the grasp judge's probability `judged` of each trip's first plan, how often the pushed row was
carried together (`carried_all`: by the trip itself, its last grasp taking two or more objects and
carrying at least that many; with `--ahead`, by the next trip, two or more objects with the whole
row among them) and how many rounds of corrective pushes the trip made.

    cargo build --release
    python3 experiments/calibration/push_success.py --first 5001 --count 100   # the fit
    python3 experiments/calibration/push_success.py --first 1 --count 100      # paper-100's scenes
    python3 experiments/calibration/push_success.py --ahead ...                # rows pushed ahead

Standard library only; the plans go to a temporary folder.
"""

import argparse
import json
import os
import subprocess
import sys
import tempfile
from concurrent.futures import ThreadPoolExecutor

# The judge the default calibration was fitted with (experiments/picks-per-hour.toml's push-mog-time).
JUDGE = {"multi": {"samples": 16, "noise": {"push_position": 0.004, "push_yaw": 0.05}}}


def run(pushmog, folder, seed, settings):
    scene = os.path.join(folder, f"scene-{seed}.json")
    plan = os.path.join(folder, f"plan-{seed}.json")
    subprocess.run([pushmog, "scene", "generate", "--objects", "34", "--seed", str(seed), "-o", scene],
                   check=True, stdout=subprocess.DEVNULL)
    subprocess.run([pushmog, "run", scene, "--policy", "push-mog-opt", "--executor", "sim", "--seed",
                    str(seed), "--settings", settings, "--plan", plan],
                   check=True, stdout=subprocess.DEVNULL)
    with open(plan) as f:
        return json.load(f)


def pushed_trips(plan):
    """(judged, carried all, corrective rounds) of each trip whose first plan pushed.

    Pushes for the trip's own grasp succeed when its last grasp took two or more objects and
    carried at least that many. Pushes ahead (the trip's `ahead` row) succeed when the next trip
    carried two or more objects, the whole row among them."""
    trips = plan["trips"]
    for k, trip in enumerate(trips):
        if trip.get("judged") is None:
            continue
        ahead = set(trip.get("ahead", []))
        if not ahead:
            looks = trip.get("looks", [])
            rounds = sum(1 for look in looks if look["after_pushes"] < len(trip["pushes"]))
            planned = len(trip["grasp"]["objects"])
            yield trip["judged"], planned >= 2 and len(trip["carried"]) >= planned, rounds
        else:
            after = set(trips[k + 1]["carried"]) if k + 1 < len(trips) else set()
            yield trip["judged"], len(after) >= 2 and ahead <= after, 0


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--first", type=int, default=5001, help="first scene seed")
    parser.add_argument("--count", type=int, default=100, help="scenes")
    parser.add_argument("--pushmog", default="target/release/pushmog", help="the command line")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--bands", default="0,0.999", help="lower edges of the judge bands")
    parser.add_argument("--ahead", action="store_true",
                        help="push clusters ahead (pricing.push_ahead) and fit `ahead_success`")
    args = parser.parse_args()
    bands = [float(b) for b in args.bands.split(",")]
    with tempfile.TemporaryDirectory() as folder:
        settings = os.path.join(folder, "settings.json")
        with open(settings, "w") as f:
            json.dump(dict(JUDGE, pricing={"push_ahead": args.ahead}), f)
        seeds = range(args.first, args.first + args.count)
        with ThreadPoolExecutor(args.jobs) as pool:
            plans = list(pool.map(lambda s: run(args.pushmog, folder, s, settings), seeds))
    rows = [row for plan in plans for row in pushed_trips(plan)]
    print(f"scenes {args.first}-{args.first + args.count - 1}: {len(rows)} pushed trips")
    print()
    print("| judged | trips | carried all | 95 % interval | corrective rounds per trip |")
    print("|---|---:|---:|---:|---:|")
    for k, low in enumerate(bands):
        high = bands[k + 1] if k + 1 < len(bands) else 1.0 + 1e-9
        band = [r for r in rows if low <= r[0] < high]
        if not band:
            continue
        n = len(band)
        q = sum(r[1] for r in band) / n
        half = 1.96 * (q * (1 - q) / n) ** 0.5
        rounds = sum(r[2] for r in band) / n
        label = f"≥ {low:g}" if k + 1 == len(bands) else f"[{low:g}, {high:g})"
        print(f"| {label} | {n} | {q:.3f} | ± {half:.3f} | {rounds:.3f} |")
    return 0


if __name__ == "__main__":
    sys.exit(main())

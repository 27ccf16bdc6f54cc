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

`--check` compares the outcomes with the fitted tables the command line carries as its defaults
(read from `pushmog schema policy`), or with those `--pricing` gives: each pushed cluster's predicted success is the band its
judged probability falls in (`Pricing::carried_all`), the clusters are grouped by decile of that
prediction, and each decile's observed success is set beside its mean prediction. `--figure` draws
that as a reliability diagram (SVG). `--objective expected_time` runs the priced policy itself
(push-mog-time with `--ahead`), so that the clusters checked are the ones it chose to push.

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
    """(judged, carried all, corrective rounds, ahead) of each trip whose first plan pushed, and of
    each row it pushed ahead.

    Pushes for the trip's own grasp succeed when its last grasp took two or more objects and
    carried at least that many. A row pushed ahead (the trip's `ahead` objects that one cluster of
    its clustering holds; a trip may push several) succeeds when the first later trip that grasps
    or pushes any of its objects grasps the whole row and carries it; pushed again first, it
    failed. Each row is counted with its own judged probability (`ahead_rows`)."""
    trips = plan["trips"]
    for k, trip in enumerate(trips):
        if trip.get("judged") is None:
            continue
        ahead = set(trip.get("ahead", []))
        if not ahead:
            looks = trip.get("looks", [])
            rounds = sum(1 for look in looks if look["after_pushes"] < len(trip["pushes"]))
            planned = len(trip["grasp"]["objects"])
            yield trip["judged"], planned >= 2 and len(trip["carried"]) >= planned, rounds, False
            continue
        # Each row with its own judged probability; plans written before rows were recorded give
        # the trip's clusters holding objects pushed ahead, each with the trip's `judged`.
        rows = [(set(r["objects"]), r["judged"]) for r in trip.get("ahead_rows", [])] or \
            [(set(c) & ahead, trip["judged"])
             for c in trip["clustering"]["clusters"] if set(c) & ahead]
        for row, judged in rows:
            outcome = False
            for later in trips[k + 1:]:
                grasped = set(later["grasp"]["objects"])
                if grasped & row:
                    outcome = row <= grasped and row <= set(later["carried"])
                    break
                if {p["object"] for p in later["pushes"]} & row:
                    break
            yield judged, outcome, 0, True


def fitted_bands(pushmog):
    """The default calibration tables: (in the trip, ahead), each [(judged, carried_all)]."""
    schema = json.loads(subprocess.run([pushmog, "schema", "policy"], check=True,
                                       capture_output=True, text=True).stdout)
    pricing = schema["properties"]["pricing"]["default"]
    return tuple([(b["judged"], b["carried_all"]) for b in pricing[key]]
                 for key in ("success", "ahead_success"))


def predicted(bands, judged):
    """The band's success for a judged probability: the highest band whose edge it reaches."""
    return [q for edge, q in bands if judged >= edge][-1]


def deciles(rows):
    """[(decile, n, mean prediction, observed, 95 % half-width)] of (prediction, success) rows."""
    out = []
    for d in range(10):
        group = [r for r in rows if min(int(r[0] * 10), 9) == d]
        if not group:
            continue
        n = len(group)
        mean = sum(r[0] for r in group) / n
        seen = sum(r[1] for r in group) / n
        out.append((d, n, mean, seen, 1.96 * (seen * (1 - seen) / n) ** 0.5))
    return out


def reliability_svg(table, title, enough, tolerance):
    """A reliability diagram: observed against predicted success per decile."""
    size, pad = 420, 56
    span = size - 2 * pad

    def x(v):
        return pad + v * span

    def y(v):
        return size - pad - v * span

    parts = [f'<svg xmlns="http://www.w3.org/2000/svg" width="{size}" height="{size}" '
             f'font-family="sans-serif" font-size="11">',
             f'<rect width="{size}" height="{size}" fill="white"/>',
             f'<text x="{size / 2}" y="20" text-anchor="middle" font-size="13">{title}</text>']
    band = " ".join(f"{x(v)},{y(min(1, v + tolerance))}" for v in (0, 1)) + " " + \
        " ".join(f"{x(v)},{y(max(0, v - tolerance))}" for v in (1, 0))
    parts.append(f'<polygon points="{band}" fill="#d8d8d8"/>')
    parts.append(f'<line x1="{x(0)}" y1="{y(0)}" x2="{x(1)}" y2="{y(1)}" stroke="black" '
                 f'stroke-dasharray="5,4"/>')
    parts.append(f'<rect x="{x(0)}" y="{y(1)}" width="{span}" height="{span}" fill="none" '
                 f'stroke="black"/>')
    for k in range(11):
        v = k / 10
        parts.append(f'<text x="{x(v)}" y="{y(0) + 16}" text-anchor="middle">{v:.1f}</text>')
        parts.append(f'<text x="{x(0) - 6}" y="{y(v) + 4}" text-anchor="end">{v:.1f}</text>')
    parts.append(f'<text x="{size / 2}" y="{size - 14}" text-anchor="middle">'
                 f'predicted success (decile mean)</text>')
    parts.append(f'<text x="16" y="{size / 2}" text-anchor="middle" '
                 f'transform="rotate(-90 16 {size / 2})">observed success (95 % interval)</text>')
    for _, n, mean, seen, half in table:
        colour = "#4e79a7" if n >= enough else "#aaaaaa"
        parts.append(f'<line x1="{x(mean)}" y1="{y(max(0, seen - half))}" x2="{x(mean)}" '
                     f'y2="{y(min(1, seen + half))}" stroke="{colour}" stroke-width="2"/>')
        parts.append(f'<circle cx="{x(mean)}" cy="{y(seen)}" r="4" fill="{colour}"/>')
        # Labels of points near the right edge go to their left, inside the frame.
        anchor, dx = ("end", -7) if mean > 0.85 else ("start", 7)
        parts.append(f'<text x="{x(mean) + dx}" y="{y(seen) - 6}" text-anchor="{anchor}" '
                     f'fill="{colour}">n={n}</text>')
    parts.append(f'<text x="{x(1) - 6}" y="{y(0) - 24}" text-anchor="end">grey band: within '
                 f'±{tolerance} of the prediction</text>')
    parts.append(f'<text x="{x(1) - 6}" y="{y(0) - 10}" text-anchor="end">grey points: fewer '
                 f'than {enough} clusters</text>')
    parts.append("</svg>")
    return "\n".join(parts) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--first", type=int, default=5001, help="first scene seed")
    parser.add_argument("--count", type=int, default=100, help="scenes")
    parser.add_argument("--pushmog", default="target/release/pushmog", help="the command line")
    parser.add_argument("--jobs", type=int, default=os.cpu_count() or 1)
    parser.add_argument("--bands", default="0,0.999", help="lower edges of the judge bands")
    parser.add_argument("--ahead", action="store_true",
                        help="push clusters ahead (pricing.push_ahead) and fit `ahead_success`")
    parser.add_argument("--objective", default="objects_per_trip",
                        choices=["objects_per_trip", "expected_time"],
                        help="pricing.objective of the runs (expected_time: the priced policy)")
    parser.add_argument("--settings", default=json.dumps(JUDGE),
                        help="the policy's other settings as JSON (default: the wide judge the "
                             "first fits used); `pricing` is added from the options here, e.g. "
                             "push-mog-time's flush pushes and default judge: "
                             "'{\"socp\": {\"flush\": true}}'")
    parser.add_argument("--pricing", default="{}",
                        help="more pricing settings as JSON, e.g. trial bands: "
                             "'{\"ahead_success\": [{\"judged\": 0, \"carried_all\": 0.7}]}'")
    parser.add_argument("--check", action="store_true",
                        help="compare with the default tables, by decile of predicted success")
    parser.add_argument("--figure", help="with --check, write the reliability diagram here (SVG)")
    parser.add_argument("--enough", type=int, default=30,
                        help="with --check, clusters a decile needs to be judged")
    parser.add_argument("--tolerance", type=float, default=0.05,
                        help="with --check, largest allowed |observed - predicted|")
    args = parser.parse_args()
    bands = [float(b) for b in args.bands.split(",")]
    with tempfile.TemporaryDirectory() as folder:
        settings = os.path.join(folder, "settings.json")
        with open(settings, "w") as f:
            pricing = dict(json.loads(args.pricing), push_ahead=args.ahead,
                           objective=args.objective)
            json.dump(dict(json.loads(args.settings), pricing=pricing), f)
        seeds = range(args.first, args.first + args.count)
        with ThreadPoolExecutor(args.jobs) as pool:
            plans = list(pool.map(lambda s: run(args.pushmog, folder, s, settings), seeds))
    rows = [row for plan in plans for row in pushed_trips(plan)]
    print(f"scenes {args.first}-{args.first + args.count - 1}: {len(rows)} pushed trips")
    print()
    print("| pushes | judged | trips | carried all | 95 % interval | corrective rounds per trip |")
    print("|---|---|---:|---:|---:|---:|")
    for kind, is_ahead in (("in the trip", False), ("ahead", True)):
        for k, low in enumerate(bands):
            high = bands[k + 1] if k + 1 < len(bands) else 1.0 + 1e-9
            band = [r for r in rows if low <= r[0] < high and r[3] == is_ahead]
            if not band:
                continue
            n = len(band)
            q = sum(r[1] for r in band) / n
            half = 1.96 * (q * (1 - q) / n) ** 0.5
            rounds = sum(r[2] for r in band) / n
            label = f"≥ {low:g}" if k + 1 == len(bands) else f"[{low:g}, {high:g})"
            print(f"| {kind} | {label} | {n} | {q:.3f} | ± {half:.3f} | {rounds:.3f} |")
    if args.check:
        in_trip, ahead = fitted_bands(args.pushmog)
        given = json.loads(args.pricing)
        in_trip = [(b["judged"], b["carried_all"]) for b in given.get("success", [])] or in_trip
        ahead = [(b["judged"], b["carried_all"]) for b in given.get("ahead_success", [])] or ahead
        rows = [(predicted(ahead if is_ahead else in_trip, p), ok) for p, ok, _, is_ahead in rows]
        table = deciles(rows)
        print()
        print("| predicted decile | clusters | mean predicted | observed | 95 % interval | "
              "|observed − predicted| | judged |")
        print("|---|---:|---:|---:|---:|---:|---|")
        failed = 0
        for d, n, mean, seen, half in table:
            gap = abs(seen - mean)
            verdict = "too few" if n < args.enough else (
                "within" if gap <= args.tolerance else "OUTSIDE")
            failed += verdict == "OUTSIDE"
            print(f"| [{d / 10:.1f}, {(d + 1) / 10:.1f}) | {n} | {mean:.3f} | {seen:.3f} | "
                  f"± {half:.3f} | {gap:.3f} | {verdict} |")
        if args.figure:
            title = (f"Push success, scenes {args.first}-{args.first + args.count - 1}, "
                     f"{'ahead' if args.ahead else 'in the trip'}")
            with open(args.figure, "w") as f:
                f.write(reliability_svg(table, title, args.enough, args.tolerance))
        return 1 if failed else 0
    return 0


if __name__ == "__main__":
    sys.exit(main())

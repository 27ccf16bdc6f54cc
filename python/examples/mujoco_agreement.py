#!/usr/bin/env python3
"""The MuJoCo check of the paper's validation section: ``mujoco_loop.py`` on several generated scenes
and policies, noise-free, with pushmog's rapier simulator on the same scenes beside it. Writes one
JSON file per run and the tables ``mujoco-agreement.md`` and ``mujoco-agreement.tex`` (``--name``
names them otherwise). With ``--noise``, both engines add pushmog's perception and actuation noise
(same seeds); the runs are ``<policy>-<seed>-noisy.json`` and the tables
``mujoco-agreement-noisy.*``. Riders (``push-mog-time-riders``) add a column of riders not carried
by their trip over riders placed.

    python python/examples/mujoco_agreement.py --seeds 1-10 --out paper/tables --runs experiments/results/mujoco
"""

from __future__ import annotations

import argparse
import json
import sys
from concurrent.futures import ProcessPoolExecutor
from pathlib import Path

sys.path.insert(0, str(Path(__file__).resolve().parent))

import mujoco  # noqa: E402

import mujoco_loop  # noqa: E402
import pushmog  # noqa: E402


def planner(name: str) -> pushmog.Planner:
    """The planner of a policy or of a named preset (``pushmog.PRESETS``: push-mog-time is
    push-mog-opt with ``experiments/push-mog-time.json``, push-mog-time-riders the same with riders
    on, as ``experiments/stacking.toml`` runs them)."""
    return pushmog.Planner(name)


def noisy(noise: bool) -> str:
    """The suffix of a noisy run's file and table names."""
    return "-noisy" if noise else ""


def one(task: tuple) -> dict:
    policy, seed, objects, runs, noise = task
    path = Path(runs) / f"{policy}-{seed}{noisy(noise)}.json"
    if path.exists():  # resumable: a finished run is read back
        return json.loads(path.read_text())
    scene = pushmog.generate_scene(objects, seed)
    result = mujoco_loop.both_engines(scene, planner(policy), seed, noise, lambda *_: None)
    result.update(policy=policy, seed=seed, objects=objects, noise=noise, mujoco=mujoco.__version__, pushmog=pushmog.__version__)
    path.write_text(json.dumps(result, indent=2) + "\n")
    print(f"{policy} seed {seed}: MuJoCo OpT {result['objects_per_trip']:.3f}, rapier {result['rapier']['objects_per_trip']:.3f}", flush=True)
    return result


def seeds(text: str) -> list:
    if "-" in text:
        first, last = text.split("-")
        return list(range(int(first), int(last) + 1))
    return [int(s) for s in text.split(",")]


def summary(results: list, engine: str) -> dict:
    rows = [r if engine == "mujoco" else r["rapier"] for r in results]
    multi = [v for r in rows for k, v in r["agreement"].items() if int(k) >= 2]
    single = [v for r in rows for k, v in r["agreement"].items() if int(k) == 1]
    return {
        "scenes": len(rows),
        "cleared": sum(r["status"] == "cleared" for r in rows),
        "opt": sum(r["objects_per_trip"] for r in rows) / len(rows),
        "multi": (sum(v[1] for v in multi), sum(v[0] for v in multi)),
        "single": (sum(v[1] for v in single), sum(v[0] for v in single)),
        "landed": sum(r["multi_misses"]["landed"] for r in rows),
        "lost": sum(r["multi_misses"]["lost in closing or lift"] for r in rows),
        "riders": (sum(r.get("riders_lost", 0) for r in rows), sum(r.get("riders_placed", 0) for r in rows)),
    }


def fraction(pair: tuple, tex: bool) -> str:
    held, n = pair
    percent = "\\,\\%" if tex else " %"
    return f"{held}/{n} ({100 * held / n:.0f}{percent})" if n else "0/0"


def tables(results: list, policies: list, first: int, last: int, noise: bool) -> tuple:
    # Riders only where some run placed one, so the tables of runs without riders stay as they were.
    riders = any(r.get("riders_placed") or r["rapier"].get("riders_placed") for r in results)
    head = ["policy", "engine", "scenes cleared", "objects per trip", "single-object as predicted", "multi-object as predicted", "misses: landed", "misses: lost in closing or lift"]
    head += ["riders not carried / placed"] if riders else []
    how = "with pushmog's perception and actuation noise" if noise else "noise-free"
    md = [f"MuJoCo {mujoco.__version__} and pushmog's rapier simulator, {how}, scenes of seeds {first}-{last}.", "", "| " + " | ".join(head) + " |", "|" + "---|" * len(head)]
    columns = "llrrrrrr" + ("r" if riders else "")
    tex = [f"\\begin{{tabular}}{{{columns}}}", "policy & engine & cleared & OpT & single & multi & landed & lost" + (" & riders lost" if riders else "") + " \\\\", "\\hline"]
    for policy in policies:
        runs = [r for r in results if r["policy"] == policy]
        for engine, label in (("mujoco", "MuJoCo"), ("rapier", "rapier")):
            s = summary(runs, engine)
            extra = [f"{s['riders'][0]}/{s['riders'][1]}" if s["riders"][1] else "–"] if riders else []
            cells = [policy, label, f"{s['cleared']}/{s['scenes']}", f"{s['opt']:.3f}", fraction(s["single"], False), fraction(s["multi"], False), str(s["landed"]), str(s["lost"]), *extra]
            md.append("| " + " | ".join(cells) + " |")
            texcells = [policy, label, f"{s['cleared']}/{s['scenes']}", f"{s['opt']:.3f}", fraction(s["single"], True), fraction(s["multi"], True), str(s["landed"]), str(s["lost"]), *(e.replace("–", "--") for e in extra)]
            tex.append(" & ".join(texcells) + " \\\\")
    tex.append("\\end{tabular}")
    return "\n".join(md) + "\n", "\n".join(tex) + "\n"


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--seeds", default="1-10")
    parser.add_argument("--objects", type=int, default=34)
    parser.add_argument("--policies", nargs="+", default=["push-mog", "push-mog-opt"], choices=[*pushmog.POLICIES, *pushmog.PRESETS])
    parser.add_argument("--out", default="paper/tables")
    parser.add_argument("--runs", default="experiments/results/mujoco")
    parser.add_argument("--jobs", type=int, default=2)
    parser.add_argument("--noise", action="store_true", help="perception and actuation noise as pushmog's simulator, in both engines")
    parser.add_argument("--name", default="mujoco-agreement", help="the tables' file name, before -noisy and the extension")
    args = parser.parse_args()
    Path(args.runs).mkdir(parents=True, exist_ok=True)
    chosen = seeds(args.seeds)
    tasks = [(p, s, args.objects, args.runs, args.noise) for p in args.policies for s in chosen]
    with ProcessPoolExecutor(max_workers=args.jobs) as pool:
        results = list(pool.map(one, tasks))
    md, tex = tables(results, args.policies, chosen[0], chosen[-1], args.noise)
    name = f"{args.name}{noisy(args.noise)}"
    Path(args.out, f"{name}.md").write_text(md)
    Path(args.out, f"{name}.tex").write_text(tex)
    print(md)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Rows with a rider carried out in MuJoCo: the second engine's side of
``cargo run --release --example rows_with_riders``.

Each entry of ``experiments/data/rows-with-riders.json`` holds a scene (a row's members as they stood
once pushmog's simulator had closed the jaws on them, and the rider on the table beside them), the
rider's place action and the row's grasp. Here MuJoCo, set up as in ``mujoco_loop.py``, puts the rider
down on the row and grasps, lifts and carries the row sideways, several times per row with the
simulator's actuation noise; the table printed counts the runs that carried the rider and the whole
row (``formulations/stacking.md``, "Rows turning in the jaws").

    python python/examples/mujoco_rows.py [--file F] [--runs 3] [--noslip 20]

``--noslip 0`` turns MuJoCo's no-slip passes off, leaving its soft contacts alone.
"""

from __future__ import annotations

import argparse
import json
import sys
from pathlib import Path

import numpy as np

import mujoco_loop

import pushmog

DEFAULT_FILE = Path(__file__).resolve().parents[2] / "experiments" / "data" / "rows-with-riders.json"


def run(entry: dict, sim: dict, seed: int) -> tuple:
    """One run of a row: (rider carried, row carried whole, a pad came down on an object)."""
    rng = np.random.default_rng(seed)
    world = mujoco_loop.World(pushmog.Scene.from_dict(entry["scene"]), sim)
    if world.place(entry["rider"], mujoco_loop.actuation(sim, rng)):
        return False, False, True
    grasp = pushmog.Grasp.from_dict(entry["grasp"])
    carried, landed = world.grasp(grasp, mujoco_loop.actuation(sim, rng))
    row = entry["grasp"]["objects"]
    return entry["rider"]["object"] in carried, all(i in carried for i in row), landed


def main(argv: list | None = None) -> int:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--file", type=Path, default=DEFAULT_FILE, help="rows file (default: %(default)s)")
    parser.add_argument("--runs", type=int, default=3, help="runs per row (default: %(default)s)")
    parser.add_argument("--noslip", type=int, default=mujoco_loop.NOSLIP, help="MuJoCo no-slip passes (default: %(default)s)")
    args = parser.parse_args(argv)
    if args.runs < 1:
        parser.error("--runs must be at least 1")
    try:
        entries = json.loads(args.file.read_text())
    except (OSError, json.JSONDecodeError) as error:
        print(f"{args.file}: {error}", file=sys.stderr)
        return 2
    mujoco_loop.NOSLIP = args.noslip
    sim = pushmog.default_settings("sim")
    print(f"MuJoCo {mujoco_loop.mujoco.__version__}, noslip passes {args.noslip}, {args.runs} runs per row\n")
    print("| row | scene seed | turn logged in rapier, ° | rider carried | row carried whole | landed |")
    print("|---:|---:|---:|---:|---:|---:|")
    totals = np.zeros(4, dtype=int)
    for index, entry in enumerate(entries):
        tally = np.zeros(4, dtype=int)
        for seed in range(1, args.runs + 1):
            rider, row, landed = run(entry, sim, seed)
            tally += [1, rider, row, landed]
        totals += tally
        source = entry["source"]
        print(
            f"| {index} | {source['scene_seed']} | {source['rapier_turn_degrees']:.1f} | "
            f"{tally[1]}/{tally[0]} | {tally[2]}/{tally[0]} | {tally[3]} |",
            flush=True,
        )
    print(f"\nAll rows: rider carried {totals[1]}/{totals[0]}, row carried whole {totals[2]}/{totals[0]}, landed {totals[3]}")
    return 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/env python3
"""What planning a trip through Python costs beyond the Rust call.

Plans one trip of the 34-object scene of seed 1 (the scene of ``cargo bench --bench planners``'s
``plan_trip/<policy>/34``) many times and reports, per call: the wall time of
``Planner.plan_trip`` as Python sees it, the time Rust spent planning inside it (``TripPlan.seconds``,
measured around ``Policy::plan_trip``), and the difference, which is the binding's cost (turning the
answer into JSON and back, the wrappers, the GIL). Compare the first column with the Rust benchmark.
A planner remembers closings it has judged, so each call gets a fresh one (made outside the timing).

    python python/benches/plan_trip.py [--calls 200]
"""

import argparse
import statistics
import time

import pushmog


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--calls", type=int, default=200)
    args = parser.parse_args()
    scene = pushmog.generate_scene(34, seed=1)
    print(f"{'policy':<14} {'python ms':>10} {'rust ms':>10} {'binding ms':>11} {'overhead':>9}   (medians of {args.calls} calls)")
    for policy in ("push-mog", "push-mog-opt"):
        pushmog.Planner(policy).plan_trip(scene)  # warm up
        outer, inner = [], []
        for _ in range(args.calls):
            planner = pushmog.Planner(policy)
            started = time.perf_counter()
            trip = planner.plan_trip(scene)
            outer.append(time.perf_counter() - started)
            inner.append(trip.seconds)
        python_ms = 1e3 * statistics.median(outer)
        rust_ms = 1e3 * statistics.median(inner)
        binding = [1e3 * (o - i) for o, i in zip(outer, inner)]
        binding_ms = statistics.median(binding)
        print(f"{policy:<14} {python_ms:>10.3f} {rust_ms:>10.3f} {binding_ms:>11.3f} {100 * binding_ms / rust_ms:>8.1f}%")


if __name__ == "__main__":
    main()

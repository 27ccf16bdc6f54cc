#!/usr/bin/env python3
"""Writes ``rounded-corners.json``: the built-in library's 34 outlines with every corner replaced by
an arc of radius 3 mm traced by 5 edges (18 to 24 vertices), the way a contour from a camera traces
a real object's rounded corners. Arcs are tangent to both edges of a corner and lie inside the
original outline; where an edge is too short for two arcs, the arc shrinks to fit.

    cargo run --release -- library --json -o /tmp/library.json
    python3 experiments/rounded_corners.py /tmp/library.json experiments/rounded-corners.json
"""

import json
import math
import sys

RADIUS = 0.003
SEGMENTS = 5


def rounded(vertices: list) -> list:
    n = len(vertices)
    area = sum(vertices[i][0] * vertices[(i + 1) % n][1] - vertices[(i + 1) % n][0] * vertices[i][1] for i in range(n))
    if area < 0:
        vertices = vertices[::-1]
    out = []
    for i, corner in enumerate(vertices):
        before, after = vertices[i - 1], vertices[(i + 1) % n]
        to_before = (before[0] - corner[0], before[1] - corner[1])
        to_after = (after[0] - corner[0], after[1] - corner[1])
        la, lb = math.hypot(*to_before), math.hypot(*to_after)
        ua = (to_before[0] / la, to_before[1] / la)
        ub = (to_after[0] / lb, to_after[1] / lb)
        angle = math.acos(max(-1.0, min(1.0, ua[0] * ub[0] + ua[1] * ub[1])))
        # Distance from the corner to the arc's tangent points, at most 40 % of either edge.
        tangent = min(RADIUS / math.tan(angle / 2), 0.4 * la, 0.4 * lb)
        radius = tangent * math.tan(angle / 2)
        bisector = (ua[0] + ub[0], ua[1] + ub[1])
        length = math.hypot(*bisector)
        bisector = (bisector[0] / length, bisector[1] / length)
        reach = radius / math.sin(angle / 2)
        centre = (corner[0] + bisector[0] * reach, corner[1] + bisector[1] * reach)
        start = math.atan2(corner[1] + ua[1] * tangent - centre[1], corner[0] + ua[0] * tangent - centre[0])
        end = math.atan2(corner[1] + ub[1] * tangent - centre[1], corner[0] + ub[0] * tangent - centre[0])
        sweep = (end - start + math.pi) % (2 * math.pi) - math.pi
        for k in range(SEGMENTS + 1):
            theta = start + sweep * k / SEGMENTS
            out.append([round(centre[0] + radius * math.cos(theta), 9), round(centre[1] + radius * math.sin(theta), 9)])
    return out


def main() -> None:
    library = json.load(open(sys.argv[1]))
    objects = [dict(o, name=o["name"] + "-rounded", vertices=rounded(o["vertices"])) for o in library["objects"]]
    json.dump({"name": "rounded-corners", "objects": objects}, open(sys.argv[2], "w"), indent=1)


if __name__ == "__main__":
    main()

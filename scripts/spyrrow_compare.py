#!/usr/bin/env python3
"""Strip-packing reference: pack the same stadium strips with sparrow (PyPI `spyrrow`).

Input: a JSON file (or - for stdin)
  {"strip_height": 400.0,          # fixed sheet height in mm (the roll width)
   "width": 10.0,                   # strip width w in mm
   "gap": 0.2,                      # required gap between parts in mm
   "lengths": [120.0, 80.5, ...]}   # tip-to-tip length of every strip in mm

Output: one JSON line
  {"tool": "spyrrow", "seconds": budget, "strip_length": mm, "density": fraction,
   "area_bound": mm, "wall_s": measured}
where area_bound is the rigorous lower bound on the strip length for any layout
(docs/fabrication.md, Nesting). Compare with your own packer on the same input: the ratio of the
strip lengths, and the ratio of the wall times, measured in one run.

Usage: spyrrow_compare.py INSTANCE.json [--seconds 30] [--seed 1] [--rotations 0,90|free]
Needs: pip install spyrrow
"""
import argparse
import json
import math
import sys
import time


def stadium(length, w, segments=16):
    """Outer boundary of a stadium (rectangle with semicircular ends), axis along x,
    as a polygon circumscribing the true arcs (so the polygon contains the part)."""
    r = w / 2.0
    half = length / 2.0 - r
    scale = 1.0 / math.cos(math.pi / (2 * segments))  # circumscribe
    pts = []
    for k in range(segments + 1):  # right cap, -90 deg .. +90 deg
        a = -math.pi / 2 + math.pi * k / segments
        rr = r if k in (0, segments) else r * scale
        pts.append((half + rr * math.cos(a), rr * math.sin(a)))
    for k in range(segments + 1):  # left cap, +90 deg .. 270 deg
        a = math.pi / 2 + math.pi * k / segments
        rr = r if k in (0, segments) else r * scale
        pts.append((-half + rr * math.cos(a), rr * math.sin(a)))
    return pts


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument("instance")
    ap.add_argument("--seconds", type=int, default=30)
    ap.add_argument("--seed", type=int, default=1)
    ap.add_argument("--rotations", default="0,90", help="comma list of degrees, or 'free'")
    a = ap.parse_args()
    import spyrrow

    src = sys.stdin if a.instance == "-" else open(a.instance)
    inst = json.load(src)
    w, g, H = float(inst["width"]), float(inst.get("gap", 0.0)), float(inst["strip_height"])
    lengths = [float(x) for x in inst["lengths"]]
    rot = None if a.rotations == "free" else [float(x) for x in a.rotations.split(",")]
    counts = {}
    for L in lengths:
        key = round(L, 6)
        counts[key] = counts.get(key, 0) + 1
    items = [spyrrow.Item(f"s{i}", stadium(L, w), demand=n, allowed_orientations=rot)
             for i, (L, n) in enumerate(sorted(counts.items()))]
    problem = spyrrow.StripPackingInstance("karigami", strip_height=H, items=items)
    cfg = spyrrow.StripPackingConfig(total_computation_time=a.seconds,
                                     min_items_separation=g if g > 0 else None, seed=a.seed)
    t0 = time.perf_counter()
    sol = problem.solve(cfg)
    wall = time.perf_counter() - t0
    a_g = sum((w + g) * (L - w) + math.pi * (w + g) ** 2 / 4 for L in lengths)
    print(json.dumps({"tool": "spyrrow", "seconds": a.seconds, "strip_length": sol.width,
                      "density": sol.density, "area_bound": a_g / (H + g) - g, "wall_s": round(wall, 3),
                      "parts": len(lengths)}))


if __name__ == "__main__":
    main()

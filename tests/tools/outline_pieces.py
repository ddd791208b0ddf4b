#!/usr/bin/env python3
"""Read the strip outlines back from a cut sheet with third-party readers:
svgelements for SVG (per <g> group, <use> expanded: how many outline paths and their length),
ezdxf for DXF (the outlines layer, blocks expanded: how many polylines, how
many closed, and their total length). Prints one JSON object; lengths in mm."""
import json
import math
import sys

path = sys.argv[1]
if path.endswith(".svg"):
    from svgelements import SVG, Group, Path

    svg = SVG.parse(path, ppi=96)
    mm = 25.4 / 96
    groups = {}
    for g in svg.elements(conditional=lambda e: isinstance(e, Group)):
        gid = g.values.get("id")
        if not gid:
            continue
        # select() walks the group's descendants, through <use> into the drawing it places.
        paths = [e for e in g.select() if isinstance(e, Path) and e.values.get("class") == "outlines"]
        if paths:
            groups[gid] = [len(paths), sum(p.length(error=1e-10) for p in paths) * mm]
    print(json.dumps({"groups": groups}))
else:
    import ezdxf
    from ezdxf import path as dxfpath
    from ezdxf.disassemble import recursive_decompose

    doc = ezdxf.readfile(path)
    count = closed = 0
    total = 0.0
    for e in recursive_decompose(doc.modelspace()):
        if e.dxftype() != "LWPOLYLINE" or e.dxf.layer != "outlines":
            continue
        count += 1
        closed += 1 if e.closed else 0
        pts = list(dxfpath.make_path(e).flattening(distance=1e-5))
        total += sum(math.dist(a, b) for a, b in zip(pts, pts[1:]))
    print(json.dumps({"count": count, "closed": closed, "length": total}))

#!/usr/bin/env python3
"""Read a cutting plotter's SVG sheet with svgelements (a third-party SVG
reader) and print one JSON line: the document size in mm and, for each
top-level group (by id), its circles, its paths, the stroke colours used
and the ids of the groups inside it. Design Space and Silhouette Studio
take a group or a colour as one operation, so the cut and draw layers must
be told apart this way."""
import json
import sys

from svgelements import SVG, Circle, Group, Path, Shape

svg = SVG.parse(sys.argv[1], ppi=96)
mm = 25.4 / 96


def walk(group, out):
    for e in group:
        if isinstance(e, Group):
            out["groups"].append(e.id)
            walk(e, out)
        elif isinstance(e, Shape):
            kind = "circles" if isinstance(e, Circle) else "paths" if isinstance(e, Path) else "other"
            out[kind] += 1
            out["strokes"].add(str(e.stroke).lower())


top = {}
for e in svg:
    if isinstance(e, Group):
        out = {"circles": 0, "paths": 0, "other": 0, "strokes": set(), "groups": []}
        walk(e, out)
        out["strokes"] = sorted(out["strokes"])
        top[e.id] = out
    elif isinstance(e, Shape):
        top.setdefault("(loose)", {"circles": 0, "paths": 0, "other": 0, "strokes": [], "groups": []})["other"] += 1
print(json.dumps({"width_mm": svg.width * mm, "height_mm": svg.height * mm, "top": top,
                  "order": [e.id for e in svg if isinstance(e, Group)]}))

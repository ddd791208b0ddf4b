#!/usr/bin/env python3
"""Measure an SVG cut sheet with svgelements (a third-party SVG reader).
Prints one JSON line: the document size in mm, the diameter of every
circle in mm (svgelements works in px at 96 ppi, so mm = px * 25.4 / 96) and
every circle's centre and radius in user units (mm). svgelements expands <use>: a strip
placed by reference counts where it is placed."""
import json
import sys

from svgelements import SVG, Circle

svg = SVG.parse(sys.argv[1], ppi=96)
mm = 25.4 / 96
circles = [c for c in svg.elements() if isinstance(c, Circle)]
# Centres in user units (mm by the viewBox), free of svgelements' rounded
# px-per-mm constant (its 3000 mm sheet reads 3000.0016 mm wide).
user = svg.viewbox.width / svg.width
holes = sorted([round(x * user, 6) for x in ((b[0] + b[2]) / 2, (b[1] + b[3]) / 2, (b[2] - b[0]) / 2)]
               for b in (c.bbox() for c in circles))
diameters = sorted({round((c.bbox()[2] - c.bbox()[0]) * mm, 6) for c in svg.elements() if isinstance(c, Circle)})
print(json.dumps({"width_mm": svg.width * mm, "height_mm": svg.height * mm, "hole_diameters_mm": diameters,
                  "holes": holes}))

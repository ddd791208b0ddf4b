#!/usr/bin/env python3
"""Measure an SVG cut sheet with svgelements (a third-party SVG reader).
Prints one JSON line: the document size in mm and the diameter of every
circle in mm (svgelements works in px at 96 ppi, so mm = px * 25.4 / 96)."""
import json
import sys

from svgelements import SVG, Circle

svg = SVG.parse(sys.argv[1], ppi=96)
mm = 25.4 / 96
diameters = sorted({round((c.bbox()[2] - c.bbox()[0]) * mm, 6) for c in svg.elements() if isinstance(c, Circle)})
print(json.dumps({"width_mm": svg.width * mm, "height_mm": svg.height * mm, "hole_diameters_mm": diameters}))

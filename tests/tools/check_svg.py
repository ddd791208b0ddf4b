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
# svgelements carries each circle's placement (its <use> and group
# transforms) into its implicit centre and radii. They equal the centre and
# half-extent of its bounding box to 1e-12 px, at a hundredth of the cost
# (bbox() traces the arc: 11 s for a 30 x 30-cell sheet's 5,405 holes).
circles = [(c.implicit_center, c.implicit_rx, c.implicit_ry)
           for c in svg.elements() if isinstance(c, Circle)]
# An ellipse is not a hole: its radii would differ.
assert all(abs(rx - ry) < 1e-9 * max(1.0, rx) for _, rx, ry in circles), "an elliptic hole"
# Centres in user units (mm by the viewBox), free of svgelements' rounded
# px-per-mm constant (its 3000 mm sheet reads 3000.0016 mm wide).
user = svg.viewbox.width / svg.width
holes = sorted([round(v * user, 6) for v in (c[0], c[1], rx)] for c, rx, _ in circles)
diameters = sorted({round(2 * rx * mm, 6) for _, rx, _ in circles})
print(json.dumps({"width_mm": svg.width * mm, "height_mm": svg.height * mm, "hole_diameters_mm": diameters,
                  "holes": holes}))

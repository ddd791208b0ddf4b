#!/usr/bin/env python3
"""Audit a DXF cut sheet with ezdxf and report what it reads.
Prints one JSON line: audit errors, units, layers of the entities, circle
radii, every circle's centre and radius, and the model-space extents. Blocks are expanded: an INSERT counts as
the entities of its block, where the insert places them."""
import json
import sys

import ezdxf
from ezdxf import bbox
from ezdxf.disassemble import recursive_decompose

doc = ezdxf.readfile(sys.argv[1])
auditor = doc.audit()
msp = doc.modelspace()
ext = bbox.extents(msp)
flat = list(recursive_decompose(msp))
print(json.dumps({
    "errors": len(auditor.errors),
    "version": doc.dxfversion,
    "units": doc.units,
    "entity_layers": sorted({f"{e.dxftype()}:{e.dxf.layer}" for e in flat}),
    "inserts": sum(1 for e in msp if e.dxftype() == "INSERT"),
    "radii": sorted({round(e.dxf.radius, 6) for e in flat if e.dxftype() == "CIRCLE"}),
    "holes": sorted([round(e.dxf.center.x, 6), round(e.dxf.center.y, 6), round(e.dxf.radius, 6)]
                    for e in flat if e.dxftype() == "CIRCLE"),
    "extmin": list(ext.extmin)[:2],
    "extmax": list(ext.extmax)[:2],
}))

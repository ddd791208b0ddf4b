#!/usr/bin/env python3
"""Audit a DXF cut sheet with ezdxf and report what it reads.
Prints one JSON line: audit errors, units, layers of the entities, circle
radii, and the model-space extents."""
import json
import sys

import ezdxf
from ezdxf import bbox

doc = ezdxf.readfile(sys.argv[1])
auditor = doc.audit()
msp = doc.modelspace()
ext = bbox.extents(msp)
print(json.dumps({
    "errors": len(auditor.errors),
    "version": doc.dxfversion,
    "units": doc.units,
    "entity_layers": sorted({f"{e.dxftype()}:{e.dxf.layer}" for e in msp}),
    "radii": sorted({round(e.dxf.radius, 6) for e in msp if e.dxftype() == "CIRCLE"}),
    "extmin": list(ext.extmin)[:2],
    "extmax": list(ext.extmax)[:2],
}))

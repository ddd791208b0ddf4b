"""Read a LightBurn project with MeerK40t's own .lbrn2 loader (meerk40t on
PyPI) and print what it sees as JSON: each operation's label, speed and
power, and every ellipse's centre and radii in mm (groups included).

The loader fills MeerK40t's element tree; a few lines of stand-in tree
(add, add_reference) take its place, so no MeerK40t kernel is started.
Usage: python3 lbrn_meerk40t.py FILE"""
import json
import sys
import threading

from meerk40t.core.units import UNITS_PER_MM
from meerk40t.extra.lbrn import LbrnLoader


class Node:
    def __init__(self, **kw):
        self.__dict__.update(kw)
        self.children = []

    def add(self, **kw):
        node = Node(**kw)
        self.children.append(node)
        return node

    def add_reference(self, node):
        self.children.append(node)

    def remove_all_children(self):
        self.children = []

    def focus(self):
        pass


class Elements:
    def __init__(self):
        self.op_branch = Node()
        self.elem_branch = Node()
        self.node_lock = threading.Lock()


def nodes(node):
    for c in node.children:
        yield c
        yield from nodes(c)


elements = Elements()
with open(sys.argv[1]) as source:
    LbrnLoader.parse(sys.argv[1], source, elements)
ops = [
    {"type": op.type, "label": op.label, "speed": op.speed, "power": op.power / 10.0,
     "shapes": len(op.children)}
    for op in elements.op_branch.children
]
ellipses = []
for n in nodes(elements.elem_branch):
    if getattr(n, "type", None) == "elem ellipse":
        m = n.matrix
        ellipses.append({"x": m.e / UNITS_PER_MM, "y": m.f / UNITS_PER_MM,
                         "rx": n.rx * m.a / UNITS_PER_MM, "ry": n.ry * m.d / UNITS_PER_MM})
print(json.dumps({"ops": ops, "ellipses": ellipses}))

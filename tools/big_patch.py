#!/usr/bin/env python3
"""A big patch for measuring the editor: CHAINS chains of LFO -> Sin ->
Multiply -> Probe (4 nodes each), ten chains to a row of the grid.

    python3 tools/big_patch.py 250 /tmp/big-1000.ron    # 1,000 nodes
    spreadlight edit /tmp/big-1000.ron --measure-frames 300
"""
import sys

chains, out = int(sys.argv[1]), sys.argv[2]
nodes, links = [], []
for c in range(chains):
    base = c * 4 + 1
    x, y = (c % 10) * 480.0, (c // 10) * 50.0
    for k, ty in enumerate(["LFO", "Sin (Value)", "Multiply (Value)", "Probe"]):
        values = ""
        if ty == "LFO":
            values = '            values: {\n                "Period": Float([%r]),\n            },\n' % (1.0 + c % 7)
        if ty == "Probe":
            values = '            values: {\n                "Name": String(["p%d"]),\n            },\n' % c
        nodes.append('        (\n            id: %d,\n            type: "%s",\n            pos: (%r, %r),\n%s        ),' % (base + k, ty, x + k * 110.0, y, values))
    for a, o, b, i in [(0, "Output", 1, "Input"), (1, "Output", 2, "Input 1"), (2, "Output", 3, "Input")]:
        links.append('        (\n            from: (%d, "%s"),\n            to: (%d, "%s"),\n        ),' % (base + a, o, base + b, i))
with open(out, "w") as f:
    f.write("(\n    version: 1,\n    nodes: [\n%s\n    ],\n    links: [\n%s\n    ],\n)\n" % ("\n".join(nodes), "\n".join(links)))

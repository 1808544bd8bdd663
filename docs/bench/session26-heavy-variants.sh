#!/usr/bin/env bash
# Session 26: heavy frames arranged otherwise than patches/emeshe-heavy.ron, as
# a user might write them (docs/benchmarks.md, "Session 26 on the H200").
# Usage: docs/bench/session26-heavy-variants.sh OLD_BINARY NEW_BINARY > lines.jsonl
# Run from the repository root on the machine that measures (the H200 host).
set -u
old=$1; new=$2
dir=$(mktemp -d)
# Two patches made from shipped ones: emeshe-heavy with point-light shadows for
# the first 8 of its 2,000 lights (cube maps at 256), and bench-gltf's 1,000
# glTF meshes under a 4-cascade sun.
python3 - "$dir" <<'PY'
import sys
out = sys.argv[1]
s = open('patches/emeshe-heavy.ron').read()
i = s.index('            id: 13,\n'); j = s.index('values: {', i) + 9
slices = ', '.join([str(k) for k in range(8)] + ['-1'] * 1992)
s = s[:j] + '\n                "Shadow Slice": Int([%s]),' % slices + s[j:]
node = '''        (\n            id: 60,\n            type: "ShadowMap (Point)",\n            pos: (528.0, 400.0),\n            values: {\n                "Resolution": Int([256]),\n            },\n        ),\n    ],\n    links: ['''
s = s.replace('    ],\n    links: [', node, 1)
links = ''.join('        (\n            from: (%d, "%s"),\n            to: (%d, "%s"),\n        ),\n' % l for l in
                [(8, 'Layer', 60, 'Layer'), (11, 'G-Buffer', 60, 'G-Buffer'), (13, 'Lights', 60, 'Lights'), (60, 'Shadows', 14, 'Shadows')])
s = s.replace('    links: [\n', '    links: [\n' + links, 1)
open(out + '/heavy-point.ron', 'w').write(s)
g = open('patches/bench-gltf.ron').read()
i = g.index('            id: 6,\n'); j = g.index('values: {', i) + 9
g = g[:j] + '\n                "Shadow Slice": Int([0]),' + g[j:]
node = '''        (\n            id: 20,\n            type: "ShadowMap (Sun)",\n            pos: (343.0, 300.0),\n            values: {\n                "Cascades": Int([4]),\n                "Distance": Float([60.0]),\n            },\n        ),\n    ],\n    links: ['''
g = g.replace('    ],\n    links: [', node, 1)
links = ''.join('        (\n            from: (%d, "%s"),\n            to: (%d, "%s"),\n        ),\n' % l for l in
                [(3, 'Layer', 20, 'Layer'), (5, 'G-Buffer', 20, 'G-Buffer'), (6, 'Lights', 20, 'Lights'), (20, 'Shadows', 8, 'Shadows')])
g = g.replace('    links: [\n', '    links: [\n' + links, 1)
g = g.replace('"assets/bench-gltf-textured.gltf"', '"%s/patches/assets/bench-gltf-textured.gltf"' % __import__('os').getcwd())
open(out + '/gltf-sun.ron', 'w').write(g)
# emeshe-heavy with its camera panning in the patch (an LFO over 40 s moves the
# camera and its target 20 units across) and its ball still: the sun's
# cascades scroll (`--orbit` reloads the patch each frame, so every layer is
# new and every map drawn whole; a camera animated in the patch is not).
p = open('patches/emeshe-heavy.ron').read()
def node(i, kind, values):
    body = ''.join('\n                "%s": %s,' % kv for kv in values)
    return ('        (\n            id: %d,\n            type: "%s",\n            pos: (0.0, 0.0),\n'
            '            values: {%s\n            },\n        ),\n' % (i, kind, body))
nodes = (node(70, 'LFO', [('Period', 'Float([40.0])')]) + node(71, 'Multiply (Value)', [('Input 2', 'Float([20.0])')])
         + node(72, 'Vector (3d Join)', [('Y', 'Float([12.0])'), ('Z', 'Float([30.0])')]) + node(73, 'Vector (3d Join)', []))
p = p.replace('    ],\n    links: [', nodes + '    ],\n    links: [', 1)
links = ''.join('        (\n            from: (%d, "%s"),\n            to: (%d, "%s"),\n        ),\n' % l for l in
                [(70, 'Output', 71, 'Input 1'), (71, 'Output', 72, 'X'), (72, 'Output', 9, 'Position'),
                 (71, 'Output', 73, 'X'), (73, 'Output', 9, 'Target')])
p = p.replace('    links: [\n', '    links: [\n' + links, 1)
p = p.replace('        (\n            from: (40, "Output"),\n            to: (41, "X"),\n        ),\n', '', 1)
open(out + '/heavy-pan.ron', 'w').write(p)
PY
H=patches/emeshe-heavy.ron
O="9.Position=0.01"   # the camera orbits: 0.01 radians a frame
run() { b=$1; c=$2; shift 2; line=$("$b" bench "$@" --json 2>/dev/null | tail -1)
  echo "{\"build\":\"$b\",\"case\":\"$c\",\"bench\":${line:-null}}"; }
for r in 1 2; do for b in "$old" "$new"; do
  run "$b" heavy-frame $H --timing frame
  run "$b" orbit-frame $H --orbit $O --timing frame
  run "$b" orbit-tess64-frame $H --orbit $O --set 1.Sectors=64 --set 1.Stacks=32 --timing frame
  run "$b" heavy2048-frame $H --set 21.Resolution=2048 --timing frame
  run "$b" orbit2048-frame $H --orbit $O --set 21.Resolution=2048 --timing frame
  run "$b" heavy-point-frame "$dir/heavy-point.ron" --timing frame
  run "$b" gltf-frame patches/bench-gltf.ron --timing frame
  run "$b" gltf-sun-frame "$dir/gltf-sun.ron" --timing frame
  run "$b" pan-frame "$dir/heavy-pan.ron" --timing frame
  run "$b" pan2048-frame "$dir/heavy-pan.ron" --set 21.Resolution=2048 --timing frame
done; done

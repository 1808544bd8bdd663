#!/usr/bin/env bash
# Issue 34: lit transparency's lights drawn forward against shaded in
# compute, each pixel alone (Compute) or tiles sharing lights (Tiled)
# (docs/benchmarks.md, "Session 18: lit transparency shaded in
# compute"; docs/post.md, "Shading: Forward or Compute").
#
#   docs/bench/transparency-compute.sh [BIN] [OUT.jsonl]
#
# BIN: a release build of this tree's `spreadlight` (default
# target/release/spreadlight); OUT: where the JSON lines go (default
# /tmp/transparency-compute.jsonl). One H200 call, from the repository root:
#   cargo build --workspace --release --locked --bin spreadlight && \
#     docs/bench/transparency-compute.sh target/release/spreadlight "$OUT/transparency-compute.jsonl"
#
# patches/bench-transparency.ron at 1920x1080 (node 12: the lights' Count;
# node 21: the Transparency, its Shading pin), 1,000 / 10,000 / 100,000
# lights, Forward, Compute and Tiled interleaved, two rounds (the order
# turns from round to round, so a drift in clocks or load does not always
# favour one). One JSON line per run: the round, the lights, the
# shading, `Transparency #21: accumulate` and `resolve` in GPU ms (medians),
# the frame's GPU ms, and bench's whole line. Then a table of the accumulate
# pass, round 1 / round 2. 100,000 lights forward took 441 ms a frame in session 17: that count
# runs 3 warm-up and 10 timed frames, the others 20 and 50 (WARMUP and
# FRAMES override both; SIZE the image, for a smoke run on lavapipe).
set -euo pipefail

bin=$(realpath "${1:-target/release/spreadlight}")
out=${2:-/tmp/transparency-compute.jsonl}
size=${SIZE:-1920x1080}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}

: >"$out"
for round in 1 2; do
    if ((round % 2)); then order="Forward Compute Tiled"; else order="Tiled Compute Forward"; fi
    for lights in 1000 10000 100000; do
        frames=(--warmup "${WARMUP:-20}" --frames "${FRAMES:-50}")
        ((lights >= 100000)) && frames=(--warmup "${WARMUP:-3}" --frames "${FRAMES:-10}")
        for shading in $order; do
            json=$("$bin" bench patches/bench-transparency.ron --size "$size" "${frames[@]}" \
                --set 12.Count=$lights --set 21.Shading=$shading --json 2>/dev/null | tail -n 1) || json=null
            [[ -n $json ]] || json=null
            python3 - "$round" "$lights" "$shading" "$json" <<'PY' | tee -a "$out"
import json, sys
round_, lights, shading, line = sys.argv[1:5]
bench = json.loads(line) if line != "null" else None
passes = {p["name"]: p["gpu_ms"] for p in (bench or {}).get("pass_order", [])}
print(json.dumps({
    "round": int(round_), "lights": int(lights), "shading": shading,
    "accumulate_ms": passes.get("Transparency #21: accumulate"),
    "resolve_ms": passes.get("Transparency #21: resolve"),
    "gpu_ms_median": (bench or {}).get("gpu_ms_median"),
    "bench": bench,
}))
PY
        done
    done
done

python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
def get(lights, shading, key):
    return [r[key] for r in rows if r["lights"] == lights and r["shading"] == shading]
fmt = lambda xs: " / ".join("-" if x is None else f"{x:.2f}" for x in xs)
shadings = ("Forward", "Compute", "Tiled")
print("| lights | " + " | ".join(f"{s}: accumulate ms" for s in shadings) + " | "
      + " | ".join(f"{s}: frame ms" for s in shadings) + " |")
print("| --- |" + " ---: |" * (2 * len(shadings)))
for n in (1000, 10000, 100000):
    cells = [fmt(get(n, s, "accumulate_ms")) for s in shadings] + [fmt(get(n, s, "gpu_ms_median")) for s in shadings]
    print(f"| {n:,} | " + " | ".join(cells) + " |")
PY

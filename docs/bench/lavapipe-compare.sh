#!/usr/bin/env bash
# Issue 33's lavapipe comparison (docs/benchmarks.md, "lavapipe (development
# machine, no GPU)"): two release builds of `spreadlight`, run alternately on
# the same patch files, one JSON line per run with the load average when it
# started, then a table of medians.
#
#   docs/bench/lavapipe-compare.sh BASE_BIN NEW_BIN PATCH_TREE OUT.jsonl [ROUNDS]
#
# BASE_BIN, NEW_BIN: the two binaries (e.g. e2187b0's and this tree's
# target/release/spreadlight). PATCH_TREE: the checkout whose patches/ are
# run (e2187b0's: "every patch that existed then", with their own assets).
# ROUNDS: how many times each patch runs under each build (default 2); the
# order of the builds alternates from round to round, so a load that rises
# or falls during the run does not always favour the same build.
#
# Run it at nice 0 on a machine as quiet as can be had: only the ratio of
# the two builds within a round means much when other work shares the cores.
# Example (the lead's re-run on a quiet machine):
#   git worktree add /work/wt/e2187b0 e2187b0
#   (cd /work/wt/e2187b0 && CARGO_TARGET_DIR=$PWD/target cargo build --workspace --release --locked --bin spreadlight)
#   cargo build --workspace --release --locked --bin spreadlight
#   docs/bench/lavapipe-compare.sh /work/wt/e2187b0/target/release/spreadlight \
#     target/release/spreadlight /work/wt/e2187b0 /tmp/lavapipe.jsonl 3
set -euo pipefail

base_bin=$(realpath "$1")
new_bin=$(realpath "$2")
tree=$(realpath "$3")
out=$4
rounds=${5:-2}
size=${SIZE:-160x90}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}

: >"$out"
for round in $(seq 1 "$rounds"); do
    if ((round % 2)); then order="base new"; else order="new base"; fi
    for patch in "$tree"/patches/*.ron; do
        case=$(basename "$patch" .ron)
        sets=()
        # The light benchmark at issue 33's 100 lights (node 12: its Count).
        [[ $case == bench-lights ]] && sets=(--set 12.Count=100)
        for build in $order; do
            bin=$base_bin
            [[ $build == new ]] && bin=$new_bin
            load=$(cut -d' ' -f1 /proc/loadavg)
            # From the tree, so that a patch's relative asset paths resolve.
            json=$(cd "$tree" && "$bin" bench "patches/$case.ron" --size "$size" \
                --warmup 10 --frames 50 --json "${sets[@]}" 2>/dev/null | tail -n 1) || json=null
            [[ -n $json ]] || json=null
            printf '{"build":"%s","case":"%s","round":%d,"load":"%s","bench":%s}\n' \
                "$build" "$case" "$round" "$load" "$json" | tee -a "$out"
        done
    done
done

# The table: per patch, each round's median GPU frame and CPU per build.
python3 - "$out" <<'EOF'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
cases = list(dict.fromkeys(r["case"] for r in rows))
def get(case, build, key):
    out = []
    for r in rows:
        if r["case"] == case and r["build"] == build:
            b = r["bench"] or {}
            out.append(b.get(key))
    return out
def fmt(v, d):  # ms: two decimals for the GPU frame, three for CPU
    return "—" if v is None else f"{v:.{d}f}"
print("| patch | base: GPU frame | new: GPU frame | new / base | base: CPU | new: CPU | load average (base / new) |")
print("|---|---:|---:|---:|---:|---:|---:|")
for c in cases:
    bg, ng = get(c, "base", "gpu_ms_median"), get(c, "new", "gpu_ms_median")
    bc, nc = get(c, "base", "cpu_ms_median"), get(c, "new", "cpu_ms_median")
    ratio = [None if (b is None or n is None or b == 0) else n / b for b, n in zip(bg, ng)]
    loads = [f'{r["load"]}' for b in ("base", "new") for r in rows if r["case"] == c and r["build"] == b]
    j = lambda xs, d: " / ".join(fmt(x, d) for x in xs)
    print(f"| {c}.ron | {j(bg,2)} | {j(ng,2)} | {j(ratio,2)} | {j(bc,3)} | {j(nc,3)} | {' / '.join(loads)} |")
EOF

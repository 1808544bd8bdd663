#!/usr/bin/env bash
# Issue 34's refraction figures on the H200 (docs/benchmarks.md, "Refraction
# blur by mips, the off-screen fallback, and the cost of drawn glass"):
#
# 1. `spreadlight accuracy transmission` with each Refraction Blur (taps:
#    the steps read by hand and the taps rows; mips: the steps through the
#    chain's level 0 and rough glass in one read), both baselines (alpha 0,
#    discarded; alpha 0.01, drawn), accumulation and chain timed at 1080p;
# 2. `spreadlight bench patches/bench-transparency.ron` (1024 glass spheres
#    under the lights benchmark's points) with Transmission off, Taps 8,
#    Taps 32 and Mips: the frame and every pass, the Transparency ones
#    (accumulate, refraction mips, resolve) among them.
#
# Two rounds, the order of the choices reversed in the second, so a clock
# or load that drifts during the run does not always favour the same one.
# One JSON line per run on stdout and in OUT (default refraction.jsonl),
# each tagged with its round and choice, then a summary of the medians.
#
#   cargo build --workspace --release --locked --bin spreadlight
#   docs/bench/refraction.sh target/release/spreadlight [OUT.jsonl] [ROUNDS]
#
# ROUNDS (default "1 2"): which rounds to run, so that a machine that allows
# a few minutes a command can take one round a call, appending to OUT
# (`... out.jsonl 1`, then `... out.jsonl 2`; OUT is only emptied by round 1).
set -euo pipefail

bin=$(realpath "${1:-target/release/spreadlight}")
out=$(realpath -m "${2:-refraction.jsonl}")
rounds=${3:-1 2}
# Overridable for a smoke test on a slow machine (SIZE=64x36 WARMUP=0 FRAMES=1).
size=${SIZE:-1920x1080}
acc_warmup=${WARMUP:-20} acc_frames=${FRAMES:-100}
bench_warmup=${WARMUP:-50} bench_frames=${FRAMES:-200}
export XDG_RUNTIME_DIR=${XDG_RUNTIME_DIR:-/tmp}
cd "$(dirname "$0")/../.."

if [[ " $rounds " == *" 1 "* ]]; then : >"$out"; fi
emit() { # round, what, choice, then the JSON line on stdin
    while IFS= read -r line; do
        [[ $line == \{* ]] || continue
        printf '{"round":%d,"what":"%s","choice":"%s","row":%s}\n' "$1" "$2" "$3" "$line" | tee -a "$out"
    done
}

blurs=(taps mips)
glass=(off taps8 taps32 mips)
for round in $rounds; do
    order_b=("${blurs[@]}") order_g=("${glass[@]}")
    if ((round == 2)); then
        order_b=(mips taps) order_g=(mips taps32 taps8 off)
    fi
    for b in "${order_b[@]}"; do
        "$bin" accuracy transmission --time-size "$size" --warmup "$acc_warmup" --frames "$acc_frames" \
            --blurs "$b" --json | emit "$round" accuracy "$b"
    done
    for g in "${order_g[@]}"; do
        case $g in
            off) sets=(--set 21.Transmission=0) ;;
            taps8) sets=(--set 21.Transmission=1 --set "21.Refraction Blur=Taps" --set "21.Refraction Taps=8") ;;
            taps32) sets=(--set 21.Transmission=1 --set "21.Refraction Blur=Taps" --set "21.Refraction Taps=32") ;;
            mips) sets=(--set 21.Transmission=1 --set "21.Refraction Blur=Mips") ;;
        esac
        "$bin" bench patches/bench-transparency.ron --size "$size" --warmup "$bench_warmup" --frames "$bench_frames" \
            --set 21.Thickness=0.3 "${sets[@]}" --json | tail -n 1 | emit "$round" bench "$g"
    done
done

python3 - "$out" <<'PY'
import json, sys
rows = [json.loads(l) for l in open(sys.argv[1]) if l.strip()]
print("\naccuracy transmission: method | setting | round: accumulate ms + mips ms | RMSE")
for r in rows:
    if r["what"] == "accuracy":
        a = r["row"]
        print(f'  {a["method"]} | {a["setting"]} | {r["round"]}: {a["accumulate_ms"]} + {a["mips_ms"]} | {a["rmse"]:.4f}')
print("\nbench-transparency.ron: choice | round: GPU frame ms | Transparency passes ms")
for r in rows:
    if r["what"] == "bench":
        b = r["row"]
        mine = {k: v for k, v in (b.get("passes") or {}).items() if "Transparency" in k}
        print(f'  {r["choice"]} | {r["round"]}: {b.get("gpu_ms_median")} | {json.dumps(mine)}')
PY

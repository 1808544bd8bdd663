#!/usr/bin/env bash
# Issue 33's light target on the H200 (docs/benchmarks.md, "100,000 lights:
# a cheaper light evaluation and a Light Cutoff"): one device call that
# compares, on patches/bench-lights.ron at 1920x1080,
#   - the builds: BASE_BIN (main before this branch) against NEW_BIN (the
#     exact per-light speed-ups: both at Light Cutoff 0, the same image);
#   - NEW_BIN's Light Cutoff (CookTorrance's quality pin: 0 is exact);
#   - Light Loop Clustered (Auto's walk on a GPU) and, at cutoff 0, Tiled;
# at 1,000 / 10,000 / 100,000 / 1,000,000 lights, interleaved (the builds
# alternate their order from round to round), ROUNDS rounds (default 2).
# One JSON line per run on stdout: {"round", "build", "lights", "loop",
# "cutoff", "bench": <spreadlight bench --json>}; the shade pass is
# bench.passes["CookTorrance #14: shade"], the assignment
# bench.passes["CookTorrance #14: clustered light assignment"]. Then, for
# the cutoffs' error, NEW_BIN's `accuracy lights --json` lines
# ({"effect": "lights", ...: rmse, ssim, lighting_ms, shade_ms}).
#
#   docs/bench/lights100k.sh BASE_BIN NEW_BIN [ROUNDS] > lights100k.jsonl
#
# Example (release builds of main and of this branch):
#   (cd /work/main && cargo build --workspace --release --locked --bin spreadlight)
#   cargo build --workspace --release --locked --bin spreadlight
#   docs/bench/lights100k.sh /work/main/target/release/spreadlight \
#     target/release/spreadlight 2 > lights100k.jsonl
# Run from this checkout's root (the patch path is relative). BASE_BIN may
# be "-" to time NEW_BIN alone.
set -euo pipefail

base_bin=$1
new_bin=$(realpath "$2")
rounds=${3:-2}
if [ "$base_bin" != "-" ]; then base_bin=$(realpath "$base_bin"); fi
patch=patches/bench-lights.ron
# Cutoffs in the lights' illuminance (lux): the bench's lights are 3,979 cd
# times a colour in 0..1, range 5, seen at exposure 0.001 (1,000 lux is
# white). A light reaches sqrt(I / cutoff): about 5.5 at 100 (most lights
# keep their range), 3.9 at 200, 2.7 at 400, 1.9 at 800.
cutoffs=(0 50 100 200 400 800)

# One run: BUILD BIN LIGHTS LOOP CUTOFF.
run() {
    local build=$1 bin=$2 lights=$3 loop=$4 cutoff=$5
    local frames=200 warmup=50
    if [ "$lights" -ge 1000000 ]; then frames=30; warmup=10; fi
    local sets=(--set "12.Count=$lights" --set "14.Light Loop=$loop")
    # BASE_BIN has no Light Cutoff pin: it runs at 0 only, without the flag.
    if [ "$build" = new ]; then sets+=(--set "14.Light Cutoff=$cutoff"); fi
    local line
    line=$("$bin" bench "$patch" --size 1920x1080 "${sets[@]}" \
        --warmup "$warmup" --frames "$frames" --json)
    printf '{"round":%s,"build":"%s","lights":%s,"loop":"%s","cutoff":%s,"bench":%s}\n' \
        "$round" "$build" "$lights" "$loop" "$cutoff" "$line"
}

for round in $(seq 1 "$rounds"); do
    if ((round % 2)); then order="base new"; else order="new base"; fi
    for lights in 1000 10000 100000 1000000; do
        for build in $order; do
            if [ "$build" = base ]; then
                [ "$base_bin" = "-" ] && continue
                run base "$base_bin" "$lights" Clustered 0
            else
                run new "$new_bin" "$lights" Clustered 0
            fi
        done
        run new "$new_bin" "$lights" Tiled 0
        for cutoff in "${cutoffs[@]:1}"; do
            run new "$new_bin" "$lights" Clustered "$cutoff"
        done
    done
done
# The cutoffs' error against the exact image (and their time again).
"$new_bin" accuracy lights --patch "$patch" --counts 1000,10000,100000 \
    --cutoffs "$(IFS=,; echo "${cutoffs[*]}")" --size 480x270 --json

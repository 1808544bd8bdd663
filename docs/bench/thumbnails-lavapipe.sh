#!/usr/bin/env bash
# What thumbnails cost post.ron's patch frame (issue 32: a rise under 5%, the
# UI pass under 8 ms), measured as docs/editor.md "Previews" describes:
# thumbnails off and on, interleaved (off, on, off, on) so that a change in
# the machine's load falls on both, at each zoom, with the load average
# before each run. Run from the repository root after
#   cargo build --release --locked --bin spreadlight
# Usage: docs/bench/thumbnails-lavapipe.sh [ZOOMS] [ROUNDS] [FRAMES] > out.jsonl
#   ZOOMS  --min-zoom values, comma-separated (default "0.3,0.1": about 25
#          and 34 thumbnails on screen at 1600x900)
#   ROUNDS off/on pairs per zoom (default 2); FRAMES editor frames a run (80)
# Each run prints one JSON line: the editor's --measure-frames report (with
# what each patch frame cost the UI: submissions and waits at the submission
# gate, docs/editor.md "What asked for those frames") plus
# "zoom", "thumbs" (off/on), "round", "load_before" and "load_after"; a
# summary per zoom follows on standard error (needs jq).
set -euo pipefail

zooms=${1:-0.3,0.1}
rounds=${2:-2}
frames=${3:-80}
bin=${SPREADLIGHT_BIN:-./target/release/spreadlight}
patch=${PATCH:-patches/post.ron}

cfg=$(mktemp -d)
trap 'rm -rf "$cfg"' EXIT
mkdir -p "$cfg/off" "$cfg/on"
echo '(thumbnails: false)' > "$cfg/off/previews.ron"

load() { cut -d' ' -f1 /proc/loadavg; }
results=$(mktemp)
trap 'rm -rf "$cfg" "$results"' EXIT

for zoom in ${zooms//,/ }; do
    for round in $(seq 1 "$rounds"); do
        for thumbs in off on; do
            before=$(load)
            line=$(SPREADLIGHT_CONFIG_DIR="$cfg/$thumbs" \
                xvfb-run -a -s "-screen 0 1920x1080x24" \
                "$bin" edit "$patch" --min-zoom "$zoom" --measure-frames "$frames" |
                grep '^{"frames"' | tail -n 1)
            after=$(load)
            echo "$line" | jq -c --arg zoom "$zoom" --arg thumbs "$thumbs" \
                --argjson round "$round" --arg before "$before" --arg after "$after" \
                '. + {zoom: ($zoom | tonumber), thumbs: $thumbs, round: $round,
                      load_before: ($before | tonumber), load_after: ($after | tonumber)}' |
                tee -a "$results"
        done
    done
done

# Per zoom and round: the patch frame off and on, the rise, the UI pass on.
jq -rs 'group_by([.zoom, .round])[] |
    (map(select(.thumbs == "off"))[0]) as $off | (map(select(.thumbs == "on"))[0]) as $on |
    "zoom \($on.zoom) round \($on.round): \($on.thumbnails) thumbnails, patch \($off.patch_ms_median) -> \($on.patch_ms_median) ms (\((($on.patch_ms_median / $off.patch_ms_median - 1) * 1000 | round) / 10)%), ui \($on.ui_ms_median) ms, thumbnail_ms \($on.thumbnail_ms), patch_alone_ms \($on.patch_alone_ms), patch frames \($off.patch_frames)/\($on.patch_frames) of \($on.frames), per patch frame off/on: submissions \($off.submissions_per_patch_frame)/\($on.submissions_per_patch_frame), gate waits \($off.gate_waits_per_patch_frame)/\($on.gate_waits_per_patch_frame), thumbnails scaled \($on.thumbnails_scaled_per_patch_frame), load \($off.load_before)-\($on.load_after)"' \
    "$results" >&2

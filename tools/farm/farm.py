#!/usr/bin/env python3
"""Render a Spreadlight sequence on a Dask cluster (docs/farm.md).

Spreadlight brings the chunkable, resumable `spreadlight render` command;
Dask distributed does the scheduling, placement and retries (a chunk whose
worker dies is run again on another). This tool:

1. asks `spreadlight render --dry-run` which frames are missing (so a
   second submission resumes, and bad input stops here, before the farm);
2. submits one task per chunk of missing frames, each running
   `spreadlight render PATCH --frames A-B ...` on a worker;
3. when every task has ended, asks again which frames are missing and
   submits only those, up to --rounds times.

    farm.py submit --scheduler tcp://HEAD:8786 PATCH --frames 0-239 --chunk 10 -o /shared/out/shot_####.exr [render options]
    farm.py local --workers 4 PATCH --frames 0-239 --chunk 10 -o out/shot_####.exr [render options]

Paths must be the same on every worker (a shared file system). Exit codes:
0 every frame exists, 1 frames still missing after the last round, 2 bad
input (from `spreadlight render`) or no cluster.
"""

import argparse
import json
import os
import signal
import subprocess
import sys
import time


def _die_with_parent():
    """In the child, before exec: die when the worker dies, so a killed
    worker leaves no renderer behind writing frames another worker now owns."""
    import ctypes

    pr_set_pdeathsig = 1
    ctypes.CDLL("libc.so.6", use_errno=True).prctl(pr_set_pdeathsig, signal.SIGKILL)


def render_chunk(command):
    """Runs on a worker: one `spreadlight render` of a chunk. Returns what it reported."""
    import socket

    started = time.time()
    done = subprocess.run(
        command, capture_output=True, text=True, preexec_fn=_die_with_parent
    )
    summary = None
    for line in done.stdout.splitlines():
        if line.startswith("{"):
            event = json.loads(line)
            if event.get("event") == "done":
                summary = event
    return {
        "returncode": done.returncode,
        "summary": summary,
        "stderr": done.stderr[-2000:],
        "host": socket.gethostname(),
        "seconds": time.time() - started,
    }


def parse(argv):
    parser = argparse.ArgumentParser(
        prog="farm.py", description=__doc__.split("\n\n")[0]
    )
    sub = parser.add_subparsers(dest="command", required=True)
    for name in ("submit", "local"):
        p = sub.add_parser(name)
        if name == "submit":
            where = p.add_mutually_exclusive_group(required=True)
            where.add_argument("--scheduler", help="the scheduler's address, tcp://HOST:8786")
            where.add_argument("--scheduler-file", help="the file `dask scheduler --scheduler-file` wrote")
        else:
            p.add_argument("--workers", type=int, default=2, help="local worker processes")
        p.add_argument("patch")
        p.add_argument("--frames", required=True, help="FIRST-LAST")
        p.add_argument("--step", type=int, default=1)
        p.add_argument("--chunk", type=int, default=10, help="frames per task")
        p.add_argument("--rounds", type=int, default=3, help="submissions of missing frames, at most")
        p.add_argument("-o", "--output", required=True)
        p.add_argument(
            "--spreadlight",
            default=os.environ.get("SPREADLIGHT", "spreadlight"),
            help="the spreadlight binary on the workers (default: $SPREADLIGHT or the PATH)",
        )
    args, render_options = parser.parse_known_args(argv)
    args.render_options = render_options
    if os.sep in args.spreadlight:
        args.spreadlight = os.path.abspath(args.spreadlight)
    return args


def render_command(args, frames):
    """`spreadlight render` with the user's options, for `frames` (A-B)."""
    return [
        args.spreadlight, "render", os.path.abspath(args.patch),
        "-o", os.path.abspath(args.output),
        "--frames", frames, "--step", str(args.step), "--json",
        *args.render_options,
    ]


def missing(args, first):
    """The frames without complete files, by `spreadlight render --dry-run`.
    After the first round, --overwrite no longer counts: what was rendered stays."""
    command = render_command(args, args.frames) + ["--dry-run"]
    if not first:
        command = [a for a in command if a != "--overwrite"]
    done = subprocess.run(command, capture_output=True, text=True)
    if done.returncode != 0:
        sys.stderr.write(done.stderr)
        sys.exit(2)
    frames = []
    for line in done.stdout.splitlines():
        event = json.loads(line)
        if event.get("event") == "frame" and event["status"] == "missing":
            frames.append(event["frame"])
    return frames


def chunks(frames, size, step):
    """Runs of consecutive frames (on the step's grid), cut to at most `size` frames."""
    runs, run = [], []
    for f in frames:
        if run and (f != run[-1] + step or len(run) == size):
            runs.append(run)
            run = []
        run.append(f)
    if run:
        runs.append(run)
    return [(r[0], r[-1]) for r in runs]


def farm(client, args):
    started = time.time()
    todo = missing(args, first=True)
    total = len(todo)
    print(f"farm: {total} frame(s) to render on {len(client.scheduler_info()['workers'])} worker(s)", flush=True)
    for round_ in range(1, args.rounds + 1):
        if not todo:
            break
        from distributed import as_completed

        work = chunks(todo, args.chunk, args.step)
        futures = {
            client.submit(
                render_chunk,
                render_command(args, f"{a}-{b}"),
                key=f"spreadlight-{a}-{b}-round{round_}",
                pure=False,
            ): (a, b)
            for a, b in work
        }
        print(f"farm: round {round_}: {len(work)} chunk(s)", flush=True)
        for future in as_completed(futures):
            a, b = futures[future]
            try:
                result = future.result()
            except Exception as e:  # the engine gave up on it (e.g. KilledWorker): re-submitted below
                print(f"farm: chunk {a}-{b} lost: {type(e).__name__}: {e}", flush=True)
                continue
            failed = (result["summary"] or {}).get("failed", [])
            if result["returncode"] != 0:
                print(
                    f"farm: chunk {a}-{b} on {result['host']} exited {result['returncode']}"
                    f" (failed frames: {failed})\n{result['stderr']}",
                    flush=True,
                )
            else:
                print(f"farm: chunk {a}-{b} done on {result['host']} in {result['seconds']:.1f} s", flush=True)
        todo = missing(args, first=False)
    seconds = time.time() - started
    rendered = total - len(todo)
    line = {"event": "farm", "rendered": rendered, "missing": todo, "seconds": seconds,
            "fps": rendered / seconds if seconds > 0 else None}
    print(json.dumps(line), flush=True)
    return 0 if not todo else 1


def main(argv):
    args = parse(argv)
    if args.chunk < 1 or args.rounds < 1:
        sys.stderr.write("--chunk and --rounds must be at least 1\n")
        return 2
    if args.output.lower().endswith((".mp4", ".mov")):
        sys.stderr.write("farm.py renders frames (-o out/shot_####.exr): a video is one file, made by one process\n")
        return 2
    try:
        from distributed import Client, LocalCluster
    except ImportError:
        sys.stderr.write(
            "farm.py needs Dask distributed: python3 -m pip install 'dask[distributed]'\n"
        )
        return 2
    if args.command == "local":
        with LocalCluster(n_workers=args.workers, threads_per_worker=1, processes=True,
                          dashboard_address=None) as cluster, Client(cluster) as client:
            return farm(client, args)
    if args.scheduler_file:
        client = Client(scheduler_file=args.scheduler_file, timeout=60)
    else:
        client = Client(args.scheduler, timeout=60)
    with client:
        return farm(client, args)


if __name__ == "__main__":
    sys.exit(main(sys.argv[1:]))

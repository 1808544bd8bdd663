#!/usr/bin/env python3
"""The farm, tested for real (run by crates/cli/tests/farm.rs in CI).

Starts a one-machine Dask cluster on localhost (a scheduler and three
workers, each under its nanny, as on a real farm), renders a short sequence
of a shipped patch with farm.py in chunks, kills one worker with SIGKILL
while its chunk is half written, and checks that every frame exists once,
is complete, and is byte for byte the frame a single `spreadlight render`
process writes. Fails (never skips) when Dask is not installed.

    test_farm.py --spreadlight target/debug/spreadlight
"""

import argparse
import os
import signal
import subprocess
import sys
import tempfile
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
PATCH = os.path.join(ROOT, "patches", "gbuffer-spheres.ron")
FRAMES, CHUNK, WORKERS = 16, 8, 3
RENDER = ["--size", "64x36", "--samples", "8"]


def fail(message):
    sys.stderr.write(f"FAIL: {message}\n")
    sys.exit(1)


def start(command, log):
    """A process of our own, in its own group (so it and its children can be ended)."""
    return subprocess.Popen(command, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)


def stop(process):
    try:
        os.killpg(process.pid, signal.SIGKILL)
    except ProcessLookupError:
        pass
    process.wait()


def frame_names():
    return [f"shot_{f:04}.png" for f in range(FRAMES)]


def kill_a_worker_mid_chunk(client, pids, out, farm):
    """Wait until a worker runs a chunk with some but not all of its frames
    written, then SIGKILL that worker's process. Returns what was killed."""
    deadline = time.time() + 120
    while time.time() < deadline:
        if farm.poll() is not None:
            fail("the farm finished before a worker could be killed mid-chunk")
        for worker, keys in client.processing().items():
            for key in keys:
                if not str(key).startswith("spreadlight-"):
                    continue
                a, b = map(int, str(key).split("-")[1:3])
                written = sum(os.path.exists(os.path.join(out, f"shot_{f:04}.png")) for f in range(a, b + 1))
                if 0 < written < b - a + 1:
                    os.kill(pids[worker], signal.SIGKILL)
                    return f"worker {worker} (pid {pids[worker]}) during chunk {a}-{b}, {written} of {b - a + 1} frames written"
        time.sleep(0.005)
    fail("no chunk was caught half written within 120 s")


def main():
    parser = argparse.ArgumentParser()
    parser.add_argument("--spreadlight", required=True)
    args = parser.parse_args()
    spreadlight = os.path.abspath(args.spreadlight)
    try:
        from distributed import Client
    except ImportError:
        fail("Dask distributed is not installed (python3 -m pip install 'dask[distributed]'; .ci/run does)")

    tmp = tempfile.mkdtemp(prefix="spreadlight-farm-")
    out, reference = os.path.join(tmp, "farm"), os.path.join(tmp, "single")
    scheduler_file = os.path.join(tmp, "scheduler.json")
    log = open(os.path.join(tmp, "cluster.log"), "w")
    python = sys.executable
    processes = []
    try:
        processes.append(start([python, "-m", "distributed.cli.dask_scheduler", "--host", "127.0.0.1",
                                "--port", "0", "--no-dashboard", "--scheduler-file", scheduler_file], log))
        deadline = time.time() + 60
        while not os.path.exists(scheduler_file):
            if time.time() > deadline:
                fail("the Dask scheduler did not start (see " + log.name + ")")
            time.sleep(0.1)
        processes.append(start([python, "-m", "distributed.cli.dask_worker", "--scheduler-file", scheduler_file,
                                "--nworkers", str(WORKERS), "--nthreads", "1", "--host", "127.0.0.1",
                                "--no-dashboard"], log))
        client = Client(scheduler_file=scheduler_file, timeout=60)
        client.wait_for_workers(WORKERS, timeout=120)
        pids = client.run(os.getpid)

        farm_log = open(os.path.join(tmp, "farm.log"), "w+")
        farm = subprocess.Popen(
            [python, os.path.join(HERE, "farm.py"), "submit", "--scheduler-file", scheduler_file,
             PATCH, "--frames", f"0-{FRAMES - 1}", "--chunk", str(CHUNK),
             "-o", os.path.join(out, "shot_####.png"), "--spreadlight", spreadlight, *RENDER],
            stdout=farm_log, stderr=subprocess.STDOUT,
        )
        killed = kill_a_worker_mid_chunk(client, pids, out, farm)
        print(f"killed {killed}")
        if farm.wait(timeout=300) != 0:
            farm_log.seek(0)
            fail(f"farm.py exited {farm.returncode}:\n{farm_log.read()}")
        farm_log.seek(0)
        print(farm_log.read())
        client.close()

        single = subprocess.run([spreadlight, "render", PATCH, "--frames", f"0-{FRAMES - 1}",
                                 "-o", os.path.join(reference, "shot_####.png"), *RENDER],
                                capture_output=True, text=True)
        if single.returncode != 0:
            fail(f"the single-process render failed:\n{single.stderr}")

        names = sorted(os.listdir(out))
        if names != frame_names():
            fail(f"the farm's folder should hold each frame once and nothing else, it holds {names}")
        for name in names:
            with open(os.path.join(out, name), "rb") as a, open(os.path.join(reference, name), "rb") as b:
                farmed, alone = a.read(), b.read()
            if not farmed.startswith(b"\x89PNG") or not farmed.rstrip(b"\0").endswith(b"IEND\xaeB`\x82"):
                fail(f"{name} is not a complete PNG")
            if farmed != alone:
                fail(f"{name} differs from the single-process render")
        print(f"ok: {FRAMES} frames in chunks of {CHUNK} on {WORKERS} workers, one killed mid-chunk; "
              "each frame once, complete, equal to the single-process render")

        # A second submission renders only what is missing.
        for f in (3, 11):
            os.remove(os.path.join(out, f"shot_{f:04}.png"))
        again = subprocess.run(
            [python, os.path.join(HERE, "farm.py"), "submit", "--scheduler-file", scheduler_file,
             PATCH, "--frames", f"0-{FRAMES - 1}", "--chunk", str(CHUNK),
             "-o", os.path.join(out, "shot_####.png"), "--spreadlight", spreadlight, *RENDER],
            capture_output=True, text=True, timeout=300,
        )
        print(again.stdout)
        if again.returncode != 0 or "2 frame(s) to render" not in again.stdout:
            fail(f"the re-submission should render the 2 missing frames:\n{again.stdout}{again.stderr}")
        chunks = sorted(line.split()[2] for line in again.stdout.splitlines() if " done on " in line)
        if chunks != ["11-11", "3-3"]:
            fail(f"only the missing frames should be submitted, not {chunks}")
        if sorted(os.listdir(out)) != frame_names():
            fail("the re-submission left the folder incomplete")
        print("ok: a re-submission rendered only the two missing frames")
    finally:
        for process in reversed(processes):
            stop(process)
        log.close()


if __name__ == "__main__":
    main()

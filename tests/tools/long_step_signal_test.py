#!/usr/bin/env python3
"""Stop signal during a long step (issue 32): SIGTERM to Open MPI's mpirun while a step of
several seconds is in progress still leaves a checkpoint of the last completed step, the run's
stop line, and a restart that continues from it.

  long_step_signal_test.py --dipc build/src/app/dipc \\
      --mpiexec "mpiexec --oversubscribe --allow-run-as-root" --work /tmp/long_step_signal [--grace 1]

Open MPI 4.1's mpirun answers SIGTERM with SIGCONT to the ranks at once, SIGTERM
`odls_base_sigkill_timeout` seconds later and SIGKILL as many seconds after that (measured:
docs/output.md, "Signals"). So the ranks learn of the stop only --grace seconds after mpirun,
and have --grace seconds to write their checkpoint. The scene (long_step_scene.json: a soft
clamped beam sagging under gravity in steps of 0.5 s) takes 15 to 30 Newton iterations per
step: 2-3 s per step on 2 idle cores, 12-17 s under load, with iterations of 0.1-0.5 s. A run
that only stops between steps finishes step 2 (or is killed in it); one that abandons the step
at its next Newton iteration stops well within the grace time.

1. The run (2 ranks, `--mca odls_base_sigkill_timeout <grace>`, Open MPI's default 1 s unless
   given) is signalled once step 1's row reaches stats.csv, after a wait that puts the ranks'
   SIGTERM about a third of the way into step 2 (step 2 takes about 0.7 of step 1's time):
   max(0, 0.3 t1 - grace), t1 being when step 1 ended. On an idle machine that is at once, and
   the ranks' SIGTERM comes 1 s into a step of 2 s or more.
2. Checked: the stop line "stopped on signal 15 after step 1", the checkpoint of step 1 and none
   of step 2, stats.csv with step 1 alone, and the checkpoint's state equal to the output's
   step 1 (positions and velocities bit for bit, previous positions those of step 0), not to a
   part of step 2.
3. A restart with -dipc_restart auto -dipc_steps 2 says it restarts from step 1's checkpoint,
   exits 0 and adds step 2 to stats.csv.
Exit status 0 when all holds; the failures are printed and the status is 1.
"""
import argparse
import csv
import os
import re
import shlex
import shutil
import signal
import subprocess
import sys
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "long_step_scene.json")

failures = []


def check(condition, what):
    if not condition:
        failures.append(what)
        print("FAIL:", what, flush=True)
    return condition


def stats_steps(out):
    try:
        with open(os.path.join(out, "stats.csv")) as f:
            return [int(row["step"]) for row in csv.DictReader(f)]
    except (OSError, ValueError, KeyError):
        return []


def run_stopped(args, out, log_path):
    """Starts the run, signals mpirun mid-step 2 and waits for it; returns its console output."""
    cmd = (shlex.split(args.mpiexec) + ["--mca", "odls_base_sigkill_timeout", str(args.grace), "-n", "2", args.dipc,
                                         SCENE, "-dipc_output", out])
    print("run:", " ".join(cmd), flush=True)
    with open(log_path, "w") as log:
        start = time.monotonic()
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, start_new_session=True)
        while stats_steps(out) != [1]:
            if proc.poll() is not None or time.monotonic() - start > args.timeout:
                proc.kill()
                sys.exit(f"the run ended or timed out before step 1 (see {log_path})")
            time.sleep(0.05)
        step1 = time.monotonic() - start
        wait = max(0.0, 0.3 * step1 - args.grace)
        time.sleep(wait)
        signalled = time.monotonic()
        proc.send_signal(signal.SIGTERM)
        try:
            status = proc.wait(timeout=2 * args.grace + 30)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            status = proc.wait()
        print(f"step 1 done {step1:.1f} s after the start; SIGTERM to mpirun {wait:.1f} s later; mpirun exited "
              f"{time.monotonic() - signalled:.1f} s after it with status {status}", flush=True)
    with open(log_path) as f:
        return f.read()


def same_state_as_step_1(out):
    """The checkpoint's positions and velocities against the output's step 1 (bit for bit)."""
    with h5py.File(os.path.join(out, "dipc.checkpoint.000001.h5"), "r") as c, \
            h5py.File(os.path.join(out, "dipc.h5"), "r") as o:
        check(c.attrs["step"] == 1, f"the checkpoint's step attribute is {c.attrs['step']}, not 1")
        check(c.attrs["time"] == 0.5, f"the checkpoint's time is {c.attrs['time']}, not 0.5")
        X = o["mesh/coordinates"][...]
        u, v = o["steps/1/displacement"][...], o["steps/1/velocity"][...]
        x_ckpt, v_ckpt = c["nodes/position"][...], c["nodes/velocity"][...]
        check(np.array_equal(x_ckpt - X, u), "the checkpoint's positions are not those of step 1 "
              f"(largest difference {np.abs(x_ckpt - X - u).max():.3g})")
        check(np.array_equal(v_ckpt, v), "the checkpoint's velocities are not those of step 1 "
              f"(largest difference {np.abs(v_ckpt - v).max():.3g})")
        # Step 1 took one sub-step, so the start of its last sub-step is step 0's state; the
        # abandoned attempt at step 2 had overwritten it with step 1's.
        x_n = c["nodes/previous_position"][...]
        check(np.array_equal(x_n - X, o["steps/0/displacement"][...]),
              "the checkpoint's previous positions are not step 0's (the start of step 1)")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--dipc", required=True)
    parser.add_argument("--mpiexec", required=True, help="Open MPI's mpirun with its flags")
    parser.add_argument("--work", required=True)
    parser.add_argument("--grace", type=int, default=1, help="odls_base_sigkill_timeout (s; Open MPI's default 1)")
    parser.add_argument("--timeout", type=float, default=120, help="for step 1 and for the restart (s)")
    args = parser.parse_args()
    shutil.rmtree(args.work, ignore_errors=True)
    os.makedirs(args.work)
    out = os.path.join(args.work, "out")
    started = time.monotonic()

    text = run_stopped(args, out, os.path.join(args.work, "stopped.log"))
    stop = re.search(r"dipc: stopped on signal (\d+) after step (\d+); checkpoint written to (\S+) ([0-9.]+) s", text)
    if check(stop, "no stop line (the ranks were killed before a checkpoint):\n" + text[-3000:]):
        check(stop.group(1) == "15" and stop.group(2) == "1",
              f"stopped on signal {stop.group(1)} after step {stop.group(2)}, not on 15 after step 1")
        print(f"the checkpoint was written {stop.group(4)} s after the ranks got SIGTERM", flush=True)
    check(re.search(r"step +2 +abandoned after \d+ Newton iterations", text), "no line saying step 2 was abandoned")
    checkpoints = sorted(f for f in os.listdir(out) if ".checkpoint." in f) if os.path.isdir(out) else []
    check(checkpoints == ["dipc.checkpoint.000001.h5"], f"checkpoints {checkpoints}, not step 1's alone")
    check(stats_steps(out) == [1], f"stats.csv has steps {stats_steps(out)}, not [1]")
    if "dipc.checkpoint.000001.h5" in checkpoints:
        same_state_as_step_1(out)

    cmd = shlex.split(args.mpiexec) + ["-n", "2", args.dipc, SCENE, "-dipc_output", out, "-dipc_restart", "auto",
                                       "-dipc_steps", "2"]
    print("restart:", " ".join(cmd), flush=True)
    resumed = subprocess.run(cmd, capture_output=True, text=True, timeout=args.timeout)
    check(resumed.returncode == 0, f"the restart exited {resumed.returncode}:\n{resumed.stdout[-3000:]}")
    check(f"restarting from {out}/dipc.checkpoint.000001.h5: step 1" in resumed.stdout,
          "the restart did not resume from step 1's checkpoint:\n" + resumed.stdout[-3000:])
    check(stats_steps(out) == [1, 2], f"after the restart stats.csv has steps {stats_steps(out)}, not [1, 2]")
    print(f"{'FAILED' if failures else 'passed'} in {time.monotonic() - started:.1f} s", flush=True)
    return 1 if failures else 0


if __name__ == "__main__":
    sys.exit(main())

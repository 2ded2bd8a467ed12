#!/usr/bin/env python3
"""Kill test (issue 13): a 2-rank run killed with SIGKILL at random moments, each kill followed
by `-dipc_restart auto`, ends where the uninterrupted run ends, and its output is readable after
every kill.

  kill_restart_test.py --dipc build/src/app/dipc --mpiexec "mpiexec --oversubscribe" \\
      --kills 50 --work /tmp/kill_restart [--seed 1] [--steps 30] [--max-delay 6]

1. The reference: the scene (tests/tools/kill_restart_scene.json: a cube dropped with friction
   onto a box on a ground plane) run uninterrupted on 2 ranks.
2. Rounds: a fresh output folder; the run is started with -dipc_checkpoint_every 1
   -dipc_restart auto and SIGKILLed (mpiexec and both ranks, by process id) after a random delay
   in [0, max-delay] s, counted from the launch for one kill in four and from the end of the
   set-up (the run header) for the others, again and again, until it completes; then its final step is compared
   with the reference's (displacement and velocity to 1e-12, every step's time exactly). Rounds
   go on until --kills kills were made (a run that completes before its kill ends the round).
3. After every kill: the .xmf parses and every step it lists is read in full from the .h5 with
   h5py; every complete line of stats.csv parses, steps in order without repeats; every
   checkpoint under its final name opens with h5py and has the dipc format attribute.
Exit status 0 when all holds; the first failure is printed and the status is 1.
"""
import argparse
import csv
import os
import random
import re
import shlex
import signal
import subprocess
import sys
import threading
import time

import h5py
import numpy as np

HERE = os.path.dirname(os.path.abspath(__file__))
SCENE = os.path.join(HERE, "kill_restart_scene.json")
HEADER = re.compile(r"^dipc \S+ \| PETSc")  # the run header: set up, about to step


def command(args, out, extra):
    return (shlex.split(args.mpiexec) + ["-n", "2", args.dipc, SCENE, "-dipc_quiet", "-dipc_steps", str(args.steps),
                                          "-dipc_output", out] + extra)


def session_pids(sid):
    """The processes of session `sid` (mpiexec and the ranks it started), by id."""
    out = subprocess.run(["ps", "-e", "-o", "pid=,sid="], capture_output=True, text=True).stdout
    return [int(p) for p, s in (line.split() for line in out.splitlines()) if int(s) == sid]


def xmf_times(path):
    with open(path) as f:
        return [float(t) for t in re.findall(r'<Time Value="([^"]+)"', f.read())]


def check_readable(out):
    """Raises AssertionError when an output file of `out` cannot be read."""
    if not os.path.isdir(out):  # killed before the run made its folder
        return
    xmf, h5 = os.path.join(out, "dipc.xmf"), os.path.join(out, "dipc.h5")
    if os.path.exists(xmf):
        times = xmf_times(xmf)
        with h5py.File(h5, "r") as f:
            n = f["mesh/coordinates"].shape[0]
            f["mesh/topology"][...]
            for k, t in enumerate(times):
                g = f["steps/%d" % k]
                assert float(g.attrs["time"]) == t, "step %d: time %r in the .h5, %r in the .xmf" % (k, g.attrs["time"], t)
                assert g["displacement"][...].shape == (n, 3) and g["velocity"][...].shape == (n, 3)
                g["volume_ratio"][...]
    stats = os.path.join(out, "stats.csv")
    if os.path.exists(stats):
        with open(stats) as f:
            text = f.read()
        lines = text.split("\n")[:-1]  # complete lines only (a killed run may leave half a line)
        rows = list(csv.reader(lines))
        steps = [int(float(r[0])) for r in rows[1:]]
        assert steps == list(range(1, len(steps) + 1)), "stats.csv steps %s" % steps
    for name in os.listdir(out):
        if re.fullmatch(r"dipc\.checkpoint\.\d+\.h5", name):
            with h5py.File(os.path.join(out, name), "r") as f:
                assert f.attrs["format"] == b"dipc checkpoint", name
                f["nodes/position"][...]


def final_state(out):
    with h5py.File(os.path.join(out, "dipc.h5"), "r") as f:
        n = len(f["steps"])
        last = f["steps/%d" % (n - 1)]
        return xmf_times(os.path.join(out, "dipc.xmf")), last["displacement"][...], last["velocity"][...]


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--dipc", required=True)
    p.add_argument("--mpiexec", default="mpiexec")
    p.add_argument("--kills", type=int, default=50)
    p.add_argument("--steps", type=int, default=30)
    p.add_argument("--max-delay", type=float, default=6.0, help="longest wait before a kill (s)")
    p.add_argument("--seed", type=int, default=1)
    p.add_argument("--work", required=True)
    args = p.parse_args()
    rng = random.Random(args.seed)
    os.makedirs(args.work, exist_ok=True)

    ref = os.path.join(args.work, "reference")
    subprocess.run(["rm", "-rf", ref])
    start = time.time()
    r = subprocess.run(command(args, ref, []), capture_output=True, text=True)
    if r.returncode != 0:
        print("reference run failed:\n" + r.stdout + r.stderr)
        return 1
    ref_times, ref_u, ref_v = final_state(ref)
    print("reference: %d steps in %.1f s" % (args.steps, time.time() - start), flush=True)

    kills, rounds = 0, 0
    while kills < args.kills:
        rounds += 1
        out = os.path.join(args.work, "round%d" % rounds)
        subprocess.run(["rm", "-rf", out])
        while True:
            proc = subprocess.Popen(command(args, out, ["-dipc_checkpoint_every", "1", "-dipc_restart", "auto"]),
                                    stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
            lines, stepping = [], threading.Event()

            def read(proc=proc, lines=lines, stepping=stepping):
                for line in proc.stdout:
                    lines.append(line)
                    if HEADER.match(line):
                        stepping.set()
                stepping.set()

            reader = threading.Thread(target=read, daemon=True)
            reader.start()
            killed = False
            if kills < args.kills:
                # One kill in four at any moment from the launch (start-up, reading the
                # checkpoint, continuing the output); the others once the run is set up and
                # stepping (its header printed), so that most land in steps and their output.
                from_launch = rng.random() < 0.25
                delay = rng.uniform(0, args.max_delay)
                if not from_launch:
                    stepping.wait()
                time.sleep(delay)
                if proc.poll() is None:
                    for pid in session_pids(proc.pid):
                        try:
                            os.kill(pid, signal.SIGKILL)
                        except ProcessLookupError:
                            pass
                    killed = True
            proc.wait()
            reader.join()
            if killed:
                kills += 1
                try:
                    check_readable(out)
                except Exception as e:  # noqa: BLE001 (any failure to read is the finding)
                    print("kill %d: output not readable: %r" % (kills, e))
                    return 1
                stats = os.path.join(out, "stats.csv")
                done = sum(1 for _ in open(stats)) - 1 if os.path.exists(stats) else 0
                print("kill %2d %.2f s after %s: %d steps in stats.csv, readable"
                      % (kills, delay, "the launch" if from_launch else "set-up", done), flush=True)
                continue
            if proc.returncode != 0:
                print("round %d: a run ended with status %d:\n%s" % (rounds, proc.returncode, "".join(lines)))
                return 1
            break
        times, u, v = final_state(out)
        du, dv = float(np.abs(u - ref_u).max()), float(np.abs(v - ref_v).max())
        print("round %d complete: %d steps, max |u - u_ref| %.3e, max |v - v_ref| %.3e" % (rounds, len(times) - 1, du, dv),
              flush=True)
        if times != ref_times or du > 1e-12 or dv > 1e-12:
            print("round %d does not end where the uninterrupted run ends (times equal: %s)" % (rounds, times == ref_times))
            return 1
        check_readable(out)
    print("%d kills in %d round(s): every round ended at the uninterrupted run's state, output readable after every kill"
          % (kills, rounds))
    return 0


if __name__ == "__main__":
    sys.exit(main())

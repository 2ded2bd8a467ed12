"""A boundary condition that depends on the state: press a soft block until the press feels a force.

    mpiexec -n 2 /usr/bin/python3 examples/python/press_until_force.py [--target 30] [--steps 40] [--hold 5]
                                                                       [--out output/press_until_force]

(PYTHONPATH must hold the built module: build/python.) A rubber block rests on the ground plane;
a steel press, a kinematic body, comes down onto it at 5 cm/s. After every step the script sums
the contact force on the press's nodes (each rank its owned nodes, then an allreduce), and once
that force reaches --target newtons it stops the press where it stands
(set_motion(..., {"type": "fixed"})) and lets the block settle under it for --hold steps. Rank 0
prints step, press height, press force and contact pairs. The run writes its frames into --out
(plot them with plot_run.py). Fails (exit status 1) when the target is not reached within --steps
steps, or when the press moved after it was stopped.
"""
import argparse
import sys

import numpy as np
from mpi4py import MPI

import dipc

BLOCK_TOP = 0.051  # the block: 10 x 10 x 5 cm from z = 1 mm (its rest height)
PRESS_BOTTOM = BLOCK_TOP + 0.002
SPEED = 0.05  # press speed [m/s]


def scene(steps, out):
    """The scene in dipc's format (docs/scenes.md; keys: src/io/scene_parser.cpp)."""
    return {
        "materials": [{"name": "rubber", "E": 1e5, "nu": 0.3, "rho": 1000},
                      {"name": "steel", "E": 2e11, "nu": 0.3, "rho": 7800}],
        "geometry": [
            {"name": "block", "material": "rubber",
             "box": {"size": [0.1, 0.1, 0.05], "resolution": [6, 6, 3], "origin": [-0.05, -0.05, BLOCK_TOP - 0.05]}},
            # Kinematic: every node follows the motion, so the press has no unknowns of its own
            # but its nodes still take the barrier's force.
            {"name": "press", "material": "steel", "self_contact": False,
             "box": {"size": [0.06, 0.06, 0.02], "resolution": [3, 3, 1], "origin": [-0.03, -0.03, PRESS_BOTTOM]},
             "kinematic": {"type": "velocity", "velocity": [0, 0, -SPEED]}}],
        "boundary_conditions": {"gravity": [0, 0, -9.81]},
        "time": {"integrator": "implicit_euler", "dt": 0.01, "steps": steps},
        "output": {"directory": out, "name": "press", "every": 1},
        # Friction holds the block on the ground: without it nothing resists a sideways drift,
        # and round-off (different on each rank count) decides how far the block slides.
        "contact": {"enabled": True, "dhat": 5e-4, "dhat_relative": False, "friction": 0.5, "epsv": 1e-4,
                    "planes": [{"point": [0, 0, 0], "normal": [0, 0, 1]}]},
    }


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--target", type=float, default=30.0, help="press force [N] at which the press stops")
    parser.add_argument("--steps", type=int, default=40, help="most steps to take (pressing and holding)")
    parser.add_argument("--hold", type=int, default=5, help="steps to hold the press still after the target")
    parser.add_argument("--out", default="output/press_until_force", help="output folder")
    args = parser.parse_args()
    comm = MPI.COMM_WORLD
    say = print if comm.rank == 0 else (lambda *a, **k: None)

    with dipc.Simulation(scene(args.steps, args.out), options=["-dipc_quiet"], report=False) as sim:
        say("prescribed sets:", [s["name"] for s in sim.prescribed_sets()])
        # This rank's press nodes: the rows of its owned nodes in the press body's node set.
        press = sim.node_sets()["press"]
        stopped_at, held_steps = None, 0  # the step after which the press was stopped; steps since
        say(f"{'step':>4} {'press z [mm]':>12} {'force [N]':>10} {'pairs':>6}")
        while (report := sim.step()) is not None:
            # contact_forces() is collective: every rank calls it, then sums its press rows.
            force = comm.allreduce(sim.contact_forces()[press, 2].sum())
            z = comm.allreduce(sim.positions()[press, 2].min(initial=np.inf), op=MPI.MIN)
            say(f"{report['step']:4d} {1e3 * z:12.3f} {force:10.3f} {report['contact_pairs']:6d}"
                + ("  (held)" if stopped_at is not None else ""))
            if stopped_at is not None:
                held_steps += 1
                if held_steps == args.hold:
                    break
            elif force >= args.target:
                sim.set_motion("press", {"type": "fixed"})
                stopped_at = report["step"]
                held = sim.positions()[press]  # a copy (boolean index) of the live view positions()
                say(f"target {args.target:g} N reached: press stopped at step {stopped_at}")
        # Each rank compares its own press nodes; the allreduce gives every rank the same verdict.
        moved = np.abs(sim.positions()[press] - held).max(initial=0.0) if stopped_at is not None else 0.0
        moved = comm.allreduce(moved, op=MPI.MAX)
        sim.finish()

    if stopped_at is None:
        say(f"error: the press force never reached {args.target:g} N in {args.steps} steps")
        sys.exit(1)
    if held_steps < args.hold:
        say(f"error: only {held_steps} of --hold {args.hold} steps left after step {stopped_at}; raise --steps")
        sys.exit(1)
    if moved != 0.0:
        say(f"error: the press moved by {moved:.3g} m while it was held")
        sys.exit(1)
    say(f"held for {args.hold} steps; press nodes unchanged since step {stopped_at}; output in {args.out}")


if __name__ == "__main__":
    main()

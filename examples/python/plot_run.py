"""Plot a dipc run over time from its output files: body heights, kinetic energy, contact forces.

    /usr/bin/python3 examples/python/plot_run.py output/boxes_drop/boxes_drop.xmf [--png run.png]
    mpiexec -n 2 /usr/bin/python3 examples/python/plot_run.py --run [--steps 60] [--out output/plot_run]

(PYTHONPATH must hold the built module: build/python.) Reads the run with dipc.read_output and
draws, against time, the node-average height of each body, the kinetic energy (from the
stats.csv beside the output, when there is one) and the largest contact force on any node with
the number of contact pairs (contact scenes). With --run it first runs scenes/boxes_drop.json
for --steps steps on every rank, writing into --out, and plots that run. Rank 0 reads and draws;
the PNG goes to --png (default: beside the .xmf, <name>.png).
"""
import argparse
import os

import matplotlib

matplotlib.use("Agg")  # files only, no display
import matplotlib.pyplot as plt
import numpy as np
from mpi4py import MPI

import dipc

ROOT = os.path.dirname(os.path.dirname(os.path.dirname(os.path.abspath(__file__))))


def plot(xmf, png):
    out = dipc.read_output(xmf)
    print(out)
    fig, axes = plt.subplots(3, 1, sharex=True, figsize=(6, 8))

    # Height: a body's nodes are those of its elements; its height the mean z of those nodes
    # (a node average, not the centre of mass: the output has no masses).
    z = out.coordinates[:, 2] + out.field("displacement")[:, :, 2]
    for b, name in enumerate(out.body_names):
        nodes = np.unique(out.hexes[out.body == b])
        axes[0].plot(out.times, z[:, nodes].mean(axis=1), label=name)
    axes[0].set_ylabel("mean node height [m]")
    axes[0].legend()

    if out.stats is not None:
        axes[1].plot(out.stats["t"], out.stats["kinetic_energy"])
    axes[1].set_ylabel("kinetic energy [J]")

    if "contact_force" in out.fields:
        force = np.linalg.norm(out.field("contact_force"), axis=2).max(axis=1)
        axes[2].plot(out.times, force)
        pairs = sum(out.contact_pairs.values())
        twin = axes[2].twinx()
        twin.plot(out.times, pairs, "C1--")
        twin.set_ylabel("contact pairs")
        axes[2].set_ylabel("largest contact force [N]")
        print(f"largest contact force {force.max():.3g} N at t = {out.times[force.argmax()]:g} s; "
              f"at most {pairs.max()} contact pairs")
    axes[2].set_xlabel("t [s]")

    fig.suptitle(os.path.basename(xmf))
    fig.tight_layout()
    fig.savefig(png, dpi=120)
    print(f"wrote {png}")


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("xmf", nargs="?", help="the run's .xmf (or .h5); not with --run")
    parser.add_argument("--run", action="store_true", help="first run scenes/boxes_drop.json and plot that")
    parser.add_argument("--steps", type=int, default=60, help="steps of the --run run (default 60)")
    parser.add_argument("--out", default="output/plot_run", help="output folder of the --run run")
    parser.add_argument("--png", help="the picture (default: <xmf without suffix>.png)")
    args = parser.parse_args()
    if args.run == (args.xmf is not None):
        parser.error("give either an .xmf or --run")

    xmf = args.xmf
    if args.run:
        options = ["-dipc_steps", str(args.steps), "-dipc_output", args.out, "-dipc_quiet"]
        with dipc.Simulation(os.path.join(ROOT, "scenes", "boxes_drop.json"), options=options, report=False) as sim:
            xmf = sim.run()["xdmf_path"]
    if MPI.COMM_WORLD.rank == 0:
        plot(xmf, args.png or os.path.splitext(xmf)[0] + ".png")


if __name__ == "__main__":
    main()

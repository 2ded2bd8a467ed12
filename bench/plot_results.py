#!/usr/bin/env python3
"""Draws the benchmark CSVs of bench/ as PNG plots (Debian: apt-get install python3-matplotlib).

  bench/plot_results.py --assembly bench/results/assembly_throughput_h100.csv \
      --breakdown bench/results/newton_breakdown_h200.csv \
      --crossover bench/results/crossover_h200.csv \
      --weak bench/results/weak_scaling_h200.csv \
      --broad-phase bench/results/broad_phase_h100.csv --out bench/results

--assembly: bench_assembly_throughput CSV -> elements/s against elements, GPU and CPU.
--breakdown, --crossover, --weak: bench_step_breakdown CSVs (several concatenated are fine):
  per-Newton-iteration phases as stacked bars per configuration; seconds per Newton iteration
  against elements per backend; per-phase time against GPU count.
--strong: bench_step_breakdown CSVs of one size on several rank counts (bench/gpu_runs.sh
  strong) -> speedup of each phase and of the whole step over 1 rank, one panel per size, one
  line style per OpenMP threads-per-rank setting; also prints the speedup table.
--broad-phase: bench_broad_phase CSV -> seconds per search against triangles, CPU and GPU.
"""
import argparse
import csv
import os

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PHASES = [("assembly_s", "assembly (minus COO insert)"), ("coo_insert_s", "COO insert"),
          ("line_search_s", "line search"), ("contact_s", "contact (CCD, broad phase)"),
          ("amg_setup_s", "AMG setup"), ("ksp_solve_s", "KSP solve")]


def rows(paths):
    out = []
    for path in paths:
        with open(path) as f:
            out += [r for r in csv.DictReader(f) if r and not r[list(r)[0]].startswith("#")]
    return out


def per_newton(r, key):
    its = max(1.0, float(r["newton_its"]))
    v = float(r[key])
    if key == "assembly_s":
        v -= float(r["coo_insert_s"])
    return v / its


def config(r):
    return f'{r["backend"]} / {r["mat_type"]} / {r["ranks"]} rank{"s" if r["ranks"] != "1" else ""}'


def save_loglog(out, name, title, xlabel, ylabel, series):
    """One log-log figure of (x, y, style, label) series, saved as out/name."""
    fig, ax = plt.subplots(figsize=(6, 4))
    for x, y, style, label in series:
        ax.loglog(x, y, style, label=label)
    ax.set_xlabel(xlabel)
    ax.set_ylabel(ylabel)
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8)
    ax.set_title(title)
    fig.tight_layout()
    fig.savefig(os.path.join(out, name), dpi=120)


def plot_assembly(path, out):
    data = rows([path])
    n = [float(r["elements"]) for r in data]
    save_loglog(out, "assembly_throughput.png", "neo-Hookean hex8 assembly throughput", "elements",
                "elements / s (value + gradient + PSD Hessian into COO)",
                [(n, [float(r["gpu_elements_per_s"]) for r in data], "o-", "GPU (one device)"),
                 (n, [float(r["cpu_elements_per_s"]) for r in data], "s-", f'CPU ({data[0]["cpu_ranks"]} MPI ranks)')])


def plot_breakdown(paths, out):
    data = rows(paths)
    labels = [f'{config(r)}\n{int(r["elements"]):,} el.' for r in data]
    fig, ax = plt.subplots(figsize=(max(6, 1.6 * len(data)), 4.5))
    bottom = [0.0] * len(data)
    for key, name in PHASES:
        vals = [per_newton(r, key) for r in data]
        ax.bar(range(len(data)), vals, bottom=bottom, label=name)
        bottom = [b + v for b, v in zip(bottom, vals)]
    ax.set_xticks(range(len(data)))
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_ylabel("seconds per Newton iteration")
    ax.set_yscale("log")
    ax.legend(fontsize=7)
    ax.set_title("Newton iteration breakdown")
    fig.tight_layout()
    fig.savefig(os.path.join(out, "newton_breakdown.png"), dpi=120)


def plot_crossover(paths, out):
    data = rows(paths)
    series = []
    for c in sorted({config(r) for r in data}):
        pts = sorted((int(r["elements"]), float(r["per_newton_s"])) for r in data if config(r) == c)
        series.append(([p[0] for p in pts], [p[1] for p in pts], "o-", c))
    save_loglog(out, "crossover.png", "CPU against GPU backend (auto's crossover)", "elements per rank",
                "seconds per Newton iteration", series)


def plot_weak(paths, out):
    """One panel per solver configuration (the CSV's optional "config" column)."""
    data = rows(paths)
    configs = list(dict.fromkeys(r.get("config", "") for r in data))
    fig, axes = plt.subplots(1, len(configs), figsize=(6 * len(configs), 4), sharey=True, squeeze=False)
    for ax, name in zip(axes[0], configs):
        sel = sorted((r for r in data if r.get("config", "") == name), key=lambda r: int(r["ranks"]))
        gpus = [int(r["ranks"]) for r in sel]
        for key, label in PHASES:
            ax.plot(gpus, [per_newton(r, key) for r in sel], "o-", label=label)
        ax.plot(gpus, [float(r["per_newton_s"]) for r in sel], "k*-", label="total per Newton iteration")
        ax.set_xticks(gpus)
        ax.set_xlabel("GPUs (one rank each)")
        ax.set_yscale("log")
        ax.grid(True, alpha=0.3)
        per_gpu = int(sel[0]["elements"]) // max(1, gpus[0])
        ax.set_title(f"{name + ': ' if name else ''}weak scaling, {per_gpu:,} elements per GPU", fontsize=9)
    axes[0][0].set_ylabel("seconds per Newton iteration")
    axes[0][0].legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "weak_scaling.png"), dpi=120)


def plot_strong(paths, out):
    """Speedup over one rank of each phase (seconds of the slowest rank, not per Newton iteration:
    the rank count can change the iterations) and of the whole step loop (assembly + line search
    + linear solve, per_step_s)."""
    data = rows(paths)
    sizes = sorted({int(r["elements"]) for r in data})
    threads = sorted({r.get("threads_per_rank", "") for r in data})
    keys = [("per_step_s", "whole step"), ("assembly_s", "assembly"), ("amg_setup_s", "AMG setup"),
            ("ksp_solve_s", "KSP solve"), ("setup_s", "setup")]
    fig, axes = plt.subplots(1, len(sizes), figsize=(6 * len(sizes), 4.5), squeeze=False)
    for ax, n in zip(axes[0], sizes):
        for t, style in zip(threads, ["-", "--", ":"]):
            sel = sorted((r for r in data if int(r["elements"]) == n and r.get("threads_per_rank", "") == t),
                         key=lambda r: int(r["ranks"]))
            base = [r for r in sel if int(r["ranks"]) == 1]
            if not base:
                continue
            ranks = [int(r["ranks"]) for r in sel]
            for (key, label), marker in zip(keys, "o^sDv"):
                speedup = [float(base[0][key]) / max(1e-12, float(r[key])) for r in sel]
                ax.plot(ranks, speedup, marker + style, label=f"{label}, {t} thread(s)/rank")
                print(f"{n} elements, {t} thread(s) per rank, {label}: " +
                      ", ".join(f"{q} ranks {v:.2f}x" for q, v in zip(ranks, speedup)))
        top = max(int(r["ranks"]) for r in data)
        ax.plot([1, top], [1, top], "k:", lw=0.8, label="ideal")
        ax.set_xscale("log", base=2)
        ax.set_yscale("log", base=2)
        ax.set_xlabel("MPI ranks")
        ax.set_ylabel("speedup over 1 rank")
        ax.set_title(f"CPU strong scaling, {n:,} elements", fontsize=9)
        ax.grid(True, alpha=0.3)
        ax.legend(fontsize=6)
    fig.tight_layout()
    fig.savefig(os.path.join(out, "strong_scaling.png"), dpi=120)


def plot_broad_phase(path, out):
    data = rows([path])
    n = [int(r["triangles"]) for r in data]
    save_loglog(out, "broad_phase.png", "contact broad phase", "surface triangles",
                "seconds per search (swept boxes)",
                [(n, [float(r["cpu_seconds"]) for r in data], "s-", "CPU (one core, BVH)"),
                 (n, [float(r["gpu_seconds"]) for r in data], "o-", "GPU (linear BVH, lists back on the host)")])


def main():
    p = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    p.add_argument("--assembly")
    p.add_argument("--breakdown", nargs="*", default=[])
    p.add_argument("--crossover", nargs="*", default=[])
    p.add_argument("--weak", nargs="*", default=[])
    p.add_argument("--strong", nargs="*", default=[])
    p.add_argument("--broad-phase")
    p.add_argument("--out", default=".")
    a = p.parse_args()
    os.makedirs(a.out, exist_ok=True)
    if a.assembly:
        plot_assembly(a.assembly, a.out)
    if a.breakdown:
        plot_breakdown(a.breakdown, a.out)
    if a.crossover:
        plot_crossover(a.crossover, a.out)
    if a.weak:
        plot_weak(a.weak, a.out)
    if a.strong:
        plot_strong(a.strong, a.out)
    if a.broad_phase:
        plot_broad_phase(a.broad_phase, a.out)


if __name__ == "__main__":
    main()

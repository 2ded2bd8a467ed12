#!/usr/bin/python3
"""The extremes matrix: writes the scenes of cases.py, runs each with dipc on 1 and 2 ranks
(-dipc_check_invariants), judges every written step with tests/tools/judge_output.py, and
collects per case and rank count the outcome, iterations, distances, drifts, wall time and
the agreement of the final displacements across rank counts.

    extremes.py generate DIR                     # write DIR/<case>.json
    extremes.py run [--ci] [--ranks 1 2] [--dipc build/src/app/dipc] [--cases REGEX]
                    [--work DIR] [--results bench/results] [--timeout S]
    extremes.py report bench/results/extremes.csv  # redraw the PNG, print the table

`run` writes <results>/extremes.csv and extremes.png and prints a Markdown table. A case that
dipc fails is recorded (exit status and its last `dipc: error:` line), never fatal. With --ci
only the quick representative cases run (CI_CASES), the results go to the work folder, and
the exit status is 1 when any of them fails or the judge finds an inversion, a crossing or a
non-positive distance.
"""
import argparse
import json
import os
import re
import shlex
import signal
import subprocess
import sys
import time

HERE = os.path.dirname(os.path.abspath(__file__))
ROOT = os.path.dirname(os.path.dirname(HERE))
sys.path.insert(0, os.path.join(ROOT, 'tests', 'tools'))

import cases  # noqa: E402
import collect  # noqa: E402
import report  # noqa: E402

# Quick cases that finish and span the knobs: a soft and the stiffest material,
# near-incompressible, the smallest time step, a 100 m/s impact (taken in cut steps: step
# recovery), a small d̂, a density ratio, the stack and the plates squeezing a soft box. The cases that do not finish (E_1e2,
# impact_200, heavy_on_light, dhat_1e-7) are explained in README "Extremes matrix".
CI_CASES = ['E_1e4', 'E_2e11', 'nu_0.499', 'dt_1e-5', 'impact_100', 'dhat_1e-5', 'light_on_heavy', 'stack_5',
            'squeeze_plates']


def write_scenes(directory, names=None):
    os.makedirs(directory, exist_ok=True)
    written = {}
    for name, (group, s) in cases.all_cases().items():
        if names is not None and name not in names:
            continue
        path = os.path.join(directory, f'{name}.json')
        with open(path, 'w') as f:
            json.dump(s, f, indent=1)
        written[name] = (group, s, path)
    return written


def run_dipc(args, scene_path, ranks, out_dir):
    """Runs one case; returns (exit status or 'timeout', wall seconds, last error line)."""
    os.makedirs(out_dir, exist_ok=True)
    cmd = (shlex.split(args.mpiexec) + ['-n', str(ranks), args.dipc, scene_path, '-dipc_check_invariants',
                                         '-dipc_output', out_dir] + shlex.split(args.dipc_options))
    env = dict(os.environ, OMPI_ALLOW_RUN_AS_ROOT='1', OMPI_ALLOW_RUN_AS_ROOT_CONFIRM='1',
               OMPI_MCA_rmaps_base_oversubscribe='1')
    start = time.monotonic()
    with open(os.path.join(out_dir, 'log.txt'), 'w') as log:
        # Its own process group, so that a timeout ends the launcher and every rank it started.
        proc = subprocess.Popen(cmd, stdout=log, stderr=subprocess.STDOUT, env=env, start_new_session=True)
        try:
            status = proc.wait(timeout=args.timeout)
        except subprocess.TimeoutExpired:
            os.killpg(proc.pid, signal.SIGKILL)
            proc.wait()
            status = 'timeout'
    wall = time.monotonic() - start
    with open(os.path.join(out_dir, 'log.txt'), errors='replace') as log:
        errors = [line.strip() for line in log if line.startswith('dipc: error:')]
    return status, wall, errors[-1] if errors else ''


def main(argv):
    parser = argparse.ArgumentParser(description=__doc__.split('\n\n')[0])
    sub = parser.add_subparsers(dest='command', required=True)
    gen = sub.add_parser('generate', help='write the scenes')
    gen.add_argument('directory')
    run = sub.add_parser('run', help='run, judge and report')
    run.add_argument('--ci', action='store_true', help='only the CI subset; exit 1 on any failure')
    run.add_argument('--ranks', type=int, nargs='+', default=[1, 2])
    run.add_argument('--dipc', default=os.environ.get('DIPC', os.path.join(ROOT, 'build', 'src', 'app', 'dipc')))
    run.add_argument('--mpiexec', default=os.environ.get('MPIEXEC', 'mpirun'), help='launcher and its flags')
    run.add_argument('--dipc-options', default='', help='extra options for every dipc run')
    run.add_argument('--cases', help='regular expression selecting case names')
    run.add_argument('--work', default=os.path.join(ROOT, 'output', 'extremes'), help='scenes and outputs')
    run.add_argument('--results', help='CSV/PNG folder (default bench/results; with --ci the work folder)')
    run.add_argument('--timeout', type=float, default=600, help='seconds per dipc run')
    run.add_argument('--no-plot', action='store_true')
    rep = sub.add_parser('report', help='redraw the PNG and print the table from a CSV of `run`')
    rep.add_argument('csv')
    args = parser.parse_args(argv)

    if args.command == 'report':
        rows = report.read_csv(args.csv)
        report.plot(rows, os.path.splitext(args.csv)[0] + '.png')
        print(report.markdown(rows))
        return 0

    if args.command == 'generate':
        for name in write_scenes(args.directory):
            print(os.path.join(args.directory, f'{name}.json'))
        return 0

    names = CI_CASES if args.ci else None
    selected = write_scenes(os.path.join(args.work, 'scenes'), names)
    if args.cases:
        selected = {n: v for n, v in selected.items() if re.search(args.cases, n)}
    rows = []
    for name, (group, s, scene_path) in selected.items():
        first_rank_h5 = None
        for ranks in sorted(args.ranks):
            out_dir = os.path.join(args.work, name, f'np{ranks}')
            status, wall, error = run_dipc(args, scene_path, ranks, out_dir)
            row = collect.collect(name, group, s, scene_path, ranks, out_dir, status, wall, error, first_rank_h5)
            if ranks == 1:
                first_rank_h5 = os.path.join(out_dir, 'run.h5')
            rows.append(row)
            print(report.progress_line(row), flush=True)
    results = args.results or (args.work if args.ci else os.path.join(ROOT, 'bench', 'results'))
    os.makedirs(results, exist_ok=True)
    report.write_csv(rows, os.path.join(results, 'extremes.csv'))
    if not args.no_plot:
        report.plot(rows, os.path.join(results, 'extremes.png'))
    print(report.markdown(rows))
    failed = [f"{r['case']} np{r['ranks']}" for r in rows if not r['ok']]
    if args.ci and failed:
        print('extremes --ci: failed: ' + ', '.join(failed), file=sys.stderr)
        return 1
    return 0


if __name__ == '__main__':
    sys.exit(main(sys.argv[1:]))

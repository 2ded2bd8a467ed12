#!/usr/bin/env python3
"""Runs every shipped scene with two dipc binaries and compares their work: Newton and CG
iterations, dt cuts, wall time, and how far their final displacements differ.

    bench/compare_builds.py --before OLD/dipc --after NEW/dipc [--ranks 2] [--max-steps 60]
                            [--csv bench/results/compare_builds.csv]

Each run writes to a scratch folder and is read back from its stats.csv and HDF5 file, so the
two binaries may differ in what they print. Wall times are whole-process times of one run each:
repeat the comparison before quoting a time.
"""
import argparse
import csv
import glob
import json
import os
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def run(binary, scene, ranks, steps, outdir, extra):
    cmd = ['mpiexec', '--oversubscribe', '--allow-run-as-root', '-n', str(ranks), binary]
    if scene:
        cmd.append(scene)
    cmd += ['-dipc_quiet', '-dipc_output', outdir] + (['-dipc_steps', str(steps)] if steps else []) + extra
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    wall = time.time() - start
    stats = os.path.join(outdir, 'stats.csv')
    rows = list(csv.DictReader(open(stats))) if os.path.exists(stats) else []
    total = lambda key: sum(float(r[key]) for r in rows if r.get(key) not in (None, ''))
    h5 = glob.glob(os.path.join(outdir, '*.h5'))
    u = None
    if h5:
        with h5py.File(h5[0], 'r') as f:
            last = max(f['steps'], key=int) if 'steps' in f else None
            if last is not None:
                u = np.array(f['steps'][last]['displacement'])
    return {'status': proc.returncode, 'steps': len(rows), 'newton': total('newton_its'), 'ksp': total('ksp_its'),
            'cuts': total('dt_cuts') if rows and 'dt_cuts' in rows[0] else 0, 'wall': wall, 'u': u,
            'error': next((l for l in proc.stdout.splitlines() if l.startswith('dipc: error')), '')}


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('--before', required=True)
    ap.add_argument('--after', required=True)
    ap.add_argument('--ranks', type=int, default=2)
    ap.add_argument('--max-steps', type=int, default=0, help='cap every scene at this many steps (0: the scene\'s)')
    ap.add_argument('--scenes', nargs='*', help='scene files (default: the default scene and scenes/*.json)')
    ap.add_argument('--options', default='', help='extra options for both binaries')
    ap.add_argument('--csv', default='')
    args = ap.parse_args()
    scenes = args.scenes if args.scenes is not None else [''] + sorted(glob.glob(os.path.join(ROOT, 'scenes', '*.json')))
    fields = ['scene', 'steps', 'newton_before', 'newton_after', 'ksp_before', 'ksp_after', 'cuts_after',
              'wall_before_s', 'wall_after_s', 'max_du_over_max_u', 'status_before', 'status_after']
    out = []
    print('| scene | steps | Newton before → after | CG before → after | dt cuts | wall s before → after | final u difference |')
    print('|---|---|---|---|---|---|---|')
    for scene in scenes:
        name = os.path.splitext(os.path.basename(scene))[0] if scene else 'default'
        scene_steps = json.load(open(scene))['time'].get('steps', 1) if scene else 40  # the default scene: 40
        steps = min(scene_steps, args.max_steps) if args.max_steps else 0
        with tempfile.TemporaryDirectory() as tmp:
            b = run(args.before, scene, args.ranks, steps, os.path.join(tmp, 'b'), args.options.split())
            a = run(args.after, scene, args.ranks, steps, os.path.join(tmp, 'a'), args.options.split())
        diff = float('nan')
        if b['u'] is not None and a['u'] is not None and b['u'].shape == a['u'].shape:
            diff = float(np.abs(a['u'] - b['u']).max() / max(np.abs(b['u']).max(), 1e-300))
        row = dict(scene=name, steps=a['steps'], newton_before=b['newton'], newton_after=a['newton'], ksp_before=b['ksp'],
                   ksp_after=a['ksp'], cuts_after=a['cuts'], wall_before_s=round(b['wall'], 2),
                   wall_after_s=round(a['wall'], 2), max_du_over_max_u=diff, status_before=b['status'],
                   status_after=a['status'])
        out.append(row)
        note = '' if a['status'] == 0 and b['status'] == 0 else f" (exit {b['status']} → {a['status']}: {a['error'] or b['error']})"
        print(f"| {name} | {a['steps']} | {b['newton']:.0f} → {a['newton']:.0f} | {b['ksp']:.0f} → {a['ksp']:.0f} | "
              f"{a['cuts']:.0f} | {b['wall']:.1f} → {a['wall']:.1f} | {diff:.1e}{note} |", flush=True)
    if args.csv:
        with open(args.csv, 'w', newline='') as f:
            w = csv.DictWriter(f, fieldnames=fields)
            w.writeheader()
            w.writerows(out)
    return 0


if __name__ == '__main__':
    sys.exit(main())

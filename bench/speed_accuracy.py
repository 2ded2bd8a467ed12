#!/usr/bin/env python3
"""Speed or accuracy: what each solver knob buys and costs on one scene (issue 12, part 1).

    bench/speed_accuracy.py [scene.json] [--binary build/src/app/dipc] [--ranks 1] [--steps N]
                            [--out bench/results]

Runs a tight reference (-dipc_velocity_tol_rel 1e-7 -ksp_rtol 1e-10), the defaults, and one run
per setting of each knob, varied alone from the defaults:

  vtol     -dipc_velocity_tol_rel 1e-3, 1e-4, 1e-6 (default 1e-5)
  ksp      -ksp_rtol 1e-3, 1e-4, 1e-6 (default 1e-8)
  pc_reuse -dipc_pc_reuse
  dhat     contact.dhat x0.1 and x10 (contact scenes; a temporary copy of the scene JSON)
  dt       time.dt x0.5 and x2, steps scaled to keep the end time (compared at the common times)
  fric_its contact.friction_iterations 2 (where contact.friction > 0)

Against the reference, per run: `err_max` = max over the common output times of
max_node |u - u_ref| / max_{t,node} |u_ref| (the error relative to the motion), `err_rms` the
same with RMS norms over the nodes, and `energy_diff` = (E_end - E_end_ref) / (max_t E_ref -
min_t E_ref), E = kinetic + elastic + gravity energy from stats.csv (the difference of the end
energies relative to how much the reference's energy changed over the run). Cost: `wall_s` the
sum of stats.csv's wall_s (the steps; setup excluded), `process_s` the whole process, Newton
and CG iterations, dt cuts. Writes <out>/speed_accuracy_<scene>.csv and .png (err_max against
wall_s, log-log, Pareto front marked) and prints a Markdown table. --steps caps the scene's steps
(the dt variants run 2N and N/2 steps). Wall times are of one run each: on a shared machine
repeat before quoting them.
"""
import argparse
import copy
import csv
import json
import os
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENE_JSON = os.path.join(ROOT, 'tests', 'io', 'data', 'default_scene.json')  # == the embedded default
MODEL_KNOBS = ('dhat', 'dt', 'fric_its')  # change the discrete problem, not only how well it is solved
REFERENCE = ['-dipc_velocity_tol_rel', '1e-7', '-ksp_rtol', '1e-10']


def scene_steps(scene):
    t = scene['time']
    if 'steps' in t:
        return int(t['steps'])
    return int(round(float(t['t_end']) / float(t['dt'])))


def write_variant(scene, scene_dir, tmp, name, edit):
    """A copy of the scene with `edit` applied, mesh paths made absolute, written into tmp."""
    s = copy.deepcopy(scene)
    for body in s.get('geometry', []):
        if 'mesh' in body and not os.path.isabs(body['mesh']):
            body['mesh'] = os.path.normpath(os.path.join(scene_dir, body['mesh']))
    edit(s)
    path = os.path.join(tmp, name + '.json')
    with open(path, 'w') as f:
        json.dump(s, f, indent=1)
    return path


def read_run(outdir):
    stats = os.path.join(outdir, 'stats.csv')
    rows = list(csv.DictReader(open(stats))) if os.path.exists(stats) else []
    fields = {}
    h5 = [p for p in os.listdir(outdir) if p.endswith('.h5')] if os.path.isdir(outdir) else []
    if h5:
        with h5py.File(os.path.join(outdir, h5[0]), 'r') as f:
            for k in f.get('steps', {}):
                g = f['steps'][k]
                fields[round(float(g.attrs['time']), 9)] = np.array(g['displacement'])
    return rows, fields


def run(binary, scene, ranks, steps, outdir, extra):
    cmd = ['mpiexec', '--oversubscribe', '--allow-run-as-root', '-n', str(ranks), binary]
    if scene:
        cmd.append(scene)
    cmd += ['-dipc_quiet', '-dipc_output', outdir, '-dipc_steps', str(steps)] + extra
    start = time.time()
    proc = subprocess.run(cmd, capture_output=True, text=True)
    process_s = time.time() - start
    rows, fields = read_run(outdir)
    total = lambda key: sum(float(r[key]) for r in rows if r.get(key) not in (None, ''))
    energy = [float(r['kinetic_energy']) + float(r['elastic_energy']) + float(r['gravity_energy']) for r in rows]
    err = next((l for l in (proc.stdout + proc.stderr).splitlines() if l.startswith('dipc: ')
                and ('error' in l or 'failed' in l or 'stop' in l)), '')
    return {'status': proc.returncode, 'steps': len(rows), 'newton': total('newton_its'), 'ksp': total('ksp_its'),
            'cuts': total('dt_cuts'), 'wall': total('wall_s'), 'process': process_s, 'energy': energy,
            'fields': fields, 'message': err}


def compare(run_, ref):
    common = sorted(set(run_['fields']) & set(ref['fields']))
    common = [t for t in common if t > 0]
    if run_['status'] != 0 or not common:
        return float('nan'), float('nan'), float('nan'), 0
    norm = lambda u: np.linalg.norm(u, axis=1)
    u_max = max(norm(u).max() for t, u in ref['fields'].items())
    u_rms = max(np.sqrt(np.mean(norm(u) ** 2)) for t, u in ref['fields'].items())
    e_max = max(norm(run_['fields'][t] - ref['fields'][t]).max() for t in common) / max(u_max, 1e-300)
    e_rms = max(np.sqrt(np.mean(norm(run_['fields'][t] - ref['fields'][t]) ** 2)) for t in common) / max(u_rms, 1e-300)
    e_ref = ref['energy']
    de = float('nan')
    if run_['energy'] and e_ref:
        de = (run_['energy'][-1] - e_ref[-1]) / max(max(e_ref) - min(e_ref), 1e-300)
    return float(e_max), float(e_rms), float(de), len(common)


def pareto(points):
    """Indices of the points no other point beats in both wall time and error."""
    front = []
    for i, (w, e) in enumerate(points):
        if not np.isfinite(e):
            continue
        if not any((w2 <= w and e2 <= e) and (w2 < w or e2 < e) for j, (w2, e2) in enumerate(points)
                   if j != i and np.isfinite(e2)):
            front.append(i)
    return front


def plot(rows, ref, path, title):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    pts = [(r['wall_s'], r['err_max']) for r in rows]
    front = set(pareto(pts))
    fig, ax = plt.subplots(figsize=(7.5, 5))
    for i, r in enumerate(rows):
        w, e = pts[i]
        if not np.isfinite(e) or e <= 0:
            continue
        model = r['knob'] in MODEL_KNOBS
        ax.scatter([w], [e], color='C3' if i in front else 'C0', s=40 if i in front else 20, zorder=3,
                   marker='^' if model else 'o')
        ax.annotate(r['setting'], (w, e), textcoords='offset points', xytext=(4, 3), fontsize=8)
    fr = sorted((pts[i] for i in front if pts[i][1] > 0), key=lambda p: p[0])
    if fr:
        ax.plot([p[0] for p in fr], [p[1] for p in fr], color='C3', lw=1, ls='--', label='Pareto front')
    ax.scatter([], [], marker='^', color='grey', label='changes the discretisation (dhat, dt, friction)')
    ax.axvline(ref['wall'], color='grey', lw=0.8, ls=':', label=f"reference ({ref['wall']:.1f} s)")
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel('wall time of the steps [s] (stats.csv wall_s, one run, shared machine)')
    ax.set_ylabel('max |u - u_ref| / max |u_ref|')
    ax.set_title(title)
    ax.grid(True, which='both', alpha=0.3)
    ax.legend(fontsize=8)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene', nargs='?', default='', help='scene file (default: the embedded default scene)')
    ap.add_argument('--binary', default=os.path.join(ROOT, 'build', 'src', 'app', 'dipc'))
    ap.add_argument('--ranks', type=int, default=1)
    ap.add_argument('--steps', type=int, default=0, help="cap the scene's steps at N (0: the scene's)")
    ap.add_argument('--out', default=os.path.join(ROOT, 'bench', 'results'))
    ap.add_argument('--options', default='', help='extra options for every run')
    ap.add_argument('--plot-only', action='store_true', help='redraw the PNG from the CSV of an earlier study')
    args = ap.parse_args()
    if args.plot_only:
        name = os.path.splitext(os.path.basename(args.scene))[0] if args.scene else 'default'
        base = os.path.join(args.out, f'speed_accuracy_{name}')
        rows = [{k: (float(v) if k in ('err_max', 'err_rms', 'energy_diff', 'wall_s') else v) for k, v in r.items()}
                for r in csv.DictReader(open(base + '.csv'))]
        plot(rows[1:], {'wall': rows[0]['wall_s']}, base + '.png',
             f"{name}: {rows[0]['steps']} steps, error against the tight reference")
        return 0

    name = os.path.splitext(os.path.basename(args.scene))[0] if args.scene else 'default'
    scene_path = args.scene or DEFAULT_SCENE_JSON
    scene = json.load(open(scene_path))
    scene_dir = os.path.dirname(os.path.abspath(scene_path))
    n = min(scene_steps(scene), args.steps) if args.steps else scene_steps(scene)
    dt = float(scene['time']['dt'])
    contact = scene.get('contact', {})
    has_contact = bool(contact.get('enabled', False))
    friction = float(contact.get('friction', 0) or 0) if has_contact else 0.0
    extra = args.options.split()

    with tempfile.TemporaryDirectory() as tmp:
        def variant(tag, edit):
            return write_variant(scene, scene_dir, tmp, tag, edit)

        def set_time(factor):
            def edit(s):
                s['time']['dt'] = dt * factor
                s['time'].pop('t_end', None)
                s['time']['steps'] = max(1, int(round(scene_steps(scene) / factor)))
            return edit

        def set_contact(key, value):
            def edit(s):
                s['contact'][key] = value
            return edit

        # (setting, knob, scene file, steps, options)
        plan = [('default', 'default', args.scene, n, [])]
        plan += [(f'vtol {v}', 'vtol', args.scene, n, ['-dipc_velocity_tol_rel', v]) for v in ('1e-3', '1e-4', '1e-6')]
        plan += [(f'ksp {v}', 'ksp', args.scene, n, ['-ksp_rtol', v]) for v in ('1e-3', '1e-4', '1e-6')]
        plan += [('pc_reuse', 'pc_reuse', args.scene, n, ['-dipc_pc_reuse'])]
        if has_contact:
            d = float(contact.get('dhat', 1e-3))
            for f in (0.1, 10):
                if contact.get('dhat_relative', True) and not d * f < 1:
                    continue
                plan.append((f'dhat x{f:g}', 'dhat', variant(f'dhat{f:g}', set_contact('dhat', d * f)), n, []))
        for f in (0.5, 2):
            steps = max(1, int(round(n / f)))
            plan.append((f'dt x{f:g}', 'dt', variant(f'dt{f:g}', set_time(f)), steps, []))
        if friction > 0:
            plan.append(('fric_its 2', 'fric_its', variant('fric2', set_contact('friction_iterations', 2)), n, []))

        print(f'# {name}: {n} steps of dt {dt:g}, {args.ranks} rank(s), {len(plan) + 1} runs', file=sys.stderr)
        ref = run(args.binary, args.scene, args.ranks, n, os.path.join(tmp, 'ref'), REFERENCE + extra)
        if ref['status'] != 0:
            print(f"reference failed (exit {ref['status']}): {ref['message']}", file=sys.stderr)
            return 2
        print(f"#   reference: {ref['wall']:.2f} s, {ref['newton']:.0f} Newton, {ref['ksp']:.0f} CG", file=sys.stderr)
        rows = [dict(scene=name, setting='reference', knob='reference', steps=ref['steps'], status=0, err_max=0.0,
                     err_rms=0.0, energy_diff=0.0, compared_times=len(ref['fields']) - 1, wall_s=round(ref['wall'], 3),
                     process_s=round(ref['process'], 2), newton_its=ref['newton'], ksp_its=ref['ksp'],
                     dt_cuts=ref['cuts'], pareto='')]
        for i, (setting, knob, sc, steps, opts) in enumerate(plan):
            r = run(args.binary, sc, args.ranks, steps, os.path.join(tmp, f'run{i}'), opts + extra)
            e_max, e_rms, de, ncmp = compare(r, ref)
            rows.append(dict(scene=name, setting=setting, knob=knob, steps=r['steps'], status=r['status'],
                             err_max=e_max, err_rms=e_rms, energy_diff=de, compared_times=ncmp,
                             wall_s=round(r['wall'], 3), process_s=round(r['process'], 2), newton_its=r['newton'],
                             ksp_its=r['ksp'], dt_cuts=r['cuts'], pareto=''))
            note = f" exit {r['status']}: {r['message']}" if r['status'] else ''
            print(f"#   {setting}: {r['wall']:.2f} s, err {e_max:.2e}{note}", file=sys.stderr)

    runs = rows[1:]
    for i in pareto([(r['wall_s'], r['err_max']) for r in runs]):
        runs[i]['pareto'] = 'yes'
    os.makedirs(args.out, exist_ok=True)
    csv_path = os.path.join(args.out, f'speed_accuracy_{name}.csv')
    with open(csv_path, 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f'{v:.3e}' if isinstance(v, float) and k in ('err_max', 'err_rms', 'energy_diff') else v)
                        for k, v in r.items()})
    png_path = os.path.join(args.out, f'speed_accuracy_{name}.png')
    plot(runs, ref, png_path, f'{name}: {n} steps, error against the tight reference')

    print(f'{name}, {n} steps of dt {dt:g}, {args.ranks} rank(s) (reference: -dipc_velocity_tol_rel 1e-7 -ksp_rtol 1e-10)\n')
    print('| setting | max-norm error | RMS error | energy diff | wall [s] | Newton | CG | dt cuts | Pareto |')
    print('|---|---|---|---|---|---|---|---|---|')
    fmt = lambda x: '0' if x == 0 else ('failed' if not np.isfinite(x) else f'{x:.1e}')
    for r in rows:
        status = f" (exit {r['status']})" if r['status'] else ''
        print(f"| {r['setting']}{status} | {fmt(r['err_max'])} | {fmt(r['err_rms'])} | {fmt(r['energy_diff'])} | "
              f"{r['wall_s']:.2f} | {r['newton_its']:.0f} | {r['ksp_its']:.0f} | {r['dt_cuts']:.0f} | "
              f"{'✓' if r['pareto'] else ''} |")
    print(f'\nwrote {csv_path} and {png_path}', file=sys.stderr)
    return 0


if __name__ == '__main__':
    sys.exit(main())

#!/usr/bin/env python3
"""Speed or accuracy: what each solver knob and preset buys and costs on one scene (issue 12).

    bench/speed_accuracy.py [scene.json] [--binary build/src/app/dipc] [--ranks 1] [--steps N]
                            [--repeat R] [--out bench/results] [--options '...'] [--knobs a,b]
                            [--tag NAME] [--cost cpu|wall]

Runs a tight reference, dipc's built-in solver values (those before presets existed), the three
presets (scenes/solver/presets/*.opts, passed with -options_file so that the study also runs a
binary without -dipc_preset) and one run per setting of each knob, varied alone from the
built-in values. Every run names all three solver options, so the preset a binary applies by
default changes none of them:

  reference  -dipc_velocity_tol_rel 1e-7 -ksp_rtol 1e-10 -dipc_pc_reuse 0
  built-in   -dipc_velocity_tol_rel 1e-5 -ksp_rtol 1e-8  -dipc_pc_reuse 0
  vtol       -dipc_velocity_tol_rel 1e-3, 1e-4, 1e-6
  ksp        -ksp_rtol 1e-3, 1e-4, 1e-6
  pc_reuse   -dipc_pc_reuse 1, alone and with -ksp_rtol 1e-4
  dhat       contact.dhat x0.1 and x10 (contact scenes; a temporary copy of the scene JSON)
  dt         time.dt x0.5 and x2, steps scaled to keep the end time (compared at the common times)
  kappa      contact.barrier_stiffness: an adaptive scene gets a fixed kappa equal to the largest
             kappa the reference reached, and 10x that; a scene with a fixed kappa gets
             "adaptive" and 10x its kappa
  fric_its   contact.friction_iterations 2 and 3 (where contact.friction > 0)
The CCD step fraction (0.8, src/contact/distributed/contact_parameters.hpp) has no option, so no row.

Errors against the reference (u = displacement, over the output times both runs have, t > 0):
  err_max      max_t max_node |u - u_ref| / max_t max_node |u_ref|  (error relative to the motion)
  err_l2       the same in the L2 norm over all (time, node) pairs: sqrt(sum |u - u_ref|^2 / sum |u_ref|^2)
  energy_diff  (E_end - E_end_ref) / (max_t E_ref - min_t E_ref), E = kinetic + elastic + gravity
  height_err   max over bodies of |h_end - h_end_ref| / max |u_ref|, h = node-average centre along
               -gravity at the last compared time: the rest height (gravity scenes)
  bounce_err   max over bodies that rebound in the reference (height rises after its lowest point by
               more than 5 % of the drop) of |h_max_after - h_max_after_ref| / max |u_ref|
  exit_vel_err max over bodies of |v_end - v_end_ref| / max_t |v_ref|, v = node-average velocity
               at the last compared time (dynamic scenes)
  end_pos_err  max over bodies of |c_end - c_end_ref| / max |u_ref|, c = node-average centre at the
               last compared time: where each body ends up (a body squeezed out sideways, say)
  min_gap      min over the run of stats.csv's min_distance_over_dhat (contact scenes): the
               penetration margin, a fraction of d-hat (0 would be contact)
Cost: wall_s the median over --repeat runs of the sum of stats.csv's wall_s (the steps, setup
excluded), split into linear_s (linear_solve_s: KSP + AMG), contact_s (broad phase + CCD +
barrier + exchange) and other_s (the rest: assembly, line search, output); process_s the whole
process; cpu_s the user + system CPU time of the whole process (setup included), the cost
measure that other work on a shared machine disturbs least (1 rank: no MPI polling); Newton
and CG iterations; dt cuts. `repeat_identical` says whether the repeats wrote bit-identical
displacements (the runs are deterministic on the CPU). Writes <out>/speed_accuracy_<scene>.csv
and .png (err_max against cpu_s, or wall_s with --cost wall, log-log, Pareto front in that cost
and error marked, each point labelled) and prints a Markdown table. --knobs runs only the named
knobs (the 1M-element GPU study: built-in,preset,ksp,pc_reuse), --tag names the output apart. A run still going after --timeout times the reference's
process time (at least 10 s) is stopped and recorded with status 124. --steps caps the scene's steps (the
CSV's steps and scene_steps columns say so).
"""
import argparse
import copy
import csv
import json
import os
import resource
import signal
import statistics
import subprocess
import sys
import tempfile
import time

import h5py
import numpy as np

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
DEFAULT_SCENE_JSON = os.path.join(ROOT, 'tests', 'io', 'data', 'default_scene.json')  # == the embedded default
PRESET_DIR = os.path.join(ROOT, 'scenes', 'solver', 'presets')
PRESETS = ('fast', 'balanced', 'accurate')
MODEL_KNOBS = ('dhat', 'dt', 'kappa', 'fric_its')  # change the discrete problem, not only how well it is solved
REFERENCE = {'-dipc_velocity_tol_rel': '1e-7', '-ksp_rtol': '1e-10', '-dipc_pc_reuse': '0'}
BUILTIN = {'-dipc_velocity_tol_rel': '1e-5', '-ksp_rtol': '1e-8', '-dipc_pc_reuse': '0'}
ERRORS = ('err_max', 'err_l2', 'energy_diff', 'height_err', 'bounce_err', 'exit_vel_err', 'end_pos_err', 'min_gap')
FLOATS = ERRORS + ('wall_s', 'wall_s_min', 'wall_s_max', 'linear_s', 'contact_s', 'other_s', 'process_s', 'cpu_s',
                   's_per_newton')


def options(base, **changes):
    o = dict(base)
    for k, v in changes.items():
        o['-' + k] = v
    return [w for k, v in o.items() for w in (k, v)]


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
    fields, mesh = {}, None
    h5 = [p for p in os.listdir(outdir) if p.endswith('.h5')] if os.path.isdir(outdir) else []
    if h5:
        with h5py.File(os.path.join(outdir, h5[0]), 'r') as f:
            mesh = {k: np.array(f['mesh'][k]) for k in ('coordinates', 'topology', 'body')}
            for k in f.get('steps', {}):
                g = f['steps'][k]
                fields[round(float(g.attrs['time']), 9)] = (np.array(g['displacement']), np.array(g['velocity']))
    return rows, fields, mesh


def run_once(binary, scene, ranks, steps, outdir, extra, timeout=None):
    cmd = ['mpiexec', '--oversubscribe', '--allow-run-as-root', '-n', str(ranks), binary]
    if scene:
        cmd.append(scene)
    cmd += ['-dipc_quiet', '-dipc_output', outdir, '-dipc_steps', str(steps)] + extra
    start, cpu0 = time.time(), resource.getrusage(resource.RUSAGE_CHILDREN)
    # Its own process group, so that a run past `timeout` is stopped with every process it started.
    proc = subprocess.Popen(cmd, stdout=subprocess.PIPE, stderr=subprocess.STDOUT, text=True, start_new_session=True)
    try:
        output, _ = proc.communicate(timeout=timeout)
        status = proc.returncode
    except subprocess.TimeoutExpired:
        os.killpg(proc.pid, signal.SIGKILL)
        output, _ = proc.communicate()
        status, output = 124, f'dipc: stopped: still running after {timeout:g} s\n' + output
    process_s = time.time() - start
    cpu1 = resource.getrusage(resource.RUSAGE_CHILDREN)
    cpu_s = (cpu1.ru_utime + cpu1.ru_stime) - (cpu0.ru_utime + cpu0.ru_stime)
    rows, fields, mesh = read_run(outdir)

    def total(*keys):
        return sum(float(r[k]) for r in rows for k in keys if r.get(k) not in (None, ''))

    energy = [float(r['kinetic_energy']) + float(r['elastic_energy']) + float(r['gravity_energy']) for r in rows]
    gaps = [float(r['min_distance_over_dhat']) for r in rows if r.get('min_distance_over_dhat') not in (None, '')]
    kappa = [float(r['kappa']) for r in rows if r.get('kappa') not in (None, '')]
    err = next((l for l in output.splitlines() if l.startswith('dipc: ')
                and ('error' in l or 'failed' in l or 'stop' in l)), '')
    wall, linear = total('wall_s'), total('linear_solve_s')
    contact = total('broad_phase_s', 'ccd_s', 'barrier_s', 'exchange_s')
    return {'status': status, 'steps': len(rows), 'newton': total('newton_its'), 'ksp': total('ksp_its'),
            'cuts': total('dt_cuts'), 'wall': wall, 'linear': linear, 'contact': contact,
            'other': wall - linear - contact, 'process': process_s, 'cpu': cpu_s, 'energy': energy,
            'min_gap': min(gaps) if gaps else float('nan'), 'kappa_max': max(kappa) if kappa else float('nan'),
            'fields': fields, 'mesh': mesh, 'message': err}


def run(binary, scene, ranks, steps, outdir, extra, repeat, timeout=None):
    """`repeat` runs; the first one's results with the median of the times."""
    runs = [run_once(binary, scene, ranks, steps, f'{outdir}_{i}', extra, timeout) for i in range(repeat)]
    r = runs[0]
    for key in ('wall', 'linear', 'contact', 'other', 'process', 'cpu'):
        r[key + '_all'] = [x[key] for x in runs]
        r[key] = statistics.median(r[key + '_all'])
    same = lambda a, b: a.keys() == b.keys() and all(np.array_equal(a[t][0], b[t][0]) for t in a)
    r['identical'] = all(x['status'] == r['status'] and same(x['fields'], r['fields']) for x in runs[1:])
    return r


def bodies(mesh):
    """Node indices of each body (from the elements' body ids)."""
    return [np.unique(mesh['topology'][mesh['body'] == b]) for b in np.unique(mesh['body'])]


def compare(run_, ref, down):
    """The errors of one run against the reference (see the module docstring). `down` is the unit
    gravity vector, or None without gravity."""
    nan = float('nan')
    out = {k: nan for k in ERRORS}
    out['min_gap'] = run_['min_gap']
    common = sorted(t for t in set(run_['fields']) & set(ref['fields']) if t > 0)
    if run_['status'] != 0 or not common:
        return out, 0
    norm = lambda u: np.linalg.norm(u, axis=1)
    u_max = max(norm(ref['fields'][t][0]).max() for t in common)
    du = [run_['fields'][t][0] - ref['fields'][t][0] for t in common]
    out['err_max'] = max(norm(d).max() for d in du) / max(u_max, 1e-300)
    out['err_l2'] = np.sqrt(sum((d ** 2).sum() for d in du) /
                            max(sum((ref['fields'][t][0] ** 2).sum() for t in common), 1e-300))
    e_ref = ref['energy']
    if run_['energy'] and e_ref:
        out['energy_diff'] = (run_['energy'][-1] - e_ref[-1]) / max(max(e_ref) - min(e_ref), 1e-300)
    x0 = ref['mesh']['coordinates']
    nodes = bodies(ref['mesh'])
    end = common[-1]
    moving = [n for n in nodes if np.abs(ref['fields'][end][0][n]).max() > 0]
    if moving:
        centre = lambda f, n: np.mean(x0[n] + f[end][0][n], axis=0)
        out['end_pos_err'] = max(np.linalg.norm(centre(run_['fields'], n) - centre(ref['fields'], n))
                                 for n in moving) / u_max
    if down is not None and moving:
        height = lambda f, t, n: -float(np.mean(x0[n] + f[t][0][n], axis=0) @ down)
        out['height_err'] = max(abs(height(run_['fields'], end, n) - height(ref['fields'], end, n))
                                for n in moving) / u_max
        bounce = []
        for n in moving:
            h_ref = np.array([height(ref['fields'], t, n) for t in common])
            low = int(np.argmin(h_ref))
            drop = height(ref['fields'], common[0], n) - h_ref[low]
            if drop > 0 and h_ref[low:].max() - h_ref[low] > 0.05 * drop:
                h_run = np.array([height(run_['fields'], t, n) for t in common])
                bounce.append(abs(h_run[low:].max() - h_ref[low:].max()) / u_max)
        if bounce:
            out['bounce_err'] = max(bounce)
    v_scale = max((norm(ref['fields'][t][1]).max() for t in common), default=0.0)
    if v_scale > 0 and moving:
        vel = lambda f, n: np.mean(f[end][1][n], axis=0)
        out['exit_vel_err'] = max(np.linalg.norm(vel(run_['fields'], n) - vel(ref['fields'], n)) for n in moving) / v_scale
    return out, len(common)


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


def plot(rows, ref_cost, cost, path, title):
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    floor = 1e-12  # errors at round-off are drawn here (log scale)
    pts = [(r[cost], r['err_max']) for r in rows]
    front = set(pareto(pts))
    fig, ax = plt.subplots(figsize=(8.5, 5.5))
    for i, r in enumerate(rows):
        w, e = pts[i]
        if not np.isfinite(e):
            continue
        e = max(e, floor)
        marker = '*' if r['knob'] == 'preset' else ('^' if r['knob'] in MODEL_KNOBS else 'o')
        ax.scatter([w], [e], color='C3' if i in front else 'C0', s=90 if r['knob'] == 'preset' else 24, zorder=3,
                   marker=marker)
        ax.annotate(r['setting'], (w, e), textcoords='offset points', xytext=(4, 3), fontsize=7)
    fr = sorted(((pts[i][0], max(pts[i][1], floor)) for i in front), key=lambda p: p[0])
    if fr:
        ax.plot([p[0] for p in fr], [p[1] for p in fr], color='C3', lw=1, ls='--', label='Pareto front')
    ax.scatter([], [], marker='*', color='grey', s=60, label='preset (scenes/solver/presets)')
    ax.scatter([], [], marker='^', color='grey', label='changes the discrete problem (dhat, dt, kappa, friction)')
    ax.axvline(ref_cost, color='grey', lw=0.8, ls=':', label=f'reference ({ref_cost:.2f} s)')
    ax.set_xscale('log')
    ax.set_yscale('log')
    ax.set_xlabel('CPU time of the run [s] (user + system of the process, median over the repeats)' if cost == 'cpu_s'
                  else "wall time of the run's steps [s] (setup excluded, median over the repeats)")
    ax.set_ylabel('max |u - u_ref| / max |u_ref| (1e-12 = round-off)')
    ax.set_title(title, fontsize=10)
    ax.grid(True, which='both', alpha=0.3)
    ax.legend(fontsize=7)
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)


def write_csv(path, rows):
    """All rows so far, through a temporary file, so that the CSV on disk is always whole."""
    os.makedirs(os.path.dirname(path), exist_ok=True)
    with open(path + '.tmp', 'w', newline='') as f:
        w = csv.DictWriter(f, fieldnames=list(rows[0]))
        w.writeheader()
        for r in rows:
            w.writerow({k: (f'{v:.4g}' if isinstance(v, float) else v) for k, v in r.items()})
    os.replace(path + '.tmp', path)


def fmt(x):
    if isinstance(x, str):
        return x
    return '0' if x == 0 else ('—' if not np.isfinite(x) else f'{x:.1e}')


def main():
    ap = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    ap.add_argument('scene', nargs='?', default='', help='scene file (default: the embedded default scene)')
    ap.add_argument('--binary', default=os.path.join(ROOT, 'build', 'src', 'app', 'dipc'))
    ap.add_argument('--ranks', type=int, default=1)
    ap.add_argument('--steps', type=int, default=0, help="cap the scene's steps at N (0: the scene's)")
    ap.add_argument('--repeat', type=int, default=1, help='runs per setting; times are their median')
    ap.add_argument('--out', default=os.path.join(ROOT, 'bench', 'results'))
    ap.add_argument('--options', default='', help='extra options for every run')
    ap.add_argument('--timeout', type=float, default=10,
                    help="stop a run after this many times the reference's process time (status 124)")
    ap.add_argument('--plot-only', action='store_true', help='redraw the PNG from the CSV of an earlier study')
    ap.add_argument('--knobs', default='', help='comma-separated knobs to run (e.g. built-in,preset,ksp,pc_reuse); '
                    'default all. The reference always runs')
    ap.add_argument('--tag', default='', help='appended to the output name (e.g. gpu_1m)')
    ap.add_argument('--cost', choices=('cpu', 'wall'), default='cpu',
                    help="the cost axis of the plot and the Pareto front: the process's CPU time (default; robust "
                    "on a shared machine) or the steps' wall time (a GPU run, where CPU time means little)")
    args = ap.parse_args()
    name = os.path.splitext(os.path.basename(args.scene))[0] if args.scene else 'default'
    if args.tag:
        name += '_' + args.tag
    cost = args.cost + '_s'
    base = os.path.join(args.out, f'speed_accuracy_{name}')
    if args.plot_only:
        rows = [{k: (float(v) if k in FLOATS else v) for k, v in r.items()} for r in csv.DictReader(open(base + '.csv'))]
        plot(rows[1:], rows[0][cost], cost, base + '.png',
             f"{name}: {rows[0]['steps']} of {rows[0]['scene_steps']} steps, error against the tight reference")
        return 0

    scene_path = args.scene or DEFAULT_SCENE_JSON
    scene = json.load(open(scene_path))
    scene_dir = os.path.dirname(os.path.abspath(scene_path))
    full = scene_steps(scene)
    n = min(full, args.steps) if args.steps else full
    dt = float(scene['time']['dt'])
    contact = scene.get('contact', {})
    has_contact = bool(contact.get('enabled', False))
    friction = float(contact.get('friction', 0) or 0) if has_contact else 0.0
    g = np.array(scene.get('boundary_conditions', {}).get('gravity', [0, 0, 0]), dtype=float)
    down = g / np.linalg.norm(g) if np.linalg.norm(g) > 0 else None
    extra = args.options.split()

    with tempfile.TemporaryDirectory() as tmp:
        def variant(tag, edit):
            return write_variant(scene, scene_dir, tmp, tag, edit)

        def set_time(factor):
            def edit(s):
                s['time']['dt'] = dt * factor
                s['time'].pop('t_end', None)
                s['time']['steps'] = max(1, int(round(full / factor)))
            return edit

        def set_contact(key, value):
            def edit(s):
                s['contact'][key] = value
            return edit

        print(f'# {name}: {n} of {full} steps of dt {dt:g}, {args.ranks} rank(s), x{args.repeat}', file=sys.stderr)
        ref = run(args.binary, args.scene, args.ranks, n, os.path.join(tmp, 'ref'), options(REFERENCE) + extra,
                  args.repeat)
        if ref['status'] != 0:
            print(f"reference failed (exit {ref['status']}): {ref['message']}", file=sys.stderr)
            return 2
        print(f"#   reference: {ref['wall']:.2f} s, {ref['newton']:.0f} Newton, {ref['ksp']:.0f} CG", file=sys.stderr)

        # (setting, knob, scene file, steps, options)
        plan = [('built-in', 'built-in', args.scene, n, options(BUILTIN))]
        plan += [(p, 'preset', args.scene, n, ['-options_file', os.path.join(PRESET_DIR, p + '.opts')])
                 for p in PRESETS]
        plan += [(f'vtol {v}', 'vtol', args.scene, n, options(BUILTIN, dipc_velocity_tol_rel=v))
                 for v in ('1e-3', '1e-4', '1e-6')]
        plan += [(f'ksp {v}', 'ksp', args.scene, n, options(BUILTIN, ksp_rtol=v)) for v in ('1e-3', '1e-4', '1e-6')]
        plan += [('reuse', 'pc_reuse', args.scene, n, options(BUILTIN, dipc_pc_reuse='1')),
                 ('reuse+ksp 1e-4', 'pc_reuse', args.scene, n, options(BUILTIN, dipc_pc_reuse='1', ksp_rtol='1e-4'))]
        if has_contact:
            d = float(contact.get('dhat', 1e-3))
            for f in (0.1, 10):
                if contact.get('dhat_relative', True) and not d * f < 1:
                    continue
                plan.append((f'dhat x{f:g}', 'dhat', variant(f'dhat{f:g}', set_contact('dhat', d * f)), n,
                             options(BUILTIN)))
            kappa = contact.get('barrier_stiffness', 'adaptive')
            if kappa == 'adaptive':
                k = ref['kappa_max']
                if np.isfinite(k) and k > 0:
                    for f, label in ((1, 'kappa fixed'), (10, 'kappa fixed x10')):
                        plan.append((label, 'kappa', variant(f'kappa{f}', set_contact('barrier_stiffness', k * f)), n,
                                     options(BUILTIN)))
            else:
                plan.append(('kappa adaptive', 'kappa', variant('kappa_a', set_contact('barrier_stiffness', 'adaptive')),
                             n, options(BUILTIN)))
                plan.append(('kappa x10', 'kappa', variant('kappa10', set_contact('barrier_stiffness', 10 * kappa)), n,
                             options(BUILTIN)))
        for f in (0.5, 2):
            steps = max(1, int(round(n / f)))
            plan.append((f'dt x{f:g}', 'dt', variant(f'dt{f:g}', set_time(f)), steps, options(BUILTIN)))
        if friction > 0:
            for its in (2, 3):
                plan.append((f'fric_its {its}', 'fric_its', variant(f'fric{its}', set_contact('friction_iterations', its)),
                             n, options(BUILTIN)))

        if args.knobs:
            keep = set(args.knobs.split(','))
            plan = [p for p in plan if p[1] in keep]

        def row(setting, knob, opts, r, errors, ncmp):
            return dict(scene=name, setting=setting, knob=knob, options=' '.join(opts), steps=r['steps'],
                        scene_steps=full, status=r['status'], **errors, compared_times=ncmp,
                        wall_s=r['wall'], wall_s_min=min(r['wall_all']), wall_s_max=max(r['wall_all']),
                        repeats=len(r['wall_all']), linear_s=r['linear'], contact_s=r['contact'], other_s=r['other'],
                        process_s=r['process'], cpu_s=r['cpu'], newton_its=r['newton'], ksp_its=r['ksp'], dt_cuts=r['cuts'],
                        s_per_newton=r['wall'] / max(r['newton'], 1), repeat_identical='yes' if r['identical'] else 'NO',
                        pareto='')

        ref_errors = {k: 0.0 for k in ERRORS}
        ref_errors.update(energy_diff=0.0, min_gap=ref['min_gap'])
        for k in ('height_err', 'bounce_err', 'exit_vel_err', 'end_pos_err'):
            ref_errors[k] = compare(ref, ref, down)[0][k]
        rows = [row('reference', 'reference', options(REFERENCE), ref, ref_errors, len(ref['fields']) - 1)]
        for i, (setting, knob, sc, steps, opts) in enumerate(plan):
            r = run(args.binary, sc, args.ranks, steps, os.path.join(tmp, f'run{i}'), opts + extra, args.repeat,
                    args.timeout * max(ref['process'], 10.0))
            errors, ncmp = compare(r, ref, down)
            rows.append(row(setting, knob, opts, r, errors, ncmp))
            write_csv(base + '.csv', rows)  # after every run, so that a study cut short keeps what it measured
            note = f" exit {r['status']}: {r['message']}" if r['status'] else ''
            print(f"#   {setting}: {r['wall']:.2f} s, err {errors['err_max']:.2e}{note}", file=sys.stderr)

    runs = rows[1:]
    for i in pareto([(r[cost], r['err_max']) for r in runs]):
        runs[i]['pareto'] = 'yes'
    write_csv(base + '.csv', rows)
    plot(runs, rows[0][cost], cost, base + '.png',
         f'{name}: {n} of {full} steps, {args.ranks} rank(s), error against the tight reference')

    print(f"{name}, {n} of {full} steps of dt {dt:g}, {args.ranks} rank(s), median of {args.repeat} run(s) "
          f"(reference: {' '.join(options(REFERENCE))})\n")
    print('| setting | err max | err L2 | energy | rest height | bounce | exit vel | end position | min gap/d̂ | CPU [s] | wall [s] | '
          'linear / contact / other [s] | Newton | CG | s/Newton | Pareto |')
    print('|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|')
    for r in rows:
        status = f" (exit {r['status']})" if r['status'] else ''
        print(f"| {r['setting']}{status} | " + ' | '.join(fmt(r[k]) for k in ERRORS) +
              f" | {r['cpu_s']:.2f} | {r['wall_s']:.2f} | {r['linear_s']:.2f} / {r['contact_s']:.2f} / {r['other_s']:.2f} | "
              f"{r['newton_its']:.0f} | {r['ksp_its']:.0f} | {r['s_per_newton']:.3f} | {'✓' if r['pareto'] else ''} |")
    print(f'\nwrote {base}.csv and {base}.png', file=sys.stderr)
    return 0


if __name__ == '__main__':
    sys.exit(main())

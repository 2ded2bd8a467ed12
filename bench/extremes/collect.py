"""One row of the extremes matrix from a finished (or failed) dipc run: stats.csv sums, the
judge's verdict on every written step, energy/momentum drift where the physics makes them
meaningful, and the agreement of the final displacement with the 1-rank run."""
import csv
import os

import h5py
import numpy as np

import cases
import judge_output

ENERGY_COLUMNS = ('kinetic_energy', 'elastic_energy', 'gravity_energy')
MOMENTUM_COLUMNS = ('momentum_x', 'momentum_y', 'momentum_z')


def read_stats(path):
    """stats.csv as {column: float array} (text columns, such as converged_by, as lists of
    strings); empty when the file is missing or has no rows."""
    if not os.path.exists(path):
        return {}
    with open(path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        return {}
    def column(k):
        try:
            return np.array([float(r[k]) for r in rows])
        except ValueError:
            return [r[k] for r in rows]
    return {k: column(k) for k in rows[0]}


def energy_drift(stats, s):
    """(E_end − E_start) / |E_start| of kinetic + elastic + gravity energy, where the columns
    exist and nothing does work on the bodies (then implicit Euler can only lose energy: a
    positive drift is a gain). None otherwise."""
    if not cases.energy_may_only_fall(s) or not all(c in stats for c in ENERGY_COLUMNS[:2]):
        return None
    total = sum(stats[c] for c in ENERGY_COLUMNS if c in stats)
    return float((total[-1] - total[0]) / max(abs(total[0]), 1e-300))


def momentum_drift(stats, s):
    """|p_end − p_start| / |p_start| where the columns exist and momentum is conserved."""
    if not cases.conserves_momentum(s) or not all(c in stats for c in MOMENTUM_COLUMNS):
        return None
    p = np.stack([stats[c] for c in MOMENTUM_COLUMNS], axis=1)
    return float(np.linalg.norm(p[-1] - p[0]) / max(np.linalg.norm(p[0]), 1e-300))


def final_displacement(h5_path):
    with h5py.File(h5_path, 'r') as h5:
        last = max(h5['steps'].keys(), key=int)
        return h5['mesh/coordinates'][...], h5[f'steps/{last}/displacement'][...], int(last)


def rank_agreement(h5_path, first_rank_h5):
    """max |u_R − u_1| / max |u_1| over nodes matched by rest position, at the final step;
    None when either run is missing, they stopped at different steps or wrote
    no step beyond the initial state."""
    if not first_rank_h5 or not os.path.exists(first_rank_h5) or not os.path.exists(h5_path):
        return None
    X1, u1, last1 = final_displacement(first_rank_h5)
    X, u, last = final_displacement(h5_path)
    if last != last1 or last == 0:  # stopped at different steps, or nothing but the initial state
        return None
    same_node = judge_output.input_order(X, X1)  # row of X1 holding each node of X
    return float(np.abs(u - u1[same_node]).max() / max(np.abs(u1).max(), 1e-300))


def collect(name, group, s, scene_path, ranks, out_dir, status, wall, error, first_rank_h5):
    stats = read_stats(os.path.join(out_dir, 'stats.csv'))
    h5_path = os.path.join(out_dir, 'run.h5')
    row = {'case': name, 'group': group, 'ranks': ranks, 'exit': status, 'steps': 0,
           'steps_planned': s['time']['steps'], 'newton_its': 0, 'ksp_its': 0, 'dt_cuts': 0,
           'min_distance': None, 'min_plane_distance': None, 'dhat': None, 'min_det_F': None,
           'inverted': None, 'intersections': None, 'energy_drift': None, 'momentum_drift': None,
           'wall_s': round(wall, 2), 'rank_agreement': None, 'judge': '', 'error': error}
    if stats:
        row['steps'] = len(stats['step'])
        row['newton_its'] = int(stats['newton_its'].sum())
        row['ksp_its'] = int(stats['ksp_its'].sum())
        row['dt_cuts'] = int(stats['dt_cuts'].sum()) if 'dt_cuts' in stats else 0
        row['energy_drift'] = energy_drift(stats, s)
        row['momentum_drift'] = momentum_drift(stats, s)
    judged_ok = False
    if os.path.exists(h5_path):
        try:
            verdict = judge_output.judge(h5_path, scene_path, first_rank_h5 if ranks > 1 else None)
            for key in ('min_distance', 'min_plane_distance', 'dhat', 'min_det_F', 'inverted', 'intersections'):
                value = verdict[key]
                row[key] = None if isinstance(value, float) and not np.isfinite(value) else value
            row['judge'] = 'ok' if verdict['ok'] else verdict['first_violation']
            judged_ok = verdict['ok']
        except (OSError, KeyError, ValueError, judge_output.JudgeInputError) as e:
            row['judge'] = f'unreadable output: {e}'
        if ranks > 1:
            row['rank_agreement'] = rank_agreement(h5_path, first_rank_h5)
    else:
        row['judge'] = 'no output'
    row['ok'] = status == 0 and judged_ok
    return row

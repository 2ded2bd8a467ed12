"""Output of the extremes matrix: the CSV, the overview plot and the Markdown table."""
import csv

COLUMNS = ['case', 'group', 'ranks', 'exit', 'ok', 'steps', 'steps_planned', 'newton_its', 'ksp_its', 'dt_cuts',
           'min_distance', 'min_plane_distance', 'dhat', 'min_det_F', 'inverted', 'intersections', 'energy_drift',
           'momentum_drift', 'wall_s', 'rank_agreement', 'judge', 'error']


def fmt(value):
    if value is None:
        return '—'
    if isinstance(value, float):
        return f'{value:.3g}'
    return str(value)


def write_csv(rows, path):
    with open(path, 'w', newline='') as f:
        writer = csv.DictWriter(f, COLUMNS)
        writer.writeheader()
        for r in rows:
            writer.writerow({k: '' if r[k] is None else r[k] for k in COLUMNS})


def read_csv(path):
    """Rows of a CSV written by write_csv, with numbers and flags parsed back."""
    ints = ('ranks', 'steps', 'steps_planned', 'newton_its', 'ksp_its', 'dt_cuts', 'inverted', 'intersections')
    floats = ('min_distance', 'min_plane_distance', 'dhat', 'min_det_F', 'energy_drift', 'momentum_drift', 'wall_s',
              'rank_agreement')
    rows = []
    with open(path) as f:
        for r in csv.DictReader(f):
            for k in ints:
                r[k] = int(r[k]) if r[k] else None
            for k in floats:
                r[k] = float(r[k]) if r[k] else None
            r['exit'] = int(r['exit']) if r['exit'].lstrip('-').isdigit() else r['exit']
            r['ok'] = r['ok'] == 'True'
            rows.append(r)
    return rows


def verdict(r):
    """Short outcome: ok, dipc's exit status / timeout, or the judge's first finding."""
    if r['ok']:
        return 'ok'
    parts = []
    if r['exit'] != 0:
        parts.append('timeout' if r['exit'] == 'timeout' else f"exit {r['exit']}")
    if r['judge'] not in ('ok', 'no output'):
        parts.append('judge: ' + r['judge'])
    return ', '.join(parts)


def progress_line(r):
    return (f"{r['case']:18s} np{r['ranks']}  {verdict(r):10s} steps {r['steps']}/{r['steps_planned']}  "
            f"newton {r['newton_its']}  ksp {r['ksp_its']}  {r['wall_s']:.1f} s  {r['error']}")


def markdown(rows):
    head = ['case', 'ranks', 'outcome', 'steps', 'Newton', 'CG', 'dt cuts', 'min d / d̂', 'min plane d / d̂',
            'min det F', 'E drift', 'p drift', '1 vs N ranks', 'wall [s]', 'last error']
    lines = ['| ' + ' | '.join(head) + ' |', '|' + '---|' * len(head)]
    for r in rows:
        over = lambda d: None if d is None or not r['dhat'] else d / r['dhat']
        cells = [r['case'], r['ranks'], verdict(r), f"{r['steps']}/{r['steps_planned']}", r['newton_its'], r['ksp_its'],
                 r['dt_cuts'], over(r['min_distance']), over(r['min_plane_distance']), r['min_det_F'], r['energy_drift'],
                 r['momentum_drift'], r['rank_agreement'], r['wall_s'], r['error'].replace('dipc: error: ', '')]
        lines.append('| ' + ' | '.join(fmt(c).replace('|', '/') for c in cells) + ' |')
    return '\n'.join(lines)


def plot(rows, path):
    """Two panels over the cases: wall time and Newton iterations (per rank count), then the
    smallest distance over d̂ and the smallest det F. Failed runs are marked with a red ×."""
    import matplotlib
    matplotlib.use('Agg')
    import matplotlib.pyplot as plt
    import numpy as np

    names = list(dict.fromkeys(r['case'] for r in rows))
    rank_counts = sorted({r['ranks'] for r in rows})
    x = np.arange(len(names))
    width = 0.8 / len(rank_counts)
    fig, (top, bottom) = plt.subplots(2, 1, figsize=(max(10, 0.45 * len(names)), 9), sharex=True)
    newton = top.twinx()
    for k, ranks in enumerate(rank_counts):
        by_case = {r['case']: r for r in rows if r['ranks'] == ranks}
        xs = x + (k - (len(rank_counts) - 1) / 2) * width
        get = lambda key: np.array([by_case[n][key] if n in by_case and by_case[n][key] is not None else np.nan
                                    for n in names], float)
        top.bar(xs, get('wall_s'), width, label=f'wall time, {ranks} rank(s)', alpha=0.7)
        newton.plot(xs, get('newton_its'), 'k.', markersize=4)
        failed = np.array([n in by_case and not by_case[n]['ok'] for n in names])
        top.plot(xs[failed], get('wall_s')[failed], 'rx', markersize=10, mew=2)
        dhat = get('dhat')
        bottom.plot(xs, get('min_distance') / dhat, 'o', label=f'min distance between bodies / d̂, {ranks} rank(s)')
        bottom.plot(xs, get('min_plane_distance') / dhat, 's', mfc='none', label=f'min distance to planes / d̂, {ranks} rank(s)')
        bottom.plot(xs, get('min_det_F'), '^', label=f'min det F, {ranks} rank(s)')
        bottom.plot(xs[failed], np.ones(failed.sum()), 'rx', markersize=10, mew=2)
    top.set_yscale('log')
    top.set_ylabel('wall time [s] (bars; red × = failed)')
    newton.set_ylabel('Newton iterations (dots)')
    top.legend(loc='upper left', fontsize=8)
    bottom.set_yscale('log')
    bottom.set_ylabel('min d / d̂, min det F (log; red × = failed)')
    bottom.legend(loc='lower left', fontsize=7, ncol=2)
    bottom.set_xticks(x)
    bottom.set_xticklabels(names, rotation=60, ha='right', fontsize=8)
    top.set_title('dipc extremes matrix (-dipc_check_invariants, judged by tests/tools/judge_output.py)')
    fig.tight_layout()
    fig.savefig(path, dpi=110)
    plt.close(fig)

"""The CSV a bench script adds its rows to: <out>/<name>, created with its folder where missing.
Rows already there are kept (a run replaces only the rows of the cases it measures again), so
results from several calls of a script, or machines, gather in one table.

    from bench_csv import earlier_rows
    csv_path, rows = earlier_rows(args.out, "setup_%s.csv" % args.tag)
"""
import csv
import os


def earlier_rows(out_dir, name):
    """(path of the CSV, its rows as dicts of strings; [] when it does not exist yet)."""
    os.makedirs(out_dir, exist_ok=True)
    path = os.path.join(out_dir, name)
    if not os.path.exists(path):
        return path, []
    with open(path) as f:
        return path, list(csv.DictReader(f))

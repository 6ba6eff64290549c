#!/usr/bin/env python3
"""CPU time against a reference solver at equal error, from CSV files in the peer
harness's columns (taylorode's `bench --csv` and the harness's own):

  python3 tools/ratios.py [--reference cvode_bdf] [--min-error 1e-4] CSV ...

For every problem and every other solver, each of its runs whose error lies inside
the reference solver's range of errors is compared with the reference's CPU time at
the same error (interpolated linearly in log error and log time between the
reference's runs); the table gives the median ratio (solver / reference: below 1 is
faster) over the runs with error >= --min-error, and how many runs that is. The
error is err_end, except e5's err_grid (the harness's measure). Prints Markdown.
"""
import argparse
import csv
import math
import statistics

ERROR_COLUMN = {"e5": "err_grid"}


def number(text):
    try:
        value = float(text)
    except (TypeError, ValueError):
        return math.nan
    return value


def runs(paths):
    table = {}
    for path in paths:
        with open(path, newline="") as handle:
            for row in csv.DictReader(handle):
                if (row.get("status") or "ok") != "ok":
                    continue
                problem = row["problem"]
                error = number(row.get(ERROR_COLUMN.get(problem, "err_end")))
                cpu = number(row.get("cpu_s"))
                if not (error > 0 and cpu > 0 and math.isfinite(error) and math.isfinite(cpu)):
                    continue
                table.setdefault(problem, {}).setdefault(row["solver"], []).append((error, cpu))
    return table


def time_at(curve, error):
    """CPU of the reference at this error, or None outside its range."""
    points = sorted(curve)
    for (e0, c0), (e1, c1) in zip(points, points[1:]):
        if e0 <= error <= e1 and e1 > e0:
            w = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
    return None


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reference", default="cvode_bdf")
    parser.add_argument("--min-error", type=float, default=1e-4)
    parser.add_argument("csv", nargs="+")
    options = parser.parse_args()
    table = runs(options.csv)
    solvers = sorted({s for p in table.values() for s in p if s != options.reference})
    print("| problem | " + " | ".join(solvers) + " |")
    print("|---|" + "---|" * len(solvers))
    for problem in sorted(table):
        reference = table[problem].get(options.reference)
        cells = []
        for solver in solvers:
            ratios = []
            for error, cpu in table[problem].get(solver, []):
                if reference is None or error < options.min_error:
                    continue
                other = time_at(reference, error)
                if other:
                    ratios.append(cpu / other)
            cells.append(f"{statistics.median(ratios):.2f} ({len(ratios)})" if ratios else "-")
        print(f"| {problem} | " + " | ".join(cells) + " |")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""CPU time against a reference solver at equal error, over interleaved rounds, from
CSV files in the peer harness's columns (taylorode's `bench --csv` and the harness's own):

  python3 tools/ratios.py [--reference cvode_bdf] [--errors 1e-8:1e-4] [--summary FILE]
                          [--median-csv DIR] ROUND_DIR ...

Each ROUND_DIR holds the CSV files of one round (tools/figures.sh: taylorode's bench
runs, then the peers' runs, the rounds one after the other); every round must hold the
same files. The error of a run is the harness's measure: err_end, except e5's err_grid.

Which runs are compared. A run is correct in the range when its status is ok and its
error lies between the range's ends (--errors LOW:HIGH, default 1e-8:1e-4): an answer
that blew up (Robertson to 1e11 returns errors near 1e7 at loose tolerances, CVODE too)
or a run that stopped is never compared. The reference's curve goes through its own ok
runs with errors within a decade of the range (so that a run near an end of the range
can be bracketed), and a correct run is compared with the reference's CPU time at the
same error, interpolated linearly in log error and log time between the two reference
runs that bracket it (never extrapolated).

What a cell says. Within a round the ratio of a solver on a problem is the median over
its compared runs of (its CPU time / the reference's at equal error; below 1 is faster);
the cell gives the median of these over the rounds, their range (min-max) in parentheses
and the number of runs compared per round in brackets. A cell without a ratio says why,
in a footnote; a blank cell: not run.

Prints the Markdown table, its footnotes and the spread of the CPU time of one run over
the rounds. --summary FILE writes one line per solver: the median and the range of its
problems' ratios. --median-csv DIR writes each CSV file with the rows of the first round
and cpu_s the median over the rounds (columns cpu_s_min, cpu_s_max, rounds added), for
the figures. Fails (exit status 1) with a message when an input is missing or empty or
when no ratio at all can be formed, rather than printing an empty table.
"""
import argparse
import csv
import math
import os
import statistics
import sys

ERROR_COLUMN = {"e5": "err_grid"}
# the harness's problem order; others follow in the order met
PROBLEM_ORDER = ["vdp1e3_wp", "vdp1e3_up", "vdp1e6_wp", "vdp1e6_up", "rober40", "rober1e11", "hires", "orego",
                 "e5", "bruss32", "bruss512", "bs1000", "bs10000", "bs100000"]
SCHEME_ORDER = ["si-t-2", "i-t-2", "imex-rk21", "radau5"]
REQUIRED = ("solver", "problem", "tol", "status", "cpu_s", "err_end")
# how far (a factor in error) beyond the range's ends the reference's curve reaches
MARGIN = 10.0

NOT_CORRECT, TOO_ACCURATE, NOT_BRACKETED, NO_REFERENCE = 1, 2, 3, 4
FOOTNOTES = {
    NOT_CORRECT: "no run of this solver is correct in the range (status ok, error in {range}): each "
                 "stopped, failed, blew up or ended outside the range",
    TOO_ACCURATE: "every ok run of this solver ended more accurate than the range (error below its low end)",
    NOT_BRACKETED: "correct runs in the range, but none at an error between two of {reference}'s "
                   "(no CPU time at equal error to compare with)",
    NO_REFERENCE: "{reference} has no ok run with an error within a decade of the range",
}
MARKS = {NOT_CORRECT: "–¹", TOO_ACCURATE: "–²", NOT_BRACKETED: "–³", NO_REFERENCE: "–⁴"}


def fail(message):
    print(f"ratios: ERROR: {message}", file=sys.stderr)
    sys.exit(1)


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return math.nan


def error_range(text):
    try:
        low, high = sorted(float(v) for v in text.split(":"))
    except ValueError:
        fail(f'--errors wants LOW:HIGH, e.g. 1e-8:1e-4, not "{text}"')
    if not 0 < low < high:
        fail(f"--errors {text}: need 0 < LOW < HIGH")
    return low, high


def read_round(directory):
    """{file name: rows} of one round's CSV files."""
    if not os.path.isdir(directory):
        fail(f"no round directory {directory}")
    names = sorted(f for f in os.listdir(directory) if f.endswith(".csv"))
    if not names:
        fail(f"{directory} holds no CSV file")
    files = {}
    for name in names:
        path = os.path.join(directory, name)
        with open(path, newline="") as handle:
            reader = csv.DictReader(handle)
            missing = [c for c in REQUIRED if c not in (reader.fieldnames or [])]
            if missing:
                fail(f"{path} lacks the columns {', '.join(missing)}")
            rows = list(reader)
        if not rows:
            fail(f"{path} holds no run")
        files[name] = rows
    return files


def run_error(row):
    return number(row.get(ERROR_COLUMN.get(row["problem"], "err_end")))


def runs(files):
    """{problem: {solver: [(status, error, cpu)]}} of one round."""
    table = {}
    for rows in files.values():
        for row in rows:
            status = row.get("status") or "ok"
            table.setdefault(row["problem"], {}).setdefault(row["solver"], []).append(
                (status, run_error(row), number(row.get("cpu_s"))))
    return table


def usable(status, error, cpu):
    return status == "ok" and error > 0 and cpu > 0 and math.isfinite(error) and math.isfinite(cpu)


def time_at(curve, error):
    """CPU of the reference at this error, from the two points that bracket it, or None."""
    for (e0, c0), (e1, c1) in zip(curve, curve[1:]):
        if e0 <= error <= e1 and e1 > e0:
            w = (math.log(error) - math.log(e0)) / (math.log(e1) - math.log(e0))
            return math.exp(math.log(c0) + w * (math.log(c1) - math.log(c0)))
    return None


def round_ratio(table, problem, solver, reference, low, high):
    """(median ratio, runs compared) of a solver on a problem in one round, or (None, reason)."""
    curve = sorted((e, c) for s, e, c in table[problem].get(reference, [])
                   if usable(s, e, c) and low / MARGIN <= e <= high * MARGIN)
    ok = [(e, c) for s, e, c in table[problem].get(solver, []) if usable(s, e, c)]
    correct = [(e, c) for e, c in ok if low <= e <= high]
    if not correct:
        return None, TOO_ACCURATE if ok and all(e < low for e, _ in ok) else NOT_CORRECT
    if len(curve) < 2:
        return None, NO_REFERENCE
    ratios = []
    for error, cpu in correct:
        other = time_at(curve, error)
        if other:
            ratios.append(cpu / other)
    if not ratios:
        return None, NOT_BRACKETED
    return statistics.median(ratios), len(ratios)


def solver_key(solver):
    if not solver.startswith("taylorode_"):
        return (0, 0, solver)
    name = solver.removeprefix("taylorode_")
    for k, scheme in enumerate(SCHEME_ORDER):
        if name == scheme or name.startswith(scheme + "_"):
            return (1, k, name)
    return (1, len(SCHEME_ORDER), name)


def problem_key(problem):
    return (PROBLEM_ORDER.index(problem) if problem in PROBLEM_ORDER else len(PROBLEM_ORDER), problem)


def span(values, fmt):
    low, high = min(values), max(values)
    return fmt.format(low) if fmt.format(low) == fmt.format(high) else fmt.format(low) + "-" + fmt.format(high)


def cpu_spread(rounds):
    """max/min over the rounds of each run's CPU time, for taylorode's runs and the peers'."""
    spread = {"taylorode": [], "peers": []}
    keys = {}
    for files in rounds:
        for name, rows in files.items():
            for row in rows:
                cpu = number(row.get("cpu_s"))
                if (row.get("status") or "ok") == "ok" and cpu > 0 and math.isfinite(cpu):
                    keys.setdefault((name, row["solver"], row["problem"], row["tol"]), []).append(cpu)
    for (_, solver, _, _), cpus in keys.items():
        if len(cpus) == len(rounds) > 1:
            spread["taylorode" if solver.startswith("taylorode_") else "peers"].append(max(cpus) / min(cpus))
    return spread


def write_medians(rounds, directory):
    """Each CSV file with the first round's rows and cpu_s the median over the rounds."""
    os.makedirs(directory, exist_ok=True)
    for name, rows in rounds[0].items():
        cpus = {}
        for files in rounds:
            for row in files.get(name, []):
                cpu = number(row.get("cpu_s"))
                if math.isfinite(cpu):
                    cpus.setdefault((row["solver"], row["problem"], row["tol"]), []).append(cpu)
        columns = list(rows[0].keys()) + ["cpu_s_min", "cpu_s_max", "rounds"]
        with open(os.path.join(directory, name), "w", newline="") as handle:
            writer = csv.DictWriter(handle, fieldnames=columns, lineterminator="\n")
            writer.writeheader()
            for row in rows:
                values = cpus.get((row["solver"], row["problem"], row["tol"]), [])
                out = dict(row)
                if values:
                    out.update(cpu_s=f"{statistics.median(values):.6g}", cpu_s_min=f"{min(values):.6g}",
                               cpu_s_max=f"{max(values):.6g}", rounds=len(values))
                writer.writerow(out)


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--reference", default="cvode_bdf")
    parser.add_argument("--errors", default="1e-8:1e-4", help="LOW:HIGH, the errors compared")
    parser.add_argument("--summary", help="write the per-solver summary lines (Markdown) here")
    parser.add_argument("--median-csv", help="write the CSV files with the median CPU over the rounds here")
    parser.add_argument("rounds", nargs="+", metavar="ROUND_DIR")
    options = parser.parse_args()
    low, high = error_range(options.errors)
    range_text = f"{low:.0e} to {high:.0e}".replace("e-0", "e-").replace("e+0", "e")

    rounds = [read_round(d) for d in options.rounds]
    for directory, files in zip(options.rounds[1:], rounds[1:]):
        if sorted(files) != sorted(rounds[0]):
            fail(f"{directory} holds {', '.join(sorted(files))}; {options.rounds[0]} holds "
                 f"{', '.join(sorted(rounds[0]))}: every round must hold the same files")
    tables = [runs(files) for files in rounds]
    reference = options.reference
    problems = sorted({p for t in tables for p in t}, key=problem_key)
    compared = [p for p in problems if any(reference in t.get(p, {}) for t in tables)]
    if not compared:
        fail(f"no run of the reference solver {reference} in any file: nothing to compare with")
    skipped = [p for p in problems if p not in compared]
    solvers = sorted({s for t in tables for p in compared for s in t.get(p, {}) if s != reference}, key=solver_key)
    if not solvers:
        fail(f"no solver beside {reference} ran on its problems")

    cells, medians, reasons, used = {}, {}, {}, set()
    for problem in compared:
        for solver in solvers:
            if not any(solver in t.get(problem, {}) for t in tables):
                cells[problem, solver] = ""
                continue
            values, counts, why = [], [], set()
            for table in tables:
                if problem not in table or solver not in table[problem]:
                    continue
                ratio, detail = round_ratio(table, problem, solver, reference, low, high)
                if ratio is None:
                    why.add(detail)
                else:
                    values.append(ratio)
                    counts.append(detail)
            if values:
                median = statistics.median(values)
                medians.setdefault(solver, []).append((median, problem))
                text = f"{median:.2f} ({span(values, '{:.2f}')}) [{span(counts, '{:d}')}]"
                if len(values) < len(tables):
                    text += f" {len(values)} of {len(tables)} rounds"
                cells[problem, solver] = text
            else:
                reason = min(why)
                reasons.setdefault(solver, {}).setdefault(reason, []).append(problem)
                used.add(reason)
                cells[problem, solver] = MARKS[reason]
    if not medians:
        fail(f"no run of any solver is correct in the range {range_text} at an error {reference}'s runs "
             "bracket: no ratio to print")

    print("| problem | " + " | ".join(solvers) + " |")
    print("|---|" + "---|" * len(solvers))
    for problem in compared:
        print(f"| {problem} | " + " | ".join(cells[problem, s] for s in solvers) + " |")
    print()
    name = "CVODE" if reference == "cvode_bdf" else reference
    notes = [f"{MARKS[k][1:]} {FOOTNOTES[k].format(range=range_text, reference=name)}." for k in sorted(used)]
    if skipped:
        notes.append(f"Not compared ({name} not run there): {', '.join(skipped)}.")
    spread = cpu_spread(rounds)
    if len(rounds) > 1:
        parts = []
        for who, values in spread.items():
            if values:
                values.sort()
                parts.append(f"{who} {len(values)} runs: median {statistics.median(values):.2f}, "
                             f"90 % of them within {values[int(0.9 * (len(values) - 1))]:.2f}, "
                             f"largest {values[-1]:.2f}")
        if parts:
            notes.append(f"The CPU time of one run over the {len(rounds)} rounds, largest / smallest: "
                         + "; ".join(parts) + ".")
    print("<br>\n".join(notes))

    if options.summary:
        with open(options.summary, "w") as handle:
            for solver in solvers:
                line = f"- `{solver}`:"
                values = sorted(medians.get(solver, []))
                if values:
                    line += (f" median {statistics.median(v for v, _ in values):.2f} x {name}'s CPU time over "
                             f"{len(values)} problem{'s' if len(values) > 1 else ''}")
                    if len(values) > 1:
                        line += f", from {values[0][0]:.2f} ({values[0][1]}) to {values[-1][0]:.2f} ({values[-1][1]})"
                    else:
                        line += f" ({values[0][1]})"
                else:
                    line += " no ratio on any problem"
                missing = reasons.get(solver, {})
                if missing.get(NOT_CORRECT):
                    line += f"; no correct run in the range on {', '.join(missing[NOT_CORRECT])}"
                if missing.get(TOO_ACCURATE):
                    line += f"; more accurate than the range at every tolerance on {', '.join(missing[TOO_ACCURATE])}"
                if missing.get(NOT_BRACKETED):
                    line += f"; none at an error {name}'s correct runs bracket on {', '.join(missing[NOT_BRACKETED])}"
                if missing.get(NO_REFERENCE):
                    line += f"; {name} not correct near the range on {', '.join(missing[NO_REFERENCE])}"
                handle.write(line + "\n")
    if options.median_csv:
        write_medians(rounds, options.median_csv)


if __name__ == "__main__":
    main()

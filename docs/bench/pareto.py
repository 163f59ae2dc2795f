#!/usr/bin/env python3
"""The Pareto front of a `weft bench accuracy` CSV as a Markdown table: per scene, every
configuration that no other one beats on both ms/frame and trajectory RMS error (the points
the plot marks), fastest first, plus the reference run's cost. The method columns
(preconditioner, integrator, Newton iterations, iterations per solve) read "-" in a CSV from
before they existed.

    python3 docs/bench/pareto.py docs/bench/accuracy.csv > docs/bench/accuracy_pareto.md
"""
import csv
import sys


def number(text):
    try:
        return float(text)
    except ValueError:
        return float("nan")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: pareto.py ACCURACY.csv")
    with open(sys.argv[1], newline="") as f:
        rows = list(csv.DictReader(f))
    scenes = []
    for r in rows:
        if r["scene"] not in scenes:
            scenes.append(r["scene"])
    print("| scene | particles | solver | precond. | integrator | Newton | tol. | cap | substeps | ms/frame"
          " | it./solve | traj. err RMS | traj. err max | lin. err (max) | rollbacks | max strain |")
    print("|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|---|")
    for scene in scenes:
        mine = [r for r in rows if r["scene"] == scene]
        ref = [r for r in mine if r["role"] == "reference"]
        runs = [r for r in mine if r["role"] == "config"]
        pts = [(number(r["ms_per_frame"]), number(r["traj_err_rms"]), r) for r in runs]
        pts = [p for p in pts if p[0] == p[0] and p[1] == p[1]]  # drop NaNs
        pts.sort(key=lambda p: (p[0], p[1]))
        front, best = [], float("inf")
        for ms, err, r in pts:
            if err < best:
                front.append(r)
                best = err
        for r in front:
            print("| %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s | %s |" % (
                scene, r["particles"], r["solver"], r.get("preconditioner", "-"), r.get("integrator", "-"),
                r.get("newton_iterations", "-"), r["tolerance"], r["max_iterations"], r["substeps"],
                r["ms_per_frame"], r.get("iterations_per_solve", "-"), r["traj_err_rms"], r["traj_err_max"],
                r["lin_err_max"], r["rollbacks"], r["max_strain"]))
        for r in ref:
            print("| %s | %s | %s | - | %s | %s | - | - | %s | %s | - | 0 | 0 | - | %s | %s |" % (
                scene, r["particles"], r["solver"], r.get("integrator", "-"), r.get("newton_iterations", "-"),
                r["substeps"], r["ms_per_frame"], r["rollbacks"], r["max_strain"]))


main()

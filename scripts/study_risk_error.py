#!/usr/bin/python3
"""Is the concentrated scene's error bar honest? Each case runs twice: on a
grid of N cells and on one of 4N, each with its own converged D_max and error
estimate (risk_max_converged, risk_max_error_estimate). The bar of the coarse
run must hold the fine run's converged value.

    scripts/study_risk_error.py [-o DIR] [--cells 128] [--cases paper,elliptical,titanium,aluminium,small_amplitude]
    scripts/study_risk_error.py --cells 64 --cases gross_slip,mu_1,mu_1_gross_slip,aluminium_small,hypersphere,oblique_bulk

Prints a table and writes DIR/risk_error.csv. The cases: the paper's (steel
ball on steel flat), an elliptical steel contact (Ry/Rx = 3, mu = 0.3), a
titanium flat under a steel ball (mu = 0.6, Ti-6Al-4V's fatigue limits) and an
aluminium flat under a steel ball (mu = 0.8, 7075-T6's fatigue limits) and the
paper's case at mu = 0.1 and 5 % of its gross-slip shift (the risk peaks in the
thin slip annulus). Two cycles of 100 steps (the running-mean risk peaks in the
first cycle).
"""
import argparse
import csv
import json
import os
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG = os.path.join(ROOT, "configs", "paper_concentrated.prm")
COMMON = {"Loading/Cycles": "2", "Loading/Steps per cycle": "100", "Output/Field snapshots per cycle": "0"}
CASES = {
    "paper": {},
    "elliptical": {"Geometry/Radius x": "0.02", "Geometry/Radius y": "0.06", "Loading/Normal load": "500",
                   "Friction/Friction coefficient": "0.3", "Loading/Sliding amplitude": "1.0e-6"},
    "titanium": {"Materials/Lower body/Young's modulus": "110e9", "Materials/Lower body/Poisson ratio": "0.34",
                 "Geometry/Radius x": "0.025", "Geometry/Radius y": "0.025", "Loading/Normal load": "500",
                 "Friction/Friction coefficient": "0.6", "Loading/Sliding amplitude": "2.0e-6",
                 "Dang Van/Bending fatigue limit": "500e6", "Dang Van/Torsion fatigue limit": "300e6"},
    "aluminium": {"Materials/Lower body/Young's modulus": "71.7e9", "Materials/Lower body/Poisson ratio": "0.33",
                  "Loading/Normal load": "100", "Friction/Friction coefficient": "0.8",
                  "Loading/Sliding amplitude": "1.5e-6",
                  "Dang Van/Bending fatigue limit": "160e6", "Dang Van/Torsion fatigue limit": "100e6"},
    "small_amplitude": {"Friction/Friction coefficient": "0.1", "Loading/Sliding amplitude": "0.07e-6"},
}
# More regimes of the paper's case, run with --cells 64 --cases ...: gross
# slip, mu = 1, a softer flat, the hypersphere centre after a warm-up cycle,
# an oblique sliding direction under a bulk stress.
MORE_CASES = {
    "gross_slip": {"Friction/Friction coefficient": "0.1", "Loading/Sliding amplitude": "1.7e-6"},
    "mu_1": {"Friction/Friction coefficient": "1.0", "Loading/Sliding amplitude": "6.9e-6"},
    "mu_1_gross_slip": {"Friction/Friction coefficient": "1.0", "Loading/Sliding amplitude": "17e-6"},
    "aluminium_small": {"Materials/Lower body/Young's modulus": "70e9", "Materials/Lower body/Poisson ratio": "0.33",
                        "Friction/Friction coefficient": "0.3", "Loading/Sliding amplitude": "0.5e-6"},
    "hypersphere": {"Dang Van/Residual stress": "hypersphere", "Dang Van/Warm-up cycles": "1", "Loading/Cycles": "3"},
    "oblique_bulk": {"Loading/Sliding direction": "1.0472", "Bulk stress/Static xx": "200e6",
                     "Bulk stress/Amplitude yy": "100e6"},
}


def run(program, output, settings):
    arguments = [program, "run", CONFIG, "-o", output, "--no-plots", "-q", "--force"]
    for key, value in settings.items():
        arguments += ["--set", f"{key}={value}"]
    started = time.time()
    subprocess.run(arguments, check=True, stdout=subprocess.DEVNULL)
    with open(os.path.join(output, "summary.json")) as stream:
        summary = json.load(stream)
    summary["seconds"] = time.time() - started
    return summary


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "results", "risk_error"))
    parser.add_argument("--cells", type=int, default=128)
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "fretsim"))
    parser.add_argument("--cases", default=",".join(CASES))
    args = parser.parse_args()
    rows = []
    print(f"{'case':<12}{'cells':>6}{'D_max':>9}{'converged':>11}{'bar':>9}{'time [s]':>10}  hot spot")
    for name in args.cases.split(","):
        results = {}
        for cells in (args.cells, 4 * args.cells):
            settings = dict(COMMON, **{**CASES, **MORE_CASES}[name],
                            **{"Grid/Cells x": str(cells), "Grid/Cells y": str(cells)})
            summary = run(args.program, os.path.join(args.output, f"{name}-{cells}"), settings)
            results[cells] = summary
            print(f"{name:<12}{cells:>6}{summary['risk_max']:>9.4f}{summary['risk_max_converged']:>11.4f}"
                  f"{summary['risk_max_error_estimate']:>9.4f}{summary['seconds']:>10.1f}  "
                  f"{summary['risk_convergence']['hot_spot']}", flush=True)
        coarse, fine = results[args.cells], results[4 * args.cells]
        miss = abs(coarse["risk_max_converged"] - fine["risk_max_converged"])
        holds = miss <= coarse["risk_max_error_estimate"]
        print(f"{name:<12}|converged {args.cells} - converged {4 * args.cells}| = {miss:.4f} "
              f"{'<=' if holds else '>'} bar {coarse['risk_max_error_estimate']:.4f}: {'holds' if holds else 'FAILS'}")
        rows.append({"case": name, "cells": args.cells, "risk_max": coarse["risk_max"],
                     "converged": coarse["risk_max_converged"], "error_estimate": coarse["risk_max_error_estimate"],
                     "fine_cells": 4 * args.cells, "fine_risk_max": fine["risk_max"],
                     "fine_converged": fine["risk_max_converged"], "fine_error_estimate": fine["risk_max_error_estimate"],
                     "hot_spot": coarse["risk_convergence"]["hot_spot"], "difference": miss, "holds": holds, "seconds": coarse["seconds"], "fine_seconds": fine["seconds"]})
    os.makedirs(args.output, exist_ok=True)
    with open(os.path.join(args.output, "risk_error.csv"), "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    return 0 if all(row["holds"] for row in rows) else 1


if __name__ == "__main__":
    sys.exit(main())

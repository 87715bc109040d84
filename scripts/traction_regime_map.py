#!/usr/bin/python3
"""Regime map of the traction models: how far `bristle`, `elastoplastic
bristle` and `exact masing` fall from the incremental `exact` solver across
friction coefficients, sliding amplitudes (against Mindlin's gross-slip
amplitude delta_t), materials and contact shapes.

    scripts/traction_regime_map.py [-o DIR] [--program build/fretsim] [--cells 64]
        [--cycles 2] [--steps 40] [--depths "0, 3.75e-5, 7.5e-5"] [--groups steel,aluminium,...]

Each regime point is one `fretsim compare-traction` of configs/paper_concentrated.prm
with overrides. delta_t of each load case (mu, materials, geometry) comes from
the summary.json of a quick run (1 cycle of 8 steps on 32x32 cells).

The map: steel ball on a steel flat (the config's) with a circular contact at
mu = 0.1, 0.3, 0.6, 1.0 and delta*/delta_t = 0.05, 0.2, 0.5, 0.8, 1.0, 1.2;
then, at mu = 0.3, 0.6 and delta*/delta_t = 0.2, 0.5, 0.8, 1.2: an aluminium
flat (E = 70 GPa, nu = 0.33), a titanium flat (110 GPa, 0.34) and an elliptical
steel contact (Ry/Rx = 5: Radius x = 0.02, Radius y = 0.1).

Writes DIR/traction_map.csv (one line per point and model: the regime
parameters, delta_t, the amplitude ratio and every column of
compare_traction.csv), DIR/traction_map.png (the relative D_max error against
the amplitude ratio, one panel per group, a line per model and mu; below, the
loop error) and prints the worst |relative D_max error| per model, over the
whole map and per group. A point already done (its compare_traction.csv exists)
is read again rather than rerun unless --rerun is given.
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
MODELS = ["bristle", "elastoplastic bristle", "exact masing", "exact"]
COLUMNS = ["wall_time_s", "speed_up_vs_exact", "traction_time_s", "traction_speed_up_vs_exact", "loop_error_mu_P",
           "slip_fraction_error", "dissipated_energy_J", "energy_error", "risk_max", "risk_max_difference",
           "risk_max_relative_error", "risk_max_distance_m", "risk_max_x_m", "risk_max_y_m", "risk_max_depth_m"]
GROUPS = {
    "steel": {"settings": {}, "mu": [0.1, 0.3, 0.6, 1.0], "ratios": [0.05, 0.2, 0.5, 0.8, 1.0, 1.2],
              "label": "steel on steel, circular"},
    "aluminium": {"settings": {"Materials/Lower body/Young's modulus": "70e9",
                               "Materials/Lower body/Poisson ratio": "0.33"},
                  "mu": [0.3, 0.6], "ratios": [0.2, 0.5, 0.8, 1.2], "label": "steel on aluminium, circular"},
    "titanium": {"settings": {"Materials/Lower body/Young's modulus": "110e9",
                              "Materials/Lower body/Poisson ratio": "0.34"},
                 "mu": [0.3, 0.6], "ratios": [0.2, 0.5, 0.8, 1.2], "label": "steel on titanium, circular"},
    "elliptical": {"settings": {"Geometry/Radius x": "0.02", "Geometry/Radius y": "0.1"},
                   "mu": [0.3, 0.6], "ratios": [0.2, 0.5, 0.8, 1.2], "label": "steel on steel, Ry/Rx = 5"},
}
SHORT = {"bristle": "bristle", "elastoplastic bristle": "elastoplastic", "exact masing": "masing", "exact": "exact"}


def arguments_of(program, command, output, settings):
    arguments = [program, command, CONFIG, "-o", output, "--no-plots", "-q", "--force"]
    for key, value in settings.items():
        arguments += ["--set", f"{key}={value}"]
    return arguments


def call(arguments):
    result = subprocess.run(arguments, capture_output=True, text=True)
    if result.returncode != 0:
        message = (result.stderr.strip() or result.stdout.strip()).splitlines()
        raise RuntimeError(f"exit {result.returncode}: {message[-1] if message else '(no message)'}")


def gross_slip_amplitude(program, output, settings):
    """delta_t [m] of one load case from a quick run's summary.json."""
    quick = dict(settings, **{"Loading/Cycles": "1", "Loading/Steps per cycle": "8", "Grid/Cells x": "32",
                              "Grid/Cells y": "32", "Convergence/Risk error estimate": "false",
                              "Output/Field snapshots per cycle": "0", "Friction/Traction model": "bristle"})
    summary_path = os.path.join(output, "summary.json")
    if not os.path.exists(summary_path):
        call(arguments_of(program, "run", output, quick))
    with open(summary_path) as stream:
        return float(json.load(stream)["gross_slip_displacement_m"])


def read_compare(directory):
    with open(os.path.join(directory, "compare_traction.csv")) as stream:
        return {row["model"]: row for row in csv.DictReader(stream)}


def number(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def plot(rows, groups, path):
    import matplotlib
    matplotlib.use("Agg")
    import matplotlib.pyplot as plt

    colours = {"bristle": "tab:blue", "elastoplastic bristle": "tab:orange", "exact masing": "black"}
    styles = ["-", "--", ":", "-."]
    fig, axes = plt.subplots(2, len(groups), figsize=(4.6 * len(groups), 8.0), sharex=True, squeeze=False,
                             constrained_layout=True)
    for column, group in enumerate(groups):
        top, bottom = axes[0][column], axes[1][column]
        for model, colour in colours.items():
            for mu, style in zip(GROUPS[group]["mu"], styles):
                points = sorted((r["amplitude_ratio"], r) for r in rows
                                if r["group"] == group and r["model"] == model and r["mu"] == mu)
                if not points:
                    continue
                ratio = [p[0] for p in points]
                top.plot(ratio, [100 * number(p[1]["risk_max_relative_error"]) for p in points], style, color=colour,
                         marker="o", markersize=3, label=f"{SHORT[model]}, μ = {mu:g}")
                bottom.plot(ratio, [number(p[1]["loop_error_mu_P"]) for p in points], style, color=colour,
                            marker="o", markersize=3)
        for limit in (-5, 5):
            top.axhline(limit, color="grey", linewidth=0.8, linestyle=":")
        top.axhline(0, color="grey", linewidth=0.6)
        top.set_title(GROUPS[group]["label"])
        top.set_ylabel("D_max error vs exact [%]")
        bottom.set_ylabel("loop error max|Q − Q_exact|/(μP) [–]")
        bottom.set_xlabel("δ*/δ_t [–]")
        for ax in (top, bottom):
            ax.grid(True, alpha=0.3)
            ax.axvline(1.0, color="grey", linewidth=0.6, linestyle="--")
        top.legend(fontsize=7, ncol=1 if len(GROUPS[group]["mu"]) <= 2 else 2)
    fig.suptitle("Traction models against the incremental exact solver (relative D_max error and loop error)")
    fig.savefig(path, dpi=110)
    plt.close(fig)


def worst(rows, model, group=None):
    """The largest |relative D_max error| of a model (over a group) and the row it sits in."""
    candidates = [r for r in rows if r["model"] == model and (group is None or r["group"] == group)
                  and number(r["risk_max_relative_error"]) == number(r["risk_max_relative_error"])]
    if not candidates:
        return None
    return max(candidates, key=lambda r: abs(number(r["risk_max_relative_error"])))


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "results", "traction_map"))
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "fretsim"))
    parser.add_argument("--groups", default=",".join(GROUPS), help="comma-separated subset of " + ",".join(GROUPS))
    parser.add_argument("--cells", type=int, default=64, help="cells in x and in y")
    parser.add_argument("--cycles", type=int, default=2)
    parser.add_argument("--steps", type=int, default=40, help="steps per cycle")
    parser.add_argument("--depths", default="0, 3.75e-5, 7.5e-5", help="Stresses/Depth layers [m]")
    parser.add_argument("--pressure", default="numerical", help="Normal contact/Pressure model")
    parser.add_argument("--min-ratio", type=float, default=0.0, help="skip amplitude ratios below this")
    parser.add_argument("--rerun", action="store_true", help="rerun points whose compare_traction.csv exists")
    args = parser.parse_args()
    groups = args.groups.split(",")
    for group in groups:
        if group not in GROUPS:
            sys.exit(f"unknown group '{group}' (known: {', '.join(GROUPS)})")
    numerics = {"Grid/Cells x": str(args.cells), "Grid/Cells y": str(args.cells), "Loading/Cycles": str(args.cycles),
                "Loading/Steps per cycle": str(args.steps), "Output/Field snapshots per cycle": "0",
                "Stresses/Depth layers": args.depths, "Normal contact/Pressure model": args.pressure}
    os.makedirs(args.output, exist_ok=True)
    rows, failures, started = [], [], time.time()
    print(f"{'group':<11}{'mu':>5}{'d/dt':>6}{'delta* [um]':>12}  "
          + "".join(f"{SHORT[m]:>14}" for m in MODELS[:3]) + f"{'D_max exact':>13}{'time [s]':>10}", flush=True)
    for group in groups:
        spec = GROUPS[group]
        for mu in spec["mu"]:
            case = dict(spec["settings"], **{"Friction/Friction coefficient": f"{mu:g}"})
            tag = f"{group}-mu{mu:g}"
            try:
                delta_t = gross_slip_amplitude(args.program, os.path.join(args.output, "delta_t", tag), case)
            except RuntimeError as error:
                failures.append(f"{tag} (delta_t): {error}")
                print(f"{tag}: delta_t run failed: {error}", flush=True)
                continue
            for ratio in spec["ratios"]:
                if ratio < args.min_ratio:
                    continue
                amplitude = ratio * delta_t
                directory = os.path.join(args.output, f"{tag}-r{ratio:g}")
                settings = dict(case, **numerics, **{"Loading/Sliding amplitude": f"{amplitude:.6e}"})
                point_started = time.time()
                if args.rerun or not os.path.exists(os.path.join(directory, "compare_traction.csv")):
                    try:
                        call(arguments_of(args.program, "compare-traction", directory, settings))
                    except RuntimeError as error:
                        failures.append(f"{tag} ratio {ratio:g}: {error}")
                        print(f"{group:<11}{mu:>5g}{ratio:>6g}{amplitude * 1e6:>12.4f}  failed: {error}", flush=True)
                        continue
                seconds = time.time() - point_started
                compared = read_compare(directory)
                for model in MODELS:
                    row = {"group": group, "lower_E_Pa": settings.get("Materials/Lower body/Young's modulus", "200e9"),
                           "lower_nu": settings.get("Materials/Lower body/Poisson ratio", "0.3"),
                           "radius_x_m": settings.get("Geometry/Radius x", "0.05"),
                           "radius_y_m": settings.get("Geometry/Radius y", "0.05"), "mu": mu,
                           "gross_slip_amplitude_m": delta_t, "amplitude_ratio": ratio, "sliding_amplitude_m": amplitude,
                           "cells": args.cells, "cycles": args.cycles, "steps_per_cycle": args.steps, "model": model}
                    row.update({k: compared.get(model, {}).get(k, "") for k in COLUMNS})
                    rows.append(row)
                errors = "".join(f"{100 * number(compared.get(m, {}).get('risk_max_relative_error')):>13.2f}%"
                                 for m in MODELS[:3])
                print(f"{group:<11}{mu:>5g}{ratio:>6g}{amplitude * 1e6:>12.4f}  {errors}"
                      f"{number(compared.get('exact', {}).get('risk_max')):>13.4f}{seconds:>10.1f}", flush=True)
    if not rows:
        sys.exit("no regime point ran:\n" + "\n".join(failures))
    with open(os.path.join(args.output, "traction_map.csv"), "w", newline="") as stream:
        writer = csv.DictWriter(stream, fieldnames=list(rows[0]))
        writer.writeheader()
        writer.writerows(rows)
    plot(rows, [g for g in groups if any(r["group"] == g for r in rows)], os.path.join(args.output, "traction_map.png"))

    print(f"\nWorst |relative D_max error| against exact ({len(rows) // len(MODELS)} points, "
          f"{time.time() - started:.0f} s):")
    print(f"{'model':<24}{'scope':<12}{'worst':>9}   where (mu, d/dt)")
    for model in MODELS[:3]:
        for scope in [None] + groups:
            row = worst(rows, model, scope)
            if row is None:
                continue
            print(f"{model:<24}{scope or 'all':<12}{100 * number(row['risk_max_relative_error']):>+8.2f}%   "
                  f"{row['group']}, {row['mu']:g}, {row['amplitude_ratio']:g}")
    print(f"\nwrote {os.path.join(args.output, 'traction_map.csv')} and traction_map.png")
    if failures:
        print("failed points:\n  " + "\n  ".join(failures))
        return 1
    return 0


if __name__ == "__main__":
    sys.exit(main())

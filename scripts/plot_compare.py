#!/usr/bin/env python3
"""The reduced ring against the full FE model, from the CSV written by
`fretsim compare CONFIG`: the errors at each compared instant (the model as
used, and the run's own modal coordinates), and the worst error against the
truncated model's size and run time; below, the ring on the scene's Winkler
foundation under the run's ball loads: full against reduced pressure along
the circumference at the instant of the highest peak (compare_pressure.csv,
beside the CSV), and the pressure error against n_cc' and run time. Prints the
path of the PNG it writes."""
import csv
import math
import os
import sys
import textwrap

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

FLOOR = 1e-12  # exact (round-off) errors stay visible on a log axis


def number(row, key):
    try:
        value = float(row[key])
    except (KeyError, ValueError):
        return math.nan
    return value


def clipped(values):
    return [max(v, FLOOR) if not math.isnan(v) else math.nan for v in values]


def main(csv_path):
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    model = sorted((r for r in rows if r["whole_model"] == "1"), key=lambda r: int(r["instant"]))
    fig, grid_axes = plt.subplots(2, 3, figsize=(18, 11))
    axes, winkler_axes = grid_axes[0], grid_axes[1]

    # Errors per instant, the model as the co-simulation uses it.
    ax = axes[0]
    x = [int(r["instant"]) for r in model]
    labels = [f"{int(r['instant'])}\nt={float(r['time_s']):.4g}" for r in model]
    series = [("error_u_r", "u_r on the grid", "o-"), ("error_u_theta", "u_theta on the grid", "o:"),
              ("error_u_z", "u_z on the grid", "o:"), ("error_stress_grid", "stress on the grid", "s-"),
              ("error_stress_raceway", "stress at the raceway points", "^-"),
              ("error_stress_raceway_far", "stress at raceway points away from the balls", "^:"),
              ("error_energy", "energy norm", "d-"), ("error_ball_approach", "ball approach r.q", "v--"),
              ("error_u_r_balls", "u_r, the balls alone", "o--"),
              ("error_u_r_tractions", "u_r, the interface tractions alone", "s--"),
              ("run_error_u_r", "run's q: u_r on the grid", "x--"),
              ("run_error_stress_grid", "run's q: stress on the grid", "+--")]
    for key, label, style in series:
        values = clipped([number(r, key) for r in model])
        if all(math.isnan(v) for v in values):
            continue
        ax.plot(x, values, style, label=label)
    ax.set_xticks(x)
    ax.set_xticklabels(labels, fontsize=7)
    ax.set_yscale("log")
    ax.set_xlabel("compared instant")
    ax.set_ylabel("max-norm error / max of the full FE field [-]")
    if model:
        ax.set_title(f"model m = {model[0]['fixed_interface_modes']}, "
                     f"n_cc = {model[0]['characteristic_constraint_modes']} against full FE")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=7)

    # The study: worst instant per truncation.
    worst = {}
    for r in rows:
        key = (int(r["fixed_interface_modes"]), int(r["characteristic_constraint_modes"]))
        entry = worst.setdefault(key, {"size": int(r["reduced_size"]), "u": 0.0, "s": 0.0, "e": 0.0, "p": 0.0,
                                       "t": 0.0, "count": 0})
        for name, column in (("u", "error_u_r"), ("s", "error_stress_grid"), ("e", "error_energy"),
                             ("p", "error_u_r_balls"), ("p", "error_u_r_tractions")):
            value = number(r, column)
            if not math.isnan(value):
                entry[name] = max(entry[name], value)
        entry["t"] += float(r["reduced_s"])
        entry["count"] += 1
    full_time = max((float(r["full_setup_s"]) + float(r["full_solve_s"]) for r in rows), default=math.nan)
    for m in sorted({k[0] for k in worst}):
        keys = sorted(k for k in worst if k[0] == m)
        sizes = [worst[k]["size"] for k in keys]
        times = [worst[k]["t"] / worst[k]["count"] for k in keys]
        u = clipped([worst[k]["u"] for k in keys])
        s = clipped([worst[k]["s"] for k in keys])
        e = clipped([worst[k]["e"] for k in keys])
        parts = clipped([worst[k]["p"] for k in keys])
        line, = axes[1].plot(sizes, u, "o-", label=f"m' = {m}: u_r")
        axes[1].plot(sizes, s, "s--", color=line.get_color(), alpha=0.7, label=f"m' = {m}: stress")
        axes[1].plot(sizes, e, "d:", color=line.get_color(), alpha=0.7, label=f"m' = {m}: energy")
        axes[1].plot(sizes, parts, "x-.", color=line.get_color(), alpha=0.7,
                     label=f"m' = {m}: u_r, balls or tractions alone")
        for k, xs, ys in zip(keys, sizes, u):
            axes[1].annotate(str(k[1]), (xs, ys), fontsize=7, textcoords="offset points", xytext=(3, 3))
        axes[2].plot(times, u, "o-", color=line.get_color(), label=f"m' = {m}: u_r")
        axes[2].plot(times, s, "s--", color=line.get_color(), alpha=0.7)
    axes[1].set_xlabel("reduced size m' + n_cc' (labels: n_cc')")
    axes[1].set_ylabel("worst error over the instants [-]")
    axes[2].set_xlabel("reduced time per instant [s] (projection + solve + recovery)")
    axes[2].set_ylabel("worst error over the instants [-] (o: u_r, s: stress)")
    axes[2].set_xscale("log")
    if not math.isnan(full_time):
        axes[2].set_title(f"full FE: {full_time:.3g} s per instant (setup + solve)")
    for ax in axes[1:]:
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)
    plot_winkler(rows, winkler_axes, os.path.join(os.path.dirname(os.path.abspath(csv_path)), "compare_pressure.csv"))
    fig.suptitle("Reduced ring against the full FE model at the same ball loads and interface tractions (top); "
                 "on the Winkler foundation under the ball loads alone (bottom)")
    fig.tight_layout()
    out = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "compare.png")
    fig.savefig(out, dpi=110)
    print(out)


def read_profile(path):
    """The comment lines and the columns of compare_pressure.csv."""
    with open(path) as f:
        lines = f.read().splitlines()
    comments = [line.lstrip("# ").strip() for line in lines if line.startswith("#")]
    reader = csv.DictReader(line for line in lines if not line.startswith("#"))
    columns = {name: [] for name in reader.fieldnames}
    for row in reader:
        for name in reader.fieldnames:
            columns[name].append(number(row, name))
    return comments, columns


def plot_winkler(rows, axes, profile_path):
    kn = next((number(r, "winkler_normal_stiffness_Pa_per_m") for r in rows), math.nan)
    # Pressure along the circumference at the instant of the highest peak.
    ax = axes[0]
    if os.path.exists(profile_path):
        comments, columns = read_profile(profile_path)
        title = comments[0] if comments else ""
        # A second comment line names what else the run had (compare's note:
        # "run_Pa is the run's own pressure, with <what>: not ...").
        other = next((line.split(", with ", 1)[1].split(": not", 1)[0]
                      for line in comments[1:] if ", with " in line), None)
        theta = columns["theta_deg"]
        reduced = [name for name in columns if name.startswith("reduced_")]
        model = [r for r in rows if r["whole_model"] == "1"]
        model_name = (f"reduced_m{model[0]['fixed_interface_modes']}_ncc{model[0]['characteristic_constraint_modes']}_Pa"
                      if model else None)
        largest_m = max((int(name.split("_m")[1].split("_")[0]) for name in reduced), default=None)
        for name in reduced:
            if name == model_name:
                continue
            m = int(name.split("_m")[1].split("_")[0])
            if m == largest_m:
                ax.plot(theta, [1e-6 * v for v in columns[name]], "-", lw=0.8, alpha=0.6,
                        label=name.replace("reduced_", "reduced ").replace("_Pa", "").replace("_", ", "))
        if model_name in columns:
            ax.plot(theta, [1e-6 * v for v in columns[model_name]], "r-", lw=1.5,
                    label="reduced, the model (" + model_name.replace("reduced_", "").replace("_Pa", "") + ")")
        ax.plot(theta, [1e-6 * v for v in columns["full_Pa"]], "k-", lw=2, label="full FE")
        ax.plot(theta, [1e-6 * v for v in columns["run_Pa"]], "b--", lw=1, label=f"the run (with {other}: not this problem)" if other
                else "the run (dynamic, with tractions)")
        ax.set_title(textwrap.fill(title, 70), fontsize=8)
    ax.set_xlabel("theta [deg] (axial mid-row of the interface grid)")
    ax.set_ylabel("pressure [MPa]")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=7)

    # Worst pressure error over the instants against n_cc' (one line per m'), and against time.
    worst = {}
    for r in rows:
        key = (int(r["fixed_interface_modes"]), int(r["characteristic_constraint_modes"]))
        entry = worst.setdefault(key, {"max": math.nan, "l2": math.nan, "t": 0.0, "count": 0})
        for name, column in (("max", "winkler_error_pressure_max"), ("l2", "winkler_error_pressure_l2")):
            value = number(r, column)
            if not math.isnan(value):
                entry[name] = value if math.isnan(entry[name]) else max(entry[name], value)
        seconds = number(r, "winkler_reduced_s")
        if not math.isnan(seconds):
            entry["t"] += seconds
            entry["count"] += 1
    full_time = max((number(r, "winkler_full_s") for r in rows), default=math.nan)
    for m in sorted({k[0] for k in worst}):
        keys = sorted(k for k in worst if k[0] == m)
        n_cc = [k[1] for k in keys]
        maxima = clipped([worst[k]["max"] for k in keys])
        l2 = clipped([worst[k]["l2"] for k in keys])
        times = [worst[k]["t"] / max(worst[k]["count"], 1) for k in keys]
        line, = axes[1].plot(n_cc, maxima, "o-", label=f"m' = {m}: max-norm")
        axes[1].plot(n_cc, l2, "s--", color=line.get_color(), alpha=0.7, label=f"m' = {m}: L2")
        axes[2].plot(times, maxima, "o-", color=line.get_color(), label=f"m' = {m}: max-norm")
        axes[2].plot(times, l2, "s--", color=line.get_color(), alpha=0.7)
        for xs, ys, c in zip(times, maxima, n_cc):
            axes[2].annotate(str(c), (xs, ys), fontsize=7, textcoords="offset points", xytext=(3, 3))
    axes[1].set_xlabel("characteristic constraint modes n_cc'")
    axes[1].set_ylabel("pressure error, worst instant [-] (max |p_r - p| / max p; L2)")
    axes[1].set_title(f"Winkler foundation, k_n = {kn:.3g} Pa/m: reduced against full FE pressure", fontsize=9)
    axes[2].set_xlabel("reduced Winkler solve per instant [s] (labels: n_cc')")
    axes[2].set_ylabel("pressure error, worst instant [-]")
    axes[2].set_xscale("log")
    if not math.isnan(full_time):
        axes[2].set_title(f"full FE Winkler solve: up to {full_time:.3g} s per instant (active set, refactorisations)",
                          fontsize=9)
    for ax in axes[1:]:
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=7)


if __name__ == "__main__":
    main(sys.argv[1])

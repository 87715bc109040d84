#!/usr/bin/env python3
"""The reduced ring against the full FE model, from the CSV written by
`fretsim compare CONFIG`: the errors at each compared instant (the model as
used, and the run's own modal coordinates), and the worst error against the
truncated model's size and run time. Prints the path of the PNG it writes."""
import csv
import math
import os
import sys

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
    fig, axes = plt.subplots(1, 3, figsize=(18, 5.5))

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
    fig.suptitle("Reduced ring against the full FE model at the same ball loads and interface tractions")
    fig.tight_layout()
    out = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "compare.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main(sys.argv[1])

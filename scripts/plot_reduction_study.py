#!/usr/bin/env python3
"""Error against run time of the Craig-Bampton reduction, from the CSV written
by `fretsim reduce CONFIG --study`. Prints the path of the PNG it writes."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path):
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    floor = 1e-12  # exact (round-off) errors stay visible on a log axis
    fig, axes = plt.subplots(1, 2, figsize=(13, 5.5))
    for m in sorted({int(r["fixed_interface_modes"]) for r in rows}):
        chosen = [r for r in rows if int(r["fixed_interface_modes"]) == m]
        chosen.sort(key=lambda r: int(r["interface_modes"]))
        times = [float(r["reduction_s"]) for r in chosen]
        sizes = [int(r["reduced_size"]) for r in chosen]
        free = [max(float(r["free_error"]), floor) for r in chosen]
        static = [max(float(r["static_displacement_error"]), floor) for r in chosen]
        line, = axes[0].plot(sizes, free, "o-", label=f"m = {m} fixed-interface modes")
        axes[0].plot(sizes, static, "s--", color=line.get_color(), alpha=0.6)
        axes[1].plot(times, free, "o-", color=line.get_color(), label=f"m = {m}")
        for r, x, y in zip(chosen, sizes, free):
            axes[0].annotate(r["interface_modes"], (x, y), fontsize=7, textcoords="offset points", xytext=(3, 3))
    for ax in axes:
        ax.axhline(5e-3, color="grey", linestyle=":", linewidth=1)
        ax.set_yscale("log")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_xlabel("reduced size m + n_cc (labels: n_cc)")
    axes[0].set_ylabel("relative error [-]\n(o: max over the lowest 10 free-free frequencies;\n"
                       "s: static squeeze, max |u_r| error on the interface grid)")
    axes[1].set_xscale("log")
    axes[1].set_xlabel("reduction time [s]")
    axes[1].set_ylabel("max error of the lowest 10 free-free frequencies [-]")
    axes[0].legend(fontsize=8)
    axes[1].legend(fontsize=8)
    fig.suptitle("Craig-Bampton with characteristic constraint modes: error against size and run time "
                 "(dotted: 0.5 %)")
    fig.tight_layout()
    out = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "reduction_study.png")
    fig.savefig(out, dpi=110)
    print(out)


if __name__ == "__main__":
    main(sys.argv[1])

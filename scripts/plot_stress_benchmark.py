#!/usr/bin/env python3
"""Error against run time of the subsurface-stress evaluators, from the CSV
written by `fretsim bench stresses`. Prints the path of the PNG it writes."""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path):
    with open(csv_path) as f:
        rows = [r for r in csv.DictReader(f) if r["measured"] == "1"]
    threads = min(int(r["threads"]) for r in rows)
    rows = [r for r in rows if int(r["threads"]) == threads]
    markers = {"direct": "s", "fft": "o", "mlmi": "^"}
    labels = {"direct": "direct summation", "fft": "DC-FFT", "mlmi": "MLMI"}
    sizes = sorted({int(r["cells"]) for r in rows})
    colours = plt.cm.viridis([i / max(1, len(sizes) - 1) for i in range(len(sizes))])
    # Round-off errors (DC-FFT) are shown at a floor so they stay on a log axis.
    floor = 1e-16
    fig, ax = plt.subplots(figsize=(8.5, 6))
    for method in ("direct", "fft", "mlmi"):
        for size, colour in zip(sizes, colours):
            chosen = [r for r in rows if r["evaluator"] == method and int(r["cells"]) == size]
            if not chosen:
                continue
            times = [float(r["time_s"]) for r in chosen]
            errors = [max(float(r["error_p0"]), floor) if float(r["error_p0"]) >= 0 else floor for r in chosen]
            # Marker area grows with the number of depth layers.
            areas = [25 + 8 * int(r["layers"]) for r in chosen]
            ax.scatter(times, errors, marker=markers[method], color=colour, s=areas, edgecolor="k", linewidth=0.5)
    for method in ("direct", "fft", "mlmi"):
        ax.scatter([], [], marker=markers[method], color="w", edgecolor="k", label=labels[method])
    for size, colour in zip(sizes, colours):
        ax.scatter([], [], marker="o", color=colour, label=f"{size} x {size} cells")
    ax.axhline(1e-3, color="grey", linestyle="--", linewidth=1)
    ax.text(min(float(r["time_s"]) for r in rows), 1.2e-3, "target 1e-3 p0", color="grey", fontsize=9)
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel(f"run time per evaluation, {threads} thread(s) [s]")
    ax.set_ylabel("max |σ − σ_ref| / p0 [–]\n(σ_ref: direct summation, DC-FFT where direct is too slow; the reference itself at 1e-16)")
    ax.set_title("Subsurface stresses of a sliding Hertz contact: error against run time\n"
                 "(each point: one grid size and depth-layer count; larger markers, more layers)")
    ax.grid(True, which="both", alpha=0.3)
    ax.legend(fontsize=8, loc="center right")
    out = os.path.join(os.path.dirname(os.path.abspath(csv_path)), "stress_benchmark.png")
    fig.tight_layout()
    fig.savefig(out, dpi=130)
    print(out)


if __name__ == "__main__":
    main(sys.argv[1])

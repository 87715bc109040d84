#!/usr/bin/python3
"""Figures of a `fretsim fe` run: python3 scripts/plot_fe_results.py RESULTS_DIR

Reads RESULTS_DIR/results.h5 and writes PNG figures into RESULTS_DIR, printing
each figure's path on a line of its own.

  fe_stress.png   static and transient runs: hoop and radial stress along
                  each circumferential sample line against theta (transient:
                  the range over the run with the first and last snapshot)
  fe_modes.png    modal runs: the eigenfrequencies

Needs Debian's python3-matplotlib and python3-h5py (run with /usr/bin/python3).
Exit status: 0 on success, 1 if the results file is missing or unreadable.
"""

import os
import sys

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    import h5py
except ImportError as error:
    print(f"plot_fe_results.py: {error}", file=sys.stderr)
    sys.exit(1)


def text(value):
    return value.decode() if isinstance(value, bytes) else str(value)


def line_groups(attrs):
    """(name, first, last) of the point groups that are lines (not grids)."""
    groups = []
    for entry in text(attrs.get("point_groups", "")).split(";"):
        parts = entry.split()
        if len(parts) == 3 and parts[0].endswith("_line"):
            groups.append((parts[0], int(parts[1]), int(parts[2])))
    return groups


def stress_figure(directory, f):
    points = f["/points"][...]
    stress = f["/fields/stress"][...]  # [n_snapshots, n_points, 6], rr tt zz tz rz rt
    time = f["/time"][...]
    groups = line_groups(f.attrs)
    if not groups or stress.shape[0] == 0:
        return None
    fig, axes = plt.subplots(len(groups), 2, figsize=(11, 3.2 * len(groups)), squeeze=False)
    colours = plt.cm.viridis(np.linspace(0, 1, max(1, stress.shape[0])))
    for row, (name, first, last) in enumerate(groups):
        theta = np.degrees(np.unwrap(np.arctan2(points[first:last, 1], points[first:last, 0])))
        for col, (component, label) in enumerate(((1, "hoop stress $\\sigma_{\\theta\\theta}$"),
                                                  (0, "radial stress $\\sigma_{rr}$"))):
            ax = axes[row][col]
            values = stress[:, first:last, component] / 1e6
            if stress.shape[0] > 6:
                # Many snapshots: their envelope, and the first and last.
                ax.fill_between(theta, values.min(axis=0), values.max(axis=0), color="0.8",
                                label="range over the run")
                shown = (0, stress.shape[0] - 1)
            else:
                shown = range(stress.shape[0])
            for s in shown:
                ax.plot(theta, values[s], color=colours[s], lw=1.0,
                        label=f"t = {time[s] * 1e3:.2f} ms" if stress.shape[0] > 1 else None)
            ax.set_xlabel("theta [deg]")
            ax.set_ylabel(f"{label} [MPa]")
            ax.set_title(name.replace("_", " "))
            ax.grid(True, alpha=0.3)
            if stress.shape[0] > 1:
                ax.legend(fontsize=8)
    fig.suptitle(f"fretsim fe ({text(f.attrs.get('analysis', ''))}): stresses at the sample points, tension positive")
    fig.tight_layout()
    path = os.path.join(directory, "fe_stress.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def modes_figure(directory, f):
    if "/frequencies" not in f:
        return None
    frequencies = f["/frequencies"][...]
    fig, ax = plt.subplots(figsize=(6, 3.5))
    ax.bar(np.arange(1, len(frequencies) + 1), frequencies / 1e3)
    ax.set_xlabel("mode")
    ax.set_ylabel("frequency [kHz]")
    ax.set_title("fretsim fe: eigenfrequencies")
    ax.grid(True, axis="y", alpha=0.3)
    fig.tight_layout()
    path = os.path.join(directory, "fe_modes.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def main():
    if len(sys.argv) != 2:
        print(__doc__, file=sys.stderr)
        return 1
    directory = sys.argv[1]
    try:
        with h5py.File(os.path.join(directory, "results.h5"), "r") as f:
            analysis = text(f.attrs.get("analysis", ""))
            path = modes_figure(directory, f) if analysis == "modes" else stress_figure(directory, f)
    except (OSError, KeyError) as error:
        print(f"plot_fe_results.py: {error}", file=sys.stderr)
        return 1
    if path:
        print(path)
    return 0


if __name__ == "__main__":
    sys.exit(main())

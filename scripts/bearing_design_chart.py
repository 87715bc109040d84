#!/usr/bin/python3
"""Design chart of the bearing seat: D_max over interference fit x load for a
steel and an aluminium housing.

    scripts/bearing_design_chart.py [-o DIR] [--passes N] [--fits A:B:N]
                                    [--displacements A:B:N] [--wall C] [--ranks R]

Runs `fretsim map` on configs/paper_dgbb_housing.prm once per housing
material, over the radial interference (default 0-30 um, 4 values) and the
inner ring's displacement (default 30-90 um, 3 values: the load), the
housing's wall C its outside radius (default 0.06 m: the 80/120 mm housing
of configs/housing_6208_reduce.prm), N ball
passes after the ramp (2 by default), each map under `mpirun -np R` when
R > 1 (default: the machine's cores; as root with OpenMPI's
OMPI_ALLOW_RUN_AS_ROOT and _CONFIRM set for it). Writes DIR/design_chart.csv (one row
per point: material, fit, displacement, D_max and where, peak pressure, peak
ball load, the radial load the balls carry) and DIR/design_chart.png (D_max
per housing as filled contours, the peak ball load on the second axis), and
prints the table and the paths. DIR: results/bearing_design_chart; each
map's own files stay in DIR/<material>/ (a map stopped part-way continues
when the command is run again).
"""
import argparse
import csv
import json
import os
import shutil
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG = os.path.join(ROOT, "configs", "paper_dgbb_housing.prm")
FIT = "Interface/Radial interference"
DISPLACEMENT = "Loading/Inner ring displacement y"
# (name, label, Young's modulus [Pa], Poisson ratio [-])
MATERIALS = [("steel", "steel housing (E 208 GPa)", 208e9, 0.3),
             ("aluminium", "aluminium housing (E 70 GPa)", 70e9, 0.33)]


def axis_values(text):
    start, stop, count = text.split(":")
    return np.linspace(float(start), float(stop), int(count))


def run_map(directory, material, args):
    _, _, modulus, poisson = material
    command = []
    if args.ranks > 1 and shutil.which("mpirun"):
        command = ["mpirun", "-np", str(args.ranks)]
    command += [os.path.join(ROOT, "build", "fretsim"), "map", CONFIG, "-o", directory, "-q",
                "--axis", f"{FIT}={args.fits}", "--axis", f"{DISPLACEMENT}={args.displacements}",
                "--set", f"Interface/Housing Young's modulus={modulus:g}",
                "--set", f"Interface/Housing Poisson ratio={poisson:g}",
                "--set", f"Interface/Housing outer radius={args.wall:g}",
                "--set", f"Loading/Ball pass periods={args.passes:g}"]
    env = dict(os.environ)
    if os.geteuid() == 0:  # OpenMPI refuses root without both
        env.update(OMPI_ALLOW_RUN_AS_ROOT="1", OMPI_ALLOW_RUN_AS_ROOT_CONFIRM="1")
    subprocess.run(command, check=True, env=env)


def point_rows(directory, material, fits, displacements):
    """The map's points, read from each point's summary.json (index = i_fit + n_fit i_displacement)."""
    rows = []
    points = os.path.join(directory, "points")
    for j, displacement in enumerate(displacements):
        for i, fit in enumerate(fits):
            index = i + len(fits) * j
            summary = os.path.join(points, f"point_{index:06d}", "summary.json")
            if not os.path.exists(summary):
                raise SystemExit(f"bearing_design_chart: no summary.json for point {index} in {points}")
            with open(summary) as f:
                s = json.load(f)
            rows.append({"housing": material[0], "radial_interference_m": fit,
                         "inner_ring_displacement_m": displacement, "risk_max": s["risk_max"],
                         "risk_max_theta_deg": s["risk_max_theta_deg"], "risk_max_depth_m": s["risk_max_depth_m"],
                         "peak_pressure_Pa": s["peak_pressure_Pa"], "peak_ball_load_N": s["peak_ball_load_N"]})
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", default=os.path.join(ROOT, "results", "bearing_design_chart"))
    parser.add_argument("--passes", type=float, default=2.0)
    parser.add_argument("--fits", default="0:30e-6:4")
    parser.add_argument("--displacements", default="30e-6:90e-6:3")
    parser.add_argument("--wall", type=float, default=0.06)
    parser.add_argument("--ranks", type=int, default=os.cpu_count() or 1)
    args = parser.parse_args()
    fits, displacements = axis_values(args.fits), axis_values(args.displacements)
    os.makedirs(args.o, exist_ok=True)
    table = []
    for material in MATERIALS:
        directory = os.path.join(args.o, material[0])
        run_map(directory, material, args)
        table += point_rows(directory, material, fits, displacements)
    for r in table:
        print(f"{r['housing']:10s} fit {r['radial_interference_m'] * 1e6:5.1f} um  inner ring "
              f"{r['inner_ring_displacement_m'] * 1e6:5.1f} um  ball {r['peak_ball_load_N']:7.0f} N  "
              f"peak {r['peak_pressure_Pa'] / 1e6:6.1f} MPa  D_max {r['risk_max']:.4f}", flush=True)
    csv_path = os.path.join(args.o, "design_chart.csv")
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)

    risk = np.array([r["risk_max"] for r in table]).reshape(len(MATERIALS), len(displacements), len(fits))
    ball = np.array([r["peak_ball_load_N"] for r in table]).reshape(risk.shape)
    levels = np.linspace(0.0, max(1.0, np.nanmax(risk)) * 1.0001, 21)
    fig, axes = plt.subplots(1, len(MATERIALS), figsize=(11, 4.6), sharey=True)
    for k, (ax, material) in enumerate(zip(axes, MATERIALS)):
        filled = ax.contourf(fits * 1e6, displacements * 1e6, risk[k], levels=levels, cmap="viridis")
        if np.nanmax(risk[k]) >= 1.0:
            ax.contour(fits * 1e6, displacements * 1e6, risk[k], levels=[1.0], colors="r", linewidths=2)
        lines = ax.contour(fits * 1e6, displacements * 1e6, risk[k], levels=levels[::2], colors="w",
                           linewidths=0.5)
        ax.clabel(lines, fmt="%.2f", fontsize=7)
        ax.plot(*np.meshgrid(fits * 1e6, displacements * 1e6), "k.", ms=3)
        ax.set_title(material[1], fontsize=10)
        ax.set_xlabel("radial interference fit [µm]")
        for j, d in enumerate(displacements):
            ax.annotate(f"{ball[k, j, 0]:.0f}-{ball[k, j, -1]:.0f} N", (fits[-1] * 1e6, d * 1e6), fontsize=7,
                        ha="right", va="bottom", color="w")
    axes[0].set_ylabel("inner ring pushed [µm] (labels: peak ball load)")
    fig.colorbar(filled, ax=axes, label="D_max at the seat (Dang Van; red: D = 1)")
    fig.suptitle(f"6208 outer ring seat: fretting-fatigue risk over fit and load, housing outside "
                 f"{2e3 * args.wall:g} mm, {args.passes:g} ball passes, μ 0.11", fontsize=10)
    png_path = os.path.join(args.o, "design_chart.png")
    fig.savefig(png_path, dpi=120)
    print(csv_path)
    print(png_path)


if __name__ == "__main__":
    sys.exit(main())

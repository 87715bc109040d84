#!/usr/bin/env python3
"""A bearing_housing run against the full FE of the same scene, from the files
`fretsim reference CONFIG` writes in DIR: the verdict in the title (both D_max,
both peak pressures, their differences and the reference's error bar), the
interface pressure around the ring at the instant of the full FE's highest
peak and D_max around the ring (largest over the width and the depth layers),
both models; below, D_max and peak pressure against the meshes. Prints the
path of the PNG it writes."""
import csv
import json
import math
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(directory):
    with open(os.path.join(directory, "compare_summary.json")) as f:
        # null (a single mesh: no error bar; a run without stresses) plots as nan
        s = {k: (math.nan if v is None else v) for k, v in json.load(f).items()}
    with open(os.path.join(directory, "reference_profile.csv")) as f:
        profile = list(csv.DictReader(f))
    with open(os.path.join(directory, "reference.csv")) as f:
        meshes = list(csv.DictReader(f))
    theta = [float(r["theta_deg"]) for r in profile]

    fig, axes = plt.subplots(2, 2, figsize=(14, 9))
    fig.suptitle(
        "D_max: co-simulation %.4g, full FE %.4g ± %.2g (%+.1f %%)    "
        "peak pressure: co-simulation %.1f MPa, full FE %.1f ± %.1f MPa (%+.1f %%)"
        % (s["cosim_risk_max"], s["full_fe_risk_max"], s["full_fe_risk_max_error_estimate"],
           100 * s["risk_max_relative_error"], s["cosim_peak_pressure_Pa"] / 1e6,
           s["full_fe_peak_pressure_Pa"] / 1e6, s["full_fe_peak_pressure_error_estimate_Pa"] / 1e6,
           100 * s["peak_pressure_relative_error"]),
        fontsize=11)

    ax = axes[0][0]
    ax.plot(theta, [float(r["cosim_pressure_Pa"]) / 1e6 for r in profile], label="co-simulation")
    ax.plot(theta, [float(r["full_fe_pressure_Pa"]) / 1e6 for r in profile], "--", label="full FE (finest mesh)")
    ax.set_xlabel("θ [deg]")
    ax.set_ylabel("pressure, largest across the width [MPa]")
    ax.set_title("interface pressure at the full FE's highest peak")
    ax.legend()

    ax = axes[0][1]
    ax.plot(theta, [float(r["cosim_risk_max"]) for r in profile], label="co-simulation")
    ax.plot(theta, [float(r["full_fe_risk_max"]) for r in profile], "--", label="full FE (finest mesh)")
    ax.set_xlabel("θ [deg]")
    ax.set_ylabel("D_max, largest over width and depth [-]")
    ax.set_title("Dang Van risk around the ring")
    ax.legend()

    dofs = [int(m["ring_dofs"]) + int(m["housing_dofs"]) for m in meshes]
    labels = [m["mesh"] for m in meshes]
    ax = axes[1][0]
    ax.plot(dofs, [float(m["risk_max"]) for m in meshes], "o-", label="full FE")
    ax.axhline(s["cosim_risk_max"], color="C1", label="co-simulation")
    for x, y, label in zip(dofs, [float(m["risk_max"]) for m in meshes], labels):
        ax.annotate(label, (x, y), fontsize=8)
    ax.set_xscale("log")
    ax.set_xlabel("full-FE DoFs (ring + housing)")
    ax.set_ylabel("D_max [-]")
    ax.set_title("D_max against the mesh")
    ax.legend()

    ax = axes[1][1]
    ax.plot(dofs, [float(m["peak_pressure_Pa"]) / 1e6 for m in meshes], "o-", label="full FE")
    ax.axhline(s["cosim_peak_pressure_Pa"] / 1e6, color="C1", label="co-simulation")
    ax.set_xscale("log")
    ax.set_xlabel("full-FE DoFs (ring + housing)")
    ax.set_ylabel("peak pressure [MPa]")
    ax.set_title("peak pressure against the mesh; time: co-simulation %.0f s, full FE %.0f s"
                 % (s["cosim_wall_time_s"], s["full_fe_wall_time_s"]))
    ax.legend()

    fig.tight_layout(rect=(0, 0, 1, 0.95))
    path = os.path.join(directory, "reference.png")
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main(sys.argv[1])

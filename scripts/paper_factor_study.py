#!/usr/bin/python3
"""What moves the bearing scene's D_max toward the paper's "< 0.0029".

    scripts/paper_factor_study.py [-o DIR] [--passes N] [--reuse]

Runs build/fretsim on configs/paper_dgbb_housing.prm once per assumption
(one change of the default each; N ball passes, 1 by default) and writes
DIR/factor_study.csv (D_max, where, peak pressure and ball load per row) and
DIR/factor_study.png (D_max per row on a log scale, the paper's bound and
the full FE's frictionless D_max beside them). DIR: results/paper_factor_study; --reuse takes a row's run already in DIR
(its summary.json) instead of running it again. Prints the table and the
paths it wrote.
"""
import argparse
import csv
import json
import os
import subprocess
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CONFIG = os.path.join(ROOT, "configs", "paper_dgbb_housing.prm")
HALF_SPACE = "Stresses/Ring stresses=half-space"
NO_R = "Interface/Ring residual flexibility=false"

# (name, what changes, --set values)
ROWS = [
    ("default", "the scene: full-FE ring stresses, steel housing", []),
    ("half_space", "half-space stresses (the paper's)", [HALF_SPACE]),
    ("aluminium", "aluminium housing (E 70 GPa)", ["Interface/Housing Young's modulus=70e9",
                                                   "Interface/Housing Poisson ratio=0.33"]),
    ("cast_iron", "cast-iron housing (E 110 GPa)", ["Interface/Housing Young's modulus=110e9",
                                                    "Interface/Housing Poisson ratio=0.26"]),
    ("soft_bristles", "bristles 100x softer (k_t 1e13 Pa/m)", ["Interface/Tangential stiffness=1e13"]),
    ("soft_layer", "layer 1e5x softer (k_n 1e13 Pa/m)", ["Interface/Normal stiffness=1e13"]),
    ("fit_10um", "radial interference 10 um", ["Interface/Radial interference=10e-6"]),
    ("load_half", "inner ring pushed 30 um (half)", ["Loading/Inner ring displacement y=30e-6"]),
    ("without_r", "ring basis without residual flexibility", [NO_R]),
    ("ncc20_without_r", "20 interface shapes, no residual flexibility",
     [NO_R, "Model/Characteristic constraint modes=20"]),
    ("ncc20_without_r_half_space", "20 shapes, no residual flexibility, half-space stresses",
     [NO_R, "Model/Characteristic constraint modes=20", HALF_SPACE]),
]
PAPER_BOUND = 0.0029
FULL_FE = (0.3073, 0.014)  # docs/fe_reference.md: frictionless, finest mesh, its error bar


def run(name, sets, directory, passes, reuse):
    out = os.path.join(directory, name)
    summary = os.path.join(out, "summary.json")
    if reuse and os.path.exists(summary):
        with open(summary) as f:
            return json.load(f)
    command = [os.path.join(ROOT, "build", "fretsim"), "run", CONFIG, "-o", out, "--force", "-q", "--no-plots",
               "--set", f"Loading/Ball pass periods={passes}"]
    for s in sets:
        command += ["--set", s]
    subprocess.run(command, check=True)
    with open(summary) as f:
        return json.load(f)


def main():
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("-o", default=os.path.join(ROOT, "results", "paper_factor_study"))
    parser.add_argument("--passes", type=float, default=1.0)
    parser.add_argument("--reuse", action="store_true")
    args = parser.parse_args()
    os.makedirs(args.o, exist_ok=True)
    table = []
    for name, label, sets in ROWS:
        s = run(name, sets, args.o, args.passes, args.reuse)
        table.append({"name": name, "assumption": label, "set": "; ".join(sets), "risk_max": s["risk_max"],
                      "risk_max_theta_deg": s["risk_max_theta_deg"], "risk_max_depth_m": s["risk_max_depth_m"],
                      "peak_pressure_Pa": s["peak_pressure_Pa"], "peak_ball_load_N": s["peak_ball_load_N"]})
        print(f"{name:28s} D_max {s['risk_max']:.4g}  peak {s['peak_pressure_Pa'] / 1e6:.1f} MPa", flush=True)
    csv_path = os.path.join(args.o, "factor_study.csv")
    with open(csv_path, "w", newline="") as f:
        writer = csv.DictWriter(f, fieldnames=list(table[0]))
        writer.writeheader()
        writer.writerows(table)

    fig, ax = plt.subplots(figsize=(9, 5.5))
    y = range(len(table))
    ax.barh(list(y), [r["risk_max"] for r in table], color=["C0" if HALF_SPACE not in r["set"] else "C1" for r in table])
    ax.set_yticks(list(y))
    ax.set_yticklabels([r["assumption"] for r in table], fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlim(1e-3, 1.0)
    ax.axvline(PAPER_BOUND, color="k", ls="--", label='paper: "< 0.0029"')
    ax.axvspan(FULL_FE[0] - FULL_FE[1], FULL_FE[0] + FULL_FE[1], color="C2", alpha=0.3,
               label="full FE of ring and housing (frictionless)")
    ax.set_xlabel("D_max")
    ax.set_title(f"6208 in its housing: D_max under each assumption, {args.passes:g} ball pass\n"
                 "blue: the ring's full-FE stresses, orange: half-space stresses", fontsize=9)
    ax.legend(fontsize=8, loc="lower right")
    fig.tight_layout()
    png_path = os.path.join(args.o, "factor_study.png")
    fig.savefig(png_path, dpi=120)
    print(csv_path)
    print(png_path)


if __name__ == "__main__":
    sys.exit(main())

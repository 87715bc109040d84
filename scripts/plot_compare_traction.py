#!/usr/bin/python3
"""Figure of `fretsim compare-traction`: the fretting loops of each traction
model and their maximum-risk maps side by side (the paper's Fig. 4 and 12).

    plot_compare_traction.py OUTPUT_DIR RUN_DIR...

Each RUN_DIR holds one model's results.h5 and summary.json. Writes
OUTPUT_DIR/compare_traction.png and prints its path.
"""
import json
import os
import sys

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402


def load(directory):
    with open(os.path.join(directory, "summary.json")) as handle:
        summary = json.load(handle)
    with h5py.File(os.path.join(directory, "results.h5"), "r") as f:
        run = {name: np.asarray(f["series/" + name][...]) for name in
               ("cycle", "displacement_x", "displacement_y", "tangential_force_x", "tangential_force_y",
                "normal_force", "tangential_force_mindlin_x")}
        run["x"], run["y"], run["z"] = (np.asarray(f["grid/" + k][...]) for k in ("x", "y", "z"))
        run["risk_max"] = np.asarray(f["fields/risk_max"][...])
    run["summary"] = summary
    return run


def main(output, directories):
    runs = [load(d) for d in directories]
    names = [r["summary"].get("traction_model", os.path.basename(d)) for r, d in zip(runs, directories)]
    fig, axes = plt.subplots(1, 1 + len(runs), figsize=(5.6 * (1 + len(runs)), 5.2), constrained_layout=True)
    ax = axes[0]
    colours = ["tab:blue", "tab:orange", "black"]
    a = runs[-1]["summary"]["contact_radius_m"]
    for run, name, colour in zip(runs, names, colours):
        last = run["cycle"] == run["cycle"].max()
        last[np.argmax(last) - 1] = True  # close the loop
        d = np.hypot(run["displacement_x"], run["displacement_y"]) * np.sign(run["displacement_x"] + run["displacement_y"])
        q = run["tangential_force_x"] + 0 * run["tangential_force_y"]
        ax.plot(d[last] / a, q[last] / run["normal_force"][last], color=colour, linewidth=2 if name == "exact" else 1.5,
                label=f"{name} ({run['summary']['wall_time_s']:.2g} s)")
    ref = runs[-1]
    last = ref["cycle"] == ref["cycle"].max()
    ax.plot(ref["displacement_x"][last] / a, ref["tangential_force_mindlin_x"][last] / ref["normal_force"][last],
            color="grey", linestyle="--", linewidth=1, label="Mindlin–Deresiewicz")
    ax.set_xlabel("sliding displacement δ/a [–]")
    ax.set_ylabel("tangential force Q/P [–]")
    ax.set_title("Fretting loop, last cycle (run time in brackets)")
    ax.grid(True, alpha=0.3)
    ax.legend(fontsize=8, loc="lower right")

    peak = max(float(np.nanmax(np.where(np.isfinite(r["risk_max"]), r["risk_max"], np.nan))) for r in runs)
    for ax, run, name in zip(axes[1:], runs, names):
        risk = np.where(np.isfinite(run["risk_max"]), run["risk_max"], np.nan)
        layer = int(np.unravel_index(np.nanargmax(risk), risk.shape)[0])
        j, i = np.unravel_index(np.nanargmax(risk[layer]), risk[layer].shape)
        mesh = ax.pcolormesh(run["x"] * 1e3, run["y"] * 1e3, risk[layer], cmap="inferno", vmin=0, vmax=peak,
                             shading="nearest")
        ax.plot([run["x"][i] * 1e3], [run["y"][j] * 1e3], "x", color="cyan", markersize=9, mew=2)
        ax.set_aspect("equal")
        ax.set_xlabel("x [mm]")
        ax.set_ylabel("y [mm]")
        ax.set_title(f"{name}: D_max = {np.nanmax(risk):.3f} at z = {run['z'][layer] * 1e6:.3g} µm")
        fig.colorbar(mesh, ax=ax, label="maximum Dang Van risk D_max [–]")
    fig.suptitle("Traction models compared: fretting loop and maximum risk (paper Fig. 4 and 12)")
    path = os.path.join(output, "compare_traction.png")
    fig.savefig(path, dpi=110)
    print(path)


if __name__ == "__main__":
    main(sys.argv[1], sys.argv[2:])

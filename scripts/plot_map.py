#!/usr/bin/python3
"""Figure of `fretsim map`: D over the map's first two axes as filled contours,
with the D = 1 boundary (solid), the partial/gross-slip boundary (dashed), the
first-yield line (dotted) and the bisected D = 1 points of --boundary
(markers); one axis: D along it with its error bar. The paper's Fig. 8 and
the classic fretting maps.

    plot_map.py OUTPUT_DIR

Reads OUTPUT_DIR/map.h5, writes OUTPUT_DIR/map.png and prints its path.
"""
import os
import sys

os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")
import h5py  # noqa: E402
import matplotlib  # noqa: E402

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

from fretsim_h5 import text_attribute  # noqa: E402

REGIME_CODE = {"stick": 0.0, "partial slip": 1.0, "gross slip": 2.0}


def parse_axis(text):
    path, rest = text.split("=", 1)
    parts = rest.split(":")
    return {"path": path, "count": int(parts[2]), "log": len(parts) > 3 and parts[3] == "log",
            "name": path.split("/")[-1]}


def load(directory):
    with h5py.File(os.path.join(directory, "map.h5"), "r") as f:
        axes = [parse_axis(line) for line in text_attribute(f.attrs["axes"]).splitlines() if line]
        points = f["points"]
        rows = min(len(points["index"]), len(points["status"]))
        data = {"index": np.asarray(points["index"][:rows]),
                "axis_values": np.asarray(points["axis_values"][:rows]).reshape(rows, len(axes))}
        for name in ("risk_max", "risk_max_converged", "risk_max_error_estimate", "yield_margin"):
            data[name] = np.asarray(points[name][:rows], dtype=float)
        data["status"] = [text_attribute(s) for s in points["status"][:rows]]
        data["regime"] = [text_attribute(s) for s in points["regime"][:rows]]
        boundary = None
        if "boundary" in f:
            g = f["boundary"]
            boundary = {"value": np.asarray(g["first_axis_value"][...]),
                        "others": np.asarray(g["other_axis_values"][...]) if "other_axis_values" in g else None}
    return axes, data, boundary


def grid_of(axes, data, values):
    """Values on the [n1, n0] grid of the first two axes (the first slice of a third)."""
    n0 = axes[0]["count"]
    n1 = axes[1]["count"] if len(axes) > 1 else 1
    out = np.full((n1, n0), np.nan)
    for k, index in enumerate(data["index"]):
        if index < n0 * n1 and data["status"][k] == "ok":
            out[index // n0, index % n0] = values[k]
    return out


def main(directory):
    axes, data, boundary = load(directory)
    converged = data["risk_max_converged"]
    risk = np.where(np.isfinite(converged), converged, data["risk_max"])
    label = "D_max converged" if np.isfinite(converged).any() else "D_max"
    fig, ax = plt.subplots(figsize=(7.5, 5.5))
    if len(axes) == 1:
        order = np.argsort(data["axis_values"][:, 0])
        x = data["axis_values"][order, 0]
        bar = data["risk_max_error_estimate"][order]
        ax.errorbar(x, risk[order], yerr=np.where(np.isfinite(bar), bar, 0.0), fmt="o-", capsize=3, label=label)
        ax.axhline(1.0, color="k", lw=1.5, label="D = 1")
        if boundary is not None and np.isfinite(boundary["value"]).any():
            for value in boundary["value"][np.isfinite(boundary["value"])]:
                ax.axvline(value, color="C3", ls="--", label="D = 1 by bisection")
        ax.set_xlabel(axes[0]["path"])
        ax.set_ylabel(label)
        if axes[0]["log"]:
            ax.set_xscale("log")
        ax.legend()
    else:
        x = np.sort(np.unique(data["axis_values"][:, 0]))
        y = np.sort(np.unique(data["axis_values"][:, 1]))
        n0, n1 = axes[0]["count"], axes[1]["count"]
        xs = np.full(n0, np.nan)
        ys = np.full(n1, np.nan)
        for k, index in enumerate(data["index"]):
            xs[index % n0] = data["axis_values"][k, 0]
            ys[(index // n0) % n1] = data["axis_values"][k, 1]
        if np.isnan(xs).any() or np.isnan(ys).any():
            xs, ys = x, y
        d = grid_of(axes, data, risk)
        finite = d[np.isfinite(d)]
        top = max(2.0, float(np.nanmax(finite))) if finite.size else 2.0
        levels = np.linspace(0.0, top, 21)
        filled = ax.contourf(xs, ys, np.ma.masked_invalid(d), levels=levels, cmap="RdYlGn_r", extend="max")
        fig.colorbar(filled, ax=ax, label=label)
        if finite.size and finite.min() < 1.0 < finite.max():
            ax.contour(xs, ys, np.ma.masked_invalid(d), levels=[1.0], colors="k", linewidths=2.0)
            ax.plot([], [], "k-", lw=2, label="D = 1 (grid)")
        regime = grid_of(axes, data, np.array([REGIME_CODE.get(r, np.nan) for r in data["regime"]]))
        if np.isfinite(regime).any() and np.nanmin(regime) < 1.5 < np.nanmax(regime):
            ax.contour(xs, ys, np.ma.masked_invalid(regime), levels=[1.5], colors="b", linestyles="--")
            ax.plot([], [], "b--", label="partial / gross slip")
        margin = grid_of(axes, data, data["yield_margin"])
        if np.isfinite(margin).any() and np.nanmin(margin) < 1.0 < np.nanmax(margin):
            ax.contour(xs, ys, np.ma.masked_invalid(margin), levels=[1.0], colors="m", linestyles=":",
                       linewidths=2.0)
            ax.plot([], [], "m:", lw=2, label="first yield (elastic limit)")
        if boundary is not None and boundary["others"] is not None:
            ok = np.isfinite(boundary["value"])
            if ok.any():
                ax.plot(boundary["value"][ok], boundary["others"][ok, 0], "kx", ms=7,
                        label="D = 1 by bisection")
        if axes[0]["log"]:
            ax.set_xscale("log")
        if axes[1]["log"]:
            ax.set_yscale("log")
        ax.set_xlabel(axes[0]["path"])
        ax.set_ylabel(axes[1]["path"])
        if ax.get_legend_handles_labels()[0]:
            ax.legend(loc="upper left", fontsize=8, framealpha=0.8)
        if len(axes) > 2:
            ax.set_title("(first value of " + axes[2]["path"] + ")", fontsize=9)
    done = sum(1 for s in data["status"] if s == "ok")
    total = int(np.prod([a["count"] for a in axes]))
    fig.suptitle("Fretting map: %d of %d points, unsafe where D > 1" % (done, total))
    fig.tight_layout()
    path = os.path.join(directory, "map.png")
    fig.savefig(path, dpi=130)
    print(path)


if __name__ == "__main__":
    main(sys.argv[1])

#!/usr/bin/python3
"""Figures of a bearing_housing run: python3 scripts/plot_bearing_housing.py RESULTS_DIR

Reads RESULTS_DIR/results.h5 of the `bearing_housing` scene (a 6208 deep groove
ball bearing whose flexible outer ring sits in a rigid housing; paper §5,
Fig. 14) and writes PNG figures into RESULTS_DIR. Prints the path of each PNG
written, one per line, and nothing else on stdout; notes and warnings go to
stderr. Only what the file holds is plotted, so a run that stopped early (few
snapshots, no /fields/risk_max) gives the figures or panels it can.

The interface grid is the outer ring's outer surface unrolled: /grid/x is the
arc length s = R θ (θ from +x towards +y, +y up, so θ = 90° is the top of the
bearing), /grid/y the axial position, /grid/z the depth of the risk layers.

  interface_maps.png     the paper's Fig. 14: effective friction τ/p, surface
                         Dang Van risk D(t), pressure and circumferential shear
                         as θ × axial maps at the snapshot of largest surface
                         risk in the last ball-pass period, balls marked
  risk_circumference.png risk against θ (maximum over axial cells and depth of
                         D_max and of D(t) at that snapshot), and pressure and
                         circumferential shear at mid-width against θ
  ball_loads.png         ball loads against time, and the pressure at the top
                         of the interface (θ ≈ 90°, mid-width) against time with
                         the instants a ball passes it and the kinematic ball
                         pass frequency

Needs Debian's python3-matplotlib and python3-h5py (run with /usr/bin/python3).
Exit status: 0 on success, 1 if the results file is missing or unreadable or a
figure failed.
"""

import math
import os
import sys

# A running simulation keeps results.h5 open for writing; reading it anyway
# (it is flushed after every step) needs HDF5's file locking off.
os.environ.setdefault("HDF5_USE_FILE_LOCKING", "FALSE")

try:
    import numpy as np
    import matplotlib

    matplotlib.use("Agg")
    import matplotlib.pyplot as plt
    from matplotlib.transforms import blended_transform_factory
    import h5py
    from fretsim_h5 import number_attribute, text_attribute
except ImportError as error:  # pragma: no cover - depends on the machine
    sys.stderr.write(
        f"plot_bearing_housing.py: {error}; needs python3-numpy, python3-matplotlib and "
        f"python3-h5py (Debian packages, for /usr/bin/python3)\n"
    )
    sys.exit(1)

SCRIPT = "plot_bearing_housing.py"


def note(text):
    """Notes and warnings go to stderr: stdout carries only the PNG paths."""
    sys.stderr.write(f"{SCRIPT}: {text}\n")


# ----------------------------------------------------------------- reading


def cell_edges(centres):
    """Cell edges from cell centres (uniform spacing assumed at the ends)."""
    centres = np.asarray(centres, dtype=float)
    if centres.size == 1:
        return np.array([centres[0] - 0.5, centres[0] + 0.5])
    middle = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate(([2 * centres[0] - middle[0]], middle, [2 * centres[-1] - middle[-1]]))


def format_number(value, digits=4):
    return f"{value:.{digits}g}"


class Run:
    """The grid, the usable snapshots and the chosen instant of results.h5."""

    def __init__(self, f, directory):
        self.f = f
        self.directory = directory
        x = np.asarray(f["grid/x"][...], dtype=float)
        self.y = np.asarray(f["grid/y"][...], dtype=float)
        self.z = np.asarray(f["grid/z"][...], dtype=float) if "grid/z" in f else None
        self.time = np.asarray(f["time"][...], dtype=float) if "time" in f else np.zeros(0)

        # Interface radius: the root attribute, else from the grid assuming the
        # x cells tile the whole circumference.
        self.radius = number_attribute(f.attrs, "interface_radius_m")
        if not self.radius or self.radius <= 0:
            spacing = float(np.median(np.diff(x))) if x.size > 1 else 0.0
            self.radius = x.size * spacing / (2 * math.pi) if spacing > 0 else None
            note("no interface_radius_m attribute; radius taken from the grid as a full circumference"
                 if self.radius else "no interface_radius_m attribute and no usable grid; θ cannot be drawn")
        if not self.radius:
            raise ValueError("interface radius unknown")

        # θ in degrees in 0..360; the columns are reordered so that θ increases
        # whatever angle the grid starts at.
        theta = np.degrees(x / self.radius) % 360.0
        self.order = np.argsort(theta, kind="stable")
        self.theta = theta[self.order]
        self.theta_edges = cell_edges(self.theta)
        self.y_mm = self.y * 1e3
        self.y_edges = cell_edges(self.y) * 1e3
        self.shape = (self.y.size, x.size)

        self.ball_pass_frequency = number_attribute(f.attrs, "ball_pass_frequency_hz")
        self.status = text_attribute(f.attrs["status"]) if "status" in f.attrs else ""

        # Fields are appended one snapshot at a time, so a run that stopped may
        # leave them one row apart: use the rows every stored field has.
        counts = [self.time.size]
        for name in ("pressure", "shear_x", "effective_friction", "risk", "ball_angle", "ball_load"):
            if self.has(name):
                counts.append(f["fields/" + name].shape[0])
        self.n = min(counts)

        # Mid-width: the axial cell nearest the middle of the width (with an
        # even count of cells it lies half a cell off the middle).
        middle = 0.5 * (self.y.min() + self.y.max())
        self.mid = int(np.argmin(np.abs(self.y - middle)))
        # Surface layer of the risk: the shallowest depth (z[0] may be 0).
        self.surface = int(np.argmin(self.z)) if self.z is not None and self.z.size else 0

        self.snapshot, self.how_chosen = self.choose_snapshot()

    def has(self, name):
        """/fields/<name> is present with the expected layout."""
        key = "fields/" + name
        if key not in self.f:
            return False
        shape = self.f[key].shape
        if name in ("pressure", "shear_x", "shear_y", "effective_friction"):
            return len(shape) == 3 and shape[1:] == self.shape
        if name == "risk":
            return (self.z is not None and len(shape) == 4 and shape[1] == self.z.size
                    and shape[2:] == self.shape)
        if name == "risk_max":
            return self.z is not None and shape == (self.z.size,) + self.shape
        if name in ("ball_angle", "ball_load"):
            return len(shape) == 2
        return True

    def field(self, name, row):
        """Snapshot `row` of a [nt, ny, nx] field with its columns in θ order."""
        return np.asarray(self.f["fields/" + name][row], dtype=float)[..., self.order]

    def ball_angles(self, row):
        """Angles of the balls at snapshot `row` in degrees 0..360, or None."""
        if not self.has("ball_angle"):
            return None
        return np.degrees(np.asarray(self.f["fields/ball_angle"][row], dtype=float)) % 360.0

    def choose_snapshot(self):
        """The snapshot of largest surface-layer risk in the last ball-pass
        period; the last snapshot when that cannot be told."""
        if self.n == 0:
            return None, ""
        last = self.n - 1
        if not self.has("risk"):
            return last, "last snapshot: no risk stored"
        first = 0
        if self.ball_pass_frequency and self.ball_pass_frequency > 0:
            period = 1.0 / self.ball_pass_frequency
            # a little slack so that a snapshot exactly one period back counts
            first = int(np.searchsorted(self.time[:self.n], self.time[last] - period * (1 + 1e-9)))
            window = "in the last ball-pass period"
        else:
            window = "of the run (no ball pass frequency stored)"
        first = min(first, last)
        layer = np.asarray(self.f["fields/risk"][first:self.n, self.surface], dtype=float)
        peaks = np.nanmax(np.where(np.isfinite(layer), layer, -np.inf).reshape(layer.shape[0], -1), axis=1)
        if not np.isfinite(peaks).any():
            return last, "last snapshot: risk not finite"
        return first + int(np.argmax(peaks)), f"largest surface risk {window}"

    def snapshot_count(self):
        return f"{self.n} snapshot" + ("" if self.n == 1 else "s")

    def time_text(self, row):
        return f"t = {format_number(self.time[row] * 1e3, 5)} ms"


# ----------------------------------------------------------------- helpers


def stress_scale(dataset):
    """Factor and label to show a stress dataset in MPa."""
    unit = text_attribute(dataset.attrs["unit"]) if "unit" in dataset.attrs else "Pa"
    return (1e-6, "MPa") if unit in ("Pa", "") else (1.0, unit)


def theta_axis(ax, label=True):
    """θ axis 0..360° with ticks every 45°."""
    ax.set_xlim(0.0, 360.0)
    ax.set_xticks(np.arange(0, 361, 45))
    if label:
        ax.set_xlabel("circumferential angle θ [°]  (90° = top)")


def mark_balls(ax, angles, y=1.0, marker="v", size=7):
    """Small triangles at the ball angles, just above the axes (y in axes units)."""
    if angles is None:
        return
    transform = blended_transform_factory(ax.transData, ax.transAxes)
    ax.plot(angles, np.full(angles.shape, y), linestyle="none", marker=marker, color="black",
            markersize=size, transform=transform, clip_on=False)


def ball_at_instants(run, angle_deg):
    """Times at which a ball passes the angle `angle_deg`, from /fields/ball_angle
    (linear between snapshots; the balls move less than a ball spacing per
    snapshot for this to be right)."""
    if not run.has("ball_angle") or run.n < 2:
        return np.zeros(0)
    angles = np.degrees(np.asarray(run.f["fields/ball_angle"][:run.n], dtype=float))
    t = run.time[:run.n]
    instants = []
    for k in range(angles.shape[1]):
        # angle of ball k relative to the cell, unwrapped, so that a pass is a
        # crossing of a multiple of 360° whatever the direction of rotation
        relative = np.unwrap(np.radians(angles[:, k] - angle_deg)) / (2 * math.pi)
        turns = np.floor(relative)
        for i in np.flatnonzero(turns[1:] != turns[:-1]):
            level = max(turns[i], turns[i + 1])
            fraction = (level - relative[i]) / (relative[i + 1] - relative[i])
            instants.append(t[i] + fraction * (t[i + 1] - t[i]))
    return np.sort(np.asarray(instants))


# ----------------------------------------------------------------- figures


def plot_interface_maps(run):
    """The paper's Fig. 14: four stacked unrolled maps at the chosen snapshot."""
    if run.snapshot is None:
        note("no interface_maps.png: no snapshots stored")
        return None
    f, row = run.f, run.snapshot
    pressure = run.field("pressure", row) if run.has("pressure") else None
    panels = []
    if run.has("effective_friction"):
        panels.append("friction")
    if run.has("risk"):
        panels.append("risk")
    if pressure is not None:
        panels.append("pressure")
    if run.has("shear_x"):
        panels.append("shear")
    if not panels:
        note("no interface_maps.png: no interface fields stored")
        return None

    fig, axes = plt.subplots(len(panels), 1, figsize=(13, 1.4 + 2.35 * len(panels)), sharex=True,
                             squeeze=False, constrained_layout=True)
    axes = axes[:, 0]
    edges = (run.theta_edges, run.y_edges)
    no_contact = pressure <= 0 if pressure is not None else None
    for index, (ax, panel) in enumerate(zip(axes, panels)):
        letter = "abcd"[index]
        if panel == "friction":
            values = np.ma.masked_invalid(run.field("effective_friction", row))
            if no_contact is not None:
                # τ/p is not defined without contact (stored as 0): grey there
                values = np.ma.masked_where(no_contact, values)
                ax.set_facecolor("0.82")
            top = float(values.max()) if values.count() and values.max() > 0 else 1.0
            mesh = ax.pcolormesh(*edges, values, cmap="Purples", vmin=0.0, vmax=top, shading="flat")
            fig.colorbar(mesh, ax=ax, label="τ/p [–]", pad=0.01)
            title = f"({letter}) effective friction |τ|/p, largest {format_number(top, 3)}"
            if no_contact is not None and no_contact.any():
                title += "   (grey: no contact)"
        elif panel == "risk":
            values = np.ma.masked_invalid(np.asarray(f["fields/risk"][row, run.surface], dtype=float)[..., run.order])
            top = float(values.max()) if values.count() and values.max() > 0 else 1.0
            mesh = ax.pcolormesh(*edges, values, cmap="Reds", vmin=0.0, vmax=top, shading="flat")
            fig.colorbar(mesh, ax=ax, label="D(t) [–]", pad=0.01)
            title = (f"({letter}) Dang Van risk D(t) at depth z = {run.z[run.surface] * 1e3:.3g} mm, "
                     f"largest {format_number(top, 3)}")
        elif panel == "pressure":
            scale, unit = stress_scale(f["fields/pressure"])
            values = pressure * scale
            top = float(np.nanmax(values)) if np.nanmax(values) > 0 else 1.0
            mesh = ax.pcolormesh(*edges, values, cmap="Blues", vmin=0.0, vmax=top, shading="flat")
            fig.colorbar(mesh, ax=ax, label=f"p [{unit}]", pad=0.01)
            title = f"({letter}) contact pressure p, largest {format_number(top, 4)} {unit}"
        else:
            scale, unit = stress_scale(f["fields/shear_x"])
            values = run.field("shear_x", row) * scale
            limit = float(np.nanmax(np.abs(values))) or 1.0
            mesh = ax.pcolormesh(*edges, values, cmap="RdBu_r", vmin=-limit, vmax=limit, shading="flat")
            fig.colorbar(mesh, ax=ax, label=f"τθ [{unit}]", pad=0.01)
            title = (f"({letter}) circumferential shear τθ on the outer ring "
                     f"(positive towards increasing θ), largest |τθ| {format_number(limit, 3)} {unit}")
        # room above the top map for the ball markers
        ax.set_title(title, loc="left", fontsize=10, pad=12 if index == 0 else 6)
        ax.set_ylabel("axial y [mm]")
        ax.set_ylim(run.y_edges[0], run.y_edges[-1])
    theta_axis(axes[-1])
    balls = run.ball_angles(row)
    mark_balls(axes[0], balls, y=1.0)

    heading = f"Outer ring–housing interface at {run.time_text(row)} ({run.how_chosen})"
    if balls is not None:
        heading += "\n▼: ball positions"
    if run.status and run.status != "complete":
        heading += f"   [run status: {run.status}, {run.snapshot_count()}]"
    fig.suptitle(heading)
    path = os.path.join(run.directory, "interface_maps.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_risk_circumference(run):
    """Risk and mid-width pressure against θ."""
    if run.snapshot is None:
        note("no risk_circumference.png: no snapshots stored")
        return None
    f, row = run.f, run.snapshot
    curves = []  # (values against θ, label, style)
    if run.has("risk_max"):
        risk_max = np.asarray(f["fields/risk_max"][...], dtype=float)[..., run.order]
        curves.append((np.nanmax(risk_max.reshape(-1, run.theta.size), axis=0),
                       "D_max over the run", dict(color="tab:red", linewidth=2.0)))
    else:
        note("risk_circumference.png: /fields/risk_max missing (run stopped early?); D_max not drawn")
    if run.has("risk"):
        now = np.asarray(f["fields/risk"][row], dtype=float)[..., run.order]
        curves.append((np.nanmax(now.reshape(-1, run.theta.size), axis=0),
                       f"D(t) at {run.time_text(row)}", dict(color="tab:orange", linewidth=1.3)))
    has_pressure, has_shear = run.has("pressure"), run.has("shear_x")
    if not curves and not has_pressure:
        note("no risk_circumference.png: neither risk nor pressure stored")
        return None

    count = (1 if curves else 0) + (1 if has_pressure or has_shear else 0)
    fig, axes = plt.subplots(count, 1, figsize=(12, 2.0 + 3.2 * count), sharex=True, squeeze=False,
                             constrained_layout=True)
    axes = list(axes[:, 0])
    balls = run.ball_angles(row)

    if curves:
        ax = axes.pop(0)
        for values, label, style in curves:
            ax.plot(run.theta, values, label=label, **style)
        ax.set_ylabel("Dang Van risk [–]\n(max over axial cells and depth)")
        ax.set_ylim(bottom=0.0)
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=9)
        peak = max(float(np.nanmax(values)) for values, _, _ in curves)
        ax.set_title(f"Dang Van risk along the circumference (largest {format_number(peak, 3)})",
                     loc="left", fontsize=10, pad=10)
        mark_balls(ax, balls)

    if has_pressure or has_shear:
        ax = axes.pop(0)
        unit = "MPa"
        if has_pressure:
            scale, unit = stress_scale(f["fields/pressure"])
            ax.plot(run.theta, run.field("pressure", row)[run.mid] * scale, color="tab:blue",
                    linewidth=1.8, label="pressure p")
        if has_shear:
            scale, unit = stress_scale(f["fields/shear_x"])
            ax.plot(run.theta, run.field("shear_x", row)[run.mid] * scale, color="tab:green",
                    linewidth=1.2, linestyle="--", label="circumferential shear τθ")
        ax.axhline(0.0, color="0.5", linewidth=0.6)
        ax.set_ylabel(f"traction [{unit}]")
        ax.grid(True, alpha=0.3)
        ax.legend(loc="upper right", fontsize=9)
        ax.set_title(f"pressure and shear at mid-width (axial cell y = {run.y_mm[run.mid]:.3g} mm) "
                     f"at {run.time_text(row)}", loc="left", fontsize=10, pad=10)
        mark_balls(ax, balls)
    theta_axis(ax)

    heading = f"Fretting risk along the outer ring circumference; D(t) and tractions at {run.time_text(row)}"
    if balls is not None:
        heading += "   (▼: balls)"
    fig.suptitle(heading)
    path = os.path.join(run.directory, "risk_circumference.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


def plot_ball_loads(run):
    """Ball loads and the pressure at the top cell against time."""
    f = run.f
    has_loads = run.has("ball_load") and run.n > 0
    has_pressure = run.has("pressure") and run.n > 0
    if not has_loads and not has_pressure:
        note("no ball_loads.png: no ball loads or pressure snapshots stored")
        return None
    t_ms = run.time[:run.n] * 1e3
    top = int(np.argmin(np.abs(run.theta - 90.0)))   # column in θ order
    passes = ball_at_instants(run, run.theta[top]) * 1e3

    count = int(has_loads) + int(has_pressure)
    fig, axes = plt.subplots(count, 1, figsize=(12, 1.8 + 3.3 * count), sharex=True, squeeze=False,
                             constrained_layout=True)
    axes = list(axes[:, 0])

    if has_loads:
        ax = axes.pop(0)
        loads = np.asarray(f["fields/ball_load"][:run.n], dtype=float)
        for k in range(loads.shape[1]):
            ax.plot(t_ms, loads[:, k], linewidth=1.2, label=f"ball {k + 1}",
                    marker="o" if run.n < 20 else None, markersize=3)
        ax.set_ylabel("ball load [N]")
        ax.grid(True, alpha=0.3)
        ax.set_title("ball–outer ring contact loads", loc="left", fontsize=10)

    if has_pressure:
        ax = axes.pop(0)
        scale, unit = stress_scale(f["fields/pressure"])
        # the top cell in the stored column order
        column = int(run.order[top])
        values = np.asarray(f["fields/pressure"][:run.n, run.mid, column], dtype=float) * scale
        ax.plot(t_ms, values, color="tab:blue", linewidth=1.5, marker="o" if run.n < 20 else None,
                markersize=3, label="pressure p")
        for i, instant in enumerate(passes):
            ax.axvline(instant, color="0.4", linewidth=0.7, linestyle=":",
                       label="a ball at this θ (from the ball angles)" if i == 0 else None)
        ax.set_ylabel(f"pressure [{unit}]")
        ax.grid(True, alpha=0.3)
        ax.set_title(f"pressure at the top of the interface: θ = {run.theta[top]:.4g}°, "
                     f"y = {run.y_mm[run.mid]:.3g} mm", loc="left", fontsize=10)
        if run.ball_pass_frequency and run.ball_pass_frequency > 0:
            text = (f"kinematic ball pass frequency (outer ring)\n"
                    f"f_BP = {format_number(run.ball_pass_frequency, 4)} Hz, "
                    f"period {format_number(1e3 / run.ball_pass_frequency, 4)} ms")
            ax.text(1.01, 0.0, text, transform=ax.transAxes, fontsize=8, va="bottom", ha="left",
                    bbox=dict(boxstyle="round", facecolor="white", alpha=0.85, edgecolor="0.7"))
    # the instant shown in interface_maps.png and risk_circumference.png
    for ax in fig.axes:
        ax.axvline(run.time[run.snapshot] * 1e3, color="tab:red", linewidth=1.0, alpha=0.6,
                   label="instant of the interface maps")
        ax.legend(loc="upper left", bbox_to_anchor=(1.0, 1.0), fontsize=8)
    ax.set_xlabel("time t [ms]")
    if run.n == 1:
        ax.set_xlim(t_ms[0] - 0.5, t_ms[0] + 0.5)

    heading = "Ball pass: ball loads and the pressure under the top of the outer ring"
    if run.status and run.status != "complete":
        heading += f"   [run status: {run.status}, {run.snapshot_count()}]"
    fig.suptitle(heading)
    path = os.path.join(run.directory, "ball_loads.png")
    fig.savefig(path, dpi=120)
    plt.close(fig)
    return path


# -------------------------------------------------------------------- main


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        sys.stderr.write(f"usage: python3 scripts/{SCRIPT} RESULTS_DIR\n")
        return 1 if len(argv) != 2 else 0
    directory = argv[1]
    path = os.path.join(directory, "results.h5")
    if not os.path.isfile(path):
        note(f"no results file {path}")
        return 1
    try:
        f = h5py.File(path, "r")
    except (OSError, ValueError) as error:
        note(f"cannot read {path}: {error}")
        return 1

    status = 0
    with f:
        if "scene" in f.attrs and text_attribute(f.attrs["scene"]) != "bearing_housing":
            note(f"{path} is from scene '{text_attribute(f.attrs['scene'])}', not bearing_housing; trying anyway")
        try:
            run = Run(f, directory)
        except (KeyError, ValueError) as error:
            note(f"cannot plot {path}: {type(error).__name__}: {error}")
            return 1
        for make in (plot_interface_maps, plot_risk_circumference, plot_ball_loads):
            try:
                written = make(run)
            except Exception as error:  # one broken figure must not stop the others
                plt.close("all")
                note(f"{make.__name__} failed for {path}: {type(error).__name__}: {error}")
                status = 1
                continue
            if written:
                print(written, flush=True)
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))

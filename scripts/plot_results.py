#!/usr/bin/python3
"""Figures of a FretSim run: python3 scripts/plot_results.py RESULTS_DIR

Reads RESULTS_DIR/results.h5 (and RESULTS_DIR/summary.json when present) and
writes PNG figures into RESULTS_DIR, printing each figure's path on a line of
its own followed by a one-line description. Only what the file holds is
plotted; a figure whose data is missing is skipped.

  loop.png            tangential force loop Q/P against delta/a over the last
                      cycle, with the Mindlin-Deresiewicz loop when stored
  surface_fields.png  pressure, shear, effective friction and stick/slip maps
                      at the last field snapshot
  risk.png            the paper's Fig. 10-12 view at the instant of largest
                      sliding displacement in the last cycle: effective
                      friction, shear in the sliding direction, instantaneous
                      Dang Van risk D(t) and maximum risk D_max on the layer
                      where D_max is largest, and D_max against depth

Needs Debian's python3-matplotlib and python3-h5py (run with /usr/bin/python3).
Exit status: 0 on success, 1 if the results file is missing or unreadable or a
figure failed.
"""

import json
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
    from matplotlib.colors import ListedColormap, BoundaryNorm
    import h5py
    from fretsim_h5 import number_attribute, text_attribute
except ImportError as error:  # pragma: no cover - depends on the machine
    sys.stderr.write(
        f"plot_results.py: {error}; needs python3-numpy, python3-matplotlib and "
        f"python3-h5py (Debian packages, for /usr/bin/python3)\n"
    )
    sys.exit(1)


# ----------------------------------------------------------------- reading


def parse_prm(text):
    """'Section/Sub/Key' -> value from deal.II parameter-file text."""
    values, sections = {}, []
    for raw in text.splitlines():
        line = raw.split("#", 1)[0].strip()
        if not line:
            continue
        words = line.split(None, 1)
        if words[0] == "subsection" and len(words) > 1:
            sections.append(words[1].strip())
        elif words[0] == "end":
            if sections:
                sections.pop()
        elif words[0] == "set" and len(words) > 1 and "=" in words[1]:
            key, value = words[1].split("=", 1)
            values["/".join(sections + [key.strip()])] = value.strip()
    return values


def parameter(parameters, key):
    try:
        return float(parameters[key])
    except (KeyError, ValueError):
        return None


def series(f, name):
    key = "series/" + name
    return np.asarray(f[key][...], dtype=float) if key in f else None


def unit_of(dataset):
    return text_attribute(dataset.attrs["unit"]) if "unit" in dataset.attrs else ""


class Run:
    """What the figures need from results.h5 and summary.json."""

    def __init__(self, directory):
        self.directory = directory
        self.path = os.path.join(directory, "results.h5")
        self.summary = {}
        summary_path = os.path.join(directory, "summary.json")
        if os.path.isfile(summary_path):
            try:
                with open(summary_path, encoding="utf-8") as handle:
                    self.summary = json.load(handle)
            except (OSError, ValueError) as error:
                print(f"note: ignoring {summary_path}: {error}")

    def summary_number(self, key):
        value = self.summary.get(key)
        return float(value) if isinstance(value, (int, float)) and not isinstance(value, bool) else None

    def contact_radius(self, f):
        """Root attribute contact_radius_m, or summary.json's, in m.

        A number attribute is taken as it is. The attribute written as text
        may carry few digits, so summary.json's value (full precision) is
        preferred when the two agree to 1 %, i.e. come from the same run."""
        attribute = f.attrs.get("contact_radius_m")
        from_file = number_attribute(f.attrs, "contact_radius_m")
        from_summary = self.summary_number("contact_radius_m")
        if from_file is not None and not isinstance(attribute, (bytes, str)):
            return from_file
        if from_summary and from_summary > 0:
            if from_file is None or abs(from_file - from_summary) <= 0.01 * from_summary:
                return from_summary
        return from_file if from_file and from_file > 0 else None


# ----------------------------------------------------------------- figures


def format_number(value, digits=4):
    return f"{value:.{digits}g}"


def last_cycle_rows(cycle):
    """Row indices of the last cycle (the one before it if the last is cut
    short), including the row before it so that the loop closes."""
    finite = np.isfinite(cycle)
    if not finite.any():
        return None, None, None
    cycles = np.unique(cycle[finite])
    last = cycles.max()
    rows = np.flatnonzero(cycle == last)
    if len(cycles) >= 2:
        previous = cycles[-2]
        previous_rows = np.flatnonzero(cycle == previous)
        if previous > 0 and len(rows) < len(previous_rows):
            last, rows = previous, previous_rows  # interrupted run: last complete cycle
    if rows.size and rows[0] > 0:
        rows = np.concatenate(([rows[0] - 1], rows))
    return int(last), rows, int(cycles.max())


def plot_loop(f, run, parameters):
    needed = ["displacement_x", "tangential_force_x", "normal_force", "cycle"]
    missing = [name for name in needed if "series/" + name not in f]
    if missing:
        print(f"note: no loop.png: /series/{', /series/'.join(missing)} missing")
        return None
    cycle = series(f, "cycle")
    number, rows, last_started = last_cycle_rows(cycle)
    if rows is None or rows.size < 3:
        print("note: no loop.png: fewer than 3 rows in the last cycle")
        return None

    # Forces and displacements along the sliding direction (the x components
    # when it is 0): from the parameters, else from the largest displacement.
    dx, qx = series(f, "displacement_x")[rows], series(f, "tangential_force_x")[rows]
    dy, qy = series(f, "displacement_y"), series(f, "tangential_force_y")
    dy = dy[rows] if dy is not None else np.zeros_like(dx)
    qy = qy[rows] if qy is not None else np.zeros_like(qx)
    direction = parameter(parameters, "Loading/Sliding direction")
    if direction is None:
        peak = int(np.nanargmax(np.hypot(dx, dy)))
        direction = math.atan2(dy[peak], dx[peak])
        if math.cos(direction) < -1e-12 or (abs(math.cos(direction)) <= 1e-12 and math.sin(direction) < 0):
            direction += math.pi
    c, s = math.cos(direction), math.sin(direction)
    displacement = dx * c + dy * s
    force = qx * c + qy * s
    normal = series(f, "normal_force")[rows]
    if not np.all(np.abs(normal) > 0):
        print("note: no loop.png: /series/normal_force is zero")
        return None

    mindlin = None
    mx, my = series(f, "tangential_force_mindlin_x"), series(f, "tangential_force_mindlin_y")
    if mx is not None and my is not None:
        mindlin = mx[rows] * c + my[rows] * s
    elif mx is not None and abs(c) > 1e-6:
        mindlin = mx[rows] / c  # stored as the x component of the force along the sliding direction

    a = run.contact_radius(f)
    mu = parameter(parameters, "Friction/Friction coefficient")
    if mu is None:
        mu = run.summary_number("friction_coefficient")
    load = float(np.nanmedian(np.abs(normal)))
    amplitude = parameter(parameters, "Loading/Sliding amplitude")
    if amplitude is None:
        amplitude = run.summary_number("sliding_amplitude_m")
    if amplitude is None:
        amplitude = float(np.nanmax(np.abs(displacement)))

    fig, ax = plt.subplots(figsize=(7.5, 6.0), constrained_layout=True)
    if a:
        x = displacement / a
        ax.set_xlabel("tangential displacement δ/a [–]")
    else:
        x = displacement * 1e6
        ax.set_xlabel("tangential displacement δ [µm]  (contact radius a not stored)")
    ratio = force / normal
    ax.plot(x, ratio, color="tab:blue", linewidth=2.2, label="bristle model (FretSim)")
    if mindlin is not None and np.isfinite(mindlin).any():
        ax.plot(x, mindlin / normal, color="black", linewidth=1.4, linestyle="--",
                label="Mindlin–Deresiewicz (analytic)")
    if mu and np.nanmax(np.abs(ratio)) > 0.6 * mu:  # otherwise the lines would squash a thin loop
        for sign in (1, -1):
            ax.axhline(sign * mu, color="tab:red", linewidth=0.9, linestyle=":")
        ax.text(0.99, mu, "  Q/P = μ: full sliding", color="tab:red", ha="right", va="bottom",
                transform=ax.get_yaxis_transform(), fontsize=9)
    ax.axhline(0, color="0.6", linewidth=0.6)
    ax.axvline(0, color="0.6", linewidth=0.6)
    ax.grid(True, alpha=0.3)
    ax.set_ylabel("tangential force Q/P [–]")
    parts = []
    if mu is not None:
        parts.append(f"μ = {format_number(mu, 3)}")
    parts.append(f"P = {format_number(load, 4)} N")
    parts.append(f"amplitude = {format_number(amplitude * 1e6, 4)} µm")
    if a:
        parts.append(f"a = {format_number(a * 1e6, 4)} µm")
    cycle_text = f"cycle {number}" + (f" (the run stopped in cycle {last_started})" if last_started != number else "")
    ax.set_title(f"Fretting loop, {cycle_text}\n" + ", ".join(parts))
    ax.legend(loc="lower right")

    notes = []
    q_amp, q_ref = run.summary_number("tangential_force_amplitude_N"), run.summary_number(
        "mindlin_tangential_force_amplitude_N")
    if q_amp is not None:
        notes.append(f"Q* = {format_number(q_amp, 4)} N" +
                     (f" (Mindlin {format_number(q_ref, 4)} N)" if q_ref is not None else ""))
    w, w_ref = run.summary_number("dissipated_energy_per_cycle_J"), run.summary_number(
        "mindlin_dissipated_energy_per_cycle_J")
    if w is not None:
        notes.append(f"energy dissipated = {format_number(w, 3)} J/cycle" +
                     (f" (Mindlin {format_number(w_ref, 3)})" if w_ref is not None else ""))
    if isinstance(run.summary.get("regime"), str):
        notes.append("regime: " + run.summary["regime"])
    if notes:
        ax.text(0.02, 0.98, "\n".join(notes), transform=ax.transAxes, va="top", ha="left", fontsize=9,
                bbox=dict(boxstyle="round", facecolor="white", alpha=0.85, edgecolor="0.7"))

    path = os.path.join(run.directory, "loop.png")
    fig.savefig(path, dpi=150)
    plt.close(fig)
    what = "δ/a" if a else "δ"
    return path, f"tangential force loop Q/P against {what}, {cycle_text}" + (
        ", with the Mindlin–Deresiewicz loop" if mindlin is not None else "")


def decorate_map(ax, title, xc, yc, contact):
    """Title, axes in mm, equal aspect, and the contact edge dashed."""
    ax.set_title(title)
    ax.set_xlabel("x [mm]")
    ax.set_ylabel("y [mm]")
    ax.set_aspect("equal")
    if contact is not None and contact.any() and not contact.all():
        ax.contour(xc, yc, contact.astype(float), levels=[0.5], colors="black", linewidths=0.8, linestyles="--")


def cell_edges(centres):
    """Cell edges from cell centres (uniform spacing assumed at the ends)."""
    centres = np.asarray(centres, dtype=float)
    if centres.size == 1:
        return np.array([centres[0] - 0.5, centres[0] + 0.5])
    middle = 0.5 * (centres[1:] + centres[:-1])
    return np.concatenate(([2 * centres[0] - middle[0]], middle, [2 * centres[-1] - middle[-1]]))


def last_snapshot(f, name):
    """The last snapshot of /fields/<name> as [ny, nx] with its unit, or None."""
    key = "fields/" + name
    if key not in f:
        return None
    dataset = f[key]
    if dataset.ndim != 3 or dataset.shape[0] == 0:
        return None
    return np.asarray(dataset[dataset.shape[0] - 1], dtype=float), unit_of(dataset)


def stress_scale(unit):
    """Factor and label to show a stress in MPa."""
    return (1e-6, "MPa") if unit in ("Pa", "") else (1.0, unit)


def plot_surface_fields(f, run, parameters):
    if "grid/x" not in f or "grid/y" not in f:
        print("note: no surface_fields.png: /grid/x or /grid/y missing")
        return None
    x = np.asarray(f["grid/x"][...], dtype=float)
    y = np.asarray(f["grid/y"][...], dtype=float)
    fields = {name: last_snapshot(f, name) for name in ("pressure", "shear_x", "effective_friction", "slip")}
    fields = {name: value for name, value in fields.items()
              if value is not None and value[0].shape == (y.size, x.size)}
    if not fields:
        print("note: no surface_fields.png: no [time, ny, nx] surface fields stored")
        return None
    times = np.asarray(f["time"][...], dtype=float) if "time" in f else None

    x_edges, y_edges = cell_edges(x) * 1e3, cell_edges(y) * 1e3
    xc, yc = x * 1e3, y * 1e3
    contact = fields["pressure"][0] > 0 if "pressure" in fields else None

    count = len(fields)
    columns = 2 if count > 1 else 1
    rows = (count + 1) // 2
    fig, axes = plt.subplots(rows, columns, figsize=(6.2 * columns, 5.2 * rows), squeeze=False,
                             constrained_layout=True)
    panels = iter(axes.ravel())

    def decorate(ax, title):
        decorate_map(ax, title, xc, yc, contact)

    if "pressure" in fields:
        ax = next(panels)
        values, unit = fields["pressure"]
        scale, label = stress_scale(unit)
        mesh = ax.pcolormesh(x_edges, y_edges, values * scale, cmap="viridis", shading="flat")
        fig.colorbar(mesh, ax=ax, label=f"contact pressure p [{label}]")
        decorate(ax, f"contact pressure (peak {format_number(np.nanmax(values) * scale, 4)} {label})")

    if "shear_x" in fields:
        ax = next(panels)
        values, unit = fields["shear_x"]
        scale, label = stress_scale(unit)
        limit = float(np.nanmax(np.abs(values))) * scale or 1.0
        mesh = ax.pcolormesh(x_edges, y_edges, values * scale, cmap="RdBu_r", vmin=-limit, vmax=limit,
                             shading="flat")
        fig.colorbar(mesh, ax=ax, label=f"shear traction τx [{label}]")
        decorate(ax, "shear traction τx (on the lower body)")

    if "effective_friction" in fields:
        ax = next(panels)
        values = fields["effective_friction"][0]
        if contact is not None:
            values = np.ma.masked_where(~contact, values)
        values = np.ma.masked_invalid(values)
        mesh = ax.pcolormesh(x_edges, y_edges, values, cmap="magma", vmin=0.0, vmax=1.0, shading="flat")
        fig.colorbar(mesh, ax=ax, label="τ/(μp) [–]")
        ax.set_facecolor("0.92")
        decorate(ax, "effective friction τ/(μp): 1 = slip")

    if "slip" in fields:
        ax = next(panels)
        slip = fields["slip"][0] >= 0.5
        if contact is not None:
            category = np.where(~contact, 0, np.where(slip, 2, 1))
            colours, names = ["0.88", "tab:blue", "tab:red"], ["no contact", "stick", "slip"]
        else:
            category = np.where(slip, 1, 0)
            colours, names = ["tab:blue", "tab:red"], ["stick", "slip"]
        cmap = ListedColormap(colours)
        norm = BoundaryNorm(np.arange(len(colours) + 1) - 0.5, len(colours))
        mesh = ax.pcolormesh(x_edges, y_edges, category, cmap=cmap, norm=norm, shading="flat")
        bar = fig.colorbar(mesh, ax=ax, ticks=range(len(colours)))
        bar.ax.set_yticklabels(names)
        title = "stick/slip map"
        if contact is not None and contact.any():
            title += f" (slip on {100.0 * slip[contact].mean():.0f} % of the contact)"
        decorate(ax, title)

    for ax in panels:
        ax.set_visible(False)

    heading = "Surface fields at the last snapshot"
    if times is not None and times.size:
        heading += f", t = {format_number(times[-1], 4)} s"
    mu = parameter(parameters, "Friction/Friction coefficient")
    if mu is not None:
        heading += f", μ = {format_number(mu, 3)}"
    if contact is not None and contact.any() and not contact.all():
        heading += "   (dashed: contact edge)"
    fig.suptitle(heading)
    path = os.path.join(run.directory, "surface_fields.png")
    fig.savefig(path, dpi=150)
    plt.close(fig)
    return path, "maps of " + ", ".join(name.replace("_", " ") for name in fields) + " at the last snapshot"


def plot_risk(f, run, parameters):
    needed = ["grid/x", "grid/y", "grid/z", "time", "fields/risk", "fields/risk_max"]
    missing = [name for name in needed if name not in f]
    if missing:
        print(f"note: no risk.png: /{', /'.join(missing)} missing")
        return None
    x = np.asarray(f["grid/x"][...], dtype=float)
    y = np.asarray(f["grid/y"][...], dtype=float)
    z = np.asarray(f["grid/z"][...], dtype=float)
    times = np.asarray(f["time"][...], dtype=float)
    risk = f["fields/risk"]
    risk_max = np.asarray(f["fields/risk_max"][...], dtype=float)
    if risk.ndim != 4 or risk.shape[0] == 0 or risk_max.shape != (z.size, y.size, x.size):
        print("note: no risk.png: risk fields have an unexpected shape")
        return None

    # The instant: the snapshot of largest sliding displacement (the paper's
    # "maximum displacement" pictures), found from the time series.
    snapshot = risk.shape[0] - 1
    series_time, dx, dy = series(f, "time"), series(f, "displacement_x"), series(f, "displacement_y")
    displacement_at = None
    if series_time is not None and dx is not None:
        dy = dy if dy is not None else np.zeros_like(dx)
        magnitude = np.hypot(dx, dy)
        at_snapshots = np.interp(times[:risk.shape[0]], series_time, magnitude)
        snapshot = int(np.argmax(at_snapshots))
        displacement_at = at_snapshots[snapshot]
    finite_max = np.where(np.isfinite(risk_max), risk_max, -np.inf)
    layer, j_max, i_max = np.unravel_index(int(np.argmax(finite_max)), finite_max.shape)
    now = np.asarray(risk[snapshot, layer], dtype=float)

    x_edges, y_edges = cell_edges(x) * 1e3, cell_edges(y) * 1e3
    xc, yc = x * 1e3, y * 1e3
    pressure = f["fields/pressure"][snapshot] if "fields/pressure" in f else None
    contact = np.asarray(pressure) > 0 if pressure is not None else None

    fig, axes = plt.subplots(2, 3, figsize=(18, 10.5), constrained_layout=True)

    def decorate(ax, title):
        decorate_map(ax, title, xc, yc, contact)

    ax = axes[0, 0]
    if "fields/effective_friction" in f:
        values = np.ma.masked_invalid(np.asarray(f["fields/effective_friction"][snapshot], dtype=float))
        if contact is not None:
            values = np.ma.masked_where(~contact, values)
        mesh = ax.pcolormesh(x_edges, y_edges, values, cmap="magma", vmin=0, vmax=1, shading="flat")
        fig.colorbar(mesh, ax=ax, label="τ/(μp) [–]")
        ax.set_facecolor("0.92")
    decorate(ax, "effective friction τ/(μp) (1 = slip)")

    ax = axes[0, 1]
    direction = parameter(parameters, "Loading/Sliding direction") or 0.0
    if "fields/shear_x" in f and "fields/shear_y" in f:
        shear = (np.asarray(f["fields/shear_x"][snapshot]) * math.cos(direction) +
                 np.asarray(f["fields/shear_y"][snapshot]) * math.sin(direction)) * 1e-6
        limit = float(np.nanmax(np.abs(shear))) or 1.0
        mesh = ax.pcolormesh(x_edges, y_edges, shear, cmap="RdBu_r", vmin=-limit, vmax=limit, shading="flat")
        fig.colorbar(mesh, ax=ax, label="shear traction along the sliding [MPa]")
    decorate(ax, "shear traction in the sliding direction (on the lower body)")

    peak = float(np.nanmax(finite_max))
    scale = max(peak, 1e-12)
    ax = axes[0, 2]
    mesh = ax.pcolormesh(x_edges, y_edges, np.ma.masked_invalid(now), cmap="inferno", vmin=0, vmax=scale,
                         shading="flat")
    fig.colorbar(mesh, ax=ax, label="Dang Van risk D(t) [–]")
    decorate(ax, f"instantaneous risk D(t) at z = {z[layer] * 1e6:.4g} µm")

    ax = axes[1, 0]
    mesh = ax.pcolormesh(x_edges, y_edges, np.ma.masked_invalid(risk_max[layer]), cmap="inferno", vmin=0,
                         vmax=scale, shading="flat")
    fig.colorbar(mesh, ax=ax, label="maximum risk D_max [–]")
    ax.plot([xc[i_max]], [yc[j_max]], marker="x", color="cyan", markersize=10, mew=2)
    decorate(ax, f"maximum risk D_max at z = {z[layer] * 1e6:.4g} µm (x: D_max = {peak:.3f})")

    ax = axes[1, 1]
    # D_max on the plane y = y(max) against x and depth: one row per layer.
    section = np.ma.masked_invalid(risk_max[:, j_max, :])
    if z.size > 1:
        mesh = ax.pcolormesh(x_edges, cell_edges(z) * 1e6 if np.all(np.diff(z) > 0) else np.arange(z.size + 1),
                             section, cmap="inferno", vmin=0, vmax=scale, shading="flat")
        ax.invert_yaxis()
        fig.colorbar(mesh, ax=ax, label="maximum risk D_max [–]")
        ax.set_ylabel("depth z [µm]" if np.all(np.diff(z) > 0) else "depth layer")
    else:
        ax.plot(xc, section[0], color="tab:red")
        ax.set_ylabel("D_max [–]")
    ax.set_xlabel("x [mm]")
    ax.set_title(f"D_max below the surface, section y = {yc[j_max]:.3g} mm (depth layers as cells)")

    ax = axes[1, 2]
    ax.plot(np.nanmax(np.where(np.isfinite(risk_max), risk_max, np.nan).reshape(z.size, -1), axis=1), z * 1e6,
            marker="o", color="tab:red")
    ax.invert_yaxis()
    ax.set_xlabel("largest D_max on the layer [–]")
    ax.set_ylabel("depth z [µm]")
    ax.grid(True, alpha=0.3)
    ax.set_title("maximum risk against depth")

    heading = f"Dang Van fretting risk at t = {format_number(times[snapshot], 4)} s"
    if displacement_at is not None:
        heading += f" (sliding displacement {displacement_at * 1e6:.3g} µm)"
    heading += f";  D_max = {peak:.3f} at x = {xc[i_max]:.3f} mm, y = {yc[j_max]:.3f} mm, z = {z[layer] * 1e6:.3g} µm"
    heading += "   (D ≥ 1: crack initiation predicted; dashed: contact edge)"
    fig.suptitle(heading)
    path = os.path.join(run.directory, "risk.png")
    fig.savefig(path, dpi=110)
    plt.close(fig)
    return path, "effective friction, shear, instantaneous and maximum Dang Van risk (paper Fig. 10-12)"


# -------------------------------------------------------------------- main


def main(argv):
    if len(argv) != 2 or argv[1] in ("-h", "--help"):
        sys.stderr.write("usage: python3 scripts/plot_results.py RESULTS_DIR\n")
        return 1 if len(argv) != 2 else 0
    run = Run(argv[1])
    if not os.path.isfile(run.path):
        sys.stderr.write(f"plot_results.py: no results file {run.path}\n")
        return 1
    try:
        f = h5py.File(run.path, "r")
    except (OSError, ValueError) as error:
        sys.stderr.write(f"plot_results.py: cannot read {run.path}: {error}\n")
        return 1

    status = 0
    with f:
        parameters = parse_prm(text_attribute(f.attrs["parameters"])) if "parameters" in f.attrs else {}
        for make in (plot_loop, plot_surface_fields, plot_risk):
            try:
                result = make(f, run, parameters)
            except Exception as error:  # one broken figure must not stop the others
                plt.close("all")
                sys.stderr.write(f"plot_results.py: {make.__name__} failed for {run.path}: "
                                 f"{type(error).__name__}: {error}\n")
                status = 1
                continue
            if result:
                path, description = result
                print(path)
                print(f"  {description}")
    return status


if __name__ == "__main__":
    sys.exit(main(sys.argv))

#!/usr/bin/env python3
"""How much of a body's local compliance its FE residual flexibility holds, per wavelength.

Reads the residual flexibility R that `fretsim reduce` stores in a model file
(/residual_flexibility/pressure: the u_r of every interface-grid cell per N on
each cell of the first column) and prints, for circumferential harmonics k of a
pressure uniform across the grid's width, the mean displacement over the width
per unit pressure amplitude, next to that of an elastic half-space of the
body's material on the same grid (Love's uniform rectangles, periodic around
the circumference, as coupling::LocalCompliance builds it). Where the ratio is
near 1 the FE model holds the body's local compliance; where it falls towards 0
the FE mesh is too coarse for that wavelength.

    scripts/residual_spectrum.py results/ring_6208_reduce-model.h5 [more model files]
Needs python3-h5py (and numpy, which it brings).
"""
import argparse
import math

import h5py
import numpy as np


def love_displacement(x, y, half_x, half_y, plane_modulus):
    """Surface normal displacement at (x, y) per unit pressure on the
    rectangle |x| < half_x, |y| < half_y of a half-space (Johnson, Contact
    Mechanics, eq. 3.25)."""

    def corner(u, v):
        r = np.sqrt(u * u + v * v)
        return u * np.log(v + r) + v * np.log(u + r)

    s = (corner(x + half_x, y + half_y) - corner(x + half_x, y - half_y) - corner(x - half_x, y + half_y) +
         corner(x - half_x, y - half_y))
    return s / (math.pi * plane_modulus)


def read_model(path):
    with h5py.File(path, "r") as f:
        grid = dict(f["operators/interface_grid"].attrs)
        table = f["residual_flexibility/pressure"][...]
    nx, ny = int(grid["nx"]), int(grid["ny"])
    return nx, ny, float(grid["hx_m"]), float(grid["hy_m"]), float(grid["radius_m"]), table


def circumferential_harmonics(response):
    """Real parts of the circumferential harmonics of a response [nx]."""
    return np.fft.rfft(response).real


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("model_files", nargs="+")
    parser.add_argument("--youngs-modulus", type=float, default=2.08e11, help="E of the half-space [Pa]")
    parser.add_argument("--poisson-ratio", type=float, default=0.3, help="nu of the half-space [-]")
    parser.add_argument("--harmonics", default="0,5,10,15,20,30,40,50,60,70,80,90,100,120,140,160,180")
    args = parser.parse_args()

    models = [read_model(path) for path in args.model_files]
    nx, ny, hx, hy, radius, _ = models[0]
    for other in models[1:]:
        if other[:5] != models[0][:5]:
            raise SystemExit("the model files' interface grids differ")
    plane_modulus = args.youngs_modulus / (1.0 - args.poisson_ratio ** 2)

    # The half-space under a pressure uniform over the whole grid width,
    # mean displacement over the width, periodic images around the ring.
    i = np.arange(nx)
    x = np.where(i > nx // 2, i - nx, i) * hx
    y = (np.arange(ny) - (ny - 1) / 2.0) * hy
    halfspace = np.zeros(nx)
    for source in range(ny):
        for target in range(ny):
            for image in range(-3, 4):
                halfspace += love_displacement(x + image * nx * hx, y[target] - y[source], hx / 2, hy / 2,
                                               plane_modulus) / ny
    halfspace_k = circumferential_harmonics(halfspace)

    residual_k = []
    for _, _, _, _, _, table in models:
        rows = table.reshape(ny, ny, nx)  # [loaded row][row][column]: cell index = row * nx + column
        sign = math.copysign(1.0, rows[0, 0, 0])  # into the body: a ring's u_r is inward, a housing's outward
        response = sign * rows.sum(axis=0).mean(axis=0) * hx * hy  # per unit pressure
        residual_k.append(circumferential_harmonics(response))

    print("E = %.3g Pa, nu = %.2f; grid %d x %d cells of %.3f x %.3f mm on radius %.1f mm" %
          (args.youngs_modulus, args.poisson_ratio, nx, ny, hx * 1e3, hy * 1e3, radius * 1e3))
    header = "  k  wavelength [mm]  half-space [m/Pa]" + "".join("  R/half-space (%d)" % (n + 1)
                                                               for n in range(len(models)))
    print(header)
    for k in (int(v) for v in args.harmonics.split(",")):
        if k > nx // 2:
            continue
        wavelength = 2.0 * math.pi * radius / k * 1e3 if k > 0 else float("inf")
        ratios = "".join("  %17.3f" % (r[k] / halfspace_k[k]) for r in residual_k)
        print("%3d  %15.2f  %17.3e%s" % (k, wavelength, halfspace_k[k], ratios))
    for n, path in enumerate(args.model_files):
        print("(%d) %s" % (n + 1, path))


if __name__ == "__main__":
    main()

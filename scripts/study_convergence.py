#!/usr/bin/python3
"""Convergence of a scene's key results with its numerical parameters.

    scripts/study_convergence.py CONFIG "Section/Name=v1,v2,..." [...] [--set Section/Name=v] [-o DIR] [--keys k1,k2]

Runs build/fretsim once per value of each parameter (the others at the
config's values, or at those --set gives every run), and prints a table of the chosen summary.json keys and the
run time; writes DIR/convergence.csv. Example, the grid and the time step of
the paper scene:

    scripts/study_convergence.py configs/paper_concentrated.prm \\
        "Grid/Cells x,Grid/Cells y=64,128,256" "Loading/Steps per cycle=40,100,200"
"""
import argparse
import csv
import json
import os
import re
import subprocess
import sys
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))


def edit(text, path, value):
    """Sets `set NAME = value` inside the right subsection (adds it if absent)."""
    *sections, name = path.split("/")
    lines, stack, done = text.splitlines(), [], False
    out = []
    for line in lines:
        words = line.split("#", 1)[0].split()
        if words[:1] == ["subsection"]:
            stack.append(" ".join(words[1:]))
        elif words[:1] == ["end"]:
            if stack == sections and not done:
                out.append(f"  set {name} = {value}")
                done = True
            stack.pop()
        elif stack == sections and re.match(rf"\s*set\s+{re.escape(name)}\s*=", line):
            line, done = f"  set {name} = {value}", True
        out.append(line)
    if not done:
        out += [f"subsection {s}" for s in sections] + [f"  set {name} = {value}"] + ["end"] * len(sections)
    return "\n".join(out) + "\n"


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("config")
    parser.add_argument("sweeps", nargs="+", help='"Path[,Path2]=v1,v2,..."')
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "fretsim"))
    parser.add_argument("--set", action="append", default=[], help='"Path=value" for every run')
    parser.add_argument("-o", "--output", default=os.path.join(ROOT, "results", "convergence"))
    parser.add_argument("--keys", default="risk_max,risk_max_location_m,risk_max_depth_m,tangential_force_amplitude_N,"
                        "loop_error_vs_mindlin")
    args = parser.parse_args()
    base = open(args.config).read()
    for fixed in args.set:
        path, value = fixed.split("=", 1)
        base = edit(base, path.strip(), value.strip())
    keys = args.keys.split(",")
    os.makedirs(args.output, exist_ok=True)
    rows = []
    for sweep in args.sweeps:
        paths, values = sweep.split("=", 1)
        for value in values.split(","):
            text = base
            for path in paths.split(","):
                text = edit(text, path.strip(), value.strip())
            tag = re.sub(r"[^A-Za-z0-9]+", "_", f"{paths.split(',')[0]}_{value}")
            scene = os.path.join(args.output, tag + ".prm")
            with open(scene, "w") as handle:
                handle.write(text)
            start = time.time()
            result = subprocess.run([args.program, "run", scene, "-o",
                                     os.path.join(args.output, tag), "--no-plots", "-q", "--force"],
                                    capture_output=True, text=True)
            seconds = time.time() - start
            if result.returncode != 0:
                sys.exit(f"{scene}: fretsim exited with {result.returncode}:\n{result.stderr}")
            summary = json.load(open(os.path.join(args.output, tag, "summary.json")))
            row = {"parameter": paths, "value": value, "wall_time_s": round(seconds, 2)}
            row.update({k: summary.get(k) for k in keys})
            rows.append(row)
            print("  ".join(f"{k}={v}" for k, v in row.items()), flush=True)
    with open(os.path.join(args.output, "convergence.csv"), "w", newline="") as handle:
        writer = csv.DictWriter(handle, fieldnames=list(rows[0].keys()))
        writer.writeheader()
        writer.writerows(rows)
    print(os.path.join(args.output, "convergence.csv"))


if __name__ == "__main__":
    main()

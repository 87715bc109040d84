#!/usr/bin/env python3
"""Config fuzzer: mutations of every shipped configuration through the checks.

    scripts/fuzz_configs.py [--count 10000] [--seed 1] [--program build/fretsim]
                            [--driver build/tests/test_app_unit_config_fuzzer]

Each input is a shipped file of configs/ with mutations: lines deleted,
duplicated or swapped, a parameter's value replaced by a random one, random
bytes written in, a misspelt name; some are written as JSON. Each goes
through `fretsim run --dry-run FILE -o DIR` and every so often `fretsim params
NAME` with a mangled scene name. The contract: exit code 0 or 2, never a
signal; a refusal (2) is one line on standard error; a dry run creates no
output folder. Anything else is printed and makes the exit code 1.

The program starts in about half a second (its libraries), so by default
the inputs run in batches inside the driver (the unit test
test_app_unit_config_fuzzer, which calls the same command-line entry point
per input); a batch that crashes is re-run input by input with the program
to name the culprit. --program alone runs every input as its own process.
"""
import argparse
import json
import os
import random
import re
import shutil
import subprocess
import sys
import tempfile
import time

ROOT = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))

RANDOM_VALUES = ["0", "-1", "1e308", "-1e308", "nan", "inf", "", "abc", "1,2,3", "3, 1, 2", "0, 0",
                 "4096", "100000000", "1e-300", "true", "false", "=", "#", "\\", "x" * 300,
                 "0x10", "1e", "--", "subsection", "end", "é", "\t"]


def random_value(rng):
    choice = rng.random()
    if choice < 0.4:
        return rng.choice(RANDOM_VALUES)
    if choice < 0.7:
        return str(rng.randint(-10, 10 ** rng.randint(1, 9)))
    return "%g" % (rng.uniform(-1, 1) * 10 ** rng.randint(-12, 12))


def mutate(text, rng):
    """A few random edits of a configuration's text (bytes in, bytes out)."""
    lines = text.split(b"\n")
    for _ in range(rng.randint(1, 4)):
        kind = rng.randrange(7)
        k = rng.randrange(len(lines))
        if kind == 0 and len(lines) > 1:
            del lines[k]
        elif kind == 1:
            lines.insert(k, lines[k])
        elif kind == 2:
            j = rng.randrange(len(lines))
            lines[k], lines[j] = lines[j], lines[k]
        elif kind == 3 or kind == 4:
            sets = [i for i, line in enumerate(lines) if b"=" in line and line.strip().startswith(b"set")]
            if sets:
                i = rng.choice(sets)
                name = lines[i].split(b"=", 1)[0]
                lines[i] = name + b"= " + random_value(rng).encode("utf-8")
        elif kind == 5:
            position = rng.randrange(len(lines[k]) + 1)
            noise = bytes(rng.randrange(256) for _ in range(rng.randint(1, 8)))
            lines[k] = lines[k][:position] + noise + lines[k][position:]
        else:
            line = lines[k]
            if len(line) > 4:
                position = rng.randrange(len(line))
                lines[k] = line[:position] + line[position + 1:]
    result = b"\n".join(lines)
    if rng.random() < 0.05:
        result = b"\xef\xbb\xbf" + result
    return result


def prm_to_json(text):
    """The .prm text as deal.II's JSON (sections as objects); None if not parseable."""
    root, stack = {}, []
    try:
        for raw in text.decode("utf-8").split("\n"):
            line = raw.split("#", 1)[0].strip()
            node = stack[-1] if stack else root
            if line.startswith("subsection "):
                child = node.setdefault(line[len("subsection "):].strip(), {})
                if not isinstance(child, dict):
                    return None
                stack.append(child)
            elif line == "end":
                stack.pop()
            elif line.startswith("set ") and "=" in line:
                name, value = line[4:].split("=", 1)
                node[name.strip()] = value.strip()
    except (UnicodeDecodeError, IndexError):
        return None
    return json.dumps(root, indent=1).encode("utf-8")


def make_inputs(directory, count, seed):
    """Writes `count` mutated files into `directory`; returns their paths."""
    rng = random.Random(seed)
    configs = sorted(os.path.join(ROOT, "configs", name) for name in os.listdir(os.path.join(ROOT, "configs"))
                     if name.endswith(".prm"))
    sources = {path: open(path, "rb").read() for path in configs}
    paths = []
    for n in range(count):
        config = configs[n % len(configs)]
        text = sources[config]
        extension = ".prm"
        if rng.random() < 0.2:
            as_json = prm_to_json(text)
            if as_json is not None:
                text, extension = as_json, ".json"
        # Files next to the shipped ones would find their reduction configurations
        # (relative paths); the copies name them through a symbolic link farm.
        path = os.path.join(directory, "%05d-%s%s" % (n, os.path.basename(config)[:-4], extension))
        with open(path, "wb") as handle:
            handle.write(mutate(text, rng))
        paths.append(path)
    for config in configs:  # relative references between the shipped files
        link = os.path.join(directory, os.path.basename(config))
        if not os.path.exists(link):
            os.symlink(config, link)
    return paths


def check_one(program, path, scratch):
    """Runs one input through the program; returns a problem or None."""
    output = os.path.join(scratch, "out-" + os.path.basename(path))
    result = subprocess.run([program, "run", "--dry-run", path, "-o", output], capture_output=True)
    return judge(result.returncode, result.stderr.decode("utf-8", "replace"), output, path)


def judge(code, errors, output, path):
    if code not in (0, 2):
        return "%s: exit code %d: %s" % (path, code, errors.strip()[:500])
    if code == 2 and errors.strip().count("\n") > 0:
        return "%s: refusal of more than one line: %s" % (path, errors.strip()[:500])
    if os.path.exists(output):
        return "%s: a dry run created its output folder" % path
    return None


def run_driver(driver, paths, scratch):
    """Runs a batch inside the driver; returns (problems, crashed)."""
    listing = os.path.join(scratch, "batch.txt")
    report = os.path.join(scratch, "report.txt")
    with open(listing, "w") as handle:
        handle.write("\n".join(paths) + "\n")
    if os.path.exists(report):
        os.remove(report)
    environment = dict(os.environ, FRETSIM_FUZZ_LIST=listing, FRETSIM_FUZZ_REPORT=report,
                       FRETSIM_FUZZ_OUTPUT=scratch)
    result = subprocess.run([driver, "--gtest_filter=ConfigFuzzer.*"], capture_output=True, env=environment)
    if result.returncode < 0 or result.returncode >= 128 or not os.path.exists(report):
        return [], True
    problems = []
    for line in open(report, encoding="utf-8", errors="replace"):
        code, lines, path = line.rstrip("\n").split("\t", 2)
        errors = "x\n" * int(lines)
        problem = judge(int(code), errors if int(lines) > 1 else "x", os.path.join(scratch, "out-" + os.path.basename(path)), path)
        if problem:
            problems.append(problem)
    return problems, False


def check_params(program, rng, count):
    problems = []
    for _ in range(count):
        name = rng.choice(["concentrated", "bearing_housing", "ring_housing", "", "x", "concentrate", "é", "-q"])
        result = subprocess.run([program, "params"] + ([name] if name else []), capture_output=True)
        if result.returncode not in (0, 2):
            problems.append("params %r: exit code %d" % (name, result.returncode))
    return problems


def main():
    parser = argparse.ArgumentParser(description=__doc__, formatter_class=argparse.RawDescriptionHelpFormatter)
    parser.add_argument("--count", type=int, default=10000)
    parser.add_argument("--seed", type=int, default=1)
    parser.add_argument("--program", default=os.path.join(ROOT, "build", "fretsim"))
    default_driver = os.path.join(ROOT, "build", "tests", "test_app_unit_config_fuzzer")
    parser.add_argument("--driver", default=default_driver if os.path.exists(default_driver) else None,
                        help="the test_app_unit_config_fuzzer executable (default: the build's, if built)")
    parser.add_argument("--batch", type=int, default=500)
    parser.add_argument("--keep", action="store_true", help="keep the inputs (printed)")
    args = parser.parse_args()

    start = time.time()
    scratch = tempfile.mkdtemp(prefix="fretsim-fuzz-")
    paths = make_inputs(scratch, args.count, args.seed)
    problems = []
    if args.driver:
        for first in range(0, len(paths), args.batch):
            batch = paths[first:first + args.batch]
            found, crashed = run_driver(args.driver, batch, scratch)
            problems += found
            if crashed:  # name the input that crashed it
                problems += [p for p in (check_one(args.program, path, scratch) for path in batch) if p]
    else:
        problems += [p for p in (check_one(args.program, path, scratch) for path in paths) if p]
    problems += check_params(args.program, random.Random(args.seed), max(5, args.count // 500))

    for problem in problems:
        print(problem)
    print("fuzz_configs: %d inputs, %d problems, %.1f s" % (args.count, len(problems), time.time() - start))
    if args.keep:
        print(scratch)
    else:
        shutil.rmtree(scratch, ignore_errors=True)
    return 1 if problems else 0


if __name__ == "__main__":
    sys.exit(main())

#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The default choices of `graphslam optimize` against every fixed choice, on held-out graphs.

usage: bench/heldout.py [--graphslam BIN] [--work DIR] [--repeats R] [--quick]
                        [--g2o-simulator2d PATH] [--g2o-simulator3d PATH] [--out FILE]

Generates a set of graphs none of the defaults was tuned on (seeds from 9001, never used by
the tests or the other benchmarks): `graphslam simulate` Manhattan worlds of several sizes,
with and without landmarks, at half and twice the simulator's noise, and 3D sphere and grid
pose graphs at two sizes and noise levels; with --g2o-simulator2d/3d (binaries built
elsewhere; nothing here builds one) g2o's simulators' graphs join the set.

Each graph is optimised with the defaults and with every fixed choice the defaults choose
among: the linear solver and ordering (--solver), the algorithm (--algorithm gn, lm,
dogleg), the default algorithm's first step (--first-step gn) and the initial guess
(--init none). The time compared is the tool's own (initialisation + optimisation, reading
and writing left out: they do not depend on the choice), the median of --repeats runs, the
variants of one graph alternating. A variant counts for "best" only when its final chi2 is
within 1e-6 (relative) of the lowest any variant reached; the default's row says when it
ended above that. Prints a markdown table (and writes it to --out when given).
"""
import argparse
import os
import re
import statistics
import subprocess
import sys
import tempfile

REPO = os.path.dirname(os.path.dirname(os.path.abspath(__file__)))
CHI2_SLACK = 1e-6
VARIANTS = [
    ("default", []),
    ("block-llt", ["--solver", "block-llt"]),
    ("eigen-ldlt", ["--solver", "eigen-ldlt"]),
    ("cholmod", ["--solver", "cholmod"]),
    ("cholmod:metis", ["--solver", "cholmod:metis"]),
    ("block-llt:metis", ["--solver", "block-llt:metis"]),
    ("gn", ["--algorithm", "gn"]),
    ("lm", ["--algorithm", "lm"]),
    ("dogleg", ["--algorithm", "dogleg"]),
    ("first-step gn", ["--first-step", "gn"]),
    ("init none", ["--init", "none"]),
]


def run(cmd):
    proc = subprocess.run(cmd, capture_output=True, text=True)
    return proc.returncode, proc.stdout + proc.stderr


def held_out_set(tool, work, quick, sim2d, sim3d):
    """(name, path) of every generated graph."""
    graphs = []
    sizes2d = [1000, 4000] if quick else [1000, 4000, 15000]
    seed = 9001
    for poses in sizes2d:
        for landmarks in (0, poses // 4):
            for noise in (0.5, 2.0):
                name = f"2d-{poses}p-{landmarks}l-n{noise:g}"
                graphs.append((name, ["--poses", str(poses), "--landmarks", str(landmarks),
                                      "--noise-scale", str(noise), "--seed", str(seed)]))
                seed += 1
    for shape in ("sphere", "grid"):
        for poses in ([500, 2000] if quick else [1000, 4000]):
            for noise in (1.0, 2.0):
                name = f"3d-{shape}-{poses}p-n{noise:g}"
                graphs.append((name, ["--3d", shape, "--poses", str(poses),
                                      "--noise-scale", str(noise), "--seed", str(seed)]))
                seed += 1
    out = []
    for name, args in graphs:
        path = os.path.join(work, name + ".g2o")
        rc, text = run([tool, "simulate", "-o", path] + args)
        if rc != 0:
            raise RuntimeError(f"simulate {name}: {text}")
        out.append((name, path))
    for sim, name, args in ((sim2d, "g2o-sim2d", ["-hasOdom", "-hasPoseSensor",
                                                   "-hasPointSensor", "-nlandmarks", "2000",
                                                   "-simSteps", "3000", "-worldSize", "60"]),
                            (sim3d, "g2o-sim3d", ["-hasOdom", "-hasPoseSensor",
                                                   "-nlandmarks", "0", "-simSteps", "2000"])):
        if sim:
            path = os.path.join(work, name + ".g2o")
            rc, text = run([sim] + args + [path])
            if rc != 0 or not os.path.exists(path):
                raise RuntimeError(f"{sim}: {text}")
            out.append((name, path))
    return out


def optimize(tool, path, args):
    """(seconds, final chi2) of one run, or None when the variant fails on the graph."""
    rc, text = run([tool, "optimize", path, "-q"] + args)
    if rc != 0:
        return None
    chi2 = re.search(r"chi2:\s+\S+ -> (\S+)", text)
    opt = re.search(r"time:\s+(\S+) s", text)
    init = re.search(r"initialisation: .* in (\S+) s", text)
    if not chi2 or not opt:
        raise RuntimeError(f"no summary from optimize {path} {args}:\n{text}")
    return float(opt.group(1)) + (float(init.group(1)) if init else 0.0), float(chi2.group(1))


def measure(tool, path, repeats):
    """variant -> (median seconds, final chi2) or None."""
    times = {name: [] for name, _ in VARIANTS}
    chi2 = {}
    for _ in range(repeats):
        for name, args in VARIANTS:
            r = optimize(tool, path, args)
            if r is None:
                times[name] = None
                continue
            if times[name] is not None:
                times[name].append(r[0])
                chi2[name] = r[1]
    return {n: (statistics.median(t), chi2[n]) if t else None for n, t in times.items()}


def table(rows):
    lines = ["| graph | default s | default chi2 | best fixed choice | best s | ratio | note |",
             "|---|---|---|---|---|---|---|"]
    for name, res in rows:
        ok = {n: r for n, r in res.items() if r is not None}
        lowest = min(r[1] for r in ok.values())
        reach = {n: r for n, r in ok.items() if r[1] <= lowest * (1 + CHI2_SLACK) + 1e-9}
        best = min((n for n in reach if n != "default"), key=lambda n: reach[n][0], default=None)
        d = res["default"]
        note = "" if "default" in reach else f"default above the lowest chi2 {lowest:.6g}"
        if best is None:
            lines.append(f"| {name} | {d[0]:.4f} | {d[1]:.6g} | - | - | - | {note} |")
            continue
        b = reach[best]
        lines.append(f"| {name} | {d[0]:.4f} | {d[1]:.6g} | {best} | {b[0]:.4f} | "
                     f"{d[0] / b[0]:.2f} | {note} |")
    return "\n".join(lines)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--graphslam", default=os.path.join(REPO, "build", "apps", "graphslam"))
    ap.add_argument("--work", default=None, help="keep the generated graphs here")
    ap.add_argument("--repeats", type=int, default=3)
    ap.add_argument("--quick", action="store_true", help="the smaller sizes only")
    ap.add_argument("--g2o-simulator2d", default=None)
    ap.add_argument("--g2o-simulator3d", default=None)
    ap.add_argument("--out", default=None)
    args = ap.parse_args()
    with tempfile.TemporaryDirectory() as tmp:
        work = args.work or tmp
        os.makedirs(work, exist_ok=True)
        rows = []
        for name, path in held_out_set(args.graphslam, work, args.quick, args.g2o_simulator2d,
                                       args.g2o_simulator3d):
            res = measure(args.graphslam, path, args.repeats)
            rows.append((name, res))
            print(f"{name}: " + ", ".join(f"{n} {r[0]:.4f}" for n, r in res.items() if r),
                  file=sys.stderr, flush=True)
    text = table(rows)
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text + "\n")


if __name__ == "__main__":
    main()

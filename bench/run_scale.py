#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""Scale benchmark: synthetic Manhattan-world pose graphs of growing size, solved to
convergence by `graphslam optimize` with its defaults; time and memory against N.

For every N: `graphslam simulate --poses N --seed S` writes the graph (odometry initial
guess) and its ground truth; `graphslam optimize` (global initialisation, default solver
"auto") solves it, as one process whose wall time and peak RSS are measured (os.wait4);
`graphslam eval ape` scores the result against the truth. The table replaces the section
between the markers <!-- scale --> and <!-- /scale --> of --doc (docs/BENCHMARKS.md),
which run_benchmarks.py keeps when it rewrites the file.

Threads: --threads sets graphslam's --threads and OMP_NUM_THREADS / OPENBLAS_NUM_THREADS
(CHOLMOD's supernodal factorisation runs in BLAS).
usage: run_scale.py [--build DIR] [--sizes 10000,100000,1000000] [--threads 2] [--doc FILE]
"""
import argparse
import datetime
import os
import re
import sys
import tempfile

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
from run_benchmarks import REPO, machine_notes, run  # noqa: E402

MARK_BEGIN, MARK_END = "<!-- scale -->", "<!-- /scale -->"


def grab(pattern, text, cast=float, default=None):
    m = re.search(pattern, text, re.M)
    return cast(m.group(1)) if m else default


def solve_one(tool, limit_bin, limit_max, simplicial_max, n, seed, threads, env, work):
    graph, truth, out = (os.path.join(work, f"{k}{n}.g2o") for k in ("m", "gt", "o"))
    code, _, err, _, _ = run([tool, "simulate", "-o", graph, "--truth", truth, "--poses", str(n),
                              "--seed", str(seed)], env)
    if code:
        raise RuntimeError(f"simulate {n}: {err}")
    stats = os.path.join(work, f"stats{n}.csv")
    code, text, err, wall, rss = run([tool, "optimize", graph, "-q", "--threads", str(threads),
                                      "-o", out, "--stats", stats], env)
    row = {"n": n, "exit": code, "wall": wall, "rss": rss, "error": err.strip()[-300:]}
    row["edges"] = grab(r"^graph: \d+ vertices, (\d+) edges", text, int)
    row["init"] = grab(r"^initialisation: .* in ([0-9.e+-]+) s", text)
    row["status"] = grab(r"^status:\s+(.*)$", text, str, "?")
    row["solver"] = grab(r"^algorithm:.*linear solver (.*)$", text, str, "?")
    row["unknowns"] = grab(r"^problem:.* (\d+) unknowns", text, int)
    row["nnz_l"] = grab(r"^problem:.*nnz\(L\) (\d+)", text, int)
    row["iterations"] = grab(r"^iterations:\s+(\d+)", text, int)
    row["chi2_0"] = grab(r"^chi2:\s+(\S+) ->", text)
    row["chi2"] = grab(r"^chi2:\s+\S+ -> (\S+)", text)
    m = re.search(r"^time:\s+(\S+) s \(linearize (\S+), build (\S+), factorize (\S+), solve (\S+)\)",
                  text, re.M)
    if m:
        row.update(zip(["opt", "lin", "build", "fact", "solve"], map(float, m.groups())))
    if code == 0:
        _, ape, _, _, _ = run([tool, "eval", "ape", truth, out], env)
        row["ape"] = grab(r"^\s+rmse\s+(\S+)", ape)
        # Per iteration (without the one-off set-up: structure, ordering, analysis).
        with open(stats) as f:
            header = f.readline().strip().split(",")
            its = [dict(zip(header, line.strip().split(","))) for line in f if line.strip()]
        # Per iteration (every step, chord steps too) and per factorisation (chord steps,
        # conjugate gradients on the previous factorisation, add their work but are not
        # counted: the stricter figure).
        row["factorisations"] = sum(int(r["factorizations"]) for r in its)
        per = max(row["factorisations"], 1)
        work = sum(float(r[k]) for r in its for k in (
            "time_linearize", "time_build", "time_factorize", "time_solve"))
        row["per_iteration"] = work / max(len(its), 1)
        row["per_fact"] = work / per
        row["fact_per_iter"] = sum(float(r["time_factorize"]) for r in its) / per
        if n <= limit_max and os.access(limit_bin, os.X_OK):
            kinds = "supernodal,simplicial" if n <= simplicial_max else "supernodal"
            lcode, lout, lerr, _, _ = run([limit_bin, graph, "--solvers", "auto",
                                           "--repeats", "3", "--kinds", kinds], env)
            if lcode == 0:
                row["limit"] = grab(r"^limit .*factorize_s=(\S+)", lout)
            else:
                row["limit_error"] = lerr.strip()[-200:]
    for path in (graph, truth, out, stats):
        if os.path.exists(path):
            os.remove(path)
    return row


def fmt(x, spec=".3g"):
    return "" if x is None else format(x, spec)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("--build", default=os.path.join(REPO, "build"))
    ap.add_argument("--sizes", default="10000,100000,1000000")
    ap.add_argument("--seed", type=int, default=42)
    ap.add_argument("--threads", type=int, default=2)
    ap.add_argument("--doc", default=os.path.join(REPO, "docs", "BENCHMARKS.md"))
    ap.add_argument("--limit-max", type=int, default=1000000,
                    help="run graphslam_factor_limit (the bare CHOLMOD factorisation) up to "
                         "this many poses")
    ap.add_argument("--simplicial-max", type=int, default=100000,
                    help="time CHOLMOD's simplicial factorisation for the limit up to this many "
                         "poses (above, supernodal only: simplicial takes minutes there and "
                         "is several times slower)")
    args = ap.parse_args()
    tool = os.path.join(args.build, "apps", "graphslam")
    limit_bin = os.path.join(args.build, "bench", "graphslam_factor_limit")
    env = dict(os.environ, OMP_NUM_THREADS=str(args.threads),
               OPENBLAS_NUM_THREADS=str(args.threads))
    rows = []
    with tempfile.TemporaryDirectory() as work:
        for n in (int(s) for s in args.sizes.split(",")):
            row = solve_one(tool, limit_bin, args.limit_max, args.simplicial_max, n, args.seed,
                            args.threads, env, work)
            print(row, flush=True)
            rows.append(row)

    L = [MARK_BEGIN, "## Scale: synthetic pose graphs of 10k to 1M poses", "",
         f"Measured by `bench/run_scale.py` on {datetime.date.today().isoformat()}; reproduce "
         "with `/usr/bin/python3 bench/run_scale.py --sizes "
         f"{args.sizes} --threads {args.threads}` (Release build).", "",
         f"Graphs: `graphslam simulate --poses N --seed {args.seed}` (a robot on a Manhattan "
         "grid of about sqrt(N)/2 cells a side, odometry plus a loop closure to an earlier "
         "visit of the same cell with probability 0.8; initial guess by dead reckoning). "
         "Solved by `graphslam optimize -q --threads "
         f"{args.threads}` (global initialisation, then Gauss-Newton with the default `auto` "
         "solver), one process: *wall* and *peak* are that process (loading, initialisation, "
         "optimisation, writing); *APE* is `graphslam eval ape` of the result against the "
         "ground truth (translation, unaligned, rmse).", "",
         "*Iterations* (factorisations: chord steps, conjugate gradients preconditioned with "
         "the previous factorisation, reuse it). *Iteration s* is linearise + assemble + "
         "factorise + solve per iteration, *per factorisation s* the same work divided by "
         "the factorisations instead (from `--stats`, without the one-off set-up; chord "
         "steps' work counted, the steps not: the stricter figure); *factorisation s* the "
         "time of one factorisation (the first of a factor "
         "includes first-touch page faults of its memory); *limit s* one bare `cholmod_factorize` of H at the optimum with the same "
         "ordering (`graphslam_factor_limit --solvers auto`, the faster of supernodal and "
         f"simplicial; supernodal only above {args.simplicial_max} poses; run up to "
         f"{args.limit_max} poses).", "",
         "| poses | edges | unknowns | solver | nnz(L) | iterations | chi2 initial -> final "
         "| init s | optimize s | iteration s | per factorisation s | factorisation s | limit s "
         "| iteration / limit | per factorisation / limit | wall s | peak MiB | APE rmse m "
         "| status |",
         "|---:|---:|---:|---|---:|---:|---|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---:|---|"]
    for r in rows:
        L.append(f"| {r['n']} | {r['edges']} | {r['unknowns']} | {r['solver']} | {r['nnz_l']} | "
                 f"{r['iterations']} ({r.get('factorisations', '?')}) | {fmt(r['chi2_0'], '.10g')} -> {fmt(r['chi2'], '.10g')} | "
                 f"{fmt(r['init'])} | {fmt(r.get('opt'))} | {fmt(r.get('per_iteration'))} | "
                 f"{fmt(r.get('per_fact'))} | {fmt(r.get('fact_per_iter'))} | "
                 f"{fmt(r.get('limit'))} | "
                 f"{fmt(r['per_iteration'] / r['limit'] if r.get('limit') else None)} | "
                 f"{fmt(r['per_fact'] / r['limit'] if r.get('limit') else None)} | "
                 f"{fmt(r['wall'])} | {fmt(r['rss'], '.0f')} | "
                 f"{fmt(r.get('ape'), '.4g')} | {r['status'] if r['exit'] == 0 else 'exit %d: %s' % (r['exit'], r['error'])} |")
    L += ["", *machine_notes(args.threads), MARK_END]
    section = "\n".join(L) + "\n"
    text = open(args.doc).read() if os.path.exists(args.doc) else "# Benchmarks\n"
    if MARK_BEGIN in text and MARK_END in text:
        head, rest = text.split(MARK_BEGIN, 1)
        text = head + section + rest.split(MARK_END, 1)[1].lstrip("\n")
    else:
        text = text.rstrip("\n") + "\n\n" + section
    with open(args.doc + ".tmp", "w") as f:
        f.write(text)
    os.replace(args.doc + ".tmp", args.doc)
    print(f"wrote {args.doc}")


if __name__ == "__main__":
    main()

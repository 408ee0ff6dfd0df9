#!/usr/bin/python3
# SPDX-License-Identifier: MIT
"""The linear-solver study of CMU 16-833 HW3 (../shared/SEEDS.md section 1, "Solvers"),
done in SciPy as the homework does it, optionally compared with `graphslam solvers`.

For each homework .npz file the script builds the homework's whitened system A x = b
(linear.py create_linear_system; for the nonlinear file, nonlinear.py's system after its
init_states and 10 Gauss-Newton iterations) and times each method, median of --repeats:
  - "coursework": the homework's solvers.py function as a whole, i.e. including forming
    A^T A and A^T b (and, for lu/lu_colamd, extracting U as the homework does);
  - "factor+solve": with A^T A (CSC) and A^T b formed beforehand, only the factorisation
    and the solve.
Methods: default (spsolve: SuperLU, COLAMD), pinv (scipy.sparse.linalg.inv; Python
evaluates the homework's inv(A^T A) @ A^T @ b left to right, so on the coursework basis
the sparse product inv(A^T A) @ A^T dominates), lu (splu NATURAL), lu_colamd (splu COLAMD). The homework's qr/qr_colamd use sparseqr
(PySPQR), which Debian does not package (nor any other sparse QR for Python: SuiteSparse
SPQR is there only as the C library libspqr2): the script times a dense numpy.linalg.qr
of A instead ("qr_dense") where A fits in --dense-qr-limit-mb, and skips qr_colamd (a
column ordering does nothing for a dense QR). All solutions are checked against default.

With --graphslam BIN it runs, in the same run and for the same files,
  BIN solvers FILE --solvers all --repeats N --csv OUT.csv
reads the CSV (solver,ordering,form,n,nnz_matrix,analyze_s,factorize_s,solve_s,total_s,
factor_nnz,residual,max_diff,status[,refine_s,max_diff_unrefined]; rows whose status is not
ok are ignored) and prints, per file, graphslam's fastest total (analyse + factorise + solve,
among the solvers whose solution without refinement is within 1e-8 of graphslam's
reference) against SciPy's fastest on both timing bases.
--graphslam-csv FILE=CSV compares with an existing CSV instead (no binary needed).

Run with /usr/bin/python3 (Debian's numpy, scipy): the python3 on PATH may lack them.
usage: scipy_solver_study.py [FILE.npz ...] [--repeats N] [--graphslam BIN] [--out FILE.md]
"""
import os

# One BLAS thread unless the caller says otherwise (set OPENBLAS_NUM_THREADS): graphslam's
# solvers run on one thread, and threads fighting over a busy machine distort the times.
for _var in ("OPENBLAS_NUM_THREADS", "OMP_NUM_THREADS", "MKL_NUM_THREADS"):
    os.environ.setdefault(_var, "1")

import argparse  # noqa: E402
import csv  # noqa: E402
import math  # noqa: E402
import statistics  # noqa: E402
import subprocess  # noqa: E402
import sys  # noqa: E402
import tempfile  # noqa: E402
import time  # noqa: E402
import warnings  # noqa: E402

import numpy as np  # noqa: E402
import scipy  # noqa: E402
import scipy.linalg  # noqa: E402
import scipy.sparse as sp  # noqa: E402
import scipy.sparse.linalg as spla  # noqa: E402

# Largest max abs difference to graphslam's reference solution (the criterion) of the
# solver named fastest, by its solve alone.
AGREEMENT = 1e-8
METHODS = ["default", "pinv", "lu", "lu_colamd", "qr_dense", "qr_colamd"]
CSV_COLUMNS = ["solver", "ordering", "form", "n", "nnz_matrix", "analyze_s", "factorize_s",
               "solve_s", "total_s", "factor_nnz", "residual", "max_diff", "status"]


def default_files():
    here = os.path.dirname(os.path.abspath(__file__))
    root = os.environ.get("GRAPHSLAM_DATA") or os.path.join(here, "..", "..", "shared", "datasets")
    seeds = os.path.join(root, "seeds")
    return [os.path.join(seeds, f) for f in ("2d_linear.npz", "2d_linear_loop.npz", "2d_nonlinear.npz")]


# --------------------------------------------------------------------------------------
# The homework's problem

def warp2pi(a):
    return a - 2 * np.pi * np.floor((a + np.pi) / (2 * np.pi))


def sqrt_inv(sigma):
    return np.linalg.inv(scipy.linalg.sqrtm(sigma)).real


class Problem:
    def __init__(self, path):
        d = np.load(path)
        missing = [k for k in ("odom", "observations", "sigma_odom", "sigma_landmark", "gt_traj", "gt_landmarks")
                   if k not in d.files]
        if missing:
            raise SystemExit(f"{path}: not a CMU 16-833 homework file (missing {', '.join(missing)})")
        self.path = path
        self.name = os.path.basename(path)
        self.gt_traj = d["gt_traj"]
        self.gt_landmarks = d["gt_landmarks"]
        self.odom = d["odom"]
        self.obs = d["observations"]
        self.sigma_odom = d["sigma_odom"]
        self.sigma_landmark = d["sigma_landmark"]
        self.n_poses = len(self.gt_traj)
        self.n_landmarks = len(self.gt_landmarks)
        self.pose_idx = self.obs[:, 0].astype(int)
        self.lm_idx = self.obs[:, 1].astype(int)
        # The model that explains the observations at the ground truth (as graphslam decides).
        dxy = self.gt_landmarks[self.lm_idx] - self.gt_traj[self.pose_idx]
        lin = np.sum((self.obs[:, 2:] - dxy) ** 2)
        br = np.sum(warp2pi(self.obs[:, 2] - np.arctan2(dxy[:, 1], dxy[:, 0])) ** 2
                    + (self.obs[:, 3] - np.hypot(dxy[:, 0], dxy[:, 1])) ** 2)
        self.nonlinear = br < lin

    def size(self):
        return 2 * (self.n_poses + self.n_landmarks)

    def system(self, x=None):
        """The homework's whitened A (CSR) and b, built sparsely (same entries as
        create_linear_system); at x for the nonlinear model."""
        n_odom, n_obs = len(self.odom), len(self.obs)
        P = self.n_poses
        w_o, w_l = sqrt_inv(self.sigma_odom), sqrt_inv(self.sigma_landmark)
        rows, cols, vals = [np.array([0, 1])], [np.array([0, 1])], [np.array([1.0, 1.0])]
        b = np.zeros(2 * (n_odom + 1 + n_obs))

        def blocks(first_row, col_a, col_b, ja, jb):
            # ja, jb: (n, 2, 2) blocks of the 2-row groups starting at first_row.
            n = len(col_a)
            r = first_row + 2 * np.arange(n)
            for (cols0, j) in ((col_a, ja), (col_b, jb)):
                for i in range(2):
                    for k in range(2):
                        rows.append(r + i)
                        cols.append(cols0 + k)
                        vals.append(j[:, i, k])

        i = np.arange(n_odom)
        h = np.array([[-1.0, 0.0], [0.0, -1.0]])
        blocks(2, 2 * i, 2 * (i + 1), np.broadcast_to(w_o @ h, (n_odom, 2, 2)),
               np.broadcast_to(-(w_o @ h), (n_odom, 2, 2)))
        if x is None:
            b[2:2 + 2 * n_odom] = (self.odom @ w_o.T).ravel()
        else:
            traj = x[:2 * P].reshape(-1, 2)
            b[2:2 + 2 * n_odom] = ((self.odom - (traj[1:] - traj[:-1])) @ w_o.T).ravel()
        first = 2 + 2 * n_odom
        ca, cb = 2 * self.pose_idx, 2 * (P + self.lm_idx)
        if not self.nonlinear:
            jl = np.broadcast_to(w_l, (n_obs, 2, 2))
            blocks(first, ca, cb, -jl, jl)
            b[first:] = (self.obs[:, 2:] @ w_l.T).ravel()
        else:
            r = x[:2 * P].reshape(-1, 2)[self.pose_idx]
            lm = x[2 * P:].reshape(-1, 2)[self.lm_idx]
            d = lm - r
            q = np.sum(d * d, axis=1)
            dist = np.sqrt(q)
            jr = np.empty((n_obs, 2, 2))
            jr[:, 0, 0], jr[:, 0, 1] = d[:, 1] / q, -d[:, 0] / q
            jr[:, 1, 0], jr[:, 1, 1] = -d[:, 0] / dist, -d[:, 1] / dist
            blocks(first, ca, cb, w_l @ jr, w_l @ -jr)
            z_est = np.stack([warp2pi(np.arctan2(d[:, 1], d[:, 0])), dist], axis=1)
            dz = np.stack([warp2pi(self.obs[:, 2] - z_est[:, 0]), self.obs[:, 3] - z_est[:, 1]], axis=1)
            b[first:] = (dz @ w_l.T).ravel()
        a = sp.csr_matrix((np.concatenate(vals), (np.concatenate(rows), np.concatenate(cols))),
                          shape=(len(b), self.size()))
        a.eliminate_zeros()  # as csr_matrix(dense A) in the homework: zero entries are not stored
        return a, b

    def init_states(self):
        traj = np.zeros((self.n_poses, 2))
        traj[1:] = np.cumsum(self.odom, axis=0)
        landmarks = np.zeros((self.n_landmarks, 2))
        seen = np.zeros(self.n_landmarks, dtype=bool)
        for k in range(len(self.obs)):
            l = self.lm_idx[k]
            if not seen[l]:
                seen[l] = True
                theta, d = self.obs[k, 2:]
                landmarks[l] = traj[self.pose_idx[k]] + d * np.array([np.cos(theta), np.sin(theta)])
        return np.concatenate([traj.ravel(), landmarks.ravel()])


# --------------------------------------------------------------------------------------
# Methods: the homework's solvers.py ("coursework") and factor+solve only

def coursework_solve(method, a, b):
    if method == "default":
        return spla.spsolve(a.T @ a, a.T @ b), None
    if method == "pinv":
        return spla.inv(a.T @ a) @ a.T @ b, None
    if method in ("lu", "lu_colamd"):
        lu = spla.splu(a.T @ a, permc_spec="NATURAL" if method == "lu" else "COLAMD")
        u = lu.U.tocsr()
        return lu.solve(a.T @ b), u.nnz + lu.L.nnz
    if method == "qr_dense":
        q, r = np.linalg.qr(a.toarray())
        return scipy.linalg.solve_triangular(r, q.T @ b), None
    raise ValueError(method)


def factor_solve(method, n_csc, rhs, a_dense, b):
    if method == "default":
        return spla.spsolve(n_csc, rhs)
    if method == "pinv":
        return spla.inv(n_csc) @ rhs
    if method in ("lu", "lu_colamd"):
        return spla.splu(n_csc, permc_spec="NATURAL" if method == "lu" else "COLAMD").solve(rhs)
    if method == "qr_dense":
        q, r = np.linalg.qr(a_dense)
        return scipy.linalg.solve_triangular(r, q.T @ b)
    raise ValueError(method)


def median_time(fn, repeats):
    times, out = [], None
    for _ in range(repeats):
        t0 = time.perf_counter()
        out = fn()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


def study(problem, methods, repeats, dense_limit_mb, log):
    """Times every method on the problem's system; returns (label, rows)."""
    if problem.nonlinear:
        x = problem.init_states()
        for _ in range(10):  # nonlinear.py: exactly 10 Gauss-Newton iterations, default solver
            a, b = problem.system(x)
            x = x + spla.spsolve(a.T @ a, a.T @ b)
        a, b = problem.system(x)
        label = "GN system after 10 iterations (nonlinear.py)"
        chi2 = float(b @ b)
        log(f"{problem.name}: nonlinear (bearing-range); after 10 Gauss-Newton iterations chi2 = {chi2:.10g}")
        dl = x[2 * problem.n_poses:].reshape(-1, 2) - problem.gt_landmarks
        dp = x[:2 * problem.n_poses].reshape(-1, 2) - problem.gt_traj
        log(f"  landmark rmse {math.sqrt(np.mean(np.sum(dl**2, axis=1))):.6f} m, "
            f"pose rmse {math.sqrt(np.mean(np.sum(dp**2, axis=1))):.6f} m")
    else:
        a, b = problem.system()
        label = "linear system (linear.py)"
    n_csc = (a.T @ a).tocsc()
    rhs = a.T @ b
    dense_mb = a.shape[0] * a.shape[1] * 8 / 2**20
    a_dense = None
    rows = []
    reference = None
    for method in methods:
        row = {"method": method, "coursework_s": None, "factor_solve_s": None, "factor_nnz": None,
               "max_diff": None, "note": ""}
        if method == "qr_colamd":
            row["note"] = ("skipped: needs sparseqr (PySPQR), not in Debian; a column ordering "
                           "does nothing for a dense QR")
            rows.append(row)
            continue
        if method == "qr_dense":
            if dense_mb > dense_limit_mb:
                row["note"] = (f"skipped: dense A would take {dense_mb:.0f} MB "
                               f"(> --dense-qr-limit-mb {dense_limit_mb:.0f})")
                rows.append(row)
                continue
            a_dense = a.toarray()
            row["note"] = "dense numpy.linalg.qr of A (sparseqr is not in Debian)"
        t_cw, (x, nnz) = median_time(lambda: coursework_solve(method, a, b), repeats)
        t_fs, x2 = median_time(lambda: factor_solve(method, n_csc, rhs, a_dense, b), repeats)
        if reference is None:
            reference = x
        scale = max(1.0, float(np.max(np.abs(reference))))
        row.update(coursework_s=t_cw, factor_solve_s=t_fs, factor_nnz=nnz,
                   max_diff=float(max(np.max(np.abs(x - reference)), np.max(np.abs(x2 - reference)))))
        if row["max_diff"] > 1e-6 * scale:
            row["note"] = (row["note"] + "; " if row["note"] else "") + "SOLUTION DIFFERS"
        log(f"  {problem.name} {method}: coursework {t_cw:.6f} s, factor+solve {t_fs:.6f} s")
        rows.append(row)
    return label, a, rows


# --------------------------------------------------------------------------------------
# graphslam

def check_graphslam(binary):
    try:
        r = subprocess.run([binary, "solvers", "--help"], capture_output=True, text=True, timeout=60)
    except OSError as e:
        raise SystemExit(f"error: cannot run {binary}: {e}")
    text = r.stdout + r.stderr
    if r.returncode != 0 or "usage" not in text or "solvers" not in text:
        first = (text.strip().splitlines() or [""])[0]
        raise SystemExit(f"error: {binary} has no 'solvers' command ('{binary} solvers --help' "
                         f"exited {r.returncode}: {first}); build a graphslam that has it, or "
                         "pass --graphslam-csv FILE=CSV")


def run_graphslam(binary, path, repeats, csv_path):
    cmd = [binary, "solvers", path, "--solvers", "all", "--repeats", str(repeats), "--csv", csv_path]
    if "nonlinear" in os.path.basename(path):
        # The same system as this study's: the one the 10th Gauss-Newton step solves.
        cmd += ["--at", "optimum", "--algorithm", "gn", "-i", "9"]
    r = subprocess.run(cmd, capture_output=True, text=True)
    if r.returncode != 0:
        raise SystemExit(f"error: {' '.join(cmd)} exited {r.returncode}:\n{r.stdout}{r.stderr}")


def read_graphslam_csv(csv_path):
    with open(csv_path, newline="") as f:
        reader = csv.DictReader(f)
        missing = [c for c in CSV_COLUMNS if c not in (reader.fieldnames or [])]
        if missing:
            raise SystemExit(f"error: {csv_path}: missing columns {', '.join(missing)}")
        rows = [r for r in reader if r["status"].strip() == "ok"]
    for r in rows:
        r["total_s"] = float(r["total_s"])
        # graphslam's total is analyse + factorise + solve; its optional refinement step is
        # a column of its own. The fastest it names must agree with the reference within
        # AGREEMENT by its solve alone (older CSVs have no such column: every row counts).
        unrefined = r.get("max_diff_unrefined")
        r["agrees"] = unrefined in (None, "", "nan") or float(unrefined) <= AGREEMENT
    return rows


# --------------------------------------------------------------------------------------

def fmt(t):
    return "—" if t is None else f"{t:.6f}"


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("files", nargs="*", help="homework .npz files (default: the three seed files)")
    ap.add_argument("--repeats", type=int, default=3, help="timed runs per method (median)")
    ap.add_argument("--methods", nargs="+", default=METHODS, choices=METHODS)
    ap.add_argument("--dense-qr-limit-mb", type=float, default=400.0,
                    help="largest dense A for qr_dense, in MB")
    ap.add_argument("--graphslam", help="graphslam binary with the 'solvers' command")
    ap.add_argument("--graphslam-csv", action="append", default=[], metavar="FILE=CSV",
                    help="compare FILE with this existing `graphslam solvers` CSV")
    ap.add_argument("--out", help="also write the markdown tables here")
    args = ap.parse_args()
    if args.repeats < 1:
        ap.error("--repeats must be at least 1")
    files = args.files or default_files()
    for f in files:
        if not os.path.exists(f):
            raise SystemExit(f"error: {f} not found")
    given_csv = {}
    for item in args.graphslam_csv:
        if "=" not in item:
            ap.error("--graphslam-csv takes FILE=CSV")
        f, c = item.split("=", 1)
        given_csv[os.path.abspath(f)] = c
    if args.graphslam:
        check_graphslam(args.graphslam)

    def log(msg):
        print(msg, file=sys.stderr, flush=True)

    warnings.simplefilter("ignore", spla.MatrixRankWarning)
    warnings.simplefilter("ignore", sp.SparseEfficiencyWarning)
    out = [f"# SciPy solver study (CMU 16-833 HW3), median of {args.repeats} runs",
           "", f"numpy {np.__version__}, scipy {scipy.__version__}; times in seconds.", "",
           "| file | system | n | nnz(A) | method | coursework (s) | factor+solve (s) | nnz(L+U) | max abs(x - x_default) | note |",
           "|---|---|---|---|---|---|---|---|---|---|"]
    compare = []
    with tempfile.TemporaryDirectory() as tmp:
        for path in files:
            problem = Problem(path)
            log(f"{problem.name}: {'nonlinear' if problem.nonlinear else 'linear'}, "
                f"{problem.n_poses} poses, {problem.n_landmarks} landmarks, {len(problem.obs)} observations")
            label, a, rows = study(problem, args.methods, args.repeats, args.dense_qr_limit_mb, log)
            for r in rows:
                nnz = "—" if r["factor_nnz"] is None else str(r["factor_nnz"])
                diff = "—" if r["max_diff"] is None else f"{r['max_diff']:.2e}"
                out.append(f"| {problem.name} | {label} | {a.shape[1]} | {a.nnz} | {r['method']} | "
                           f"{fmt(r['coursework_s'])} | {fmt(r['factor_solve_s'])} | {nnz} | {diff} | "
                           f"{r['note']} |")
            csv_path = given_csv.get(os.path.abspath(path))
            if csv_path is None and args.graphslam:
                csv_path = os.path.join(tmp, problem.name + ".csv")
                log(f"  running {args.graphslam} solvers {path} --solvers all --repeats {args.repeats}")
                run_graphslam(args.graphslam, path, args.repeats, csv_path)
            if csv_path is not None:
                compare.append((problem.name, read_graphslam_csv(csv_path), rows))
    if compare:
        out += ["", "## graphslam against SciPy (fastest of each; ratio = SciPy time / graphslam time)", "",
                "| file | graphslam fastest | total (s) | SciPy fastest, coursework basis | (s) | ratio | "
                "SciPy fastest, factor+solve | (s) | ratio |",
                "|---|---|---|---|---|---|---|---|---|"]
        for name, gs_rows, rows in compare:
            timed = [r for r in rows if r["coursework_s"] is not None]
            if not gs_rows:
                out.append(f"| {name} | no row with status ok | — | | | | | | |")
                continue
            agreeing = [r for r in gs_rows if r["agrees"]] or gs_rows
            g = min(agreeing, key=lambda r: r["total_s"])
            g_label = f"{g['solver']} ({g['ordering']}, {g['form']})"
            cw = min(timed, key=lambda r: r["coursework_s"])
            fs = min(timed, key=lambda r: r["factor_solve_s"])
            ratio = lambda t: f"{t / g['total_s']:.1f}x" if g["total_s"] > 0 else "—"  # noqa: E731
            out.append(f"| {name} | {g_label} | {g['total_s']:.6f} | {cw['method']} | {cw['coursework_s']:.6f} | "
                       f"{ratio(cw['coursework_s'])} | {fs['method']} | {fs['factor_solve_s']:.6f} | "
                       f"{ratio(fs['factor_solve_s'])} |")
    text = "\n".join(out) + "\n"
    print(text)
    if args.out:
        with open(args.out, "w") as f:
            f.write(text)


if __name__ == "__main__":
    main()

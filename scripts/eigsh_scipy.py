#!/usr/bin/env python3
"""SciPy's shift-invert Lanczos (ARPACK through scipy.sparse.linalg.eigsh) on the problem of
`ifem_bench eigen`, for the comparison in BENCHMARKS.md ("Eigenpairs k = 50 (issue 15, item 4)").

    build/examples/ifem_bench eigen --write DIR      # writes DIR/L.mtx and DIR/M.mtx
    python3 scripts/eigsh_scipy.py DIR [--k 50] [--repeat 3]

Solves L φ = λ M φ for the k smallest λ with the same shift as ifem (σ = −0.01 / total area),
extra pairs (k + 6 computed, k kept) and tolerance (1e-10), and ARPACK's default basis size
(ncv = max(2·nev + 1, 20)). Prints, medians of --repeat runs: the factorization of L − σM alone
(SuperLU, what eigsh uses for sigma= by default; CHOLMOD through scikit-sparse when installed),
the whole eigsh call with each, the operator applications, and the k-th eigenvalue.
"""
import argparse
import os
import statistics
import time

import numpy as np
import scipy
import scipy.io
import scipy.sparse
import scipy.sparse.linalg as sla


def median_time(repeat, f):
    times, out = [], None
    for _ in range(repeat):
        t0 = time.perf_counter()
        out = f()
        times.append(time.perf_counter() - t0)
    return statistics.median(times), out


class CountingOp(sla.LinearOperator):
    """x -> (L - σM)^{-1} x through a given solve, counting the applications."""

    def __init__(self, solve, n):
        super().__init__(np.float64, (n, n))
        self.solve, self.count = solve, 0

    def _matvec(self, x):
        self.count += 1
        return self.solve(np.asarray(x).ravel())


def run(L, M, sigma, k, solve, repeat, label):
    n, nev = L.shape[0], k + 6
    ops = []

    def once():
        op = CountingOp(solve, n) if solve else None
        vals = sla.eigsh(L, k=nev, M=M, sigma=sigma, which="LM", OPinv=op, tol=1e-10,
                         return_eigenvectors=True)[0]
        ops.append(op.count if op else "–")
        return np.sort(vals)

    t, vals = median_time(repeat, once)
    print(f"| {label} | {k} | {t:.3f} | {ops[-1]} | {vals[k - 1]:.6f} |", flush=True)


def main():
    ap = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    ap.add_argument("dir")
    ap.add_argument("--k", type=int, nargs="+", default=[10, 50])
    ap.add_argument("--repeat", type=int, default=3)
    a = ap.parse_args()
    L = scipy.sparse.csc_matrix(scipy.io.mmread(os.path.join(a.dir, "L.mtx")))
    M = scipy.sparse.csc_matrix(scipy.io.mmread(os.path.join(a.dir, "M.mtx")))
    sigma = -0.01 / M.diagonal().sum()
    A = scipy.sparse.csc_matrix(L - sigma * M)
    print(f"load average at start: {' '.join(f'{x:.2f}' for x in os.getloadavg())}; "
          f"scipy {scipy.__version__}, numpy {np.__version__}; {L.shape[0]} vertices\n")
    # eigsh(L, k, M, sigma) as a user would call it: it factors L − σM with SuperLU inside
    solvers = [("ARPACK, eigsh's own factor (inside the time)", None)]
    for perm in ("COLAMD", "MMD_AT_PLUS_A"):  # splu's default; a symmetric ordering
        t, lu = median_time(a.repeat, lambda p=perm: sla.splu(A, permc_spec=p))
        print(f"SuperLU factorization of L − σM (splu, permc_spec={perm}): {t:.3f} s, "
              f"nnz(L + U) {lu.L.nnz + lu.U.nnz:,}")
        solvers.append((f"ARPACK + SuperLU {perm} factor given", lu.solve))
    try:
        from sksparse.cholmod import cholesky  # noqa: PLC0415
        t, f = median_time(a.repeat, lambda: cholesky(A))
        print(f"CHOLMOD factorization (scikit-sparse): {t:.3f} s")
        solvers.append(("ARPACK + CHOLMOD factor given", f))
    except ImportError:
        print("scikit-sparse is not installed: no CHOLMOD-based OPinv")
    print("\nseconds: the eigsh call; with a factor given, the factorization is not in it\n")
    print("| eigsh | k | seconds | operator applications | λ_k |\n|---|---|---|---|---|")
    for k in a.k:
        for label, solve in solvers:
            run(L, M, sigma, k, solve, a.repeat, label)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Why the summation-by-parts gradient's free-surface closure needs its own weights (issue 14).

A 1D column of unit spacing and unit volumes, the interior pair coefficients of a kernel with
two neighbours a side, a_{k,k+1} = alpha, a_{k,k+2} = beta, 2 alpha + 4 beta = 1 (exact for
linear fields, rows summing to zero). The free surface is the top row N-1, its closure plane half
a spacing above it (shift s = -1 in R2). The question: can antisymmetric corrections confined to
the top m rows make every row exact (R2 on all, R1 off the surface row) while the rows below
keep their coefficients? That is what "the closure is local" means; if not, the least squares
of make_gradient_conservative() must carry the defect through the whole depth.

Printed: the residual of the best local correction against m.
- with the weights omega = V (conservative_gradient.inl before the twenty-first session): the
  top m rows have 2m - 1 constraints on 2m - 3 pairs, and the residual only decays like 1/m^2;
  no shift of the closure plane fixes it;
- with the weights of the top two rows free (the committed closure): exact from m = 2, with
  omega = (1 + beta, 1 - beta) V, the boundary weights of a diagonal-norm SBP operator.

Usage: python3 sbp_closure_1d.py [beta]   (beta = 0.12 by default; needs numpy)
"""
import sys

import numpy as np

BETA = float(sys.argv[1]) if len(sys.argv) > 1 else 0.12
ALPHA = (1 - 4 * BETA) / 2
N = 40  # rows 0..N-1, the free surface on row N-1


def a0(k, l):
    d = l - k
    return {1: ALPHA, 2: BETA}.get(abs(d), 0.0) * np.sign(d)


def local_closure(m, shift=-1.0, free_weights=()):
    """Least-squares residual, weights and largest correction for the top m rows."""
    rows = list(range(N - m, N))
    pairs = [(k, l) for k in rows for l in rows if k < l and l - k <= 2]
    n_unknowns = len(pairs) + len(free_weights)
    A, b = [], []
    for k in rows:
        neighbours = [l for l in range(max(0, k - 2), min(N, k + 3)) if l != k]
        s = shift if k == N - 1 else 0.0
        # R2: sum_l a_kl (y_l - y_k + s) = omega_k
        row = np.zeros(n_unknowns)
        for p, (i, j) in enumerate(pairs):
            if i == k:
                row[p] += (j - k) + s
            if j == k:
                row[p] -= (i - k) + s
        if k in free_weights:
            row[len(pairs) + free_weights.index(k)] = -1.0
        A.append(row)
        b.append(1.0 - sum(a0(k, l) * ((l - k) + s) for l in neighbours))
        if k != N - 1:  # R1 off the surface row
            row = np.zeros(n_unknowns)
            for p, (i, j) in enumerate(pairs):
                row[p] += 1.0 if i == k else (-1.0 if j == k else 0.0)
            A.append(row)
            b.append(-sum(a0(k, l) for l in neighbours))
    A, b = np.array(A), np.array(b)
    x = np.linalg.lstsq(A, b, rcond=None)[0]
    return np.linalg.norm(A @ x - b), 1.0 + x[len(pairs):], np.abs(x[:len(pairs)]).max()


def main():
    print(f"interior pair: alpha = {ALPHA:.3f}, beta = {BETA:.3f}")
    print("rows m | omega = V: residual, largest correction | top two weights free: residual, omega/V")
    for m in range(2, 9):
        r0, _, c0 = local_closure(m)
        r1, w1, _ = local_closure(m, free_weights=(N - 1, N - 2)) if m >= 2 else (np.nan, [], 0)
        print(f"{m:6d} | {r0:9.2e}, {c0:.3f}                    | {r1:9.2e}, {np.round(w1, 4)}")
    print("closure plane shift (omega = V, m = 6):",
          ", ".join(f"s = {s}: {local_closure(6, s)[0]:.2e}" for s in (-0.5, -0.75, -1.0, -1.25, -1.5)))


if __name__ == "__main__":
    main()

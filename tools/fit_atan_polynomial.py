#!/usr/bin/env python3
# Fits the odd polynomial t + t^3 Q(t^2) of src/simd/fast_atan2.hpp to atan on [0, 1] (Remez exchange).
#
# Minimizes the maximum absolute error of t + sum_{k=1..m} c_k t^(2k+1) against atan(t);
# the leading coefficient is kept at exactly 1 so that the kernel can add the small term
# t^3 Q to t with one fused multiply-add (its rounding is then relative to |t^3 Q|, not to t).
# Needs mpmath (Debian: python3-mpmath). Usage: fit_atan_polynomial.py [m], default m = 8.
import sys

import mpmath as mp

mp.mp.dps = 40


def fit(m, iterations=12, grid_size=4000):
    n = m + 1  # unknowns: m coefficients and the levelled error
    points = [mp.sin(mp.pi / 2 * (i + 1) / n) for i in range(n)]
    grid = [mp.mpf(i) / grid_size for i in range(grid_size + 1)]
    for _ in range(iterations):
        a = mp.matrix(n, n)
        b = mp.matrix(n, 1)
        for i, t in enumerate(points):
            for k in range(m):
                a[i, k] = t ** (2 * k + 3)
            a[i, m] = (-1) ** i
            b[i] = mp.atan(t) - t
        solution = mp.lu_solve(a, b)
        c = [solution[k] for k in range(m)]
        values = [t + sum(c[k] * t ** (2 * k + 3) for k in range(m)) - mp.atan(t) for t in grid]
        # The new reference points: the error's local extrema, and the interval's end.
        extrema = [grid[i] for i in range(1, grid_size)
                   if (values[i] - values[i - 1]) * (values[i + 1] - values[i]) <= 0] + [grid[-1]]
        points = extrema[-n:]
    return c, max(abs(v) for v in values)


if __name__ == "__main__":
    m = int(sys.argv[1]) if len(sys.argv) > 1 else 8
    coefficients, error = fit(m)
    print("max error (exact arithmetic): %s rad" % mp.nstr(error, 3))
    for k, c in enumerate(coefficients, start=1):
        print("c%d = %.9e" % (k, float(c)))

#!/usr/bin/python3
"""Fits the polynomial kernels of plume's transcendental functions.

Each kernel g(t) is fitted on its reduced interval with a weighted Remez
exchange (mpmath, 60 digits); the coefficients are printed as C++ literals.
Run with Debian's python3 (python3-mpmath):  /usr/bin/python3 tools/fit_coefficients.py
The printed sets are what include/plume/numerics/detail/*_coeffs.hpp hold;
the error column is the relative minimax error of the exact-coefficient fit.
"""
import mpmath as mp

mp.mp.dps = 60


def remez(f, a, b, deg, w=None, iters=30):
    """Minimax polynomial p of degree deg for f on [a,b], minimising max |w*(f-p)|
    (w defaults to 1/|f|: relative error)."""
    if w is None:
        w = lambda t: 1 / abs(f(t))
    n = deg + 2
    xs = [(a + b) / 2 + (b - a) / 2 * mp.cos(mp.pi * (n - 1 - i) / (n - 1)) for i in range(n)]
    coeffs = None
    for _ in range(iters):
        # solve p(x_i) + (-1)^i E / w(x_i) = f(x_i)
        A = mp.matrix(n, n)
        rhs = mp.matrix(n, 1)
        for i, x in enumerate(xs):
            for j in range(deg + 1):
                A[i, j] = x ** j
            A[i, deg + 1] = (-1) ** i / w(x)
            rhs[i] = f(x)
        sol = mp.lu_solve(A, rhs)
        coeffs = [sol[j] for j in range(deg + 1)]
        err = lambda t: w(t) * (f(t) - mp.polyval(coeffs[::-1], t))
        # new extrema: sample densely, pick one extremum per sign alternation
        grid = [a + (b - a) * k / 4000 for k in range(4001)]
        vals = [err(t) for t in grid]
        ext = []
        for k, v in enumerate(vals):
            if ext and mp.sign(v) == mp.sign(vals[ext[-1]]):
                if abs(v) > abs(vals[ext[-1]]):
                    ext[-1] = k
            else:
                ext.append(k)
        while len(ext) > n:
            # drop the smaller end
            if abs(vals[ext[0]]) < abs(vals[ext[-1]]):
                ext.pop(0)
            else:
                ext.pop()
        if len(ext) < n:
            break
        xs = [grid[k] for k in ext]
    maxerr = max(abs(err(a + (b - a) * k / 20000)) for k in range(20001))
    return coeffs, maxerr


def show(name, coeffs, maxerr, kind):
    print(f"// {name}: relative error {mp.nstr(maxerr, 3)} (2^{mp.nstr(mp.log(maxerr, 2), 4)})")
    for c in reversed(coeffs):  # highest degree first: Horner order
        if kind == "f":
            print(f"    {float(mp.mpf(float(c))):.9e}f,")
        else:
            print(f"    {float(c):.17e},")


def f32(v):
    """v rounded to float (round to nearest even), as a Python float."""
    import struct
    return struct.unpack("f", struct.pack("f", float(v)))[0]


def fit(name, f, a, b, deg, kind, w=None):
    c, e = remez(f, a, b, deg, w)
    show(name, c, e, kind)


def fit_asin(kind, deg):
    """asin's kernel R(u) = z P(z), u = 4z (z = s^2 <= 1/4), minimising the error of
    s + s z P(z) relative to s (weight z: what reaches the result). Coefficients are
    rounded to the type, then scaled exactly by 4^-(k+1) for the variable u; printed as
    hexadecimal literals, highest degree first."""
    c, e = remez(P_asin, mp.mpf(0), mp.mpf(1) / 4, deg, w=lambda z: z if z > 0 else eps)
    r = [f32(x) if kind == "f" else float(x) for x in c]
    print(f"// asin {'float' if kind == 'f' else 'double'}: relative error of s + s z P(z)"
          f" 2^{mp.nstr(mp.log(e, 2), 4)}")
    for k in reversed(range(deg + 1)):
        v = r[k] / 4 ** (k + 1)
        print(f"    {v.hex()}{'f' if kind == 'f' else ''},")


eps = mp.mpf(10) ** -30
# asin(s) = s + s*z*P(z), z = s^2 in [0, 1/4]
P_asin = lambda z: (mp.asin(mp.sqrt(z)) / mp.sqrt(z) - 1) / z if z > eps else mp.mpf(1) / 6 + 3 * z / 40
# atan(t) = t + t*z*P(z), z = t^2 in [0, tan(pi/8)^2]
P_atan = lambda z: (mp.atan(mp.sqrt(z)) / mp.sqrt(z) - 1) / z if z > eps else -mp.mpf(1) / 3 + z / 5
# exp(r) = 1 + r + r^2 P(r), r in [-ln2/2, ln2/2]
P_exp = lambda r: (mp.exp(r) - 1 - r) / r ** 2 if abs(r) > eps else mp.mpf(1) / 2 + r / 6
# 2^r = 1 + r P(r), r in [-1/2, 1/2]
P_exp2 = lambda r: (mp.power(2, r) - 1) / r if abs(r) > eps else mp.log(2) + r * mp.log(2) ** 2 / 2
# log(1+f) = 2s + s*R, R = z*Q(z), z = s^2, s = f/(2+f), |s| <= (sqrt2-1)/(sqrt2+1)
P_log = lambda z: ((2 * mp.atanh(mp.sqrt(z)) / mp.sqrt(z)) - 2) / z if z > eps else mp.mpf(2) / 3 + 2 * z / 5
# tan(r) = r + r*z*P(z), z = r^2 in [0, (pi/4)^2]
P_tan = lambda z: (mp.tan(mp.sqrt(z)) / mp.sqrt(z) - 1) / z if z > eps else mp.mpf(1) / 3 + 2 * z / 15

smax = (mp.sqrt(2) - 1) / (mp.sqrt(2) + 1)
t8 = mp.tan(mp.pi / 8)
jobs = {
    # name: (kernel, interval, float degree, double degree); the degrees are the
    # smallest that keep the kernel's share of the final error under 0.1 ulp.
    # asin: fit_asin (another weight and variable), degrees 4 and 11
    "atan": (P_atan, 0, t8 ** 2, 5, 10),
    "exp": (P_exp, -mp.log(2) / 2, mp.log(2) / 2, 4, 10),
    "exp2": (P_exp2, -mp.mpf(1) / 2, mp.mpf(1) / 2, 6, 11),
    "log": (P_log, 0, smax ** 2, 2, 6),
    # tan: float only (double tan is cephes' rational function); the double degree is unused
    "tan": (P_tan, 0, (mp.pi / 4) ** 2, 6, 15),
}
if __name__ == "__main__":
    import sys
    which = sys.argv[1:] or list(jobs) + ["asin"]
    for name in which:
        if name == "asin":
            fit_asin("f", 4)
            fit_asin("d", 11)
            continue
        f, a, b, df, dd = jobs[name]
        fit(name + " float", f, mp.mpf(a), mp.mpf(b), df, "f")
        fit(name + " double", f, mp.mpf(a), mp.mpf(b), dd, "d")

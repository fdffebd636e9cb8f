#!/usr/bin/env python3
"""Viscoelastic contacts d'' + A d^beta d' + d^p = 0, d(0) = 0, d'(0) = 1 (dimensionless; beta = 1/2
is Kuwabara-Kono damping), by mpmath and independently of pldamp's C++ code and its Taylor
integrator (nothing of solvers/ or harness/ is used). A is set from the group g (alpha_eff):
delta_u = ((p + 1)/2)^(1/(p + 1)) and A = g sqrt(2 (p + 1))/delta_u^(beta - (p - 1)/2). Each row:
  delta_max, t_peak   the largest overlap (d' = 0) and its time;
  tau, e              the first t > 0 with d = 0 again, and e = -d'(tau);
  t_cut, e_cap        the first time in unloading where the force d^p + A d^beta d' is 0 (there
                      d'' = 0, so e_cap = -d'(t_cut) is the largest unloading speed).

Method. d^beta is not analytic in t at d = 0 (d ~ t there), so nothing here is a series in t. With
q the common denominator of p and beta (q = 2 for every row) write d = s^q, a = q beta, b = q p,
and take as the independent variable the regularised time sigma, dt = q s^(q-1) dsigma
(a Sundman transformation). The motion becomes the polynomial system
    s' = v,   v' = -q A s^(q-1+a) v - q s^(q-1+b),   t' = q s^(q-1)      (' = d/dsigma),
analytic through both d = 0 ends and the turning point, with s(0) = 0, v(0) = 1, t(0) = 0. It is
integrated by a Taylor method written here: exact Taylor coefficients from the recurrences of the
Cauchy products (order N), each step h the largest with |c_k| h^k <= tol for the last five orders
k. The events are roots of the step's Taylor polynomials, found by bracketed Newton on them:
v = 0 (turning point), s^(b-a) + A v = 0 with v < 0 (force end; the force is s^a times it) and
s = 0 (end; s crosses 0 with ds/dsigma = -e != 0, so the root is simple). Every row's contact
returns (with beta = 1/2 the damping force vanishes with d, and on unloading
dr/dt = d^p - A d^beta r > 0 wherever r = |d'| = 0, so r stays positive down to d = 0); the
script stops if one does not. The values printed are those at 64 digits, to 36 significant
digits (nstr, trailing zeros dropped).

Checks, every run (the script stops with an error when one fails):
  1. the whole table twice, at 45 digits with N = 48, tol = 1e-48 and at 64 digits with N = 72,
     tol = 1e-68 (other steps, other event brackets); every number must agree to 36 digits
     (they agree to 45);
  2. the energy balance 1/2 - e^2/2 = int A d^beta v^2 dt, the integral taken apart from e by
     Gauss-Legendre quadrature (mpmath.quad) of the dense Taylor output over each step;
     residual below 1e-40 (it is below 1e-45);
  3. a second, separate method at 45 digits (--quick leaves it out): the energy method in the
     phase plane, dw/dd = -2 A d^beta v - 2 d^p for w = v^2, in legs where the variable is
     regular, each integrated by mpmath.odefun (mpmath's own Taylor series, from Euler steps and
     finite differences at high precision, not the recurrences above): |v| and t against s from
     s = 0 to s_a = 0.6 s_max; s and t against u = -v from there to the turning point v = 0
     (ds/dv is regular there); s and t against r = -v from there to r_b = e_cap/2; |v| and t
     against s from there down to s = 0, with t_cut from mpmath.findroot on r = s^(b-a)/A
     (where dr/ds = 0). s_max and e_cap are taken, rounded to 3 digits, from the first method
     only to place the two switches, which do not change the results. Each leg also integrates
     the dissipated work int A d^beta |v| |dd|, whose total must be 1/2 - e^2/2 to 1e-40; every
     number must agree with the first method to 36 digits (they agree to 45);
  4. closed forms for each p: the elastic contact (A = 0), delta_max = delta_u, e = 1,
     tau = 2 t_peak = 2 delta_u B(1/(p + 1), 1/2)/(p + 1), to 36 digits (64 agree); and the first
     order in A, (1 - e)/A = 2 delta_u^(beta+1) B((beta+1)/(p+1), 3/2)/(p+1) + O(A) (the work of
     the damping along the elastic motion) at A = 1e-20, to 19 digits (20 agree).

Run from the repository root, with /usr/bin/python3 (mpmath 1.2.1) or a newer mpmath (1.3.0
writes the same file): about 2 minutes on one core, 30 seconds with --quick; -j 2 spreads the
rows over two processes (and writes the same file):

    python3 data/reference/viscoelastic.py > data/reference/viscoelastic.csv

The CSV goes to standard output; the checks and their worst agreements to standard error.
"""
import argparse
import sys
import time
from fractions import Fraction
from math import gcd

from mpmath import beta as beta_function
from mpmath import findroot, inf, log10, mp, mpf, nstr, odefun, quad, sqrt

# p, beta, groups
CASES = [
    ("1.5", "0.5", ["0.01", "0.05", "0.1", "0.2", "0.3", "0.5", "0.75", "1", "1.5"]),
    ("2", "0.5", ["0.1", "0.3", "0.75"]),
    ("1", "0.5", ["0.1", "0.3", "0.75"]),
]
COLUMNS = ["A", "delta_max", "t_peak", "tau", "e", "t_cut", "e_cap"]
DIGITS = 36  # printed
REQUIRED = 36  # agreement, in significant digits, between every pair of computations
# (digits, Taylor order, tolerance exponent): the printed run last
RUNS = [(45, 48, -48), (64, 72, -68)]


def exponents(p, beta):
    """q, a = q beta, b = q p for rational p and beta (decimal strings)."""
    p, beta = Fraction(p), Fraction(beta)
    q = p.denominator * beta.denominator // gcd(p.denominator, beta.denominator)
    return q, int(beta * q), int(p * q)


def damping(p, beta, g):
    p, beta, g = mpf(p), mpf(beta), mpf(g)
    delta_u = ((p + 1) / 2) ** (1 / (p + 1))
    return g * sqrt(2 * (p + 1)) / delta_u ** (beta - (p - 1) / 2)


def horner(c, x):
    y = c[-1]
    for ck in reversed(c[:-1]):
        y = y * x + ck
    return y


def horner_derivative(c, x):
    y = (len(c) - 1) * c[-1]
    for k in range(len(c) - 2, 0, -1):
        y = y * x + k * c[k]
    return y


def cauchy(x, y, k):
    return sum(x[i] * y[k - i] for i in range(k + 1))


def polynomial_root(c, hi):
    """The root in (0, hi] of the polynomial c, positive at 0 and not positive at hi."""
    lo, f_lo, f_hi = mpf(0), horner(c, 0), horner(c, hi)
    x = lo + f_lo * (hi - lo) / (f_lo - f_hi)
    for _ in range(200):
        f = horner(c, x)
        if f > 0:
            lo = x
        else:
            hi = x
        dfdx = horner_derivative(c, x)
        step = f / dfdx if dfdx else mpf(0)
        new = x - step
        if not lo < new < hi:
            new = (lo + hi) / 2
        if abs(new - x) <= abs(x) * mp.eps * 4 or hi - lo <= abs(x) * mp.eps * 4:
            return new
        x = new
    raise RuntimeError("no convergence of the event's Newton iteration")


def sundman(p, beta, A, order, tol_exponent):
    """The contact by the Taylor method in sigma: the six values, and the residual of the energy
    balance."""
    q, a, b = exponents(p, beta)
    N, tol = order, mpf(10) ** tol_exponent
    jmax = max(q - 1 + b, b - a)
    s, v, t = mpf(0), mpf(1), mpf(0)
    found, loaded, work = {}, False, mpf(0)
    for _ in range(100000):
        S, V, T = [s] + [mpf(0)] * N, [v] + [mpf(0)] * N, [t] + [mpf(0)] * N
        P = [[mpf(1)] + [mpf(0)] * N, S] + [[mpf(0)] * (N + 1) for _ in range(jmax - 1)]
        for k in range(N):
            for j in range(2, jmax + 1):
                P[j][k] = cauchy(P[j - 1], S, k)
            S[k + 1] = V[k] / (k + 1)
            V[k + 1] = (-q * A * cauchy(P[q - 1 + a], V, k) - q * P[q - 1 + b][k]) / (k + 1)
            T[k + 1] = q * P[q - 1][k] / (k + 1)
        for j in range(2, jmax + 1):
            P[j][N] = cauchy(P[j - 1], S, N)
        # the step from the last coefficients (several: some vanish in the first step when A = 0)
        h = min((tol / c) ** (mpf(1) / k) for k in range(N - 4, N + 1)
                for c in [max(abs(S[k]), abs(V[k]), abs(T[k]))] if c)
        F = [P[b - a][k] + A * V[k] for k in range(N + 1)]  # the force over s^a
        end = None
        if not loaded and horner(V, h) <= 0:
            x = polynomial_root(V, h)
            found["delta_max"], found["t_peak"] = horner(S, x) ** q, horner(T, x)
            loaded = True
        if loaded and A and "t_cut" not in found and F[0] > 0 and horner(F, h) <= 0:
            x = polynomial_root(F, h)
            found["t_cut"], found["e_cap"] = horner(T, x), -horner(V, x)
        if s > 0 and horner(S, h) <= 0:
            end = polynomial_root(S, h)
            found["tau"], found["e"] = horner(T, end), -horner(V, end)
        span = end if end is not None else h
        # dissipated power in sigma, q A s^(q-1+a) v^2, from the step's dense output
        work += quad(lambda x: q * A * horner(P[q - 1 + a], x) * horner(V, x) ** 2, [0, span],
                     method="gauss-legendre")
        if end is not None:
            break
        s, v, t = horner(S, h), horner(V, h), horner(T, h)
    else:
        raise RuntimeError("the contact did not end")
    residual = 1 / mpf(2) - found["e"] ** 2 / 2 - work
    return found, residual


def phase_plane(p, beta, A, s_max, e_cap):
    """The contact by the energy method in legs, each by mpmath.odefun (see the docstring)."""
    q, a, b = exponents(p, beta)
    # loading, against s: y = (v, t, W)
    s_a = mpf(nstr(0.6 * s_max, 3))
    leg1 = odefun(lambda s, y: [q * s ** (q - 1) * (-A * s ** a - s ** b / y[0]),
                                q * s ** (q - 1) / y[0],
                                q * A * s ** (q - 1 + a) * y[0]], 0, [mpf(1), mpf(0), mpf(0)])
    v_a, t_a, W_a = leg1(s_a)
    # to the turning point, against u = -v: y = (s, t, W)
    def turning(u, y):
        s, v = y[0], -u
        force = A * s ** a * v + s ** b
        return [v / (q * s ** (q - 1) * force), 1 / force, A * s ** a * v * v / force]
    s_m, t_peak, W_m = odefun(turning, -v_a, [s_a, t_a, W_a])(0)
    # unloading from the turning point, against r = -v: y = (s, t, W)
    def unloading(r, y):
        s = y[0]
        force = s ** b - A * s ** a * r
        return [-r / (q * s ** (q - 1) * force), 1 / force, A * s ** a * r * r / force]
    r_b = mpf(nstr(e_cap / 2, 3))
    s_b, t_b, W_b = odefun(unloading, 0, [s_m, t_peak, W_m])(r_b)
    # down to s = 0, against x = s_b - s: y = (r, t, W)
    def descent(x, y):
        s, r = s_b - x, y[0]
        return [q * s ** (q - 1) * (s ** b - A * s ** a * r) / r, q * s ** (q - 1) / r,
                q * A * s ** (q - 1 + a) * r]
    leg4 = odefun(descent, 0, [r_b, t_b, W_b])
    e, tau, W = leg4(s_b)
    x_cut = findroot(lambda x: (s_b - x) ** (b - a) - A * leg4(x)[0], (mpf(0), s_b),
                     solver="anderson")
    r_cut, t_cut, _ = leg4(x_cut)
    found = {"delta_max": s_m ** q, "t_peak": t_peak, "tau": tau, "e": e, "t_cut": t_cut,
             "e_cap": r_cut}
    return found, 1 / mpf(2) - e * e / 2 - W


def agreement(x, y):
    """Significant digits to which x and y agree (inf when equal)."""
    if x == y:
        return inf
    return -log10(abs(x - y) / max(abs(x), abs(y)))


def row(args):
    p, beta, g, verify = args
    report, values = [], None
    previous = None
    for dps, order, tol_exponent in RUNS:
        mp.dps = dps
        A = damping(p, beta, g)
        found, residual = sundman(p, beta, A, order, tol_exponent)
        found["A"] = A
        if abs(residual) > mpf(10) ** -40:
            raise SystemExit(f"p={p} g={g}: energy residual {nstr(residual, 3)} at {dps} digits")
        report.append(("energy residual, %d digits" % dps, abs(residual)))
        if previous is not None:
            worst = min(agreement(found[c], previous[c]) for c in COLUMNS)
            report.append(("digits, 45 vs 64", worst))
        previous = found
    values = previous
    if verify:
        mp.dps = 45
        A = damping(p, beta, g)
        other, residual = phase_plane(p, beta, A, sqrt(values["delta_max"]), values["e_cap"])
        other["A"] = A
        if abs(residual) > mpf(10) ** -40:
            raise SystemExit(f"p={p} g={g}: energy residual {nstr(residual, 3)} by odefun")
        report.append(("energy residual, odefun", abs(residual)))
        report.append(("digits, odefun vs Taylor", min(agreement(other[c], values[c])
                                                      for c in COLUMNS)))
    mp.dps = RUNS[-1][0]
    return values, report


def limit_checks():
    """Against closed forms, for each p: the elastic contact (A = 0), and the first order in A,
    1 - e = 2 A delta_u^(beta+1) B((beta+1)/(p+1), 3/2)/(p+1) + O(A^2) (the work of the damping
    along the elastic motion), at A = 1e-20. Returns the worst agreements, in digits."""
    elastic = slope = inf
    dps, order, tol_exponent = RUNS[-1]
    mp.dps = dps
    for p, beta, _ in CASES:
        P, B = mpf(p), mpf(beta)
        delta_u = ((P + 1) / 2) ** (1 / (P + 1))
        found, _ = sundman(p, beta, mpf(0), order, tol_exponent)
        tau = 2 * delta_u * beta_function(1 / (P + 1), mpf(1) / 2) / (P + 1)
        elastic = min(elastic, agreement(found["delta_max"], delta_u), agreement(found["e"], 1),
                      agreement(found["tau"], tau), agreement(found["t_peak"], tau / 2))
        A = mpf(10) ** -20
        found, _ = sundman(p, beta, A, order, tol_exponent)
        first = 2 * delta_u ** (B + 1) * beta_function((B + 1) / (P + 1), mpf(3) / 2) / (P + 1)
        slope = min(slope, agreement((1 - found["e"]) / A, first))
    return elastic, slope


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n\n")[0])
    parser.add_argument("--quick", action="store_true",
                        help="without the second method (mpmath.odefun): 3/4 of the time")
    parser.add_argument("-j", type=int, default=1, help="processes")
    options = parser.parse_args()
    start = time.time()
    jobs = [(p, beta, g, not options.quick) for p, beta, groups in CASES for g in groups]
    if options.j > 1:
        from multiprocessing import Pool
        with Pool(options.j) as pool:
            results = pool.map(row, jobs, chunksize=1)
    else:
        results = [row(job) for job in jobs]
    worst = {}
    failed = False
    for (p, beta, g, _), (values, report) in zip(jobs, results):
        print(f"p={p} beta={beta} g={g}: " + ", ".join(f"{name} {nstr(x, 3)}"
                                                      for name, x in report), file=sys.stderr)
        for name, x in report:
            if name.startswith("digits"):
                worst[name] = min(worst.get(name, inf), x)
                failed |= x < REQUIRED
            else:
                worst[name] = max(worst.get(name, 0), x)
    elastic, slope = limit_checks()
    worst["digits, elastic (A = 0) vs closed form"] = elastic
    worst["digits, (1 - e)/A at A = 1e-20 vs closed form"] = slope
    failed |= elastic < REQUIRED or slope < 19
    for name, x in worst.items():
        print(f"worst {name}: {nstr(x, 3)}", file=sys.stderr)
    print(f"{time.time() - start:.0f} s", file=sys.stderr)
    if failed:
        raise SystemExit(f"fewer than {REQUIRED} digits agree")
    mp.dps = RUNS[-1][0]
    print(f"# generated by data/reference/viscoelastic.py (mpmath, {RUNS[-1][0]} digits, "
          f"printed to {DIGITS}); d'' + A d^beta d' + d^p = 0, d(0) = 0, d'(0) = 1")
    print("p,beta,group," + ",".join(COLUMNS))
    for (p, beta, g, _), (values, _) in zip(jobs, results):
        print(f"{p},{beta},{g}," + ",".join(nstr(values[c], DIGITS) for c in COLUMNS))


if __name__ == "__main__":
    main()

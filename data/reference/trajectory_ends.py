#!/usr/bin/env python3
"""delta(t) and v(t) at the extreme times t = 2^n, from n = -(2^31 - 400) (near the smallest
cpp_bin_float_50) to 2^31 - 400, by mpmath at 80 digits and independently of pldamp's C++ code
(docs/MATH.md §3 "Time-domain solution"): no series at either end, no matched constant.

The contact is solved through the map of §2: delta = A (L xi)^q, v = v0 e^(-z s)(C - z S) with
s = Omega0 times the map's parameter, xi = e^(-z s) S, and the time t = T I(s),
I(s) = int_0^s xi^nu. I is taken
  - by tanh-sinh quadrature (mpmath.quad) in w = (s'/s)^q, where the integrand (xi(s')/s')^nu is
    smooth, whenever s < 1 or the contact returns;
  - in closed form once s >= 1 when it never returns (alpha_eff >= 1): critically damped,
    int_0^s u^nu e^(kappa u) du = s^q/q 1F1(q; q + 1; kappa s) (kappa = 1 - q); overdamped, with
    w = e^(-2 r u), r = sqrt(alpha_eff^2 - 1), lambda = alpha_eff - r and kappa = -nu lambda,
    I = (2r)^(-q) B(-kappa/(2r), q; w from e^(-2 r s) to 1), the incomplete Beta function continued
    to a negative first parameter (mpmath.betainc). Both are checked against the quadrature at
    s = 1/2, 3 and 20 before any row is written.
s(t) solves ln I(s) = ln(t/T) by Newton's method inside a bracket. An underdamped contact whose
t is past tau (tau by quadrature of I over the whole contact) is in its exit state: delta = 0,
v = -v0 e^(-pi z/sqrt(1 - z^2)), the closed form of e being x' at the end of the map's half period.

Each row also has the condition numbers d ln delta/d ln t = t v/delta and
d ln|v|/d ln t = t v'/v, with v' = -(alpha Omega0 delta^((p-1)/2) v + Omega0^2 delta^p) from the
equation of motion itself: the error a computation in a type of epsilon eps can be asked for is
eps times the larger of 1 and these. Writes trajectory_ends.csv beside itself (a few minutes):

    /usr/bin/python3 data/reference/trajectory_ends.py
"""
import os
from decimal import Decimal

from mpmath import (betainc, cos, cosh, exp, hyp1f1, inf, ldexp, log, mp, mpf, nstr, pi, quad,
                    sin, sinh, sqrt)

mp.dps = 80

P_VALUES = ["1", "1.5", "2", "3", "5"]
# 1 + 1e-6 as the double nearest it, written out exactly: every precision reads the same number
# (near critical damping μ = 1 − z² is 2e−6, and a rounding of z by 1e−34 would move it by 1e−28).
Z_VALUES = ["0.5", "1", str(Decimal(1 + 1e-6)), "2", "10"]
# (v0, m, k): unit scales for every (p, alpha_eff); one other set, exact in binary, for a few.
SCALES = [("1", "1", "1"), ("4", "0.5", "2")]
# t = 2^n. Small: through double's switch to the onset series (about 2^-4 to 2^-40 by type),
# double's smallest normal and subnormal (2^-1022, 2^-1074), long double's and float128's
# (2^-16382, 2^-16445, 2^-16494), and on to near cpp_bin_float_50's smallest (2^-2147483312).
SMALL = [-1, -3, -6, -10, -14, -20, -28, -40, -64, -128, -1022, -1074, -16382, -16445, -16494,
         -2**20, -2**30, -(2**31 - 400)]
# Large, when the contact never returns: through the switch to the late form (2^20 to 2^400 by
# type and damping), 1e10, 1e100, 1e300, double's largest power of 2, long double's and float128's
# (2^16383), and on to near cpp_bin_float_50's largest.
LARGE = [1, 4, 8, 16, 24, 33, 48, 64, 96, 128, 192, 332, 512, 997, 1023, 16383, 2**20, 2**26,
         2**30, 2**31 - 400]
# The scaled set: a few of each.
SCALED_TIMES = [-3, -40, -1074, -16445, 4, 64, 997, 16383]


class Contact:
    def __init__(self, p, z, v0, m, k):
        self.p, self.z = mpf(p), mpf(z)
        self.v0, self.m, self.k = mpf(v0), mpf(m), mpf(k)
        p, z = self.p, self.z
        self.q = 2 / (p + 1)
        self.nu = self.q - 1
        self.mu = 1 - z * z
        self.A = ((p + 1) / 2) ** (1 / (p + 1))
        self.omega0 = sqrt(self.k / self.m)
        self.L = self.v0 / self.omega0
        self.T = self.A * self.q * self.L ** self.nu / self.omega0
        self.alpha = z * sqrt(2 * (p + 1))
        if self.mu > 0:
            self.s_end = pi / sqrt(self.mu)
            self.I_end = quad(lambda s: self.xi(s) ** self.nu, [0, self.s_end / 2, self.s_end])
        else:
            self.s_end = inf
            self.r = sqrt(-self.mu)
            self.lam = z - self.r
            self.kappa = -self.nu * self.lam

    def S(self, s):  # sin(sqrt(mu) s)/sqrt(mu), continued
        if self.mu > 0:
            return sin(sqrt(self.mu) * s) / sqrt(self.mu)
        if self.mu == 0:
            return s
        return sinh(self.r * s) / self.r

    def C(self, s):
        if self.mu > 0:
            return cos(sqrt(self.mu) * s)
        if self.mu == 0:
            return mpf(1)
        return cosh(self.r * s)

    def xi(self, s):
        return exp(-self.z * s) * self.S(s)

    def I_quadrature(self, s):
        if self.nu == 0:
            return s
        integrand = lambda w: (self.xi(s * w ** (1 / self.q)) / (s * w ** (1 / self.q))) ** self.nu
        return s ** self.q / self.q * quad(integrand, [0, 1])

    def I_closed(self, s):
        q = self.q
        if self.mu == 0:
            return s ** q / q * hyp1f1(q, q + 1, self.kappa * s)
        beta = self.kappa / (2 * self.r)
        return (2 * self.r) ** (-q) * betainc(-beta, q, exp(-2 * self.r * s), 1)

    def I(self, s):
        if self.nu == 0:
            return s
        if self.mu <= 0 and s >= 1:
            return self.I_closed(s)
        return self.I_quadrature(s)

    def solve(self, log_theta):
        """s with ln I(s) = log_theta, by Newton inside a bracket."""
        if self.nu == 0:
            return exp(log_theta)
        f = lambda s: log(self.I(s)) - log_theta
        if self.mu <= 0 and log_theta > 0:
            guess = log_theta / self.kappa  # I ~ e^(kappa s) late
        else:
            guess = exp((log_theta + log(self.q)) / self.q)  # I ~ s^q/q near 0
        if self.mu > 0:
            guess = min(guess, self.s_end / 2)
        lo = hi = guess
        if f(guess) < 0:
            while f(hi) < 0:
                lo, hi = hi, (hi * 2 if self.mu <= 0 else min(hi * 2, (hi + self.s_end) / 2))
        else:
            while f(lo) > 0:
                hi, lo = lo, lo / 2
        s = guess
        for _ in range(400):
            value = f(s)
            if value < 0:
                lo = s
            else:
                hi = s
            step = value * self.I(s) / self.xi(s) ** self.nu
            following = s - step
            if not lo < following < hi:
                following = (lo + hi) / 2
            if abs(following - s) <= mpf(10) ** -70 * s:
                return following
            s = following
        raise RuntimeError("Newton did not converge")

    def state(self, n):
        """(delta, v, d ln delta/d ln t, d ln|v|/d ln t) at t = 2^n."""
        t = ldexp(mpf(1), n)
        log_theta = log(t) - log(self.T)
        if self.mu > 0 and log_theta >= log(self.I_end):
            return mpf(0), -self.v0 * exp(-pi * self.z / sqrt(self.mu)), mpf(0), mpf(0)
        s = self.solve(log_theta)
        if self.nu == 0 and self.mu <= 0 and self.lam * s > 2**33:
            # p = 1 far into its decay: delta ~ e^(-lambda s) is below 2^(-10^10), under every
            # type's range (and e^(-s) itself would take mpmath a Python integer of that size),
            # as is v; both condition numbers are -lambda s to all digits printed.
            return mpf(0), mpf(0), -self.lam * s, -self.lam * s
        xi = self.xi(s)
        delta = self.A * (self.L * xi) ** self.q
        v = self.v0 * exp(-self.z * s) * (self.C(s) - self.z * self.S(s))
        acceleration = -(self.alpha * self.omega0 * delta ** ((self.p - 1) / 2) * v +
                         self.omega0 ** 2 * delta ** self.p)
        return delta, v, t * v / delta, t * acceleration / v


def digits(value):
    """55 significant digits; 0 below 2^-2147483400, where every type, cpp_bin_float_50 included,
    underflows (p = 1 decays as e^(-lambda Omega0 t))."""
    if value != 0 and mp.mag(value) < -2147483400:
        return "0"
    return nstr(value, 55, strip_zeros=False)


def check_closed_forms():
    for p in P_VALUES[1:]:
        for z in Z_VALUES[1:]:
            c = Contact(p, z, "1", "1", "1")
            for s in [mpf(1) / 2, mpf(3), mpf(20)]:
                error = abs(c.I_closed(s) / c.I_quadrature(s) - 1)
                assert error < mpf(10) ** -65, (p, z, s, error)


def rows():
    for v0, m, k in SCALES:
        scaled = (v0, m, k) != ("1", "1", "1")
        for p in P_VALUES:
            for z in Z_VALUES:
                if scaled and (p not in ("1.5", "3") or z not in ("0.5", "1", "2")):
                    continue
                c = Contact(p, z, v0, m, k)
                times = SCALED_TIMES if scaled else SMALL + (LARGE if c.mu <= 0 else [1023])
                for n in times:
                    delta, v, cond_delta, cond_v = c.state(n)
                    yield [p, z, v0, m, k, str(n), digits(delta), digits(v),
                           nstr(cond_delta, 6), nstr(cond_v, 6)]


def main():
    check_closed_forms()
    here = os.path.dirname(os.path.abspath(__file__))
    temporary = os.path.join(here, "trajectory_ends.csv.tmp")
    with open(temporary, "w") as out:
        out.write("# generated by data/reference/trajectory_ends.py (mpmath, 80 digits, printed to "
                  "55); t = 2^log2_t\n")
        out.write("p,alpha_eff,v0,m,k,log2_t,delta,v,cond_delta,cond_v\n")
        for row in rows():
            out.write(",".join(row) + "\n")
            out.flush()
    os.replace(temporary, os.path.join(here, "trajectory_ends.csv"))


if __name__ == "__main__":
    main()

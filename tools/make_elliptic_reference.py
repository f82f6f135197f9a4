#!/usr/bin/python3
"""Writes tests/math/elliptic_reference.inc: 40-digit reference values of the Jacobi
elliptic functions sn, cn, dn, of K, and of the incomplete integrals F and Pi, all
parameterised by the complementary parameter mc = 1 - m (docs/design.md section 2.3).

Every argument is a double; mpmath evaluates at that exact binary value (mpf(float) is
exact), with 60 working digits, and each value is checked against a second evaluation at
80 digits before it is written (agreement to 40 digits or the script fails). A sample of
the sn, cn, dn rows is also checked against an independent route, the inversion of the
incomplete integral F(phi|m) = u by bracketed root finding (agreement to 1e-18 relative or
the script fails), so that an error in mpmath's ellipfun near m = 1 cannot go unnoticed.

Usage (from the repository root):  /usr/bin/python3 tools/make_elliptic_reference.py

With --free-body it instead (re)writes the generated block of multiprecision free-body
trajectories in tests/analysis/free_body_solution_test.cpp: Euler's equations and the
quaternion kinematics integrated from the exact double initial data with mpmath's Taylor
integrator (odefun) at two precisions (30 and 38 digits) that must agree to 1e-20. These
check analysis::FreeBodySolution near and on the separatrix, where a double or long
double integrator cannot resolve 1 - k^2 (takes a few minutes).
"""

import os
import random
import sys

import mpmath
from mpmath import mp, mpf

OUT = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests", "math",
                   "elliptic_reference.inc")

# Complementary parameters from 1 (m = 0, circular functions) to 1e-16 and 0 (m = 1,
# hyperbolic functions). 6.6492854004460934e-6 is the wing nut of docs/design.md section 6.
MC_VALUES = [1.0, 0.9, 0.5, 0.1, 1e-2, 1e-3, 1e-4, 6.6492854004460934e-6, 6.6e-6, 1e-6,
             1e-8, 1e-10, 1e-12, 1e-14, 1e-16, 0.0]

# Arguments as multiples of K (periodic cases): zeros, symmetric points, near the
# quarter period from both sides, and far out (hundreds of K) for the argument reduction.
K_MULTIPLES = [1e-12, 1e-6, 1e-3, 0.1, 0.25, 0.5, 0.75, 0.9, 1.0 - 1e-9, 1.0, 1.0 + 1e-7,
               1.3, 1.999, 2.0, 2.5, 3.0, 3.7, -0.4, -1.2, -2.9, 10.3, 41.0, 101.7, 250.05,
               -300.3]
# Arguments for mc = 0 (sn = tanh, cn = dn = sech).
HYPERBOLIC_U = [1e-9, 0.5, 1.0, 5.0, 20.0, 37.0, -3.0, -40.0, 300.0]

CHECK_DIGITS = 40


def mpv(f, dps):
    with mpmath.workdps(dps):
        return f()


def checked(f):
    """f() at 60 and at 80 digits; fails unless they agree to CHECK_DIGITS digits."""
    a = mpv(f, 60)
    b = mpv(f, 80)
    with mpmath.workdps(80):
        scale = max(abs(b), mpf(10) ** -300)
        if abs(a - b) > scale * mpf(10) ** -CHECK_DIGITS:
            sys.exit("reference value not converged: %s vs %s" % (a, b))
    return b


def dstr(x):
    """Shortest repr that rounds back: 17 significant digits, exponent form."""
    with mpmath.workdps(80):
        if mpmath.isinf(x):
            return "kInf"
        return mpmath.nstr(x, 20, min_fixed=1, max_fixed=0, strip_zeros=False) \
            .replace("e+", "e")


def jacobi_row(u, mc, crosscheck):
    def fn(name):
        return lambda: mpmath.ellipfun(name, mpf(u), m=1 - mpf(mc))
    sn, cn, dn = checked(fn("sn")), checked(fn("cn")), checked(fn("dn"))
    if crosscheck:
        crosscheck_by_inversion(u, mc, sn, cn, dn)
    if mc == 0.0:
        k = mpmath.inf
    else:
        k = checked(lambda: mpmath.ellipk(1 - mpf(mc)))
    return "  {%s, %s, %s, %s, %s, %s}," % (repr(u), repr(mc), dstr(sn), dstr(cn), dstr(dn),
                                            dstr(k))


def crosscheck_by_inversion(u, mc, sn, cn, dn):
    """sn, cn, dn from am(u) found by root finding on F(phi|m) = u; fails on disagreement."""
    with mpmath.workdps(60):
        u, mc = mpf(u), mpf(mc)
        m = 1 - mc
        if mc == 0:
            s, c, d = mpmath.tanh(u), mpmath.sech(u), mpmath.sech(u)
        else:
            k = mpmath.ellipk(m)
            r = u - 4 * k * mpmath.nint(u / (4 * k))  # |r| <= 2K
            sign = -1 if r < 0 else 1
            r = abs(r)
            past_quarter = r > k  # sn(2K - r) = sn(r), cn(2K - r) = -cn(r)
            r = 2 * k - r if past_quarter else r
            phi = mpf(0)
            if r > 0:
                phi = mpmath.findroot(lambda p: mpmath.ellipf(p, m) - r, (mpf(0), mpmath.pi / 2),
                                      solver="anderson")
            s = sign * mpmath.sin(phi)
            c = -mpmath.cos(phi) if past_quarter else mpmath.cos(phi)
            d = mpmath.sqrt(1 - m * mpmath.sin(phi) ** 2)
        for a, b in ((s, sn), (c, cn), (d, dn)):
            if abs(a - b) > mpf(10) ** -18 * max(abs(a), mpf(10) ** -300):
                sys.exit("cross-check failed at u=%r mc=%r: %s vs %s" % (u, mc, a, b))


def main():
    rng = random.Random(20240611)
    rows = []
    for mc in MC_VALUES:
        if mc == 0.0:
            us = HYPERBOLIC_U
        else:
            with mpmath.workdps(60):
                k = float(mpmath.ellipk(1 - mpf(mc)))
            us = [f * k for f in K_MULTIPLES] + [rng.uniform(-4 * k, 4 * k) for _ in range(4)]
        for i, u in enumerate(us):
            rows.append(jacobi_row(float(u), mc, crosscheck=(i % 3 == 0)))

    k_rows = []
    for mc in MC_VALUES + [0.25, 3e-5, 1e-20, 1e-100]:
        if mc == 0.0:
            continue
        k = checked(lambda: mpmath.ellipk(1 - mpf(mc)))
        k_rows.append("  {%s, %s}," % (repr(mc), dstr(k)))

    # Incomplete integrals F(phi|m) and Pi(n; phi|m) (mpmath's n is the characteristic of
    # 1/(1 - n sin^2)), |phi| <= pi/2, n < 1.
    fp_rows = []
    for mc in [1.0, 0.5, 1e-3, 6.6492854004460934e-6, 1e-12, 1e-16, 0.0]:
        for phi in [0.3, 1.2, 1.5707963267948966 - 1e-7, -0.8, 1.5707963]:
            for n in [-3.0, -0.25, 0.0, 0.6]:
                fv = checked(lambda: mpmath.ellipf(mpf(phi), 1 - mpf(mc)))
                pv = checked(lambda: mpmath.ellippi(mpf(n), mpf(phi), 1 - mpf(mc)))
                fp_rows.append("  {%s, %s, %s, %s, %s}," % (repr(n), repr(phi), repr(mc),
                                                           dstr(fv), dstr(pv)))
    pc_rows = []
    for mc in [1.0, 0.5, 1e-3, 6.6492854004460934e-6, 1e-12]:
        for n in [-3.0, -0.25, 0.0, 0.6]:
            pv = checked(lambda: mpmath.ellippi(mpf(n), 1 - mpf(mc)))
            pc_rows.append("  {%s, %s, %s}," % (repr(n), repr(mc), dstr(pv)))

    with open(OUT, "w") as f:
        f.write("// Generated by tools/make_elliptic_reference.py (mpmath %s, checked to %d "
                "digits).\n// Do not edit; rerun the script. Values at the exact binary "
                "arguments.\n\n" % (mpmath.__version__, CHECK_DIGITS))
        f.write("constexpr double kInf = std::numeric_limits<double>::infinity();\n\n")
        f.write("/// u, mc, sn(u|m), cn(u|m), dn(u|m), K(m), m = 1 - mc.\n")
        f.write("struct JacobiReference {\n  double u, mc, sn, cn, dn, K;\n};\n")
        f.write("constexpr JacobiReference kJacobiReference[] = {\n")
        f.write("\n".join(rows) + "\n};\n\n")
        f.write("/// mc, K(m).\nstruct KReference {\n  double mc, K;\n};\n")
        f.write("constexpr KReference kKReference[] = {\n" + "\n".join(k_rows) + "\n};\n\n")
        f.write("/// n, phi, mc, F(phi|m), Pi(n; phi|m).\n")
        f.write("struct IncompleteReference {\n  double n, phi, mc, F, Pi;\n};\n")
        f.write("constexpr IncompleteReference kIncompleteReference[] = {\n" +
                "\n".join(fp_rows) + "\n};\n\n")
        f.write("/// n, mc, Pi(n|m).\nstruct CompletePiReference {\n  double n, mc, Pi;\n};\n")
        f.write("constexpr CompletePiReference kCompletePiReference[] = {\n" +
                "\n".join(pc_rows) + "\n};\n")
    print("wrote %d Jacobi rows, %d K rows, %d incomplete rows, %d complete Pi rows to %s"
          % (len(rows), len(k_rows), len(fp_rows), len(pc_rows), os.path.normpath(OUT)))


# Free-body cases: body-frame diagonal J (axes deliberately not in ascending order),
# H_B(t0), q_NB(t0) as (w, x, y, z), t0, and the sample times as fractions of the period
# (periodic) or as multiples of 1/lambda (separatrix); see tests/analysis.
FREE_BODY_CASES = [
    ("near intermediate axis, 1-k^2 ~ 2e-12", (3.5, 2.0, 3.0), (13e-6, 10e-6, 10.0),
     (1.0, 0.0, 0.0, 0.0)),
    ("near intermediate axis, major side, 1-k^2 ~ 4e-15", (3.5, 2.0, 3.0), (3e-7, 1e-7, -10.0),
     (0.5, 0.5, -0.5, 0.5)),
    ("far from the axis (cancellation), 1-k^2 ~ 1e-10", (3.5, 2.0, 3.0), (5.0, 2.67261241929, 3.0),
     (0.0, 0.6, 0.8, 0.0)),
    ("on the separatrix, opposite signs", (6.0, 3.0, 4.0), (-0.5, 0.5, -0.75),
     (0.8, 0.0, -0.6, 0.0)),
    ("generic, minor-axis circulation", (1.0, 2.5, 2.0), (0.3, -0.5, 0.8),
     (0.9, 0.1, -0.3, 0.2)),
]
FREE_BODY_T0 = 0.25
PERIOD_FRACTIONS = [0.13, 0.5, 0.77, 1.0]
SEPARATRIX_LAMBDA_TIMES = [3.0, 8.0, 14.0]
FREE_BODY_TEST = os.path.join(os.path.dirname(os.path.abspath(__file__)), "..", "tests",
                              "analysis", "free_body_solution_test.cpp")
BEGIN_MARK = "// BEGIN generated by tools/make_elliptic_reference.py --free-body"
END_MARK = "// END generated"


def free_body_times(J, H):
    """Sample times from the principal invariants (only to choose where to look)."""
    with mpmath.workdps(40):
        order = sorted(range(3), key=lambda i: J[i])
        I1, I2, I3 = [mpf(J[i]) for i in order]
        h1, h2, h3 = [mpf(H[i]) for i in order]
        P1 = h2 ** 2 * (I2 - I1) / I2 + h3 ** 2 * (I3 - I1) / I3
        P3 = h1 ** 2 * (I3 - I1) / I1 + h2 ** 2 * (I3 - I2) / I2
        P2 = h1 ** 2 * (I2 - I1) / I1 - h3 ** 2 * (I3 - I2) / I3
        if P2 == 0:
            lam = mpmath.sqrt((I2 - I1) * P3 / (I1 * I2 * I3))
            return [FREE_BODY_T0 + float(x / lam) for x in SEPARATRIX_LAMBDA_TIMES]
        if P2 > 0:
            mc = (I3 - I1) * P2 / ((I2 - I1) * P3)
            lam = mpmath.sqrt((I2 - I1) * P3 / (I1 * I2 * I3))
        else:
            mc = (I3 - I1) * (-P2) / ((I3 - I2) * P1)
            lam = mpmath.sqrt((I3 - I2) * P1 / (I1 * I2 * I3))
        period = 4 * mpmath.ellipk(1 - mc) / lam
        return [FREE_BODY_T0 + float(f * period) for f in PERIOD_FRACTIONS]


def integrate_free_body(J, H, q, times, dps, tol_digits, degree):
    with mpmath.workdps(dps):
        Jm = [mpf(x) for x in J]
        qn = mpmath.sqrt(sum(mpf(x) ** 2 for x in q))
        y0 = [mpf(x) for x in H] + [mpf(x) / qn for x in q]

        def f(t, y):
            w = [y[i] / Jm[i] for i in range(3)]
            qw, qx, qy, qz = y[3:]
            return [y[1] * w[2] - y[2] * w[1], y[2] * w[0] - y[0] * w[2],
                    y[0] * w[1] - y[1] * w[0],
                    -(qx * w[0] + qy * w[1] + qz * w[2]) / 2,
                    (qw * w[0] + qy * w[2] - qz * w[1]) / 2,
                    (qw * w[1] + qz * w[0] - qx * w[2]) / 2,
                    (qw * w[2] + qx * w[1] - qy * w[0]) / 2]

        sol = mpmath.odefun(f, mpf(FREE_BODY_T0), y0, tol=mpf(10) ** -tol_digits,
                            degree=degree)
        return [[+v for v in sol(mpf(t))] for t in times]


def free_body_main():
    rows = []
    for name, J, H, q in FREE_BODY_CASES:
        times = free_body_times(J, H)
        lo = integrate_free_body(J, H, q, times, 30, 24, 20)
        hi = integrate_free_body(J, H, q, times, 38, 30, 26)
        with mpmath.workdps(40):
            for a_row, b_row in zip(lo, hi):
                for a, b in zip(a_row, b_row):
                    if abs(a - b) > mpf(10) ** -20 * max(1, abs(b)):
                        sys.exit("free body %r not converged: %s vs %s" % (name, a, b))
        for t, y in zip(times, hi):
            rows.append("    {\"%s\", {%r, %r, %r}, {%r, %r, %r}, {%r, %r, %r, %r}, %r, %r,\n"
                        "     {%s, %s, %s}, {%s, %s, %s, %s}}," % (
                            (name,) + tuple(J) + tuple(H) + tuple(q) + (FREE_BODY_T0, t) +
                            tuple(dstr(v) for v in y)))
        print("%s: done" % name)
    block = (BEGIN_MARK + "\n// (mpmath %s, 38 digits, checked against 30 digits to 1e-20). "
             "Do not edit; rerun the script.\n" % mpmath.__version__ + "// clang-format off\n" +
             "const MultiprecisionSample kMultiprecisionSamples[] = {\n" + "\n".join(rows) +
             "\n};\n// clang-format on\n" + END_MARK)
    with open(FREE_BODY_TEST) as f:
        text = f.read()
    begin = text.index(BEGIN_MARK)
    end = text.index(END_MARK) + len(END_MARK)
    with open(FREE_BODY_TEST, "w") as f:
        f.write(text[:begin] + block + text[end:])
    print("updated %s" % os.path.normpath(FREE_BODY_TEST))


if __name__ == "__main__":
    if "--free-body" in sys.argv[1:]:
        free_body_main()
    else:
        main()

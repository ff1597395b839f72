#!/usr/bin/env python3
"""An oracle for the lattice rows that shares no code with nuld.

Usage: /usr/bin/python3 tools/experiments/lattice_oracle.py [quarterdisc|smooth|edges] [SEED]

Rank-1 lattices (i/N, frac(i g/N)) with a uniform toroidal shift, the
generator chosen by brute force (the longest shortest vector, smallest g on
ties; among g coprime with N, or among all g as nuld chose before
November 29, 2026), and the same shifted sets folded by the baker's
transform x -> 1 - |2x - 1|, against scipy's Owen-scrambled Sobol points:

  quarterdisc  the integration study's quarterdisc*bilinear: points through
               the quarter disc's Rosenblatt map, the bilinear's mean
               (256 randomizations), MSE over Sobol's at N = 16 .. 1024
  smooth       exp(x + y/2) on the square: RMS error of the shifted and the
               folded lattice over 3000 shifts (the C++ test's figures)
  edges        indicators of random half-planes (400 edges through the
               middle of the square, 64 randomizations each), MSE over
               Sobol's with the ratio's standard error over edges: the
               discontinuities of renders in miniature
"""
import math
import sys

import numpy as np
from scipy.stats import qmc


def shortest2(n, g):
    """Squared shortest vector of the lattice spanned by (1, g), (0, n)."""
    a, b = np.array([0, n]), np.array([1, g])
    if a @ a < b @ b:
        a, b = b, a
    while True:
        a = a - math.floor((a @ b) / (b @ b) + 0.5) * b
        if a @ a >= b @ b:
            return int(b @ b)
        a, b = b, a


def generator(n, coprime=True):
    gs = [g for g in range(1, n) if not coprime or math.gcd(g, n) == 1]
    return max(gs, key=lambda g: (shortest2(n, g), -g))


def lattice(n, g):
    i = np.arange(n)
    return np.stack([i / n, (i * g % n) / n], 1)


def fold(u):
    return 1 - np.abs(2 * u - 1)


def quarterdisc(rng):
    # x by the marginal's inverse CDF (tabulated finely), y uniform below the arc.
    xs = np.linspace(0, 1, 200001)
    cdf = (2 / np.pi) * (xs * np.sqrt(1 - xs**2) + np.arcsin(xs))
    a, b, c, d = 0.25, 1, 0.5, 2
    exact = a + 4 / math.pi * ((b + c) / 3 + d / 8)

    def estimate(u):
        x = np.interp(u[:, 0], cdf, xs)
        y = u[:, 1] * np.sqrt(np.maximum(0, 1 - x * x))
        return np.mean(a + b * x + c * y + d * x * y)

    print("N  g(old) g(coprime)  old/sobol  coprime/sobol  baker/sobol  (quarterdisc*bilinear MSE)")
    for n in (16, 64, 256, 1024):
        old, new = generator(n, False), generator(n, True)
        err = {"old": [], "coprime": [], "baker": [], "sobol": []}
        for _ in range(256):
            err["old"].append(estimate((lattice(n, old) + rng.random(2)) % 1) - exact)
            shifted = (lattice(n, new) + rng.random(2)) % 1
            err["coprime"].append(estimate(shifted) - exact)
            err["baker"].append(estimate(fold(shifted)) - exact)
            err["sobol"].append(estimate(qmc.Sobol(2, scramble=True, seed=rng).random(n)) - exact)
        mse = {k: np.mean(np.square(v)) for k, v in err.items()}
        print(f"{n:<4} {old:>5} {new:>6}   {mse['old'] / mse['sobol']:9.2f}  "
              f"{mse['coprime'] / mse['sobol']:13.2f}  {mse['baker'] / mse['sobol']:11.2f}")


def smooth(rng):
    exact = (math.e - 1) * 2 * (math.exp(0.5) - 1)
    print("N  g  rms(shifted)  rms(folded)  ratio  (exp(x + y/2))")
    for n in (16, 64, 144):
        g = generator(n)
        a, b = [], []
        for _ in range(3000):
            u = (lattice(n, g) + rng.random(2)) % 1
            a.append(np.mean(np.exp(u[:, 0] + u[:, 1] / 2)) - exact)
            f = fold(u)
            b.append(np.mean(np.exp(f[:, 0] + f[:, 1] / 2)) - exact)
        ra, rb = math.sqrt(np.mean(np.square(a))), math.sqrt(np.mean(np.square(b)))
        print(f"{n:<4} {g:>3} {ra:12.3g} {rb:12.3g} {ra / rb:6.1f}")


def edges(rng, count=400, randomizations=64):
    grid = (np.arange(2048) + 0.5) / 2048
    gx, gy = np.meshgrid(grid, grid)

    def ratio(a, b):
        q = a.mean() / b.mean()
        cov = np.cov(a, b) / len(a)
        var = cov[0, 0] / a.mean() ** 2 + cov[1, 1] / b.mean() ** 2 - 2 * cov[0, 1] / (a.mean() * b.mean())
        return q, q * math.sqrt(max(var, 0))

    print("N  g(old) g(coprime)  MSE over Sobol's, +- standard error (random half-planes)")
    for n in (16, 64, 256):
        old, new = generator(n, False), generator(n, True)
        mse = {k: np.zeros(count) for k in ("old", "coprime", "baker", "sobol")}
        for e in range(count):
            angle = rng.uniform(0, 2 * math.pi)
            normal = np.array([math.cos(angle), math.sin(angle)])
            offset = normal @ rng.uniform(0.2, 0.8, 2)
            exact = np.mean(normal[0] * gx + normal[1] * gy < offset)
            f = lambda p: np.mean(p @ normal < offset)  # noqa: E731
            for _ in range(randomizations):
                shifted = (lattice(n, new) + rng.random(2)) % 1
                mse["coprime"][e] += (f(shifted) - exact) ** 2
                mse["baker"][e] += (f(fold(shifted)) - exact) ** 2
                mse["old"][e] += (f((lattice(n, old) + rng.random(2)) % 1) - exact) ** 2
                mse["sobol"][e] += (f(qmc.Sobol(2, scramble=True, seed=rng).random(n)) - exact) ** 2
        cells = "  ".join("%s %.2f +- %.2f" % ((k,) + ratio(mse[k], mse["sobol"]))
                          for k in ("old", "coprime", "baker"))
        print(f"{n:<4} {old:>5} {new:>6}   {cells}")


if __name__ == "__main__":
    part = sys.argv[1] if len(sys.argv) > 1 else "quarterdisc"
    rng = np.random.default_rng(int(sys.argv[2]) if len(sys.argv) > 2 else 5)
    {"quarterdisc": quarterdisc, "smooth": smooth, "edges": edges}[part](rng)

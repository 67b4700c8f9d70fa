#!/usr/bin/env python3
"""The DEM's scatter of one run at the truth, estimated from the grid, against the 200
runs made at the truth itself (studies/quick/README.md, trial F).

The grid (doe.csv, 5 x 5 x 4) gives each point's replicate variance; the rules below turn
those into a scatter at the truth (0.25, 0.45). truth_runs.csv (200 runs at the truth, kept
out of the grid) gives the scatter there directly, to about +-10 % at 95 % (199 dof).

  pooled      today's sigma_dem: sum of squares over all points / their dof
  kernel h    calibrate/scatter_budget.hpp's local_replicate_scatter (Gaussian weights of
              width h in bound-scaled units; the diagnosis uses h = 0.35)
  log-linear  surrogate/scatter_trend.hpp's model (gamma GLM, log link), evaluated at the
              truth
  log-quad    the same with squares and the cross term (seen after the others; not used)

Standard library only. Usage: python3 studies/sandglass-recovery-lined/scatter_at_truth.py
[--study DIR] [--truth MU_R,MU_S]
"""

import argparse
import csv
import math
import pathlib
import statistics

BOX = {"mu_r": (0.05, 0.6), "mu_s": (0.2, 0.9)}
OBSERVABLES = ("discharge_time_s", "angle_of_repose_deg")


def unit(mu_r, mu_s):
    return [(mu_r - BOX["mu_r"][0]) / (BOX["mu_r"][1] - BOX["mu_r"][0]),
            (mu_s - BOX["mu_s"][0]) / (BOX["mu_s"][1] - BOX["mu_s"][0])]


def number(text):
    try:
        v = float(text)
    except ValueError:
        return None
    return None if math.isnan(v) else v


def solve(a, b):
    """Gaussian elimination with partial pivoting (a is small and well conditioned)."""
    n = len(b)
    m = [row[:] + [b[i]] for i, row in enumerate(a)]
    for c in range(n):
        p = max(range(c, n), key=lambda r: abs(m[r][c]))
        m[c], m[p] = m[p], m[c]
        for r in range(c + 1, n):
            f = m[r][c] / m[c][c]
            for k in range(c, n + 1):
                m[r][k] -= f * m[c][k]
    x = [0.0] * n
    for r in reversed(range(n)):
        x[r] = (m[r][n] - sum(m[r][k] * x[k] for k in range(r + 1, n))) / m[r][r]
    return x


def gamma_glm_sd(features, variances, dofs, at):
    """log sigma^2 = b . f by Fisher scoring (weights nu/2); the fitted sd at `at`."""
    pooled = sum(v * d for v, d in zip(variances, dofs)) / sum(dofs)
    b = [math.log(pooled)] + [0.0] * (len(features[0]) - 1)
    for _ in range(100):
        a = [[0.0] * len(b) for _ in b]
        rhs = [0.0] * len(b)
        for f, v, d in zip(features, variances, dofs):
            eta = sum(bi * fi for bi, fi in zip(b, f))
            z = eta + (v - math.exp(eta)) / math.exp(eta)
            for i in range(len(b)):
                rhs[i] += d / 2 * f[i] * z
                for j in range(len(b)):
                    a[i][j] += d / 2 * f[i] * f[j]
        b = solve(a, rhs)
    return math.sqrt(math.exp(sum(bi * fi for bi, fi in zip(b, at))))


def main():
    here = pathlib.Path(__file__).resolve().parent
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--study", type=pathlib.Path, default=here)
    parser.add_argument("--truth", default="0.25,0.45")
    args = parser.parse_args()
    truth = [float(v) for v in args.truth.split(",")]
    ut = unit(*truth)
    with open(args.study / "doe.csv", newline="") as f:
        grid = list(csv.DictReader(f))
    with open(args.study / "truth_runs.csv", newline="") as f:
        at_truth = list(csv.DictReader(f))
    print(f"scatter of one run at (mu_r, mu_s) = ({truth[0]}, {truth[1]}), {args.study.name}")
    for obs in OBSERVABLES:
        points = {}
        for row in grid:
            v = number(row[obs])
            if v is not None:
                points.setdefault(row["point"], (float(row["mu_r"]), float(row["mu_s"]), []))[2].append(v)
        u, var, dof = [], [], []
        for mu_r, mu_s, values in points.values():
            if len(values) > 1:
                u.append(unit(mu_r, mu_s))
                var.append(statistics.variance(values))
                dof.append(len(values) - 1)
        rules = {"pooled": math.sqrt(sum(v * d for v, d in zip(var, dof)) / sum(dof))}
        for h in (0.2, 0.35, 0.5):
            w = [math.exp(-((p[0] - ut[0]) ** 2 + (p[1] - ut[1]) ** 2) / (2 * h * h)) for p in u]
            rules[f"kernel {h}"] = math.sqrt(sum(wi * v * d for wi, v, d in zip(w, var, dof))
                                             / sum(wi * d for wi, d in zip(w, dof)))
        linear = [[1.0, p[0], p[1]] for p in u]
        rules["log-linear"] = gamma_glm_sd(linear, var, dof, [1.0, ut[0], ut[1]])
        quadratic = [[1.0, p[0], p[1], p[0] ** 2, p[1] ** 2, p[0] * p[1]] for p in u]
        rules["log-quadratic"] = gamma_glm_sd(
            quadratic, var, dof, [1.0, ut[0], ut[1], ut[0] ** 2, ut[1] ** 2, ut[0] * ut[1]])
        runs = [v for v in (number(r[obs]) for r in at_truth) if v is not None]
        direct = statistics.stdev(runs)
        print(f"  {obs}: {len(runs)} runs at the truth: sd {direct:.4g}")
        for name, sd in rules.items():
            print(f"    {name:14s} {sd:.4g}  ({100 * (sd / direct - 1):+.0f} %, log ratio "
                  f"{math.log(sd / direct):+.2f})")


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""Where a candidate's evidence goes: the terms of its log Bayes factor over the base model
and over the generic discrepancy, from one diagnosis.json (issue 19, "where the candidates
lose their evidence").

    python3 tests/concealed/evidence_breakdown.py OUT/<study>/reports/diagnosis/diagnosis.json

Every model's Laplace evidence (calibrate/model_evidence.hpp) is

    log Z = log L(theta_hat) + log prior density + Occam,
    log L = -chi^2/2 - sum_i log sigma_total_i - (n/2) log 2 pi,

so, for a candidate c against the base model b (same targets, n of them),

    log B_cb = -(chi2_c - chi2_b)/2               the fit gained
               - sum_i log(sigma_c,i / sigma_b,i)  the normalisation: each target's total sd
                                                   at the candidate's fit against the base's
                                                   (DEM scatter, surrogate variance there)
               + (log prior_c - log prior_b)       the candidate parameter's prior range
               + (Occam_c - Occam_b)               the posterior's width, the bound terms

with Occam = log Z - log L - log prior (what is left once the others are taken out). The
discrepancy's evidence is formed at the base fit with the base's sigma_total
(docs/model_discrepancy.md), so log B_cD = log B_cb - (log Z_D - log Z_b), and the
normalisation term is the part of the candidate's deficit that is its surrogates' and its
local scatter's, not the physics'. Standard library only.
"""
import json
import math
import sys


def sigma_total(calibration):
    return calibration["minima"][0]["sigma_total"]


def label(t):
    return f"{t['setup']} {t['observable']}"


def breakdown(path):
    d = json.load(open(path))
    base = d["base"]
    be = d["base_evidence"]
    disc = (d.get("discrepancy_judgement") or {}).get("discrepancy") or {}
    log_z_disc = (disc.get("evidence") or {}).get("log_evidence")
    sb = sigma_total(base)
    n = len(sb)
    log_l_b = -0.5 * be["chi_square_min"] - sum(math.log(s) for s in sb) - 0.5 * n * math.log(2 * math.pi)
    occam_b = be["log_evidence"] - log_l_b - be["log_prior_density"]
    print(f"{path}")
    print(f"  outcome {d.get('outcome')}, chosen {d.get('chosen')}; {n} targets")
    print(f"  base: chi2 {be['chi_square_min']:.2f}, log Z {be['log_evidence']:.2f} "
          f"(log L {log_l_b:.2f}, log prior {be['log_prior_density']:.2f}, Occam {occam_b:.2f})")
    if log_z_disc is not None:
        print(f"  discrepancy: log Z {log_z_disc:.2f} = base {be['log_evidence']:+.2f} "
              f"{log_z_disc - be['log_evidence']:+.2f} (bias amplitude {disc.get('bias_amplitude', float('nan')):.3g}, "
              f"process amplitude {disc.get('process_amplitude', float('nan')):.3g} sigma)")
    rows = []
    for f in d.get("fits") or []:
        e = f["evidence"]
        sc = sigma_total(f["calibration"])
        if len(sc) != n or e.get("log_evidence") is None:
            continue
        log_l_c = -0.5 * e["chi_square_min"] - sum(math.log(s) for s in sc) - 0.5 * n * math.log(2 * math.pi)
        occam_c = e["log_evidence"] - log_l_c - e["log_prior_density"]
        fit = -0.5 * (e["chi_square_min"] - be["chi_square_min"])
        norm = -sum(math.log(c / b) for c, b in zip(sc, sb))
        prior = e["log_prior_density"] - be["log_prior_density"]
        occam = occam_c - occam_b
        over_base = e["log_evidence"] - be["log_evidence"]
        over_disc = e["log_evidence"] - log_z_disc if log_z_disc is not None else float("nan")
        rows.append((f["name"], e["chi_square_min"], fit, norm, prior, occam, over_base, over_disc, sc))
    print("  candidate           chi2    fit   norm  prior  Occam | over base  over discrepancy")
    for name, chi2, fit, norm, prior, occam, ob, od, _ in sorted(rows, key=lambda r: -r[6]):
        print(f"  {name:16s} {chi2:7.2f} {fit:+6.2f} {norm:+6.2f} {prior:+6.2f} {occam:+6.2f} | "
              f"{ob:+9.2f}  {od:+9.2f}")
    if rows:
        best = max(rows, key=lambda r: r[6])
        fit = next(f for f in d["fits"] if f["name"] == best[0])
        print(f"  per target, sigma_total at the base's fit -> at {best[0]}'s (log ratio), and what "
              f"the latter is made of: sigma_total^2 = measured^2 + DEM scatter^2 + surrogate variance")
        for t, tc, c, b in zip(base["targets"], fit["calibration"]["targets"], best[8], sb):
            surrogate = max(c * c - tc["sigma_measured"] ** 2 - tc["sigma_dem"] ** 2, 0.0)
            print(f"    {label(t):45s} {b:10.4g} -> {c:10.4g}  {math.log(c / b):+6.2f}   "
                  f"measured {tc['sigma_measured']:.3g}, DEM {tc['sigma_dem']:.3g} (base {t['sigma_dem']:.3g}), "
                  f"surrogate sd {math.sqrt(surrogate):.3g}")


def main():
    if len(sys.argv) < 2:
        sys.exit(__doc__)
    for p in sys.argv[1:]:
        breakdown(p)


if __name__ == "__main__":
    main()

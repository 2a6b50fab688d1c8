#!/usr/bin/python3
"""Danger fraction vs number of boxes (paper Fig. "Results from Monte Carlo Simulation"), from the
CSV of icanc_montecarlo --csv (the paper model; its analytic column is the paper rule's P(D)).

    scripts/plot_montecarlo.py MC.csv OUT.png
"""
import csv
import math
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_montecarlo: {csv_path} has no rows")
    boxes = [int(r["boxes"]) for r in rows]
    mean = [float(r["mean_fraction"]) for r in rows]
    sd = [float(r["std_fraction"]) for r in rows]
    trials = [int(r["trials"]) for r in rows]
    analytic = float(rows[0]["analytic"])
    n_range = int(rows[0]["range"])
    alpha = float(rows[0]["reaction_time_s"])
    ci = [1.96 * s / math.sqrt(t) for s, t in zip(sd, trials)]
    overall = sum(mean) / len(mean)

    fig, (top, bottom) = plt.subplots(2, 1, figsize=(7.5, 6.2), sharex=True,
                                      gridspec_kw={"height_ratios": [2.2, 1]})
    top.errorbar(boxes, mean, yerr=ci, fmt="o", ms=3.5, color="tab:blue", ecolor="tab:blue",
                 elinewidth=0.8, capsize=0, label="simulated mean (95 % CI)")
    label = (f"analytic P(D) = 150/360 (1/2 + 1/(2n)) = {analytic:.4f}" if alpha == 1.0
             else f"analytic P(D) = {analytic:.4f} (alpha = {alpha:g})")
    top.axhline(analytic, color="tab:red", lw=1.6, label=label)
    top.axhline(overall, color="tab:green", lw=1.0, ls="--",
                label=f"mean of the {len(boxes)} averages = {overall:.4f}")
    # The paper's hypothesis (no dependence on the number of boxes): weighted least-squares slope
    # of the fraction on the box count, weights = boxes assessed (as icanc_montecarlo reports it).
    w = [b * t for b, t in zip(boxes, trials)]
    pooled = sum(wi * m for wi, m in zip(w, mean)) / sum(w)
    xw = sum(wi * b for wi, b in zip(w, boxes)) / sum(w)
    sxx = sum(wi * (b - xw) ** 2 for wi, b in zip(w, boxes))
    if sxx > 0:
        slope = sum(wi * (b - xw) * (m - pooled) for wi, b, m in zip(w, boxes, mean)) / sxx
        se = math.sqrt(pooled * (1 - pooled) / sxx)
        top.text(0.02, 0.04, f"slope {slope:+.1e} per box, 95 % CI [{slope - 1.96 * se:+.1e}, "
                 f"{slope + 1.96 * se:+.1e}]", transform=top.transAxes, fontsize=8.5)
    top.set_ylabel("fraction deemed dangerous")
    top.set_ylim(max(0.0, analytic - 0.06), analytic + 0.06)
    top.grid(True, alpha=0.3)
    top.legend(loc="upper right", fontsize=8.5)
    top.set_title(f"Monte Carlo (paper Algorithm 1): d, s ~ unif{{1..{n_range}}}, "
                  f"psi ~ unif{{1..360}}, {trials[0]} trials each", fontsize=10)

    theory = [math.sqrt(analytic * (1 - analytic) / b) for b in boxes]
    bottom.plot(boxes, sd, "o", ms=3, color="tab:blue", label="simulated")
    bottom.plot(boxes, theory, color="tab:red", lw=1.2, label="binomial sqrt(p(1-p)/boxes)")
    bottom.set_ylabel("sd of the per-frame\nfraction")
    bottom.set_xlabel("number of boxes in a frame")
    bottom.grid(True, alpha=0.3)
    bottom.legend(loc="upper right", fontsize=8.5)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])

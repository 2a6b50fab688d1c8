#!/usr/bin/python3
"""Headlight energy per lamp type and case (paper Fig. "Energy consumed in the worst case, average
case, and best case scenarios"), from icanc_energy --csv; optionally beside the energy of a
replayed run (icanc_energy --bag ... --csv).

    scripts/plot_energy.py ENERGY.csv OUT.png [ENERGY_BAG.csv]
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = ["tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown"]


def grouped_bars(ax, groups, series, values, fmt):
    """values[s][g]: one bar per series s in each group g, labelled with its value."""
    width = 0.8 / len(series)
    for s, name in enumerate(series):
        xs = [g + (s - (len(series) - 1) / 2) * width for g in range(len(groups))]
        bars = ax.bar(xs, values[s], width * 0.95, label=name, color=COLOURS[s % len(COLOURS)],
                      alpha=0.8)
        for bar, v in zip(bars, values[s]):
            ax.annotate(fmt(v), (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                        textcoords="offset points", xytext=(0, 2), ha="center", fontsize=7.5)
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(groups, fontsize=9)
    ax.grid(True, axis="y", alpha=0.3)


def main(csv_path, png_path, bag_csv=None):
    with open(csv_path) as f:
        rows = [r for r in csv.DictReader(f) if r["rounding"] == "paper"]
    if not rows:
        sys.exit(f"plot_energy: no rounding=paper rows in {csv_path}")
    lamps = list(dict.fromkeys(r["label"] for r in rows))
    wh = {(r["label"], r["case"]): float(r["wh"]) for r in rows}
    hours = {r["case"]: float(r["on_hours"]) for r in rows}
    beam = rows[0]["beam"]

    bag_rows = []
    if bag_csv:
        with open(bag_csv) as f:
            bag_rows = list(csv.DictReader(f))
    fig, axes = plt.subplots(1, 2 if bag_rows else 1, figsize=(11.5 if bag_rows else 7.5, 4.8),
                             gridspec_kw={"width_ratios": [1.5, 1]} if bag_rows else None)
    ax = axes[0] if bag_rows else axes
    fraction = float(rows[0]["danger_fraction"])
    cases = [("worst", "Worst case\n(always on)"),
             ("average", f"Average case\n(on {100 * fraction:.0f} % of the drive)"),
             ("best", "Best case\n(dangerous objects x tau)")]
    groups = [f"{label}\n{hours[c]:.3f} h" for c, label in cases]
    grouped_bars(ax, groups, lamps, [[wh[(l, c)] for c, _ in cases] for l in lamps],
                 lambda v: f"{v:.4g}")
    ax.set_ylabel("energy consumed (Wh)")
    ax.set_title(f"Paper's 22-minute drive, {beam} beam (numbers of its energy figure)", fontsize=10)
    ax.legend(title="headlight type", fontsize=8.5)

    if bag_rows:
        ax2 = axes[1]
        labels = [r["label"] for r in bag_rows]
        on = [float(r["wh"]) * 1000 for r in bag_rows]
        always = [float(r["wh_always_on"]) * 1000 for r in bag_rows]
        width = 0.38
        xs = range(len(labels))
        ax2.bar([x - width / 2 for x in xs], always, width, color="0.65", label="always on")
        ax2.bar([x + width / 2 for x in xs], on, width, color="tab:orange", label="ICanC (measured)")
        for x, a, o in zip(xs, always, on):
            ax2.annotate(f"{a:.3g}", (x - width / 2, a), textcoords="offset points", xytext=(0, 2),
                         ha="center", fontsize=7.5)
            ax2.annotate(f"{o:.3g}", (x + width / 2, o), textcoords="offset points", xytext=(0, 2),
                         ha="center", fontsize=7.5)
        ax2.set_xticks(list(xs))
        ax2.set_xticklabels(labels, fontsize=9)
        ax2.set_ylabel("energy (mWh)")
        r0 = bag_rows[0]
        ax2.set_title(f"Replayed run: lamp on {float(r0['on_s']):.1f} s of {float(r0['span_s']):.1f} s "
                      f"(saves {float(r0['saving_pct']):.0f} %)", fontsize=10)
        ax2.grid(True, axis="y", alpha=0.3)
        ax2.legend(fontsize=8.5)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) not in (3, 4):
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3] if len(sys.argv) == 4 else None)

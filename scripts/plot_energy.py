#!/usr/bin/python3
"""Headlight energy per lamp type and case (paper Fig. "Energy consumed in the worst case, average
case, and best case scenarios"), the binary lamp and the segmented lamp beside it, from
icanc_energy --csv; optionally beside the energy of replayed runs (icanc_energy --bag ... --csv,
scripts/utilisation's energy_bag.csv): the simulated scenario and the real KITTI drive.

    scripts/plot_energy.py ENERGY.csv OUT.png [ENERGY_BAG.csv] [--kitti KITTI_ENERGY_BAG.csv |
                           --no-kitti REASON]

--no-kitti REASON writes in the figure why the real drive is not shown (e.g. ../shared absent).
"""
import argparse
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

COLOURS = ["tab:blue", "tab:red", "tab:green", "tab:orange", "tab:purple", "tab:brown"]


def grouped_bars(ax, groups, series, values, fmt, colours, hatches):
    """values[s][g]: one bar per series s in each group g, labelled with its value."""
    width = 0.84 / len(series)
    for s, name in enumerate(series):
        xs = [g + (s - (len(series) - 1) / 2) * width for g in range(len(groups))]
        bars = ax.bar(xs, values[s], width * 0.95, label=name, color=colours[s], hatch=hatches[s],
                      edgecolor="white" if hatches[s] else None, alpha=0.85)
        for bar, v in zip(bars, values[s]):
            ax.annotate(fmt(v), (bar.get_x() + bar.get_width() / 2, bar.get_height()),
                        textcoords="offset points", xytext=(0, 2), ha="center", fontsize=6.5,
                        rotation=90)
    ax.set_xticks(range(len(groups)))
    ax.set_xticklabels(groups, fontsize=9)
    ax.grid(True, axis="y", alpha=0.3)


def bag_panel(ax, bag_rows, title):
    """Always-on against the measured on-time per lamp type of one replayed run."""
    labels = [r["label"] for r in bag_rows]
    on = [float(r["wh"]) * 1000 for r in bag_rows]
    always = [float(r["wh_always_on"]) * 1000 for r in bag_rows]
    width = 0.38
    xs = range(len(labels))
    ax.bar([x - width / 2 for x in xs], always, width, color="0.65", label="always on")
    ax.bar([x + width / 2 for x in xs], on, width, color="tab:orange", label="ICanC (measured)")
    for x, a, o in zip(xs, always, on):
        ax.annotate(f"{a:.3g}", (x - width / 2, a), textcoords="offset points", xytext=(0, 2),
                    ha="center", fontsize=7.5)
        ax.annotate(f"{o:.3g}", (x + width / 2, o), textcoords="offset points", xytext=(0, 2),
                    ha="center", fontsize=7.5)
    ax.set_xticks(list(xs))
    ax.set_xticklabels(labels, fontsize=9)
    ax.set_ylabel("energy (mWh)")
    r0 = bag_rows[0]
    ax.set_title(f"{title}\nlamp on {float(r0['on_s']):.1f} s of {float(r0['span_s']):.1f} s "
                 f"(saves {float(r0['saving_pct']):.1f} %)", fontsize=9.5)
    ax.grid(True, axis="y", alpha=0.3)
    ax.legend(fontsize=8)


def read_csv(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def main():
    ap = argparse.ArgumentParser(usage=__doc__)
    ap.add_argument("energy_csv")
    ap.add_argument("png")
    ap.add_argument("bag_csv", nargs="?")
    ap.add_argument("--kitti", help="energy_bag.csv of the KITTI drive replayed through the graph")
    ap.add_argument("--no-kitti", help="why the KITTI drive is not shown (written in the figure)")
    a = ap.parse_args()

    rows = [r for r in read_csv(a.energy_csv) if r["rounding"] == "paper"]
    if not rows:
        sys.exit(f"plot_energy: no rounding=paper rows in {a.energy_csv}")
    binary = [r for r in rows if r.get("segments", "1") == "1"]
    segmented = [r for r in rows if r.get("segments", "1") != "1"]
    lamps = list(dict.fromkeys(r["label"] for r in binary))
    wh = {(r["label"], r["case"]): float(r["wh"]) for r in binary}
    seg_wh = {(r["label"], r["case"]): float(r["wh"]) for r in segmented}
    hours = {r["case"]: float(r["on_hours"]) for r in binary}
    beam = binary[0]["beam"]

    panels = []  # (title, rows) of the replayed runs
    if a.bag_csv:
        panels.append(("Replayed simulated scenario", read_csv(a.bag_csv)))
    if a.kitti:
        panels.append(("Real drive: KITTI 0000 through the graph", read_csv(a.kitti)))
    show_note = a.no_kitti and not a.kitti
    extra = len(panels) + (1 if show_note and a.bag_csv else 0)
    fig, axes = plt.subplots(1, 1 + extra, figsize=(8.5 + 4.2 * extra, 5.0), squeeze=False,
                             gridspec_kw={"width_ratios": [1.9] + [1] * extra})
    axes = axes[0]
    ax = axes[0]
    fraction = float(binary[0]["danger_fraction"])
    cases = [("worst", "Worst case\n(always on)"),
             ("average", f"Average case\n(on {100 * fraction:.0f} % of the drive)"),
             ("best", "Best case\n(dangerous objects x tau)")]
    groups = [f"{label}\n{hours[c]:.3f} h" for c, label in cases]
    series, values, colours, hatches = [], [], [], []
    for i, lamp in enumerate(lamps):
        series.append(f"{lamp}")
        values.append([wh[(lamp, c)] for c, _ in cases])
        colours.append(COLOURS[i % len(COLOURS)])
        hatches.append(None)
        if segmented:
            series.append(f"{lamp}, {segmented[0]['segments']} segments, "
                          f"{segmented[0]['segments_lit']} lit per object")
            values.append([seg_wh[(lamp, c)] for c, _ in cases])
            colours.append(COLOURS[i % len(COLOURS)])
            hatches.append("///")
    grouped_bars(ax, groups, series, values, lambda v: f"{v:.4g}", colours, hatches)
    ax.set_ylabel("energy consumed (Wh)")
    ax.set_ylim(top=ax.get_ylim()[1] * 1.35)
    ax.set_title(f"Paper's 22-minute drive, {beam} beam: binary lamp (paper's numbers)"
                 + (" and segmented lamp (hatched)" if segmented else ""), fontsize=9.5)
    ax.legend(title="headlight type", fontsize=7, title_fontsize=8, ncol=2, loc="upper right")

    for axis, (title, bag_rows) in zip(axes[1:], panels):
        bag_panel(axis, bag_rows, title)
    if show_note:
        note = f"Real drive (KITTI 0000) not shown:\n{a.no_kitti}"
        if a.bag_csv:
            axes[-1].axis("off")
            axes[-1].text(0.5, 0.5, note, ha="center", va="center", fontsize=9, wrap=True,
                          transform=axes[-1].transAxes)
        else:
            fig.text(0.99, 0.01, note.replace("\n", " "), ha="right", va="bottom", fontsize=7.5)
        print(f"plot_energy: {note}")
    fig.tight_layout(rect=(0, 0.03, 1, 1) if show_note and not a.bag_csv else None)
    fig.savefig(a.png, dpi=110)
    print(f"wrote {a.png}")


if __name__ == "__main__":
    main()

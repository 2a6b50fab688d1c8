#!/usr/bin/python3
"""CPU and memory of the nodelet manager over time (paper Fig. "CPU usage plotted against time"),
from scripts/utilisation's utilisation.csv.

    scripts/plot_utilisation.py UTILISATION.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def main(csv_path, png_path):
    with open(csv_path) as f:
        rows = list(csv.DictReader(f))
    if not rows:
        sys.exit(f"plot_utilisation: {csv_path} has no samples")
    t = [float(r["t_s"]) for r in rows]
    cpu = [float(r["cpu_percent"]) for r in rows]
    cpu_machine = [float(r["cpu_percent_machine"]) for r in rows]
    rss = [float(r["rss_mib"]) for r in rows]
    mem = [float(r["mem_percent"]) for r in rows]
    period = t[1] - t[0] if len(t) > 1 else t[0]

    fig, ax = plt.subplots(figsize=(7.5, 5.0))
    ax.plot(t, cpu, "s-", color="tab:red", ms=4, label=f"CPU, % of one core (mean {sum(cpu) / len(cpu):.1f} %)")
    ax.plot(t, cpu_machine, "s--", color="tab:red", ms=3, alpha=0.45,
            label=f"CPU, % of the machine (mean {sum(cpu_machine) / len(cpu_machine):.1f} %)")
    ax.plot(t, mem, "^-", color="tab:green", ms=4, label=f"memory, % of RAM (mean {sum(mem) / len(mem):.3f} %)")
    ax.axhline(4.0, color="0.4", lw=0.8, ls=":", label="paper: about 4 % CPU")
    ax.set_xlabel("time (s)")
    ax.set_ylabel("usage (%)")
    ax.set_ylim(0, max(5.0, max(cpu) * 1.15))
    ax.grid(True, alpha=0.3)
    right = ax.twinx()
    right.plot(t, rss, color="tab:blue", lw=1.2, alpha=0.7)
    right.set_ylabel("resident memory (MiB)", color="tab:blue")
    right.set_ylim(0, max(rss) * 1.3)
    right.tick_params(axis="y", colors="tab:blue")
    ax.plot([], [], color="tab:blue", label=f"resident memory, MiB (max {max(rss):.1f})")
    ax.legend(loc="upper center", bbox_to_anchor=(0.5, -0.15), ncol=2, fontsize=8, frameon=False)
    ax.set_title(f"Nodelet manager (detector + danger + light) while the bag replays, "
                 f"sampled every {period:.3g} s", fontsize=10)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 3:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2])

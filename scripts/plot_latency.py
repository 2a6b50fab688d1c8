#!/usr/bin/python3
"""End-to-end latency per frame (paper Fig. "Latency over time"), from scripts/utilisation's
latency_frames.csv and latency_light.csv (written by icanc_latency_log).

    scripts/plot_latency.py LATENCY_FRAMES.csv LATENCY_LIGHT.csv OUT.png
"""
import csv
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402


def read(path):
    with open(path) as f:
        return list(csv.DictReader(f))


def percentile(values, p):
    v = sorted(values)
    return v[min(len(v) - 1, int(p * (len(v) - 1) + 0.5))] if v else float("nan")


def main(frames_csv, light_csv, png_path):
    frames = [r for r in read(frames_csv) if float(r["cloud_to_danger_ms"]) >= 0]
    light = read(light_csv)
    if not frames:
        sys.exit(f"plot_latency: {frames_csv} has no frames")
    t0 = float(frames[0]["stamp_s"])
    t = [float(r["stamp_s"]) - t0 for r in frames]
    e2e = [float(r["cloud_to_danger_ms"]) for r in frames]
    det = [float(r["detector_ms"]) for r in frames]

    fig, ax = plt.subplots(figsize=(7.5, 4.3))
    ax.axhspan(25, 30, color="0.85", label="paper: 25-30 ms (cloud -> light command)")
    ax.plot(t, e2e, "-", color="tab:blue", lw=1.1,
            label=f"cloud received -> danger-marked boxes (p50 {percentile(e2e, 0.5):.1f}, "
                  f"p99 {percentile(e2e, 0.99):.1f} ms)")
    ax.plot(t, det, "-", color="tab:orange", lw=0.9, alpha=0.8,
            label=f"ObstacleDetector processing (p50 {percentile(det, 0.5):.1f} ms)")
    if light:
        lt = [float(r["stamp_s"]) - t0 for r in light]
        lat = [float(r["cloud_to_light_ms"]) for r in light]
        ax.plot(lt, lat, "r*", ms=12, label=f"cloud received -> light command ({len(light)} "
                f"trigger{'s' if len(light) != 1 else ''}, p50 {percentile(lat, 0.5):.1f} ms)")
    ax.set_xlabel("time in the recording (s)")
    ax.set_ylabel("latency (ms)")
    ax.set_ylim(0, max(48.0, max(e2e) * 1.1))
    ax.grid(True, alpha=0.3)
    ax.legend(loc="upper right", fontsize=8, framealpha=0.9)
    ax.set_title(f"End-to-end latency per frame ({len(frames)} frames, replay at recorded speed)",
                 fontsize=10)
    fig.tight_layout()
    fig.savefig(png_path, dpi=110)
    print(f"wrote {png_path}")


if __name__ == "__main__":
    if len(sys.argv) != 4:
        sys.exit(__doc__)
    main(sys.argv[1], sys.argv[2], sys.argv[3])

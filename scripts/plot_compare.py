#!/usr/bin/env python3
"""Draws `furnace compare --html DIR`'s page from DIR/compare.json.

Usage: plot_compare.py DIR   (run by furnace compare, verify/compare_report.h)

Uses plot_report.py's plotting (tone mapping, image panels, colour bars,
atomic saves; it lives beside this file). Per tested channel it writes
DIR/compare_<channel>.png with five panels:
  mean A, mean B       the two sides' mean images, one tone mapping (radiance
                       x 0.8 / the 99.5th percentile of B, sRGB);
  difference           (A - B) / mean of B, symmetric range (99th percentile
                       of |difference|), red where A is brighter;
  pixel t              Welch t of A - B per pixel, range +-4;
  tile t               Welch t of each tile mean, range +- the larger of 4
                       and the worst tile's |t| (a rejecting tile stands out).
and DIR/index.html, a self-contained page with the text report.
"""
import html
import json
import math
import os
import sys

sys.path.insert(0, os.path.dirname(os.path.abspath(__file__)))
import plot_report as pr  # noqa: E402  (matplotlib set up there, Agg backend)

import numpy as np  # noqa: E402

plt = pr.plt


def finite(values):
    """JSON null (a non-finite t) as +inf, so it shows at the end of the range."""
    return np.array([math.inf if v is None else v for v in values], dtype=float)


def plot_channel(report, image, out_dir):
    shape = {"width": report["width"], "height": report["height"]}
    a = pr.image(image["mean_a"], shape)
    b = pr.image(image["mean_b"], shape)
    scale = pr.exposure(b)
    mean_b = float(b.mean()) if b.mean() != 0 else 1.0
    difference = (a - b) / mean_b
    top = float(np.percentile(np.abs(difference), 99)) or 1.0
    t = np.clip(pr.image(finite(image["pixel_t"]), shape), -pr.T_RANGE, pr.T_RANGE)
    tiles = finite(image["tile_t"]).reshape(report["tiles_y"], report["tiles_x"])
    channel = next(c for c in report["channels"] if c["channel"] == image["channel"])
    worst = channel["tiles"]["worst_t"]
    tile_range = max(pr.T_RANGE, abs(worst) if worst is not None else pr.T_RANGE)
    tiles = np.clip(tiles, -tile_range, tile_range)

    fig, axes = plt.subplots(1, 5, figsize=(15, 3.3))
    pr.show(axes[0], pr.tone_map(a, scale), "mean A", cmap="gray", vmin=0, vmax=1)
    pr.show(axes[1], pr.tone_map(b, scale), "mean B", cmap="gray", vmin=0, vmax=1)
    im = pr.show(axes[2], difference, "(A - B) / mean B", cmap="RdBu_r", vmin=-top, vmax=top)
    pr.colour_bar(fig, im, axes[2])
    im = pr.show(axes[3], t, "pixel Welch t", cmap="RdBu_r", vmin=-pr.T_RANGE, vmax=pr.T_RANGE)
    pr.colour_bar(fig, im, axes[3])
    im = pr.show(axes[4], tiles, f"tile Welch t ({report['tile_size']}x{report['tile_size']})", cmap="RdBu_r",
                 vmin=-tile_range, vmax=tile_range)
    pr.colour_bar(fig, im, axes[4])
    fig.suptitle(f"channel {image['channel']}", fontsize=9)
    fig.tight_layout()
    return pr.save(fig, out_dir, f"compare_{pr.slug(image['channel'])}.png")


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_compare.py DIR (DIR/compare.json written by furnace compare --html)")
    out_dir = sys.argv[1]
    with open(os.path.join(out_dir, "compare.json"), encoding="utf-8") as f:
        report = json.load(f)
    body = [f"<h1>furnace compare: {html.escape(report['verdict'])}</h1>",
            "<p>A: " + html.escape(", ".join(report["a"]["images"])) + "<br>B: " +
            html.escape(", ".join(report["b"]["images"])) + "</p>",
            "<pre>" + html.escape(report["report_text"]) + "</pre>",
            "<p>Every number and pixel of this page: <a href=\"compare.json\">compare.json</a>. Red: A brighter"
            " than B.</p>"]
    for image in report["images"]:
        body.append(f"<img src=\"{plot_channel(report, image, out_dir)}\" alt=\"{html.escape(image['channel'])}\">")
    pr.write_page(out_dir, "furnace compare", body)


if __name__ == "__main__":
    main()

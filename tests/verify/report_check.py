#!/usr/bin/env python3
"""Checks a folder written by `furnace report` (run by report_test.sh).

- index.html parses, fetches nothing from a network, has no script, and every
  file it references (img src, a href) exists in the folder;
- every PNG decodes with a real library (matplotlib.image, i.e. Pillow), is
  at least 100 x 100 pixels and is not uniform: its pixels' standard
  deviation exceeds MIN_STD and it has more than MIN_COLOURS distinct colours;
  a plot has data drawn in colour, an image figure is filled with mid-tones
  or colour (an empty plot or a blank render would not);
- negative controls: a uniform PNG and an empty plot are flagged trivial;
- each scene has its four PNGs and the page has the seed figure;
- (the content rule suits disk_occluder, the scene the test renders: a scene
  whose exact reference is constant, a furnace, has a flat gray reference
  image and would be flagged;)
- the page's numbers are report.json's: each case's slope and the seed
  figure's RMSEs, times and variance ratios, formatted as the page formats them.
"""
import html.parser
import json
import os
import sys

import matplotlib.image
import numpy as np

MIN_SIDE = 100
MIN_STD = 0.02      # of colour values in [0, 1]; a blank figure with a few lines of text has about 0.05
MIN_COLOURS = 16
COLOUR_SATURATION = 0.25  # max - min of R, G, B: above it a pixel is coloured (data), below gray (axes, text)
# Measured on matplotlib 3.6 at 80 dpi: an empty plot (axes, title) has 0 coloured pixels and 2.4 %
# mid-tones; disk_occluder's convergence plot with 3 strategies 0.5 % coloured, its images >= 39 % content.
MIN_PLOT_COLOURED = 0.002
MIN_IMAGE_CONTENT = 0.10


class Links(html.parser.HTMLParser):
    def __init__(self):
        super().__init__()
        self.links, self.tags = [], set()

    def handle_starttag(self, tag, attrs):
        self.tags.add(tag)
        for name, value in attrs:
            if name in ("src", "href"):
                self.links.append(value)


def trivial(path, kind):
    """Why the PNG at `path` is trivial, or None: decoded with matplotlib.image (Pillow).

    kind "plot": its data must be drawn in colour (axes and text are gray);
    kind "image": renders and maps must fill the figure with mid-tones or colour.
    """
    pixels = matplotlib.image.imread(path)
    height, width = pixels.shape[:2]
    colours = len(np.unique(pixels.reshape(height * width, -1), axis=0))
    rgb = pixels[..., :3]
    std = float(rgb.std())
    saturation = rgb.max(axis=2) - rgb.min(axis=2)
    luminance = rgb.mean(axis=2)
    coloured = float((saturation > COLOUR_SATURATION).mean())
    content = coloured + float(((luminance > 0.05) & (luminance < 0.9) & (saturation <= COLOUR_SATURATION)).mean())
    summary = f"{width}x{height}, std {std:.3f}, {colours} colours, coloured {coloured:.4f}, content {content:.3f}"
    print(f"{os.path.basename(path)} ({kind}): {summary}")
    if min(width, height) < MIN_SIDE or std <= MIN_STD or colours <= MIN_COLOURS:
        return summary
    if kind == "plot" and coloured <= MIN_PLOT_COLOURED:
        return summary + ": no data drawn"
    if kind == "image" and content <= MIN_IMAGE_CONTENT:
        return summary + ": no image content"
    return None


def kind_of(name):
    return "plot" if name.endswith(("_convergence.png", "_efficiency.png")) else "image"


def negative_controls(out):
    """The triviality check must reject a uniform image and an empty plot."""
    import matplotlib.pyplot as plt
    uniform = os.path.join(out, ".control_uniform.png")
    matplotlib.image.imsave(uniform, np.full((200, 200), 0.5), cmap="gray", vmin=0, vmax=1)
    fig, ax = plt.subplots(figsize=(4, 3))
    ax.set_title("empty")
    empty = os.path.join(out, ".control_empty_plot.png")
    fig.savefig(empty, dpi=80)
    plt.close(fig)
    failures = [f"negative control {os.path.basename(p)} ({kind}) was not flagged trivial"
                for p in (uniform, empty) for kind in ("plot", "image") if trivial(p, kind) is None]
    for p in (uniform, empty):
        os.remove(p)
    return failures


def main():
    out = sys.argv[1]
    failures = negative_controls(out)
    page = open(os.path.join(out, "index.html"), encoding="utf-8").read()
    report = json.load(open(os.path.join(out, "report.json"), encoding="utf-8"))
    parser = Links()
    parser.feed(page)
    if "script" in parser.tags:
        failures.append("index.html has a <script>")
    for link in parser.links:
        if "://" in link or link.startswith("/") or link.startswith("//"):
            failures.append(f"index.html references {link}, not a file in the folder")
        elif not link.startswith("#") and not os.path.isfile(os.path.join(out, link)):
            failures.append(f"index.html references {link}, which does not exist")
    pngs = [link for link in parser.links if link.endswith(".png")]
    scenes = sorted({c["scene"] for c in report["cases"]})
    for scene in scenes:
        for kind in ("convergence", "efficiency", "reference", "images"):
            if f"{scene}_{kind}.png" not in pngs:
                failures.append(f"no {scene}_{kind}.png on the page")
    if "seed_figure.png" not in pngs:
        failures.append("no seed_figure.png on the page")
    for name in pngs:
        why = trivial(os.path.join(out, name), kind_of(name))
        if why:
            failures.append(f"{name} is trivial: {why}")
    for c in report["cases"]:
        if f"{c['slope']:.3f}" not in page:
            failures.append(f"slope {c['slope']:.3f} of {c['strategy']} not on the page")
    f = report["seed_figure"]
    for r in (f["hemisphere"], f["light"]):
        for key in ("rmse", "relative_rmse", "seconds"):
            if f"{r[key]:.4g}" not in page:
                failures.append(f"seed figure {r['strategy']} {key} {r[key]:.4g} not on the page")
    for key in ("predicted_variance_ratio", "measured_variance_ratio", "measured_mse_ratio"):
        if f"{f[key]:.4g}" not in page:
            failures.append(f"seed figure {key} {f[key]:.4g} not on the page")
    print(f"{len(parser.links)} links, {len(pngs)} PNGs, {len(report['cases'])} cases")
    for failure in failures:
        print("FAIL:", failure)
    print("PASS" if not failures else "FAIL")
    sys.exit(1 if failures else 0)


if __name__ == "__main__":
    main()

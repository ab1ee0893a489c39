#!/usr/bin/env python3
"""Draws furnace's HTML convergence report from DIR/report.json.

Usage: plot_report.py DIR   (run by `furnace report`, verify/report_html.h)

Writes DIR/*.png with matplotlib (plots, tone-mapped renders, false-colour
error and t maps with colour bars) and then DIR/index.html, a self-contained
page: relative links to those files only, no script, no network.

Per scene:
  <scene>_convergence.png  relative RMSE against spp and against seconds,
                           log-log, every strategy, the ideal slope -1/2;
  <scene>_efficiency.png   1 / (relative MSE x seconds) at the largest spp;
  <scene>_reference.png    the exact reference;
  <scene>_images.png       per strategy: the render at equal spp and at equal
                           time, each with its signed relative error map and
                           its per-pixel t map.
seed_figure.png            the lecture notes' comparison with its numbers.

Tone mapping, the same for every image of a scene: radiance x (TONE_TOP / the
99.5th percentile of the reference), clipped to [0, 1], then the sRGB transfer
curve. (A scene whose reference is constant, a furnace, shows a flat gray.)
Signed relative error: (render - reference) / mean reference, one symmetric
range per scene (the 99th percentile of |error| over all its renders), so the
strategies compare at a glance. t: (render - reference) / sqrt(s^2 / spp),
fixed range [-4, 4]; a pixel with s^2 = 0 has t = 0 where it matches its
reference and is drawn at the end of the range where it does not.
"""
import html
import json
import math
import os
import re
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402
import numpy as np  # noqa: E402

T_RANGE = 4.0  # |t| beyond ~4 is rare for a correct estimator at any pixel count shown here
DPI = 80
# The reference's 99.5th percentile maps to this linear value (0.91 after the
# sRGB curve): light enough to read, short of white so that noise above the
# reference still shows instead of clipping.
TONE_TOP = 0.8
MARKERS = "osD^v<>phX*P"


def slug(name):
    return re.sub(r"[^A-Za-z0-9_.-]+", "_", name)


def fmt_g(x, digits=3):
    """The text table's {:.Ng}; None (a non-finite number in the JSON) prints as inf."""
    if x is None:
        return "inf"
    return f"{x:.{digits}g}"


def save(fig, out_dir, name):
    """Writes the PNG under a temporary name and renames it into place."""
    tmp = os.path.join(out_dir, f".{name}.tmp-{os.getpid()}.png")
    fig.savefig(tmp, dpi=DPI)
    plt.close(fig)
    os.replace(tmp, os.path.join(out_dir, name))
    return name


def image(values, case_or_figure):
    return np.asarray(values, dtype=float).reshape(case_or_figure["height"], case_or_figure["width"])


def exposure(reference):
    top = np.percentile(reference, 99.5)
    if not top > 0:
        top = reference.max()
    return TONE_TOP / top if top > 0 else 1.0


def tone_map(radiance, scale):
    x = np.clip(radiance * scale, 0.0, 1.0)
    return np.where(x <= 0.0031308, 12.92 * x, 1.055 * np.power(x, 1 / 2.4) - 0.055)


def t_map(mean, variance, spp, reference):
    error = mean - reference
    with np.errstate(divide="ignore", invalid="ignore"):
        t = error / np.sqrt(variance / spp)
    exact = variance <= 0
    tolerance = 1e-12 * max(1.0, float(np.abs(reference).max()))
    t[exact & (np.abs(error) <= tolerance)] = 0.0
    t[exact & (np.abs(error) > tolerance)] = np.sign(error[exact & (np.abs(error) > tolerance)]) * np.inf
    return np.clip(t, -T_RANGE, T_RANGE)


def show(ax, data, title, **kwargs):
    im = ax.imshow(data, interpolation="nearest", origin="upper", **kwargs)
    ax.set_title(title, fontsize=8)
    ax.set_xticks([])
    ax.set_yticks([])
    return im


def colour_bar(fig, im, ax, label=None):
    bar = fig.colorbar(im, ax=ax, fraction=0.046, pad=0.03)
    bar.ax.tick_params(labelsize=6)
    if label:
        bar.set_label(label, fontsize=6)


def plot_convergence(scene, cases, out_dir):
    fig, axes = plt.subplots(1, 2, figsize=(12, 5.2 + 0.18 * ((len(cases) + 3) // 3)))
    colours = plt.cm.tab20(np.linspace(0, 1, max(len(cases), 2)))
    anchors = []
    for i, c in enumerate(cases):
        points = [p for p in c["points"] if p["relative_rmse"] > 0]
        if not points:
            axes[0].plot([], [], label=f"{c['strategy']} (exact: RMSE 0)", color=colours[i])
            continue
        spp = [p["spp"] for p in points]
        sec = [p["seconds"] for p in points]
        err = [p["relative_rmse"] for p in points]
        style = dict(color=colours[i], marker=MARKERS[i % len(MARKERS)], markersize=4, linewidth=1.2)
        axes[0].loglog(spp, err, label=f"{c['strategy']} (slope {c['slope']:.3f})", **style)
        axes[1].loglog(sec, err, **style)
        anchors.append((spp[0], sec[0], err[0]))
    if anchors:
        # The ideal N^(-1/2) through the median starting error, over the data's range.
        e0 = float(np.median([a[2] for a in anchors]))
        for ax, index in ((axes[0], 0), (axes[1], 1)):
            lo = min(a[index] for a in anchors)
            hi = max(max(p["spp"] if index == 0 else p["seconds"] for p in c["points"]) for c in cases)
            x = np.geomspace(lo, hi, 20)
            ax.loglog(x, e0 * (x / lo) ** -0.5, "--", color="0.35", linewidth=1.5, zorder=1,
                      label="ideal slope -1/2")
    for ax in axes:
        ax.set_xscale("log")
        ax.set_yscale("log")
    if not anchors:
        # Every strategy exact: nothing positive to draw on log axes.
        spp = [p["spp"] for c in cases for p in c["points"]]
        sec = [p["seconds"] for c in cases for p in c["points"] if p["seconds"] > 0] or [1e-3, 1]
        for ax, (lo, hi) in ((axes[0], (min(spp), max(spp))), (axes[1], (min(sec), max(sec)))):
            ax.set_xlim(lo, hi * 1.01)
            ax.set_ylim(1e-3, 1)
            ax.text(0.5, 0.5, "every strategy exact: RMSE 0 at every spp", transform=ax.transAxes,
                    ha="center", fontsize=9)
    axes[0].set_xlabel("samples per pixel")
    axes[1].set_xlabel("render seconds (wall clock)")
    for ax in axes:
        ax.set_ylabel("relative RMSE")
        ax.grid(True, which="both", alpha=0.3)
    axes[0].set_title(f"{scene}: relative RMSE against spp", fontsize=10)
    axes[1].set_title(f"{scene}: relative RMSE against time", fontsize=10)
    handles, labels = axes[0].get_legend_handles_labels()
    rows = (len(labels) + 2) // 3
    fig.legend(handles, labels, loc="lower center", ncol=3, fontsize=8)
    fig.tight_layout(rect=(0, 0.035 * rows + 0.02, 1, 1))
    return save(fig, out_dir, f"{slug(scene)}_convergence.png")


def plot_efficiency(scene, cases, out_dir):
    fig, ax = plt.subplots(figsize=(7, 0.35 * len(cases) + 1.2))
    names = [c["strategy"] for c in cases]
    values = [c["efficiency"] for c in cases]
    finite = [v for v in values if v is not None and v > 0]
    top = max(finite) if finite else 1.0
    y = np.arange(len(cases))
    bars = [v if (v is not None and v > 0) else np.nan for v in values]
    ax.barh(y, bars, color="#4c72b0")
    for yi, v in zip(y, values):
        if v is None:
            ax.text(top, yi, " exact (RMSE 0): infinite", va="center", fontsize=7)
    if not finite:
        ax.set_xlim(0.5, 10)  # every strategy exact: no bar to draw, only the labels
    ax.set_yticks(y)
    ax.set_yticklabels(names, fontsize=8)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.set_xlabel("efficiency 1 / (relative MSE x seconds) at the largest spp (higher is better)")
    ax.set_title(f"{scene}: efficiency", fontsize=10)
    ax.grid(True, axis="x", which="both", alpha=0.3)
    fig.tight_layout()
    return save(fig, out_dir, f"{slug(scene)}_efficiency.png")


def plot_reference(scene, case, scale, out_dir):
    fig, ax = plt.subplots(figsize=(3.2, 3.2))
    show(ax, tone_map(image(case["reference"], case), scale), f"{scene}: exact reference", cmap="gray",
         vmin=0, vmax=1)
    fig.tight_layout()
    return save(fig, out_dir, f"{slug(scene)}_reference.png")


def plot_images(scene, cases, scale, out_dir):
    references = [image(c["reference"], c) for c in cases]
    norms = []
    for c, ref in zip(cases, references):
        mean_ref = float(np.mean(ref))
        norms.append(mean_ref if mean_ref > 0 else max(float(np.abs(ref).max()), 1.0))
    errors = []
    for c, ref, norm in zip(cases, references, norms):
        for kind in ("equal_spp", "equal_time"):
            errors.append(np.abs(image(c[kind]["mean"], c) - ref).ravel() / norm)
    limit = float(np.percentile(np.concatenate(errors), 99))
    if not limit > 0:
        limit = 1e-12
    fig, axes = plt.subplots(len(cases), 6, figsize=(15, 2.3 * len(cases) + 0.4), squeeze=False)
    for row, (c, ref, norm) in enumerate(zip(cases, references, norms)):
        for k, kind in enumerate(("equal_spp", "equal_time")):
            r = c[kind]
            mean = image(r["mean"], c)
            variance = image(r["variance"], c)
            label = "equal spp" if kind == "equal_spp" else "equal time"
            ax = axes[row][3 * k]
            show(ax, tone_map(mean, scale), f"{c['strategy']}\n{label}: {r['spp']} spp, {r['seconds']:.3g} s",
                 cmap="gray", vmin=0, vmax=1)
            im = show(axes[row][3 * k + 1], (mean - ref) / norm, "signed error / mean ref.", cmap="RdBu_r",
                      vmin=-limit, vmax=limit)
            colour_bar(fig, im, axes[row][3 * k + 1])
            im = show(axes[row][3 * k + 2], t_map(mean, variance, r["spp"], ref), "per-pixel t", cmap="coolwarm",
                      vmin=-T_RANGE, vmax=T_RANGE)
            colour_bar(fig, im, axes[row][3 * k + 2])
    fig.tight_layout()
    return save(fig, out_dir, f"{slug(scene)}_images.png")


def plot_seed_figure(f, out_dir):
    ref = image(f["reference"], f)
    scale = exposure(ref)
    fig, axes = plt.subplots(1, 3, figsize=(13, 4.8))
    for ax, r in zip(axes, (f["hemisphere"], f["light"])):
        name = "hemisphere sampling" if r is f["hemisphere"] else "light-area sampling"
        show(ax, tone_map(image(r["mean"], f), scale),
             f"{name} ({r['strategy']}), {r['spp']} spp\nrel. RMSE {r['relative_rmse']:.3g}, {r['seconds']:.3g} s",
             cmap="gray", vmin=0, vmax=1)
    show(axes[2], tone_map(ref, scale), "exact reference", cmap="gray", vmin=0, vmax=1)
    fig.suptitle(f"{f['scene']} (disk light, blocker): pixel variance ratio hemisphere/light "
                 f"predicted {f['predicted_variance_ratio']:.3g}, measured {f['measured_variance_ratio']:.3g}",
                 fontsize=11)
    fig.tight_layout(rect=(0, 0, 1, 0.93))
    return save(fig, out_dir, "seed_figure.png")


STYLE = """body{font-family:sans-serif;margin:1.5em;max-width:1250px;color:#222}
table{border-collapse:collapse;font-size:13px;margin:0.5em 0}
th,td{border:1px solid #ccc;padding:2px 8px;text-align:right}th.l,td.l{text-align:left}
img{max-width:100%;border:1px solid #eee;margin:4px 0}code{background:#f4f4f4}
.row{display:flex;gap:16px;align-items:flex-start;flex-wrap:wrap}"""


def write_page(out_dir, title, body):
    """Writes out_dir/index.html, a self-contained page of the HTML pieces in `body`,
    atomically (a temporary file renamed over it)."""
    page = ("<!DOCTYPE html>\n<html lang=\"en\"><head><meta charset=\"utf-8\">"
            f"<title>{html.escape(title)}</title>\n<style>{STYLE}</style></head><body>\n" + "\n".join(body) +
            "\n</body></html>\n")
    tmp = os.path.join(out_dir, f".index.html.tmp-{os.getpid()}")
    with open(tmp, "w", encoding="utf-8") as f:
        f.write(page)
    os.replace(tmp, os.path.join(out_dir, "index.html"))


def table_html(cases):
    rows = ["<table><tr><th class=l>strategy</th><th>slope</th><th>rel. RMSE at max spp</th>"
            "<th>seconds at max spp</th><th>efficiency</th><th>s to 1 %</th><th>equal-time spp</th>"
            "<th>rel. RMSE at equal time</th></tr>"]
    for c in cases:
        last = c["points"][-1]
        ref = np.asarray(c["reference"], dtype=float)
        mean_ref = float(ref.mean())
        eq = np.asarray(c["equal_time"]["mean"], dtype=float)
        rmse_t = float(np.sqrt(np.mean((eq - ref) ** 2)))
        rel_t = rmse_t / mean_ref if mean_ref > 0 else rmse_t
        rows.append(
            f"<tr><td class=l>{html.escape(c['strategy'])}</td><td>{c['slope']:.3f}</td>"
            f"<td>{last['relative_rmse']:.3e}</td><td>{last['seconds']:.3f}</td><td>{fmt_g(c['efficiency'])}</td>"
            f"<td>{fmt_g(c['seconds_to_one_percent'])}</td><td>{c['equal_time']['spp']}</td>"
            f"<td>{rel_t:.3e}</td></tr>")
    rows.append("</table>")
    return "\n".join(rows)


def seed_html(f, png):
    h, l = f["hemisphere"], f["light"]
    rows = "".join(
        f"<tr><td class=l>{html.escape(r['strategy'])}</td><td>{r['spp']}</td><td>{r['rmse']:.4g}</td>"
        f"<td>{r['relative_rmse']:.4g}</td><td>{r['seconds']:.4g}</td><td>{r['mean_sample_variance']:.4g}</td>"
        f"<td>{r['mean_predicted_variance']:.4g}</td></tr>" for r in (h, l))
    return f"""<h2 id="seed">The lecture notes' comparison, with numbers</h2>
<p>{html.escape(f['scene'])} rendered at {f['width']}&times;{f['height']}: a Lambertian receiver under a disk light
with a disk blocker between them. Hemisphere sampling at {h['spp']} spp beside light-area sampling at {l['spp']} spp
(the lecture notes' figure), with the exact reference. Both are unbiased; light-area sampling is far less noisy with
fewer samples because its samples never miss the light, only the blocker.</p>
<img src="{png}" alt="seed figure">
<table><tr><th class=l>strategy</th><th>spp</th><th>RMSE</th><th>rel. RMSE</th><th>seconds</th>
<th>per-sample variance s&sup2; (mean over pixels)</th><th>predicted &sigma;&sup2; (analytic)</th></tr>{rows}</table>
<table><tr><th class=l>pixel-variance ratio hemisphere / light-area, (&sigma;&sup2;<sub>h</sub>/{h['spp']}) /
(&sigma;&sup2;<sub>l</sub>/{l['spp']})</th><th>value</th></tr>
<tr><td class=l>predicted from the analytic second moments (<code>furnace analytic --estimator</code>)</td>
<td>{f['predicted_variance_ratio']:.4g}</td></tr>
<tr><td class=l>measured from the per-pixel sample variances</td><td>{f['measured_variance_ratio']:.4g}</td></tr>
<tr><td class=l>measured as the ratio of the two images' MSE against the reference</td>
<td>{f['measured_mse_ratio']:.4g}</td></tr></table>"""


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_report.py DIR (DIR/report.json written by furnace report)")
    out_dir = sys.argv[1]
    with open(os.path.join(out_dir, "report.json"), encoding="utf-8") as f:
        report = json.load(f)

    scenes = {}
    for c in report["cases"]:
        scenes.setdefault(c["scene"], []).append(c)

    body = [f"<h1>furnace convergence report</h1>",
            f"<p>Generated by <code>{html.escape(report['command_line'])}</code> ({html.escape(report['generator'])}),"
            f" seed {report['seed']}, spp {report['min_spp']}&ndash;{report['max_spp']} (each spp an independent"
            " render). Times are wall-clock on the machine that generated the report: compare strategies within one"
            " report, not across reports. Also here: <a href=\"convergence.md\">convergence.md</a>,"
            " <a href=\"convergence.csv\">convergence.csv</a>, <a href=\"report.json\">report.json</a>"
            " (every number and pixel on this page).</p>",
            "<p><b>Reading it.</b> Relative RMSE: RMSE over pixels against the exact reference, divided by the mean"
            " reference. Slope: least-squares slope of log RMSE against log spp (&minus;&frac12; for an unbiased"
            " estimator of finite variance; flatter means bias or infinite variance). Efficiency: 1/(relative MSE"
            " &times; seconds) at the largest spp. <code>name@power</code>: the case runs under power light"
            " selection (uniform otherwise); <code>name/dN</code>: a path tracer limited to N segments (<code>/inf</code>: unlimited). Equal time:"
            " each strategy's spp scaled to the scene's budget, the fastest strategy's time at the largest spp."
            " Images of a scene share one tone mapping (radiance &times; 0.8 / 99.5th percentile of the reference, sRGB) and one"
            " error range; red is too bright. t: the pixel's error over its standard error, range &plusmn;4.</p>"]

    body.append(seed_html(report["seed_figure"], plot_seed_figure(report["seed_figure"], out_dir)))
    body.append("<h2>Scenes</h2><p>" + " &middot; ".join(
        f"<a href=\"#{slug(s)}\">{html.escape(s)}</a>" for s in scenes) + "</p>")
    for scene, cases in scenes.items():
        scale = exposure(image(cases[0]["reference"], cases[0]))
        own = [c["strategy"] for c in cases[1:] if c["reference"] != cases[0]["reference"]]
        note = (f"<p>Shown: the reference of {html.escape(cases[0]['strategy'])}; "
                f"{html.escape(', '.join(own))} converge to their own (depth-limited) reference, which their error"
                " maps use.</p>") if own else ""
        body.append(f"<h2 id=\"{slug(scene)}\">{html.escape(scene)}</h2>")
        body.append(table_html(cases))
        body.append(f"<p>Equal-time budget: {cases[0]['time_budget']:.3g} s (the fastest strategy at"
                    f" {cases[0]['equal_spp']['spp']} spp); each render's own time is in its title.</p>")
        body.append(f"<img src=\"{plot_convergence(scene, cases, out_dir)}\" alt=\"{html.escape(scene)} convergence\">")
        body.append("<div class=row>"
                    f"<img src=\"{plot_reference(scene, cases[0], scale, out_dir)}\" alt=\"reference\">"
                    f"<img src=\"{plot_efficiency(scene, cases, out_dir)}\" alt=\"efficiency\"></div>" + note)
        body.append(f"<img src=\"{plot_images(scene, cases, scale, out_dir)}\" alt=\"{html.escape(scene)} images\">")

    write_page(out_dir, "furnace convergence report", body)


if __name__ == "__main__":
    main()

#!/usr/bin/python3
"""Plots of `dwatch bench paper`, made from its CSV files: DIR/{table1,fig7,fig8,table2}.png.

Usage: /usr/bin/python3 scripts/plot_paper.py DIR

Run it with Debian's /usr/bin/python3: Debian's python3-matplotlib is importable only there
(docs/design.md §9). The CSV files are the interface; the paper's published numbers come in their
paper_* columns, so nothing here knows a measurement.
"""
import csv
import os
import sys

import matplotlib

matplotlib.use("Agg")
import matplotlib.pyplot as plt  # noqa: E402

PAPER_STYLE = dict(linestyle="--", marker="s", markerfacecolor="none")
DWATCH_STYLE = dict(linestyle="-", marker="o")
COLORS = plt.rcParams["axes.prop_cycle"].by_key()["color"]


def read(directory, name):
    with open(os.path.join(directory, name), newline="") as f:
        return list(csv.DictReader(f))


def finish(fig, ax, path, title):
    ax.set_title(title)
    ax.grid(True, which="major", alpha=0.35)
    ax.grid(True, which="minor", alpha=0.12)
    fig.tight_layout()
    fig.savefig(path, dpi=120)
    plt.close(fig)


def table1(directory):
    rows = read(directory, "table1.csv")
    fig, ax = plt.subplots(figsize=(8, 5.2))
    published = [r for r in rows if r["paper_matches"]]
    if published:
        ax.plot([float(r["paper_matches"]) for r in published], [float(r["paper_seconds"]) for r in published],
                color=COLORS[1], label="paper (DPRSim, dual-core, 2011)", **PAPER_STYLE)
        for r in published:
            ax.annotate("[" + r["tuple"] + "]", (float(r["paper_matches"]), float(r["paper_seconds"])),
                        textcoords="offset points", xytext=(6, 4), fontsize=8, color=COLORS[1])
    ax.plot([float(r["matches"]) for r in rows], [float(r["best_seconds"]) for r in rows], color=COLORS[0],
            label="dwatch (this machine, live run)", **DWATCH_STYLE)
    for r in rows:
        ax.annotate("[" + r["tuple"] + "]", (float(r["matches"]), float(r["best_seconds"])),
                    textcoords="offset points", xytext=(6, -11), fontsize=8, color=COLORS[0])
    ax.set_xscale("log")
    ax.set_yscale("log")
    ax.set_xlabel("successful matches in %s steps (each system's own count)" % rows[0]["steps"])
    ax.set_ylabel("execution time (s)")
    ax.legend(loc="center right")
    ax.margins(x=0.15, y=0.15)
    finish(fig, ax, os.path.join(directory, "table1.png"),
           "Table I: matches vs. execution time, %s modules, distributed" % f"{int(rows[0]['modules']):,}")


def fig7(directory):
    rows = read(directory, "fig7.csv")
    fig, ax = plt.subplots(figsize=(8, 5.2))
    tuples = list(dict.fromkeys(r["tuple"] for r in rows))
    for i, t in enumerate(tuples):
        for algorithm, style in (("distributed", "-"), ("centralized", "--")):
            series = [r for r in rows if r["tuple"] == t and r["algorithm"] == algorithm]
            if not series:
                continue
            ax.plot([int(r["filled"]) for r in series], [max(float(r["created"]), 0.5) for r in series],
                    linestyle=style, marker="o" if algorithm == "distributed" else "s",
                    markerfacecolor=None if algorithm == "distributed" else "none", color=COLORS[i % len(COLORS)],
                    label="[%s] %s" % (t, algorithm))
    ax.set_yscale("log")
    ax.set_xticks([1, 2, 3, 4])
    ax.set_xlabel("slots filled")
    ax.set_ylabel("PatternMatchers created in %s steps (%s modules)" % (rows[0]["steps"], f"{int(rows[0]['modules']):,}"))
    ax.legend(fontsize=8, ncol=2, loc="upper left")
    ax.text(0.99, 0.02, "the paper's Fig. 7 prints no values", transform=ax.transAxes, ha="right", fontsize=8,
            color="gray")
    finish(fig, ax, os.path.join(directory, "fig7.png"),
           "Fig. 7: PatternMatchers by slots filled (distributed solid, centralized dashed)")


def fig8(directory):
    rows = read(directory, "fig8.csv")
    fig, ax = plt.subplots(figsize=(8, 5.2))
    baseline = sorted((r for r in rows if not r["paper_overhead_percent"]), key=lambda r: int(r["modules"]))
    for i, series in enumerate(dict.fromkeys(r["series"] for r in rows)):
        points = sorted((r for r in rows if r["series"] == series), key=lambda r: int(r["modules"]))
        x = [int(r["modules"]) for r in points]
        color = COLORS[i % len(COLORS)]
        ax.plot(x, [1000 * float(r["best_seconds"]) for r in points], "o", color=color,
                label="%s (measured)" % series)
        ax.plot(x, [1000 * float(r["fit_seconds"]) for r in points], "-", color=color,
                label="%s: linear fit, R² = %.3f" % (series, float(points[0]["r_squared"])))
        if points[0]["paper_overhead_percent"]:
            # The paper publishes Fig. 8's mean overheads only: drawn over dwatch's own baseline.
            overhead = float(points[0]["paper_overhead_percent"])
            ax.plot([int(r["modules"]) for r in baseline],
                    [1000 * float(r["fit_seconds"]) * (1 + overhead / 100) for r in baseline], "--", color=color,
                    label="%s at the paper's mean overhead (%.0f%%) over the no-watchpoint fit" % (series, overhead))
    side = round((int(rows[0]["modules"]) / int(rows[0]["planes"])) ** 0.5)
    ax.set_xlabel("modules (%d × %d stacked planes)" % (side, side))
    ax.set_ylabel("execution time of %s steps (ms)" % rows[0]["steps"])
    ax.set_xlim(left=0)
    ax.set_ylim(bottom=0)
    ax.legend(fontsize=8, loc="upper left")
    finish(fig, ax, os.path.join(directory, "fig8.png"),
           "Fig. 8: medium-intensity workload with and without the watchpoint, [2:2:2:2]")


def table2(directory):
    rows = read(directory, "table2.csv")
    fig, ax = plt.subplots(figsize=(8, 5.2))
    floor = 0.1  # a log axis shows no overhead at or below zero: such points sit on this floor
    clipped = False
    for i, frequency in enumerate(dict.fromkeys(r["frequency"] for r in rows)):
        points = sorted((r for r in rows if r["frequency"] == frequency), key=lambda r: int(r["size"]))
        sizes = [int(r["size"]) for r in points]
        label = "%s (max %s)" % (frequency, points[0]["max"])
        color = COLORS[i % len(COLORS)]
        ax.plot(sizes, [float(r["paper_overhead_percent"]) for r in points], color=color,
                label=label + ", paper", **PAPER_STYLE)
        measured = [float(r["overhead_percent"]) for r in points]
        clipped = clipped or min(measured) <= floor
        ax.plot(sizes, [max(v, floor) for v in measured], color=color, label=label + ", dwatch", **DWATCH_STYLE)
    ax.set_yscale("log")
    ax.set_xticks([1, 2, 3, 4, 5])
    ax.set_xlabel("expression size (slots)")
    ax.set_ylabel("overhead (%)" + (", ≤ 0 drawn at 0.1" if clipped else ""))
    ax.legend(fontsize=8, ncol=2, loc="upper left")
    finish(fig, ax, os.path.join(directory, "table2.png"),
           "Table II: centralized overhead vs. expression size\n%s modules, baseline workload: %s"
           % (f"{int(rows[0]['modules']):,}", rows[0]["workload"]))


def main():
    if len(sys.argv) != 2:
        sys.exit("usage: plot_paper.py DIR (the --out of dwatch bench paper)")
    for plot in (table1, fig7, fig8, table2):
        plot(sys.argv[1])


if __name__ == "__main__":
    main()

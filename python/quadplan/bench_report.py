"""Charts and one Markdown report from `quadplan bench ... --out DIR` (which runs this itself):

    python3 -m quadplan.bench_report DIR

Reads DIR/SUITE.md, SUITE.csv (one row per measurement: ours, baseline, ratio, target) and
SUITE_series.csv (chart, x, series, value, unit) for every suite there, draws PNG charts with
matplotlib (Debian's python3-matplotlib) and writes DIR/report.md: each suite's table (with the
machine and the date it ran) followed by its charts.
"""
import csv
import pathlib
import re
import sys

SUITES = ["plans", "edit", "render", "schemes", "fas", "displacement", "editor", "scene", "animation"]


def slug(text):
    return re.sub(r"[^a-z0-9]+", "-", text.lower()).strip("-")


def read_csv(path):
    with open(path, newline="") as f:
        return list(csv.DictReader(f))


def as_float(text):
    try:
        return float(text)
    except (TypeError, ValueError):
        return float("nan")


def ratio_chart(plt, suite, rows, out):
    """Ours / baseline per measurement, log scale, coloured by whether the target was met."""
    rows = [r for r in rows if as_float(r["ratio"]) == as_float(r["ratio"])]
    if not rows:
        return None
    labels = [f'{r["cage"][:18]}: {r["benchmark"][:70]}' for r in rows]
    ratios = [as_float(r["ratio"]) for r in rows]
    colours = [{"pass": "tab:green", "informative": "tab:gray"}.get(r["result"], "tab:red") for r in rows]
    fig, ax = plt.subplots(figsize=(11, 0.32 * len(rows) + 1.4))
    y = range(len(rows))
    ax.barh(list(y), ratios, color=colours)
    ax.set_yticks(list(y), labels, fontsize=7)
    ax.invert_yaxis()
    ax.set_xscale("log")
    ax.axvline(1.0, color="black", linewidth=0.8)
    ax.set_xlabel("ratio = ours / baseline (log); green: target met, red: missed, grey: informative")
    ax.set_title(f"quadplan bench {suite}: ratios")
    fig.tight_layout()
    path = out / f"{suite}_ratios.png"
    fig.savefig(path, dpi=90)
    plt.close(fig)
    return path


def series_charts(plt, suite, points, out):
    charts = {}
    for p in points:
        charts.setdefault(p["chart"], []).append(p)
    paths = []
    for chart, pts in charts.items():
        unit = pts[0]["unit"]
        xs = list(dict.fromkeys(p["x"] for p in pts))
        names = list(dict.fromkeys(p["series"] for p in pts))
        value = {(p["x"], p["series"]): as_float(p["value"]) for p in pts}
        numeric = all(re.fullmatch(r"[0-9.]+", x) for x in xs)
        fig, ax = plt.subplots(figsize=(9, 4.8))
        if numeric:  # lines over a numeric x (tessellation factors)
            for name in names:
                ax.plot([float(x) for x in xs], [value.get((x, name), float("nan")) for x in xs], marker="o", label=name)
            ax.set_xscale("log", base=2)
            ax.set_yscale("log")
            ax.set_xlabel("tessellation factor")
            if unit == "x":  # a ratio: where both sides are equal
                ax.axhline(1.0, color="black", linewidth=0.8)
        elif chart.startswith("memory"):  # stacked columns
            bottom = [0.0] * len(xs)
            for name in names:
                heights = [value.get((x, name), 0.0) for x in xs]
                ax.bar(xs, heights, bottom=bottom, label=name)
                bottom = [b + h for b, h in zip(bottom, heights)]
        else:  # grouped bars
            width = 0.8 / len(names)
            for k, name in enumerate(names):
                ax.bar([i + k * width for i in range(len(xs))], [value.get((x, name), float("nan")) for x in xs],
                       width=width, label=name)
            ax.set_xticks([i + 0.4 - width / 2 for i in range(len(xs))], xs, rotation=30, ha="right", fontsize=8)
            ax.set_yscale("log")
        ax.set_ylabel(unit)
        ax.set_title(chart)
        ax.grid(True, which="both", alpha=0.3)
        ax.legend(fontsize=8)
        fig.tight_layout()
        path = out / f"{suite}_{slug(chart)}.png"
        fig.savefig(path, dpi=90)
        plt.close(fig)
        paths.append(path)
    return paths


def main(argv):
    if len(argv) != 2:
        print(__doc__, file=sys.stderr)
        return 2
    out = pathlib.Path(argv[1])
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        print("error: the bench charts need matplotlib: install Debian's python3-matplotlib (scripts/install-deps.sh)",
              file=sys.stderr)
        return 1
    report = ["# Quadplan benchmark report", "",
              "Each suite states the machine and the date it ran; figures are medians of repeated runs, "
              "ratios are ours / baseline measured in the same process. Data: SUITE.csv (the tables) and "
              "SUITE_series.csv (the charts).", ""]
    found = False
    for suite in SUITES:
        md, table = out / f"{suite}.md", out / f"{suite}.csv"
        if not md.exists() or not table.exists():
            continue
        found = True
        report.append(md.read_text().replace("## quadplan bench", "## Suite:", 1))
        charts = []
        ratio = ratio_chart(plt, suite, read_csv(table), out)
        if ratio:
            charts.append(ratio)
        series = out / f"{suite}_series.csv"
        if series.exists():
            charts += series_charts(plt, suite, read_csv(series), out)
        for chart in charts:
            report += [f"![{chart.stem}]({chart.name})", ""]
    if not found:
        print(f"error: no suite results (SUITE.md and SUITE.csv) in {out}", file=sys.stderr)
        return 1
    (out / "report.md").write_text("\n".join(report) + "\n")
    print(f"report: {out / 'report.md'}")
    return 0


if __name__ == "__main__":
    sys.exit(main(sys.argv))

"""Plot of an indentation: the force of the rigid sphere against depth, with Hertz's force
F = 4/3 E/(1 - nu^2) sqrt(R) delta^(3/2), and their ratio (msm_lab indent --plot).

Usage: python3 plot_indentation.py INDENT.json OUT.png
INDENT.json is `msm_lab indent --json`'s object, or a list of such objects (one curve each),
each optionally with a "label".
"""
import json
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_indentation.py INDENT.json OUT.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plotting needs matplotlib: apt-get install python3-matplotlib")
    with open(sys.argv[1]) as f:
        runs = json.load(f)
    if isinstance(runs, dict):
        runs = [runs]
    fig, (force_axis, ratio_axis) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True,
                                                 gridspec_kw={"height_ratios": [2, 1]})
    for k, run in enumerate(runs):
        colour = "C{}".format(k)
        label = run.get("label", "{} nodes".format(run.get("nodes", "?")))
        rows = [row for row in run["profile"] if row[2] > 0.0]
        depth = [1e3 * row[0] for row in rows]
        force_axis.plot(depth, [row[1] for row in rows], "o", markersize=3, color=colour,
                        label=label)
        force_axis.plot(depth, [row[2] for row in rows], "-", color=colour, linewidth=1,
                        label="Hertz" if len(runs) == 1 else None)
        ratio_axis.plot(depth, [row[1] / row[2] for row in rows], "o-", markersize=3,
                        color=colour)
    force_axis.set_ylabel("force on the sphere (N)")
    force_axis.grid(True, color="0.9")
    force_axis.legend(loc="upper left", title="points: simulated, lines: Hertz")
    ratio_axis.axhspan(0.9, 1.1, color="0.92")
    ratio_axis.axhline(1.0, color="0.6", linewidth=0.8)
    ratio_axis.set_ylabel("force / Hertz")
    ratio_axis.set_xlabel("depth past first contact (mm)")
    ratio_axis.grid(True, color="0.9")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()

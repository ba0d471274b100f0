"""Plot of a tensile fit: the measured engineering stress against strain and the model's
(msm_lab fit --tensile --plot), with their difference as a share of the largest measured stress.

Usage: python3 plot_tensile.py FIT.json OUT.png
FIT.json is `msm_lab fit --tensile --json`'s object with its "curve" rows
[strain, measured stress (Pa), model stress (Pa)].
"""
import json
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_tensile.py FIT.json OUT.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
    except ImportError:
        sys.exit("plotting needs matplotlib: apt-get install python3-matplotlib")
    with open(sys.argv[1]) as f:
        fit = json.load(f)
    rows = fit["curve"]
    strain = [100.0 * row[0] for row in rows]
    largest = max(row[1] for row in rows)
    fig, (stress_axis, error_axis) = plt.subplots(2, 1, figsize=(6.4, 6.4), sharex=True,
                                                  gridspec_kw={"height_ratios": [2, 1]})
    stress_axis.plot(strain, [1e-3 * row[1] for row in rows], "o", markersize=3,
                     label="measured")
    stress_axis.plot(strain, [1e-3 * row[2] for row in rows], "-", linewidth=1.2,
                     label="model: E {:.4g} kPa, alpha {:.3g}, beta {:.3g}".format(
                         1e-3 * fit["youngs"], fit["alpha"], fit["beta"]))
    stress_axis.set_ylabel("engineering stress (kPa)")
    stress_axis.set_title("{} (RMS {:.2f} % of the largest stress)".format(
        fit.get("label", "tensile fit"), 100.0 * fit["rms_error"]), fontsize=10)
    stress_axis.grid(True, color="0.9")
    stress_axis.legend(loc="upper left")
    error_axis.axhspan(-5.0, 5.0, color="0.92")
    error_axis.axhline(0.0, color="0.6", linewidth=0.8)
    error_axis.plot(strain, [100.0 * (row[2] - row[1]) / largest for row in rows], "o-",
                    markersize=3)
    error_axis.set_ylabel("model - measured (%)")
    error_axis.set_xlabel("engineering strain (%)")
    error_axis.grid(True, color="0.9")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()

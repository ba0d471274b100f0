"""Plot of a poisson-sweep: measured Poisson's ratio against the dispersion ratio Q, with the
eMSM theory nu(Q) = (1 + 5Q/3) / (2 (2 + 5Q/3)) (Kot & Nagahashi 2015, figs. 7-8).

Usage: python3 plot_poisson_sweep.py SWEEP.json OUT.png   (msm_lab poisson-sweep --plot runs it)
"""
import json
import sys


def main():
    if len(sys.argv) != 3:
        sys.exit("usage: plot_poisson_sweep.py SWEEP.json OUT.png")
    try:
        import matplotlib
        matplotlib.use("Agg")
        import matplotlib.pyplot as plt
        import numpy as np
    except ImportError:
        sys.exit("plotting needs matplotlib: apt-get install python3-matplotlib")
    with open(sys.argv[1]) as f:
        sweep = json.load(f)
    rows = sweep["results"]
    q_measured = [r["dispersion_ratio"] for r in rows]
    nu_measured = [r["poisson_measured"] for r in rows]
    q_max = max(q_measured + [1.0])
    q = np.concatenate([np.linspace(-0.999, 1.0, 200), np.geomspace(1.0, q_max * 1.2, 200)])
    s = 5.0 * q / 3.0
    theory = (1.0 + s) / (2.0 * (2.0 + s))

    fig, ax = plt.subplots(figsize=(6.4, 4.4))
    ax.plot(q, theory, color="tab:red", label="theory nu(Q)")
    ax.plot(q_measured, nu_measured, "o", color="tab:blue", label="measured")
    ax.set_xscale("symlog", linthresh=1.0)
    ax.set_xlabel("dispersion ratio Q = B / K_direct")
    ax.set_ylabel("Poisson's ratio")
    ax.set_ylim(-1.0, 0.5)
    ax.axhline(0.5, color="0.8", linewidth=0.8)
    ax.grid(True, which="both", color="0.9")
    ax.set_title("{} eMSM, {} nodes".format(sweep["model"], rows[0]["nodes"]))
    ax.legend(loc="lower right")
    fig.tight_layout()
    fig.savefig(sys.argv[2], dpi=120)


if __name__ == "__main__":
    main()

#!/usr/bin/env python3
"""The uniaxial tensile curve of a compressible neo-Hookean or Mooney-Rivlin solid, written
analytically, for `msm_lab fit --tensile` (docs/materials.md, "From a hyperelastic law").

    W = C10 (I1bar - 3) + C01 (I2bar - 3) + (J - 1)^2 / D1

as CalculiX's *HYPERELASTIC, NEO HOOKE (C01 = 0) and MOONEY-RIVLIN define it. Under uniaxial
stress with axial stretch l and lateral stretch t, J = l t^2 and bbar = J^(-2/3) diag(l^2, t^2,
t^2); the Cauchy stress is

    sigma = (2 / J) dev[(C10 + C01 I1bar) bbar - C01 bbar^2] + (2 / D1) (J - 1) I,

t is the root of sigma_yy = 0 (bisection) and the engineering stress is sigma_xx t^2.
Give either --youngs and --poisson (C10 = mu / 2, C01 = 0, D1 = 2 / K, the small-strain moduli of
a neo-Hookean solid) or the deck's --c10, --c01, --d1 (Pa, Pa, 1/Pa; small-strain mu = 2 (C10 +
C01), K = 2 / D1). Writes CSV rows "Engineering Strain,Engineering Stress (Pa)" from 0 to
--max-strain.

  hyperelastic_tensile.py --youngs 259e3 --poisson 0.49 --out curve.csv
"""
import argparse
import sys


def stresses(stretch, lateral, c10, c01, d1):
    """(sigma_xx, sigma_yy) for stretches (l, t)."""
    j = stretch * lateral * lateral
    scale = j ** (-2.0 / 3.0)
    b = [scale * stretch ** 2, scale * lateral ** 2]
    i1 = b[0] + 2.0 * b[1]
    a = [(c10 + c01 * i1) * bi - c01 * bi * bi for bi in b]
    mean = (a[0] + 2.0 * a[1]) / 3.0
    pressure = 2.0 / d1 * (j - 1.0)
    return (2.0 / j * (a[0] - mean) + pressure, 2.0 / j * (a[1] - mean) + pressure)


def engineering_stress(strain, c10, c01, d1):
    stretch = 1.0 + strain
    low, high = 1e-3, 1.0  # sigma_yy > 0 at t = 1 in tension, < 0 as t -> 0
    for _ in range(200):
        middle = 0.5 * (low + high)
        if stresses(stretch, middle, c10, c01, d1)[1] > 0.0:
            high = middle
        else:
            low = middle
    lateral = 0.5 * (low + high)
    return stresses(stretch, lateral, c10, c01, d1)[0] * lateral * lateral


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--youngs", type=float)
    parser.add_argument("--poisson", type=float)
    parser.add_argument("--c10", type=float)
    parser.add_argument("--c01", type=float, default=0.0)
    parser.add_argument("--d1", type=float)
    parser.add_argument("--max-strain", type=float, default=1.0)
    parser.add_argument("--points", type=int, default=100)
    parser.add_argument("--out", required=True)
    args = parser.parse_args()
    if args.youngs is not None and args.poisson is not None and args.c10 is None:
        if not (args.youngs > 0.0 and -1.0 < args.poisson < 0.5):
            sys.exit("hyperelastic_tensile.py: error: E must be > 0 and nu in (-1, 0.5)")
        c10 = args.youngs / (4.0 * (1.0 + args.poisson))
        c01, d1 = 0.0, 6.0 * (1.0 - 2.0 * args.poisson) / args.youngs
    elif args.c10 is not None and args.d1 is not None and args.youngs is None:
        c10, c01, d1 = args.c10, args.c01, args.d1
        if not (c10 + c01 > 0.0 and d1 > 0.0):
            sys.exit("hyperelastic_tensile.py: error: C10 + C01 and D1 must be > 0")
    else:
        sys.exit("hyperelastic_tensile.py: error: give --youngs and --poisson, or --c10 [--c01] "
                 "and --d1")
    with open(args.out, "w") as out:
        out.write("# hyperelastic_tensile.py: C10 %.9g Pa, C01 %.9g Pa, D1 %.9g 1/Pa\n"
                  % (c10, c01, d1))
        out.write("Engineering Strain,Engineering Stress (Pa)\n")
        for k in range(args.points + 1):
            strain = args.max_strain * k / args.points
            out.write("%.6g,%.9g\n" % (strain, engineering_stress(strain, c10, c01, d1)))


if __name__ == "__main__":
    main()

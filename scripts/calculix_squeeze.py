#!/usr/bin/env python3
"""The CalculiX reference of `msm_lab squeeze` (issue 61): a compressible neo-Hookean sphere
between two rigid, frictionless, flat plates, closed under displacement control.

By symmetry the deck models a quarter of the sphere's meridian section: axisymmetric CAX8R
elements (r >= 0, y >= 0), the equator y = 0 a symmetry plane (u_y = 0), the axis r = 0 held
radially, and one plate, which touches the pole at the start and moves down by half the total
approach. Material: *HYPERELASTIC, NEO HOOKE with C10 = mu / 2 and D1 = 2 / K from the
small-strain E and nu (scripts/hyperelastic_tensile.py writes its uniaxial curve). NLGEOM, fixed
increments. The plate's nodes are all displaced as one (a rigid plate: its elements only carry
the master surface); node-to-surface penalty contact without friction.

Writes CSV rows approach_m,force_N,contact_radius_m: the total approach of both plates, the
force on one plate (minus the deck's vertical reaction times 180: CalculiX expands axisymmetric
elements over a 2 degree segment and reports forces for that segment) and the radius of the
contact patch (the largest deformed radius of a surface node less than 1e-5 R below the plate). Usage:

  calculix_squeeze.py --poisson 0.49 --elements 16 --out curve.csv [--ccx ccx]

Runs `ccx` (OMP_NUM_THREADS=1) in a temporary directory; --keep DIR keeps the deck there.
"""
import argparse
import math
import os
import re
import shutil
import subprocess
import sys
import tempfile


def quarter_disk(radius, n):
    """Nodes {key: (r, y)} and CAX8 elements (8 node keys, counter-clockwise) of the quarter disk:
    an inner square of side 0.55 R (n x n) and two patches between its edges and the arc (n x n
    each), built from (2n + 1)^2 point grids so that the midside nodes lie on the mapping."""
    a = 0.55 * radius
    q = math.pi / 4.0

    def inner(u, v):
        return (a * u, a * v)

    def top(u, v):  # square's top edge to the arc from the pole down to 45 degrees
        return ((1 - v) * a * u + v * radius * math.sin(q * u),
                (1 - v) * a + v * radius * math.cos(q * u))

    def side(u, v):  # square's right edge to the arc from the equator up to 45 degrees
        return ((1 - v) * a + v * radius * math.cos(q * u),
                (1 - v) * a * u + v * radius * math.sin(q * u))

    nodes, elements = {}, []

    def key(p):
        return (round(p[0] / radius * 1e8), round(p[1] / radius * 1e8))

    for patch in (inner, top, side):
        grid = [[patch(i / (2.0 * n), j / (2.0 * n)) for j in range(2 * n + 1)]
                for i in range(2 * n + 1)]
        for i in range(0, 2 * n, 2):
            for j in range(0, 2 * n, 2):
                corners = [(i, j), (i + 2, j), (i + 2, j + 2), (i, j + 2)]
                mids = [(i + 1, j), (i + 2, j + 1), (i + 1, j + 2), (i, j + 1)]
                pts = [grid[c][d] for c, d in corners]
                area = sum(pts[k][0] * pts[(k + 1) % 4][1] - pts[(k + 1) % 4][0] * pts[k][1]
                           for k in range(4))
                if area < 0:  # a mirrored patch: reverse the order, keep midsides between
                    corners = [corners[0], corners[3], corners[2], corners[1]]
                    mids = [mids[3], mids[2], mids[1], mids[0]]
                element = []
                for c, d in corners + mids:
                    p = grid[c][d]
                    nodes.setdefault(key(p), p)
                    element.append(key(p))
                elements.append(element)
    return nodes, elements


def write_analysis(deck, args, mu, bulk):
    """The materials, the frictionless contact, the supports and the displacement-controlled
    step of the deck; returns the plate's drop (m, half the total approach)."""
    radius, n = args.radius, args.elements
    deck.write("*MATERIAL, NAME=RUBBER\n*HYPERELASTIC, NEO HOOKE\n%.12g, %.12g\n"
               % (mu / 2.0, 2.0 / bulk))
    deck.write("*MATERIAL, NAME=STEEL\n*ELASTIC\n%.12g, 0.3\n" % (1e4 * args.youngs))
    deck.write("*SOLID SECTION, ELSET=SPHERE, MATERIAL=RUBBER\n")
    deck.write("*SOLID SECTION, ELSET=PLATE, MATERIAL=STEEL\n")
    # Penalty slope (pressure per overclosure): at a contact pressure of order E the
    # overclosure is a thousandth of an element, far below the approach of a row.
    element = radius / (2.0 * n)
    deck.write("*CONTACT PAIR, INTERACTION=SI, TYPE=NODE TO SURFACE\nSSLAVE, SMASTER\n")
    deck.write("*SURFACE INTERACTION, NAME=SI\n*SURFACE BEHAVIOR, PRESSURE-OVERCLOSURE="
               "LINEAR\n%.12g, %.12g\n" % (1e3 * args.youngs / element, 1e-3 * args.youngs))
    deck.write("*BOUNDARY\nNEQUATOR, 2, 2\nNAXIS, 1, 1\nNPLATE, 1, 1\n")
    drop = 0.5 * args.approach_fraction * 2.0 * radius
    deck.write("*STEP, NLGEOM, INC=10000\n*STATIC, DIRECT\n%.6g, 1.0\n"
               % (1.0 / args.increments))
    deck.write("*BOUNDARY\nNPLATE, 2, 2, %.12g\n" % -drop)
    deck.write("*NODE PRINT, NSET=NPLATE, TOTALS=ONLY\nRF\n")
    deck.write("*NODE PRINT, NSET=NSURF\nU\n*END STEP\n")
    return drop


def write_deck(path, args):
    radius, n = args.radius, args.elements
    mu = args.youngs / (2.0 * (1.0 + args.poisson))
    bulk = args.youngs / (3.0 * (1.0 - 2.0 * args.poisson))
    nodes, elements = quarter_disk(radius, n)
    number = {k: i + 1 for i, k in enumerate(nodes)}
    plate_r = 1.4 * radius
    plate_n = 4 * n
    thickness = 0.1 * radius
    plate = {}
    for i in range(2 * plate_n + 1):
        for j in range(3):
            plate[(i, j)] = len(number) + len(plate) + 1
    with open(path, "w") as deck:
        deck.write("*NODE, NSET=NALL\n")
        for k, (r, y) in nodes.items():
            deck.write("%d, %.12g, %.12g\n" % (number[k], r, y))
        for (i, j), m in plate.items():
            deck.write("%d, %.12g, %.12g\n" % (m, plate_r * i / (2 * plate_n),
                                               radius + 0.5 * thickness * j))
        deck.write("*ELEMENT, TYPE=CAX8R, ELSET=SPHERE\n")
        for e, element in enumerate(elements):
            deck.write("%d, %s\n" % (e + 1, ", ".join(str(number[k]) for k in element)))
        deck.write("*ELEMENT, TYPE=CAX8R, ELSET=PLATE\n")
        first = len(elements) + 1
        for e in range(plate_n):
            i = 2 * e
            order = [(i, 0), (i + 2, 0), (i + 2, 2), (i, 2), (i + 1, 0), (i + 2, 1), (i + 1, 2),
                     (i, 1)]
            deck.write("%d, %s\n" % (first + e, ", ".join(str(plate[o]) for o in order)))
        surface = [number[k] for k, (r, y) in nodes.items()
                   if abs(math.hypot(r, y) - radius) < 1e-7 * radius]
        sets = {
            "NSURF": surface,
            "NEQUATOR": [number[k] for k, (r, y) in nodes.items() if abs(y) < 1e-9 * radius],
            "NAXIS": [number[k] for k, (r, y) in nodes.items() if abs(r) < 1e-9 * radius],
            "NPLATE": list(plate.values()),
        }
        for name, members in sets.items():
            deck.write("*NSET, NSET=%s\n" % name)
            deck.write("".join("%d,\n" % m for m in members))
        deck.write("*ELSET, ELSET=EPLATE\n%s\n" % ",\n".join(
            str(first + e) for e in range(plate_n)))
        deck.write("*SURFACE, NAME=SSLAVE, TYPE=NODE\nNSURF\n")
        deck.write("*SURFACE, NAME=SMASTER\nEPLATE, S1\n")
        drop = write_analysis(deck, args, mu, bulk)
    return {number[k]: p for k, p in nodes.items() if number[k] in set(surface)}, drop


def parse(dat, surface, drop, radius):
    """Rows (approach, force, contact radius) of every increment in the .dat file."""
    rows, time, force, displaced = [], None, None, {}
    block = None
    for line in open(dat):
        header = re.match(r"\s*(total force|displacements).*time\s+(\S+)", line)
        if header:
            block, time = header.group(1), float(header.group(2))
            if block == "displacements":
                displaced = {}
            continue
        values = line.split()
        if block == "total force" and len(values) == 3:
            force = -float(values[1]) * 180.0  # the plate pushes down
            block = None
        elif block == "displacements" and len(values) == 4:
            displaced[int(values[0])] = (float(values[1]), float(values[2]))
            if len(displaced) == len(surface):
                plate_y = radius - drop * time
                tolerance = 1e-5 * radius
                contact = [surface[m][0] + u[0] for m, u in displaced.items()
                           if surface[m][1] + u[1] > plate_y - tolerance]
                rows.append((2.0 * drop * time, force, max(contact) if contact else 0.0))
                block = None
    return rows


def main():
    parser = argparse.ArgumentParser(description=__doc__.split("\n")[0])
    parser.add_argument("--radius", type=float, default=0.025)
    parser.add_argument("--youngs", type=float, default=259e3)
    parser.add_argument("--poisson", type=float, required=True)
    parser.add_argument("--approach-fraction", type=float, default=0.3,
                        help="total approach over the diameter")
    parser.add_argument("--elements", type=int, default=16, help="elements along a 45 deg arc")
    parser.add_argument("--increments", type=int, default=60)
    parser.add_argument("--ccx", default="ccx")
    parser.add_argument("--out", required=True)
    parser.add_argument("--keep", help="write the deck and CalculiX's files here")
    args = parser.parse_args()
    if not 0.0 < args.approach_fraction < 1.0 or not -1.0 < args.poisson < 0.5:
        sys.exit("calculix_squeeze.py: error: the approach fraction must be in (0, 1) and nu "
                 "in (-1, 0.5)")
    if shutil.which(args.ccx) is None:
        sys.exit("calculix_squeeze.py: error: %s not found (install calculix-ccx)" % args.ccx)
    directory = args.keep or tempfile.mkdtemp(prefix="msm_sim_squeeze_")
    os.makedirs(directory, exist_ok=True)
    surface, drop = write_deck(os.path.join(directory, "squeeze.inp"), args)
    environment = dict(os.environ, OMP_NUM_THREADS="1", CCX_NPROC_EQUATION_SOLVER="1")
    run = subprocess.run([args.ccx, "-i", "squeeze"], cwd=directory, env=environment,
                         capture_output=True, text=True)
    rows = parse(os.path.join(directory, "squeeze.dat"), surface, drop, args.radius)
    if not args.keep:
        shutil.rmtree(directory, ignore_errors=True)
    if run.returncode != 0 or not rows or rows[-1][0] < 2.0 * drop * (1 - 1e-9):
        sys.exit("calculix_squeeze.py: error: ccx stopped at approach %.4g m of %.4g: %s"
                 % (rows[-1][0] if rows else 0.0, 2.0 * drop,
                    (run.stdout.strip().splitlines() or ["no output"])[-1]))
    with open(args.out, "w") as out:
        out.write("# calculix_squeeze.py --radius %g --youngs %g --poisson %g --elements %d "
                  "--increments %d\napproach_m,force_N,contact_radius_m\n"
                  % (args.radius, args.youngs, args.poisson, args.elements, args.increments))
        for row in rows:
            out.write("%.6e,%.6e,%.6e\n" % row)


if __name__ == "__main__":
    main()

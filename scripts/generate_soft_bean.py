#!/usr/bin/env python3
"""Writes meshes/soft_bean.obj: a closed, bent ellipsoid ("bean") of 5,120 triangles, 12 x 7 x 6 cm.

A stand-in for a scanned soft object: smooth, with a concave side (so springs of a random MSM must
not bridge it), several thousand triangles. An icosphere subdivided 4 times, scaled to semi-axes
(60, 35, 30) mm and bent by y += 8 x^2 (m), a shear that cannot self-intersect. Units: metres.
Deterministic: running it again writes the same file.
"""
import math
import os

def icosphere(subdivisions):
    g = (1 + math.sqrt(5)) / 2
    v = [(-1, g, 0), (1, g, 0), (-1, -g, 0), (1, -g, 0), (0, -1, g), (0, 1, g), (0, -1, -g),
         (0, 1, -g), (g, 0, -1), (g, 0, 1), (-g, 0, -1), (-g, 0, 1)]
    v = [tuple(c / math.sqrt(sum(x * x for x in p)) for c in p) for p in v]
    f = [(0, 11, 5), (0, 5, 1), (0, 1, 7), (0, 7, 10), (0, 10, 11), (1, 5, 9), (5, 11, 4),
         (11, 10, 2), (10, 7, 6), (7, 1, 8), (3, 9, 4), (3, 4, 2), (3, 2, 6), (3, 6, 8), (3, 8, 9),
         (4, 9, 5), (2, 4, 11), (6, 2, 10), (8, 6, 7), (9, 8, 1)]
    for _ in range(subdivisions):
        cache = {}
        def middle(a, b):
            key = (min(a, b), max(a, b))
            if key not in cache:
                m = [(v[a][i] + v[b][i]) / 2 for i in range(3)]
                n = math.sqrt(sum(x * x for x in m))
                v.append(tuple(x / n for x in m))
                cache[key] = len(v) - 1
            return cache[key]
        finer = []
        for a, b, c in f:
            ab, bc, ca = middle(a, b), middle(b, c), middle(c, a)
            finer += [(a, ab, ca), (b, bc, ab), (c, ca, bc), (ab, bc, ca)]
        f = finer
    return v, f

def main():
    vertices, faces = icosphere(4)
    out = os.path.join(os.path.dirname(os.path.abspath(__file__)), '..', 'meshes', 'soft_bean.obj')
    with open(out, 'w') as obj:
        obj.write('# soft_bean: bent ellipsoid, 12 x 7 x 6 cm, metres (scripts/generate_soft_bean.py)\n')
        for x, y, z in vertices:
            x, y, z = 0.060 * x, 0.035 * y, 0.030 * z
            y += 8.0 * x * x
            obj.write('v %.7f %.7f %.7f\n' % (x, y, z))
        for a, b, c in faces:
            obj.write('f %d %d %d\n' % (a + 1, b + 1, c + 1))

if __name__ == '__main__':
    main()

#!/usr/bin/env python3
"""Young's modulus along a lattice axis of the discrete LPS material.

  python3 lattice_modulus.py [--delta D ...] [--omega EXPR] [--K K] [--G G]

PeriDeal's LPS (linear peridynamic solid) at a point of a cubic lattice of
spacing h, far from any surface, with the horizon D h and the influence
function omega(r), r = |xi| / horizon. Under a homogeneous strain eps every
bond has e = xi.eps.xi / |xi|, the weighted volume m and the dilatation are
computed from the discrete family as in the code, and the strain energy
density is

  W = K/2 (tr eps)^2 + (15 G / m) / 2 sum_j omega_j |xi_j|^2 (n_j.dev(eps).n_j)^2

(the cell volumes h^3 cancel). The lattice's second moments are isotropic, so
the dilatation is exact; its fourth moments are only cubic, so the discrete
material is cubic, not isotropic: C11, C12 and C44 of d2W/deps2 differ from
K + 4G/3, K - 2G/3 and G, and Young's modulus along an axis,
E100 = (C11 - C12)(C11 + 2 C12) / (C11 + C12), differs from 9KG/(3K+G).
This is what a uniaxial test of a thick specimen measures with a cubic grid,
and it does not change when the grid is refined at a fixed D.
"""

import argparse
import math

parser = argparse.ArgumentParser(description=__doc__,
                                 formatter_class=argparse.RawDescriptionHelpFormatter)
parser.add_argument("--delta", type=float, nargs="+", default=[3.015],
                    help="horizon over the spacing (default 3.015)")
parser.add_argument("--omega", default="1",
                    help="influence function of r = |xi|/horizon, a Python expression (default 1)")
parser.add_argument("--K", type=float, default=150.0, help="bulk modulus (default 150)")
parser.add_argument("--G", type=float, default=69.23, help="shear modulus (default 69.23)")
args = parser.parse_args()


def stiffness(delta):
    reach = int(delta) + 1
    family = []
    for i in range(-reach, reach + 1):
        for j in range(-reach, reach + 1):
            for k in range(-reach, reach + 1):
                length2 = i * i + j * j + k * k
                if 0 < length2 <= delta * delta:
                    r = math.sqrt(length2) / delta
                    family.append(((i, j, k), length2, eval(args.omega, {"math": math, "r": r})))
    m = sum(omega * length2 for _, length2, omega in family)

    def energy(v):  # Voigt: e11 e22 e33 2e23 2e13 2e12
        eps = [[v[0], v[5] / 2, v[4] / 2], [v[5] / 2, v[1], v[3] / 2], [v[4] / 2, v[3] / 2, v[2]]]
        trace = eps[0][0] + eps[1][1] + eps[2][2]
        dev = [[eps[a][b] - (trace / 3 if a == b else 0) for b in range(3)] for a in range(3)]
        s = 0.0
        for xi, length2, omega in family:
            q = sum(xi[a] * dev[a][b] * xi[b] for a in range(3) for b in range(3)) / length2
            s += omega * length2 * q * q
        return args.K / 2 * trace * trace + 15 * args.G / m / 2 * s

    def entry(a, b):  # W is quadratic: the central difference is exact
        def w(sa, sb):
            v = [0.0] * 6
            v[a] += sa
            v[b] += sb
            return energy(v)
        return (w(1, 1) - w(1, -1) - w(-1, 1) + w(-1, -1)) / 4

    return len(family), entry(0, 0), entry(0, 1), entry(3, 3)


K, G = args.K, args.G
E_classical = 9 * K * G / (3 * K + G)
print("isotropic: C11 %.2f C12 %.2f C44 %.2f E %.2f" % (K + 4 * G / 3, K - 2 * G / 3, G, E_classical))
for delta in args.delta:
    n, C11, C12, C44 = stiffness(delta)
    E100 = (C11 - C12) * (C11 + 2 * C12) / (C11 + C12)
    print("horizon %.3f h, omega = %s, %d bonds: C11 %.2f C12 %.2f C44 %.2f E100 %.2f (%+.2f%% from 9KG/(3K+G))"
          % (delta, args.omega, n, C11, C12, C44, E100, 100 * (E100 / E_classical - 1)))

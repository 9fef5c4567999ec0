"""Uniaxial stress along a grid axis of the discrete state-based model on the
cubic lattice of the dog-bone (horizon 3.015 spacings, omega = 1): the
Young's modulus E100 and the stress at which Elastic plastic yields, sigma /
q with q = sqrt(m/5) ||t^d|| its von Mises measure (q = Y at yield). The
infinite lattice, small strain; no surface.

  python3 lattice_yield.py      (numpy only)
"""
import itertools

import numpy as np

K, G, delta = 150e9, 69.23e9, 3.015
xi = np.array([p for p in itertools.product(range(-3, 4), repeat=3) if 0 < np.dot(p, p) <= delta**2], float)
r = np.linalg.norm(xi, axis=1)
n = xi / r[:, None]
m = np.sum(r * r)                   # weighted volume, V_j = 1
alpha = 15 * G / m
pairs = [(0, 0), (1, 1), (2, 2), (0, 1), (0, 2), (1, 2)]


def state(eps):
    """Stress sum_j t xi^ (x) xi V_j and q of the homogeneous strain eps."""
    e = np.einsum("ij,jk,ik->i", n, eps, n) * r
    theta = 3 / m * np.sum(r * e)
    ed = e - theta * r / 3
    t = 3 * K * theta / m * r + alpha * ed
    return np.einsum("i,ij,ik->jk", t, n, xi), np.sqrt(m / 5 * np.sum((alpha * ed) ** 2))


# stiffness in Voigt-like pairs, then the strain of a unit uniaxial stress along x
C = np.zeros((6, 6))
for a, (i, j) in enumerate(pairs):
    E = np.zeros((3, 3))
    E[i, j] = E[j, i] = 1
    s, _ = state(E)
    C[:, a] = [s[p, q] for p, q in pairs]
x = np.linalg.solve(C, np.array([1.0, 0, 0, 0, 0, 0]))
E = np.zeros((3, 3))
for a, (i, j) in enumerate(pairs):
    E[i, j] = E[j, i] = x[a]
s, q = state(E)
print("E100 = %.2f GPa (9KG/(3K+G) = %.2f GPa)" % (s[0, 0] / E[0, 0] / 1e9, 9 * K * G / (3 * K + G) / 1e9))
print("uniaxial stress at yield: sigma = %.4f Y" % (s[0, 0] / q))

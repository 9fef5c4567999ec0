#!/usr/bin/env python3
"""Writes box_tets_points.txt: the tetrahedra of box_tets.msh (Gmsh 4.1 ASCII)
as Peridigm Text File points, 'x y z block volume' (the centroid, the volume
physical group, det/6), independently of PeriDeal's reader; run once:
python3 box_tets_points.py box_tets.msh > box_tets_points.txt"""
import sys

lines = [l.split() for l in open(sys.argv[1]) if l.strip()]
i = 0
nodes, physical, points = {}, {}, []
while i < len(lines):
    head = lines[i][0]
    if head == "$Entities":
        counts = [int(c) for c in lines[i + 1][:4]]
        i += 2
        for d in range(4):
            for _ in range(counts[d]):
                t = lines[i]
                n = 4 if d == 0 else 7
                physical[(d, int(t[0]))] = int(t[n + 1]) if int(t[n]) > 0 else 0
                i += 1
    elif head == "$Nodes":
        blocks = int(lines[i + 1][0])
        i += 2
        for _ in range(blocks):
            n = int(lines[i][3])
            tags = [int(lines[i + 1 + k][0]) for k in range(n)]
            for k in range(n):
                nodes[tags[k]] = [float(c) for c in lines[i + 1 + n + k][:3]]
            i += 1 + 2 * n
    elif head == "$Elements":
        blocks = int(lines[i + 1][0])
        i += 2
        for _ in range(blocks):
            entity_dim, entity, kind, n = (int(c) for c in lines[i][:4])
            for k in range(n):
                if kind == 4:
                    v = [nodes[int(t)] for t in lines[i + 1 + k][1:5]]
                    e = [[v[j][d] - v[0][d] for d in range(3)] for j in (1, 2, 3)]
                    det = (e[0][0] * (e[1][1] * e[2][2] - e[1][2] * e[2][1])
                           - e[0][1] * (e[1][0] * e[2][2] - e[1][2] * e[2][0])
                           + e[0][2] * (e[1][0] * e[2][1] - e[1][1] * e[2][0]))
                    c = [(v[0][d] + v[1][d] + v[2][d] + v[3][d]) / 4 for d in range(3)]
                    points.append((c, physical[(entity_dim, entity)], det / 6))
            i += 1 + n
    else:
        i += 1
print("# The %d tetrahedra of box_tets.msh as points: x y z block volume" % len(points))
print("# (box_tets_points.py: the centroid, the volume physical group, det/6).")
for c, block, volume in points:
    print(repr(c[0]), repr(c[1]), repr(c[2]), block, repr(volume))

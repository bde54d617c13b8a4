#!/usr/bin/env python3
"""A median-split BVH over an OBJ mesh, written in accelviz's exchange format
(docs/structure-format.md), in plain Python. Check it with
    accelviz check MESH.obj tree.json
Usage: median_bvh.py MESH.obj tree.json [max triangles per leaf, default 4]"""
import json, sys, zlib

def read_obj(path):
    verts, tris = [], []
    for line in open(path, encoding="utf-8", errors="replace"):
        w = line.split()
        if w and w[0] == "v":
            verts.append(tuple(float(x) for x in w[1:4]))
        elif w and w[0] == "f":  # a polygon is split as a fan, as accelviz reads it
            ids = [int(c.split("/")[0]) for c in w[1:]]
            ids = [i - 1 if i > 0 else len(verts) + i for i in ids]
            tris += [(ids[0], ids[k], ids[k + 1]) for k in range(1, len(ids) - 1)]
    return [[verts[i] for i in t] for t in tris]

def box(tris, ids):
    pts = [p for t in ids for p in tris[t]]
    return [min(p[a] for p in pts) for a in range(3)] + [max(p[a] for p in pts) for a in range(3)]

def build(tris, ids, first, nodes, leaf_size):
    """Appends the node over triangles ids (at order[first:]) and its subtree; returns its index."""
    me = len(nodes)
    nodes.append({"box": box(tris, ids)})
    if len(ids) <= leaf_size:
        nodes[me].update(first=first, count=len(ids))
        return me
    b = nodes[me]["box"]
    axis = max(range(3), key=lambda a: b[a + 3] - b[a])  # the longest axis
    ids.sort(key=lambda t: sum(p[axis] for p in tris[t]))  # by centroid (times 3)
    half = len(ids) // 2  # the median
    left, right = ids[:half], ids[half:]
    l = build(tris, left, first, nodes, leaf_size)
    r = build(tris, right, first + half, nodes, leaf_size)
    ids[:] = left + right  # the children sorted their halves further: keep that order
    nodes[me]["children"] = [l, r]
    return me

def main(mesh, out, leaf_size=4):
    sys.setrecursionlimit(10000)
    tris = read_obj(mesh)
    order, nodes = list(range(len(tris))), []
    if tris:
        build(tris, order, 0, nodes, int(leaf_size))
    crc = zlib.crc32(open(mesh, "rb").read())
    doc = {"format": "accelviz-structure", "version": 1, "type": "bvh", "builder": "median_bvh.py",
           "mesh": {"path": mesh, "triangles": len(tris), "crc32": "%08x" % crc},
           "order": order, "nodes": nodes}
    json.dump(doc, open(out, "w"))

if __name__ == "__main__":
    main(*sys.argv[1:])

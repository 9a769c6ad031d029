# SPDX-License-Identifier: Apache-2.0
"""Disjoint copies of a T-mesh in its JSON form, as tests/integration/tmesh_copies.cc makes them:
larger real meshes whose solves take long enough to be watched, made from a bundled sample."""
import copy
import json
import sys


def _shift(ids, offset):
    return [i + offset if i >= 0 else i for i in ids]

def _shifted(i, offset):
    return i + offset if i >= 0 else i

def disjoint_copies(mesh, copies):
    """copies disjoint copies of mesh in one T-mesh (as tests/integration/tmesh_copies.cc)."""
    counts = {key: len(mesh.get(key, [])) for key in ("nodes", "arcs", "patches", "blocks")}
    dropped = ("levels", "stats", "nodes", "arcs", "patches", "blocks", "criticalEntities")
    result = {key: value for key, value in mesh.items() if key not in dropped}
    result["name"] = f"{mesh.get('name', '')}x{copies}"
    for key in counts:
        result[key] = []
    for k in range(copies):
        n, a, p, b = (k * counts[key] for key in ("nodes", "arcs", "patches", "blocks"))
        m = copy.deepcopy(mesh)
        for node in m.get("nodes", []):
            node["outgoingHalfarcs"] = _shift(node.get("outgoingHalfarcs", []), 2 * a)
        for arc in m.get("arcs", []):
            arc["from"] = _shifted(arc.get("from", 0), n)
            arc["to"] = _shifted(arc.get("to", 0), n)
            arc["halfpatches"] = _shift(arc.get("halfpatches", []), 2 * p)
        for patch in m.get("patches", []):
            patch["blocks"] = _shift(patch.get("blocks", []), b)
            patch["halfarcs"] = _shift(patch.get("halfarcs", []), 2 * a)
            patch["refBlock"] = _shifted(patch.get("refBlock", 0), b)
            for side in patch.get("halfarcsByDir", []):
                side["halfarcs"] = _shift(side.get("halfarcs", []), 2 * a)
        for block in m.get("blocks", []):
            for corner in block.get("corners", []):
                corner["node"] = _shifted(corner.get("node", 0), n)
            for edge in block.get("edges", []):
                edge["arcs"] = _shift(edge.get("arcs", []), a)
                edge["halfarcs"] = _shift(edge.get("halfarcs", []), 2 * a)
            for face in block.get("faces", []):
                face["patches"] = _shift(face.get("patches", []), p)
                face["arcs"] = _shift(face.get("arcs", []), a)
                face["nodes"] = _shift(face.get("nodes", []), n)
            block["halfpatches"] = _shift(block.get("halfpatches", []), 2 * p)
            for arcs in block.get("arcsByDir", []):
                arcs["arcs"] = _shift(arcs.get("arcs", []), a)
            for uvw in block.get("nodeUvw", []):
                uvw["node"] = _shifted(uvw.get("node", 0), n)
        for key in counts:
            result[key] += m.get(key, [])
    return result

if __name__ == "__main__":
    mesh = json.load(open(sys.argv[1]))
    json.dump(disjoint_copies(mesh, int(sys.argv[2])), open(sys.argv[3], "w"))

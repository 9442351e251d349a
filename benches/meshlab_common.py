"""What the side-by-side scripts against MeshLab share."""
import pymeshlab


def hausdorff_pct(original, result):
    """Symmetric Hausdorff distance between two mesh files (pymeshlab's
    `get_hausdorff_distance` both ways, max), as % of the original's bounding-box diagonal."""
    ms = pymeshlab.MeshSet()
    ms.load_new_mesh(original)
    ms.meshing_remove_unreferenced_vertices()
    ms.load_new_mesh(result)
    diag = ms.mesh(0).bounding_box().diagonal()
    there = ms.get_hausdorff_distance(sampledmesh=0, targetmesh=1, samplevert=True, sampleface=True)
    back = ms.get_hausdorff_distance(sampledmesh=1, targetmesh=0, samplevert=True, sampleface=True)
    return 100 * max(there["max"], back["max"]) / diag

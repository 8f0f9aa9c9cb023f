"""JASNOM against ground truth (thesis ch. 7, issues 14, 29): closed models cut in two, one half moved, stitched back.

Every model whose largest piece is a closed 2-manifold (``heatdata.jasnom.cuts.closed_part``)
from the embedded set and from Sweet Home 3D libraries (imported into a temporary
folder, never committed), and six smooth analytic shapes with a little asymmetry, is
cut by a plane and by a wavy surface (``split_model``) in a seeded random direction, at
a random offset of up to 10% of the size from the centre; one half gets a seeded random
rigid motion and JASNOM, at its defaults, puts it back. Per cut:

- rotation error, and translation error as the distance between where the found and the
  true motion put the moved half's centroid (so that it does not depend on where the
  file's origin is), over the size (the bounding-box diagonal);
- J at the found motion, at the true one, and the cheapest J among the poses the search
  visited that are more than 2 deg or 1% from the truth (the cost prefers the truth when
  J at the truth is at or below it), the runner-up's J and whether it is ambiguous;
- whether the stitched model is watertight and consistently wound (trimesh), both as
  returned and as read back from the PLY it writes (trimesh merges vertices on reading),
  and the symmetric Hausdorff distance from surface samples of each of the result and
  the original to the other's surface, over the size.

With ``--holes-out``, also the hole patching of 7.5 (Fig. 7.11): a cap of about 10% of
each model's faces is cut off, moved a little (a patch from another mesh) and stitched
back with beta = 0, beside pymeshlab's ``meshing_close_holes`` on the same hole.

    .venv/bin/python scripts/jasnom_cuts.py [--limit 30] [--out docs/results/jasnom_cuts.csv] \\
        [--holes-out docs/results/jasnom_holes.csv]
"""

from __future__ import annotations

import argparse
import tempfile
import time
from pathlib import Path

import numpy as np
import pandas as pd
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.core.mesh import surface_distances
from heatdata.errors import HeatdataError
from heatdata.io.catalog import embedded_catalog, load_catalog_model, read_catalog
from heatdata.io.models import Model, save_model, transformed
from heatdata.io.sh3f import import_sh3f
from heatdata.jasnom.align import align, alignment_at
from heatdata.jasnom.boundary import boundaries
from heatdata.jasnom.cuts import closed_part, split_model
from heatdata.jasnom.seam import stitch
from heatdata.log import progress

LIBRARIES = ["BlendSwap-CC-0", "BlendSwap-CC-BY", "KatorLegaz", "Scopia", "Contributions", "eTeks"]
FURNITURE = Path("/usr/share/sweethome3d/furniture")


def hausdorff(a: trimesh.Trimesh, b: trimesh.Trimesh) -> float:
    """Symmetric Hausdorff distance on 20,000 surface samples of each mesh."""
    there, back = surface_distances((a.vertices, a.faces), (b.vertices, b.faces))
    return float(max(there.max(), back.max()))


def close_with_pymeshlab(model) -> trimesh.Trimesh:
    """pymeshlab's close-holes filter on every hole of ``model`` (holes of up to all its boundary edges)."""
    import pymeshlab

    meshes = pymeshlab.MeshSet()
    meshes.add_mesh(pymeshlab.Mesh(vertex_matrix=model.vertices, face_matrix=model.faces.astype(np.int32)))
    meshes.meshing_close_holes(maxholesize=len(model.faces), selfintersection=False)
    closed = meshes.current_mesh()
    return trimesh.Trimesh(closed.vertex_matrix(), closed.face_matrix(), process=False)


def hole_row(model, rng, samples: int) -> dict:
    """Cut a cap of ~10% of the faces, patch it back with JASNOM (beta = 0) and with pymeshlab."""
    size = float(np.linalg.norm(model.extents))
    normal = rng.normal(size=3)
    normal /= np.linalg.norm(normal)
    heights = (model.vertices[model.faces].mean(axis=1) - model.center) @ normal
    body, cap = split_model(model, -normal, offset=-float(np.quantile(heights, 0.9)) / size)
    motion = Rotation.from_rotvec(rng.normal(scale=0.1, size=3))
    patch = transformed(cap, motion.as_matrix(), 0.02 * size * rng.normal(size=3))
    original = trimesh.Trimesh(model.vertices, model.faces, process=False)
    row = {"object": model.name, "faces": len(model.faces), "hole_faces": len(cap.faces)}
    start = time.perf_counter()
    try:
        result = stitch(body, patch, beta=0.0, samples=samples)
    except HeatdataError as error:
        return {**row, "error": str(error)}
    jasnom = trimesh.Trimesh(result.model.vertices, result.model.faces, process=False)
    row.update(
        jasnom_seconds=time.perf_counter() - start,
        jasnom_watertight=bool(jasnom.is_watertight),
        jasnom_hausdorff=hausdorff(original, jasnom) / size,
    )
    start = time.perf_counter()
    meshlab = close_with_pymeshlab(body)
    row.update(
        meshlab_seconds=time.perf_counter() - start,
        meshlab_watertight=bool(meshlab.is_watertight),
        meshlab_hausdorff=hausdorff(original, meshlab) / size,
        error="",
    )
    return row


def analytic_shapes() -> list[Model]:
    """Smooth closed shapes with a little asymmetry, the hardest for a boundary method: an ellipsoid cut by a plane
    has an elliptic, nearly symmetric boundary."""
    sphere = trimesh.creation.icosphere(subdivisions=4)
    v = sphere.vertices
    egg = v * [0.12, 0.09, 0.07] * (1.0 + 0.08 * v[:, [0]])
    bumpy = v * [0.1, 0.08, 0.06] * (1.0 + 0.03 * np.sin(3 * v[:, [0]] + 2 * v[:, [1]]))
    tilted = v * [0.1, 0.07, 0.05] + 0.02 * v[:, [0]] * v[:, [1]] * [0.0, 0.0, 1.0]
    capsule = trimesh.creation.capsule(height=0.15, radius=0.04, count=[48, 48])
    capsule.vertices *= [1.0, 0.8, 1.0] * (1.0 + 0.1 * (capsule.vertices[:, [2]] > 0))
    torus = trimesh.creation.torus(major_radius=0.1, minor_radius=0.035, major_sections=64, minor_sections=24)
    torus.vertices *= [1.0, 0.85, 1.0]
    cylinder = trimesh.creation.cylinder(radius=0.05, height=0.12, sections=64).subdivide().subdivide()
    cylinder.vertices[:, 0] *= 1.0 + 0.1 * (cylinder.vertices[:, 0] > 0)
    shapes = {
        "egg": (egg, sphere.faces),
        "bumpy-ellipsoid": (bumpy, sphere.faces),
        "tilted-ellipsoid": (tilted, sphere.faces),
        "capsule": (capsule.vertices, capsule.faces),
        "oval-torus": (torus.vertices, torus.faces),
        "lopsided-cylinder": (cylinder.vertices, cylinder.faces),
    }
    return [
        closed_part(Model.untextured(name, vertices, faces, (0.6, 0.6, 0.6), label="analytic"))
        for name, (vertices, faces) in shapes.items()
    ]


def candidates(folder: Path, limit: int, min_faces: int, max_faces: int) -> list:
    rows = [row for _, row in read_catalog(embedded_catalog()).iterrows()]
    for library in LIBRARIES:
        path = FURNITURE / f"{library}.sh3f"
        if path.is_file():
            import_sh3f(path, folder / library)
            rows += [row for _, row in read_catalog(folder / library / "catalog.csv").iterrows()]
    models = []
    for row in progress(rows, desc="closed models", unit="model"):
        try:
            part = closed_part(load_catalog_model(row))
        except HeatdataError:
            continue
        if min_faces <= len(part.faces) <= max_faces:
            models.append(part)
        if len(models) >= limit:
            break
    return models


def cut_row(model: Model, rng, args) -> list[dict]:
    """One random plane and one wavy cut of ``model`` (a random offset from the centre), one half moved at random."""
    size = float(np.linalg.norm(model.extents))
    original = trimesh.Trimesh(model.vertices, model.faces, process=False)
    normal = rng.normal(size=3)
    offset = float(rng.uniform(-0.1, 0.1))
    rotation = Rotation.random(random_state=int(rng.integers(1 << 31)))
    translation = 0.5 * size * rng.normal(size=3)
    rows = []
    for cut, amplitude in (("plane", 0.0), ("wavy", 0.03)):
        row = {
            "object": model.name,
            "kind": model.label or "model",
            "faces": len(model.faces),
            "size": size,
            "cut": cut,
            "offset": offset,
        }
        try:
            a, b = split_model(model, normal, offset=offset, amplitude=amplitude)
            b = transformed(b, rotation.as_matrix(), translation)
            start = time.perf_counter()
            b1, b2 = boundaries(a), boundaries(b)
            visited: list = []
            found = align(b1, b2, samples=args.samples, trace=visited)
            motion = np.eye(4)
            motion[:3, :3], motion[:3, 3] = found.rotation, found.translation
            result = stitch(a, b, samples=args.samples, motion=motion)
            seconds = time.perf_counter() - start
        except HeatdataError as error:
            rows.append({**row, "error": str(error)})
            continue
        truth_r, truth_t = rotation.inv().as_matrix(), -rotation.inv().apply(translation)
        truth = alignment_at(b1, b2, truth_r, truth_t, samples=args.samples).cost
        centre = b.vertices.mean(axis=0)  # the moved half's centroid: errors that do not depend on the origin
        wrong = [
            j
            for r, t, j in visited
            if np.degrees(Rotation.from_matrix(r @ truth_r.T).magnitude()) > 2
            or np.linalg.norm(r @ centre + t - truth_r @ centre - truth_t) > 0.01 * size
        ]
        mesh = trimesh.Trimesh(result.model.vertices, result.model.faces, process=False)
        with tempfile.TemporaryDirectory() as folder:  # as a user reads the file: trimesh merges vertices
            save_model(result.model, Path(folder) / "out.ply")
            reread = trimesh.load(Path(folder) / "out.ply")
        rows.append(
            {
                **row,
                "boundary": len(b1[0].loop),
                "loops": len(b1),
                "loop_pairs": result.loop_pairs,
                "open_loops": result.open_loops,
                "rotation_error_deg": float(np.degrees((Rotation.from_matrix(found.rotation) * rotation).magnitude())),
                "translation_error": float(
                    np.linalg.norm(found.rotation @ centre + found.translation - truth_r @ centre - truth_t)
                )
                / size,
                "watertight": bool(mesh.is_watertight and reread.is_watertight),
                "winding_consistent": bool(mesh.is_winding_consistent and reread.is_winding_consistent),
                "hausdorff": hausdorff(original, mesh) / size,
                "cost": found.cost,
                "cost_at_truth": truth,
                "cheapest_wrong": min(wrong, default=np.nan),
                "runner_up": found.runner_up,
                "ambiguous": found.ambiguous,
                "seconds": seconds,
                "error": "",
            }
        )
    return rows


def main() -> None:
    parser = argparse.ArgumentParser(description=__doc__.splitlines()[0])
    parser.add_argument("--limit", type=int, default=30, help="real models to cut (default 30)")
    parser.add_argument("--min-faces", type=int, default=200)
    parser.add_argument("--max-faces", type=int, default=40000)
    parser.add_argument("--samples", type=int, default=128)
    parser.add_argument("--seed", type=int, default=0)
    parser.add_argument("--out")
    parser.add_argument("--holes-out", help="also patch holes (7.5) and write their table here")
    args = parser.parse_args()
    begin = time.perf_counter()
    with tempfile.TemporaryDirectory() as folder:
        models = candidates(Path(folder), args.limit, args.min_faces, args.max_faces) + analytic_shapes()
    print(f"{len(models)} closed models in {time.perf_counter() - begin:.0f} s")
    rng = np.random.default_rng(args.seed)
    rows = [row for model in progress(models, desc="cut and stitch", unit="model") for row in cut_row(model, rng, args)]
    table = pd.DataFrame(rows)
    ok = table[table["error"] == ""]
    good = (ok["rotation_error_deg"] <= 2) & (ok["translation_error"] <= 0.01)
    prefers = (ok["cost_at_truth"] <= ok["cheapest_wrong"]) | ok["cheapest_wrong"].isna()
    print(table.drop(columns=["error"]).round(4).to_string(index=False))
    print(
        f"{len(ok)} of {len(table)} cuts stitched; rotation <= 2 deg and translation <= 1%: {good.mean():.1%} "
        f"({good.sum()}); watertight and consistently wound: "
        f"{(ok['watertight'] & ok['winding_consistent']).mean():.1%}; "
        f"Hausdorff <= 1%: {(ok['hausdorff'] <= 0.01).mean():.1%}; J at the truth at or below every wrong pose "
        f"visited: {prefers.mean():.1%}; ambiguous: {ok['ambiguous'].mean():.1%}; median "
        f"{ok['seconds'].median():.2f} "
        f"s a cut; {time.perf_counter() - begin:.0f} s in all"
    )
    if args.out:
        table.round(6).to_csv(args.out, index=False)
    if args.holes_out:
        holes = pd.DataFrame(
            [hole_row(model, rng, args.samples) for model in progress(models, desc="holes", unit="model")]
        )
        done = holes[holes["error"] == ""]
        print(holes.drop(columns=["error"]).round(4).to_string(index=False))
        print(
            f"{len(done)} of {len(holes)} holes patched; watertight: JASNOM {done['jasnom_watertight'].mean():.1%}, "
            f"pymeshlab {done['meshlab_watertight'].mean():.1%}; median Hausdorff to the original: JASNOM "
            f"{done['jasnom_hausdorff'].median():.2%}, pymeshlab {done['meshlab_hausdorff'].median():.2%}"
        )
        holes.round(6).to_csv(args.holes_out, index=False)


if __name__ == "__main__":
    main()

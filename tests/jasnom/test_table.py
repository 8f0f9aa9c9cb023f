"""The support-plane term of JASNOM on objects whose scans and bands are known: a box and a cylinder, scanned standing
and flipped from opposite sides with a band of grazing faces neither scan sees."""

import numpy as np
import pytest
import trimesh
from scipy.spatial.transform import Rotation

from heatdata.errors import StitchError
from heatdata.io.models import Model
from heatdata.jasnom.align import align
from heatdata.jasnom.boundary import boundaries
from heatdata.jasnom.cost import ScanSurface, _Curve, _weights
from heatdata.jasnom.defaults import TABLE
from heatdata.jasnom.table import TURNS, TableContact

ELEVATION = 35.0  # degrees: the camera above the table
DISTANCE = 0.6  # m


def scans(mesh: trimesh.Trimesh, band_degrees: float):
    """The object standing on the table y = 0 and flipped about x onto it, each seen by one camera above the table
    in front: each scan holds the faces that turn more than ``band_degrees`` towards the camera, in the camera's
    frame (a depth sensor's). Returns both scans, both planes (normal towards the object, camera frames) and the true
    motion of scan 2 into scan 1's frame."""
    from heatdata.views.render import camera_pose

    mesh = mesh.copy()
    mesh.apply_translation([0.0, -mesh.bounds[0, 1], 0.0])  # standing on y = 0
    flip = np.eye(4)
    flip[:3, :3] = Rotation.from_rotvec([np.pi, 0.0, 0.0]).as_matrix()
    flip[1, 3] = mesh.bounds[1, 1]  # its top on y = 0
    camera = camera_pose(np.array([0.0, 0.05, 0.0]), 0.0, ELEVATION, DISTANCE)
    to_camera = np.linalg.inv(camera)
    table = np.array([0.0, 1.0, 0.0, 0.0]) @ camera  # y = 0, normal up, in the camera frame
    found = []
    for pose in (np.eye(4), flip):
        placed = mesh.copy()
        placed.apply_transform(to_camera @ pose)
        facing = -np.einsum("ij,ij->i", placed.face_normals, placed.triangles_center)
        facing /= np.linalg.norm(placed.triangles_center, axis=1)
        keep = facing > np.sin(np.radians(band_degrees))
        found.append(Model.untextured("scan", placed.vertices, placed.faces[keep]))
    truth = to_camera @ np.linalg.inv(flip) @ camera
    return found[0], found[1], table, table, truth


def box() -> trimesh.Trimesh:
    """A box turned 45 deg about the vertical: the camera sees two sides and the top, the flipped scan the other two
    and the bottom; no face grazes, so there is no band."""
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_rotvec([0.0, np.pi / 4, 0.0]).as_matrix()
    return trimesh.creation.box(extents=[0.2, 0.1, 0.14], transform=turn).subdivide().subdivide()


def cylinder() -> trimesh.Trimesh:
    return trimesh.creation.cylinder(radius=0.05, height=0.12, sections=64, transform=_upright()).subdivide()


def _upright() -> np.ndarray:
    turn = np.eye(4)
    turn[:3, :3] = Rotation.from_rotvec([np.pi / 2, 0.0, 0.0]).as_matrix()  # trimesh's cylinders stand along z
    return turn


def scale_of(first: Model) -> float:
    return _weights(_Curve.of(boundaries(first), 128), 4.0, 1.0, 0.0, 1.0, 0.0, 128).scale


@pytest.mark.parametrize("make", [box, cylinder])
def test_the_term_is_zero_at_the_truth_grows_as_the_square_of_a_lift_and_ignores_a_slide(make):
    first, second, plane1, plane2, truth = scans(make(), 10.0)
    contact = TableContact.of(first, second, plane1, plane2)
    s = scale_of(first)
    rotation, translation = truth[:3, :3], truth[:3, 3]
    normal = plane1[:3]
    along = np.cross(normal, [1.0, 0.0, 0.0])

    def term(shift) -> float:
        return TABLE * float(np.sum(contact.residuals(rotation, translation + shift, s) ** 2))

    assert term(np.zeros(3)) < 1e-20
    for lift in (0.02 * s, 0.1 * s):  # both contacts rise by the lift: T = 2 table (lift / s)^2
        assert term(lift * normal) == pytest.approx(2 * TABLE * (lift / s) ** 2, rel=1e-6)
    assert term(-0.05 * s * normal) > term(0.05 * s * normal)  # sinking into the table costs more
    assert term(0.3 * s * along) < 1e-20  # sliding along the table: nothing


def test_the_flip_candidates_turn_the_flipped_scan_upright_onto_the_table():
    first, second, plane1, plane2, truth = scans(box(), 10.0)
    contact = TableContact.of(first, second, plane1, plane2)
    rotations, translations = contact.flip_candidates()
    assert len(rotations) == TURNS
    np.testing.assert_allclose(rotations @ plane2[:3], np.tile(-plane1[:3], (TURNS, 1)), atol=1e-12)
    heights = [contact.heights(r, t)[0] for r, t in zip(rotations, translations, strict=True)]
    np.testing.assert_allclose([np.quantile(h, 0.02) for h in heights], 0.0, atol=1e-12)
    errors = np.degrees(Rotation.from_matrix(rotations @ truth[:3, :3].T).magnitude())
    assert errors.min() <= 180.0 / TURNS + 1e-9


def height_error(found, truth: np.ndarray, second: Model, normal: np.ndarray) -> float:
    """How far the motion found puts the flipped scan's centroid from the truth along the table normal, in metres."""
    centre = second.vertices.mean(axis=0)
    return abs(float((found.rotation @ centre + found.translation - truth[:3, :3] @ centre - truth[:3, 3]) @ normal))


@pytest.mark.slow
def test_without_a_band_the_box_is_found_exactly_with_or_without_its_table():
    first, second, plane1, plane2, truth = scans(box(), 10.0)
    loops1, loops2 = boundaries(first), boundaries(second)
    surfaces = (ScanSurface.of(first), ScanSurface.of(second))
    contact = TableContact.of(first, second, plane1, plane2)
    for found in (
        align(loops1, loops2, samples=64, along=0.1, robust=0.05, scans=surfaces),
        align(loops1, loops2, samples=64, along=0.1, robust=0.05, scans=surfaces, contact=contact),
    ):
        assert np.degrees(Rotation.from_matrix(found.rotation @ truth[:3, :3].T).magnitude()) < 1e-4
        np.testing.assert_allclose(found.translation, truth[:3, 3], atol=1e-6)
    assert found.table_cost < 1e-20
    assert found.cost == pytest.approx(found.edge_cost + found.crossing_cost + found.table_cost, rel=1e-9)


@pytest.mark.slow
def test_the_table_holds_the_cylinder_at_its_height_where_the_band_lets_it_sink():
    first, second, plane1, plane2, truth = scans(cylinder(), 10.0)  # a band 2 r sin(10 deg) wide each side
    size = float(np.linalg.norm(cylinder().extents))
    loops1, loops2 = boundaries(first), boundaries(second)
    surfaces = (ScanSurface.of(first), ScanSurface.of(second))
    contact = TableContact.of(first, second, plane1, plane2)
    alone = align(loops1, loops2, samples=64, along=0.1, robust=0.05, scans=surfaces)
    found = align(loops1, loops2, samples=64, along=0.1, robust=0.05, scans=surfaces, contact=contact)
    # measured: 0.70% of the size alone, 0.26% with the table; what is left is a tilt of the flipped scan that
    # keeps its lowest points on the table (the contact is their 2% quantile)
    assert height_error(alone, truth, second, plane1[:3]) > 0.005 * size
    assert height_error(found, truth, second, plane1[:3]) < 0.004 * size


def test_a_point_in_front_of_what_the_other_camera_measured_costs_its_depth_beyond_the_spacing():
    k = {"fx": 100.0, "fy": 100.0, "cx": 50.0, "cy": 40.0, "width": 100, "height": 80}
    wall = np.full((80, 100), 1.0)  # each camera read a wall 1 m away, and nothing in its left half
    wall[:, :50] = np.nan
    ahead = np.array([[0.1, 0.0, 0.9], [0.2, 0.1, 0.95], [0.1, 0.0, 1.2], [-0.2, 0.0, 0.5], [0.0, 0.0, -1.0]])
    planes = np.array([[0.0, -1.0, 0.0, 1.0], [0.0, -1.0, 0.0, 1.0]])
    contact = TableContact(planes, (ahead, ahead), 0.01, (wall, wall), (k, k))
    residuals = contact.residuals(np.eye(3), np.zeros(3), 0.5)
    # in front by 0.1 and 0.05 m less the spacing; behind the wall, where it read nothing and behind the camera: 0
    expected = np.sqrt(np.mean(np.array([0.09, 0.04, 0.0, 0.0, 0.0]) ** 2)) / 0.5
    assert len(residuals) == 6
    np.testing.assert_allclose(residuals[4:], expected, rtol=1e-12)


def test_bad_planes_are_clear_errors():
    first, second, plane1, plane2, _ = scans(box(), 10.0)
    with pytest.raises(StitchError, match="plane 1 must be four finite numbers"):
        TableContact.of(first, second, [0.0, 0.0, 0.0, 1.0], plane2)
    with pytest.raises(StitchError, match="plane 2 must be four numbers"):
        TableContact.of(first, second, plane1, [1.0, 2.0])
    with pytest.raises(StitchError, match="lies below plane 1: its normal must point towards the object"):
        TableContact.of(first, second, -plane1 - [0, 0, 0, 0.05], plane2)


def embedded(name: str) -> Model:
    from heatdata.io.catalog import embedded_catalog, load_catalog_model, read_catalog

    catalog = read_catalog(embedded_catalog())
    return load_catalog_model(catalog[catalog["object"] == name].iloc[0])


def write_frames(tmp_path, frames, names=("standing", "flipped")) -> list:
    from heatdata.experiments.scenes import write_scene

    paths = []
    for frame, name in zip(frames, names, strict=True):
        write_scene(frame, {"objects": [{}]}, tmp_path / f"{name}.png")
        paths.append(tmp_path / f"{name}.png")
    return paths


@pytest.mark.slow
def test_the_command_stitches_two_frames_of_an_object_standing_then_flipped_on_a_table(tmp_path, capsys):
    import json

    from heatdata.cli import main
    from heatdata.experiments.scenes import render_flipped_pair

    model = embedded("speaker-tall")
    standing, flipped, truth = render_flipped_pair(model, elevation=35.0, yaw=30.0, flip_axis=5.0)
    first, second = write_frames(tmp_path, (standing, flipped))
    assert main(["stitch", "--scans", str(first), str(second), "-o", str(tmp_path / "whole.ply"), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    rotation, translation = np.array(printed["rotation"]), np.array(printed["translation"])
    assert np.degrees(Rotation.from_matrix(rotation @ truth[:3, :3].T).magnitude()) < 5.0
    scan = trimesh.load(tmp_path / "whole.ply")
    centre = scan.vertices.mean(axis=0)  # a point the error is measured at, in the standing frame
    back = truth[:3, :3].T @ (centre - truth[:3, 3])
    assert np.linalg.norm(rotation @ back + translation - centre) < 0.02 * np.linalg.norm(model.extents)
    assert printed["table_cost"] < 0.01


@pytest.mark.slow
def test_frames_that_cannot_be_stitched_on_their_tables_say_why_in_one_line(tmp_path, caplog):
    from dataclasses import replace

    from heatdata.cli import main
    from heatdata.experiments.scenes import render_flipped_pair
    from heatdata.views.render import Placement, camera_pose, render_scene

    speaker = embedded("speaker-tall")
    standing, flipped, _ = render_flipped_pair(speaker, elevation=35.0)
    alone = render_scene([Placement(speaker, np.eye(4))], camera_pose(np.zeros(3), 0.0, 35.0, 0.6), sensor="ideal")
    _, small, _ = render_flipped_pair(embedded("speaker-small"), elevation=35.0)
    columns = np.nonzero(flipped.labels == len(flipped.names) - 1)[1]
    cut = int(columns.mean())  # the image's right border through the object's middle
    near = replace(
        flipped,
        depth=flipped.depth[:, :cut],
        rgb=flipped.rgb[:, :cut],
        labels=flipped.labels[:, :cut],
        intrinsics={**flipped.intrinsics, "width": cut},
    )
    cases = {
        "no table plane in the frame": (standing, alone),
        "not one object scanned standing and flipped": (standing, small),
        "the object touches the image border": (standing, near),
    }
    for k, (message, frames) in enumerate(cases.items()):
        caplog.clear()
        paths = write_frames(tmp_path, frames, (f"a{k}", f"b{k}"))
        assert main(["stitch", "--scans", *map(str, paths), "-o", str(tmp_path / "out.ply")]) == 1
        errors = [r.getMessage() for r in caplog.records if r.levelname == "ERROR"]
        assert len(errors) == 1 and message in errors[0] and "\n" not in errors[0], (message, errors)
    assert main(["stitch", str(paths[0]), str(paths[1]), "-o", str(tmp_path / "out.ply")]) == 1
    assert "add --scans" in caplog.text

"""Registration of overlapping scans (heatdata.jasnom.register) and the join that chooses it or JASNOM
(heatdata.jasnom.join), on two rendered views of the bread (not symmetric: a mug's opposite views are the same
surface turned, which registration rightly matches)."""

import numpy as np
import pytest
from scipy.spatial.transform import Rotation

import heatdata as hd
from heatdata.jasnom.join import join
from heatdata.jasnom.register import in_front, overlap_share, register


@pytest.fixture(scope="module")
def bread(catalog):
    return hd.load_catalog_model(catalog[catalog["object"] == "bread"].iloc[0])


def scan(model, azimuth):
    view = hd.render_view(model, azimuth=azimuth, elevation=20.0, distance=0.6, noise=False)
    mesh = hd.Model.untextured(f"az{azimuth:g}", view.vertices, view.faces, view.colors[view.faces])
    return mesh, np.linalg.inv(view.pose)  # the view's camera frame from the object's


def angle(a, b):
    return float(np.degrees(Rotation.from_matrix(a @ b.T).magnitude()))


def test_in_front_counts_points_between_the_camera_and_the_surface():
    xy = np.stack(np.meshgrid(np.linspace(-0.1, 0.1, 21), np.linspace(-0.1, 0.1, 21)), -1).reshape(-1, 2)
    wall = np.column_stack([xy, np.ones(len(xy))])
    assert in_front(wall, 0.5 * wall, 0.01) == 1.0  # the same rays, half as far: every point in front
    assert in_front(wall, 2.0 * wall, 0.01) == 0.0  # behind it: not seen, not in front
    assert in_front(wall, wall + [5.0, 0, 0], 0.01) == 0.0  # rays that miss the wall count as not in front
    assert overlap_share(wall, wall, np.eye(4), 1e-6) == 1.0


def test_two_overlapping_views_register_to_their_true_motion_and_join_says_so(bread):
    first, pose1 = scan(bread, 0.0)
    second, pose2 = scan(bread, 40.0)
    truth = pose1 @ np.linalg.inv(pose2)
    found = register(first.vertices, second.vertices)
    assert found.overlapping and found.overlap > 0.5 and found.in_front < 0.05
    assert angle(found.rotation, truth[:3, :3]) < 1.0
    joined = join(first, second)
    assert joined.method == "registration" and "the scans overlap" in joined.why and joined.stitched is None
    assert len(joined.model.vertices) == len(first.vertices) + len(second.vertices)
    assert joined.summary()["method"] == "registration"


def test_opposite_views_do_not_register_and_are_stitched_by_jasnom(bread):
    first, _ = scan(bread, 0.0)
    second, _ = scan(bread, 180.0)
    joined = join(first, second, samples=64)
    assert joined.method == "jasnom" and "do not overlap" in joined.why
    assert not joined.registration.overlapping and joined.stitched is not None
    assert joined.summary()["strip_faces"] > 0


def test_a_scan_too_small_to_register_is_refused():
    points = np.random.default_rng(0).uniform(0.9, 1.1, (10, 3))
    with pytest.raises(hd.StitchError, match="at least 30 are needed"):
        register(points, points)


def test_the_command_registers_two_overlapping_pcd_files_and_stitches_two_opposite_ones(
    bread, tmp_path, capsys, caplog
):
    import json

    from heatdata.cli import main
    from heatdata.frames.pcd import write_view_pcd

    views = {az: hd.render_view(bread, azimuth=az, elevation=20.0, distance=0.6, noise=False) for az in (0, 40, 180)}
    files = {az: write_view_pcd(view, tmp_path / f"az{az}.pcd") for az, view in views.items()}
    assert main(["stitch", str(files[0]), str(files[40]), "-o", str(tmp_path / "both.ply"), "--json"]) == 0
    printed = json.loads(capsys.readouterr().out)
    truth = np.linalg.inv(views[0].pose) @ views[40].pose
    assert printed["method"] == "registration" and "the scans overlap" in printed["why"]
    assert angle(np.array(printed["rotation"]), truth[:3, :3]) < 1.0
    whole = ["stitch", str(files[0]), str(files[180]), "-o", str(tmp_path / "whole.ply"), "--close-holes", "30"]
    assert main(whole) == 0
    table = capsys.readouterr().out
    assert "method   JASNOM: the scans do not overlap" in table and "hole(s) inside the scans, " in table
    assert " loop(s) closed" in table and "left open" not in table
    assert "free space" in table
    assert main(["stitch", str(files[0]), str(tmp_path / "whole.ply"), "-o", str(tmp_path / "x.ply")]) == 1
    assert "give two scans (PCD or range-grid PLY files) or two meshes, not one of each" in caplog.text

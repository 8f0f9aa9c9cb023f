"""The heatdata command: the demo job end to end on a small plan, and its exit codes."""

import contextlib
import fcntl
import json
import os
import pty
import re
import struct
import subprocess
import sys
import termios
import zipfile

import numpy as np
import pytest
import trimesh

import heatdata as hd
from heatdata.cli import main
from heatdata.io.tables import DESCRIPTOR_SCHEMA, read_table


@pytest.fixture(scope="module")
def demo_run(tmp_path_factory):
    out = tmp_path_factory.mktemp("demo")
    code = main(
        [
            "demo",
            "--objects",
            "plastic-cup,milk-carton",
            "--train",
            "6",
            "--test",
            "6",
            "--jobs",
            "2",
            "--out",
            str(out),
        ]
    )
    return code, out


@pytest.mark.slow
def test_demo_writes_tables_figures_and_summary(demo_run):
    code, out = demo_run
    assert code == 0
    descriptors, meta = read_table(out / "descriptors.parquet")
    assert list(descriptors.columns) == DESCRIPTOR_SCHEMA.names
    assert len(descriptors) == 2 * 12 * 5  # objects x views x descriptors
    assert descriptors["values"].map(len).eq(64).all()
    assert meta["train"] == 6 and meta["heatdata_version"]
    assert np.allclose(descriptors["time"] * descriptors["lambda2"], 1.0)
    predictions, _ = read_table(out / "predictions.parquet")
    assert len(predictions) == 5 * 2 * 6
    assert predictions["correct"].mean() > 0.8
    for name in (
        "summary.md",
        "precision.csv",
        "views.png",
        "confusion_objects_pvhk_arclength_closest_64.png",
        "confusion_views_pvhk_polar_center_64.png",
    ):
        assert (out / name).stat().st_size > 0
    summary = (out / "summary.md").read_text()
    assert "not real sensor data" in summary and "accuracy" not in summary.lower()


@pytest.mark.slow
def test_demo_is_reproducible(demo_run, tmp_path):
    _, out = demo_run
    assert (
        main(["demo", "--objects", "plastic-cup", "--train", "6", "--test", "6", "--jobs", "1", "--out", str(tmp_path)])
        == 0
    )
    first, _ = read_table(out / "descriptors.parquet")
    again, _ = read_table(tmp_path / "descriptors.parquet")
    first = first[first["object"] == "plastic-cup"].reset_index(drop=True)
    assert np.array_equal(np.stack(first["values"]), np.stack(again["values"]))


def test_render_describe_classify(demo_run, tmp_path, capsys):
    _, out = demo_run
    model = tmp_path.parent / "model.ply"
    trimesh.creation.box(extents=(0.2, 0.1, 0.15)).export(model)
    assert main(["render", str(model), "--azimuth", "30", "--out", str(tmp_path / "v.npz"), "--json"]) == 0
    rendered = json.loads(capsys.readouterr().out)
    assert rendered["vertices"] > 1000 and rendered["views"] == [str(tmp_path / "v.npz")]
    assert main(["render", str(model), "--azimuth", "30", "--out", str(tmp_path / "v.npz")]) == 0
    assert capsys.readouterr().out.startswith(f"{tmp_path / 'v.npz'}: {rendered['vertices']:,} vertices, ")
    assert main(["describe", str(tmp_path / "v.npz"), "--samples", "16", "--sampling", "polar"]) == 0
    described = json.loads(capsys.readouterr().out)
    assert len(described["values"]) == 16 and described["descriptor"] == "pvhk/polar/closest/16"
    assert main(["describe", str(tmp_path / "v.npz"), "--color-map", "c3", "--samples", "0"]) == 0
    assert json.loads(capsys.readouterr().out)["descriptor"].startswith("c-pvhk")
    view = str(tmp_path / "v.npz")
    assert main(["describe", view, "--kind", "ft-pvhk", "--time", "0.01", "--samples", "16"]) == 0
    fixed = json.loads(capsys.readouterr().out)
    assert fixed["time"] == 0.01 and len(fixed["weights"]) == 16
    assert main(["describe", view, "--kind", "pvst", "--source", "center", "--threshold", "0.5"]) == 0
    assert json.loads(capsys.readouterr().out)["descriptor"] == "pvst/arclength/center/64/T0.5"
    assert main(["describe", view, "--kind", "ft-pvhk"]) == 1  # no --time: a clear error
    assert main(["describe", view]) == 0  # no kind or boundary option: the default descriptor, HGD with colour
    assert json.loads(capsys.readouterr().out)["descriptor"] == "hgd/color=hue-saturation"
    assert main(["describe", view, "--threshold", "0.5"]) == 0  # a threshold is a PVST's
    assert json.loads(capsys.readouterr().out)["descriptor"] == "pvst/arclength/interior/64/T0.5"
    assert main(["describe", view, "--kind", "esf", "--option", "triplets=2000"]) == 0
    esf = json.loads(capsys.readouterr().out)
    assert esf["descriptor"] == "esf/triplets=2000" and len(esf["values"]) == 640 and esf["source"] == -1
    assert main(["describe", view, "--kind", "esf", "--samples", "16"]) == 1  # an esf takes no samples
    assert main(["describe", view, "--kind", "esf", "--option", "seed"]) == 1  # not KEY=VALUE
    assert main(["describe", view, "--kind", "si-hks"]) == 1  # learned on library views first
    assert main(["kinds"]) == 0
    listed = capsys.readouterr().out
    assert all(f"{kind}:" in listed for kind in hd.DESCRIPTORS) and "triplets (default 20000)" in listed
    assert listed.count("available here") == len(hd.DESCRIPTORS)  # each kind says whether it can run here
    assert main(["classify", str(out / "descriptors.parquet"), "--descriptor", "pvhk/polar/center/64"]) == 0
    printed = capsys.readouterr().out
    assert "precision of 12 test views (every train view" in printed
    assert re.search(r"descriptor +library views +object precision +class precision", printed)
    assert re.search(r"pvhk/polar/center/64 +6 +\d+\.\d% +\d+\.\d%", printed)


def test_classify_library_sizes(demo_run, tmp_path, capsys):
    _, out = demo_run
    table = str(out / "descriptors.parquet")
    assert (
        main(
            [
                "classify",
                table,
                "--descriptor",
                "pvhk/polar/center/64",
                "--library-size",
                "2",
                "--library-size",
                "6",
                "--out",
                str(tmp_path / "p.parquet"),
            ]
        )
        == 0
    )
    printed = capsys.readouterr().out
    assert re.search(r"pvhk/polar/center/64 +2 ", printed) and re.search(r"pvhk/polar/center/64 +6 ", printed)
    predictions, _ = read_table(tmp_path / "p.parquet")
    assert sorted(predictions["library_size"].unique()) == [2, 6] and len(predictions) == 2 * 12
    every, _ = read_table(out / "predictions.parquet")
    every = every[every["descriptor"] == "pvhk/polar/center/64"].set_index("view_id")["predicted_view_id"]
    six = predictions[predictions["library_size"] == 6].set_index("view_id")["predicted_view_id"]
    assert six.sort_index().equals(every.sort_index())  # 6 of 6 train views: the whole library
    assert main(["classify", table, "--library-size", "7"]) == 1  # more than the 6 train views


@pytest.mark.slow
def test_long_commands_show_a_progress_bar_on_a_terminal_only(demo_run):
    _, out = demo_run
    command = [sys.executable, "-m", "heatdata.cli", "classify", str(out / "descriptors.parquet")]
    primary, secondary = pty.openpty()
    fcntl.ioctl(secondary, termios.TIOCSWINSZ, struct.pack("HHHH", 24, 120, 0, 0))  # a 120-column terminal
    run = subprocess.run(command, stdout=subprocess.PIPE, stderr=secondary, timeout=120)
    os.close(secondary)
    on_terminal = b""
    with contextlib.suppress(OSError):  # the pty reads EIO once drained
        while chunk := os.read(primary, 65536):
            on_terminal += chunk
    os.close(primary)
    assert run.returncode == 0
    assert re.search(rb"classifying: 100%.*5/5", on_terminal)
    piped = subprocess.run(command, capture_output=True, timeout=120)
    assert piped.returncode == 0 and b"classifying" not in piped.stderr and b"%|" not in piped.stderr


def test_exit_codes(tmp_path, caplog):
    assert main(["render", str(tmp_path / "missing.obj"), "--out", str(tmp_path / "v.npz")]) == 1
    assert "missing.obj: no such model file" in caplog.text
    assert main(["demo", "--objects", "unicorn", "--out", str(tmp_path)]) == 1
    assert main(["classify", str(tmp_path / "none.parquet")]) == 1
    with pytest.raises(SystemExit) as usage:
        main(["render"])
    assert usage.value.code == 2


def write_sh3f(path, props):
    with zipfile.ZipFile(path, "w") as archive:
        archive.writestr("PluginFurnitureCatalog.properties", props)
    return path


@pytest.mark.parametrize(
    "args, code, message",
    [
        (["render", "{model}", "--scale", "nan", "--out", "{tmp}/a.npz"], 2, "need a positive number"),
        (["render", "{model}", "--azimuth", "nan", "--out", "{tmp}/a.npz"], 2, "need a finite number"),
        (["render", "{model}", "--size", "-0.154", "0.165", "0.102", "--out", "{tmp}/a.npz"], 2, "need a number >= 0"),
        (["render", "{model}", "--out", "{tmp}/a.txt"], 1, "ending in .npz"),
        (["render", "{model}", "--out", "{tmp}"], 1, "ending in .npz"),
        (["describe", "{tmp}/truncated.npz"], 1, "not a zip archive: truncated"),
        (["describe", "{model}"], 1, "not a readable .npz view file"),
        (["import-sh3f", "{tmp}/nowidth.sh3f", "{tmp}/out"], 1, "missing or non-numeric size"),
        (["import-sh3f", "{tmp}/badwidth.sh3f", "{tmp}/out"], 1, "missing or non-numeric size"),
        (["import-sh3f", "{tmp}/good.sh3f", "{tmp}/out", "--names", "("], 1, "is not a regular expression"),
        (["import-sh3f", "{tmp}/good.sh3f", "{tmp}/afile"], 1, "the output folder is a file"),
        (["demo", "--jobs", "0"], 2, "need a number >= 1"),
        (["classify", "{tmp}/nolabel.parquet"], 1, "lacks column(s) label"),
        (["describe", "{tmp}/v.npz", "--time", "0.01"], 1, "--time is the fixed time of a time-scaled kind"),
    ],
)
def test_bad_command_lines_are_one_clear_line(demo_run, tmp_path, capsys, caplog, args, code, message):
    """Each used to end in a traceback (or, for --size and --out, in a mirrored model or a renamed file)."""
    _, out = demo_run
    box = tmp_path / "box.ply"
    trimesh.creation.box(extents=(0.2, 0.1, 0.15)).export(box)
    assert main(["render", str(box), "--out", str(tmp_path / "v.npz")]) == 0
    (tmp_path / "truncated.npz").write_bytes((tmp_path / "v.npz").read_bytes()[:300])
    size = "width#1=12\ndepth#1=8\nheight#1=10\n"
    write_sh3f(tmp_path / "nowidth.sh3f", "name#1=Mug\nmodel#1=m/q.obj\ndepth#1=1\nheight#1=1\n")
    write_sh3f(tmp_path / "badwidth.sh3f", "name#1=Mug\nmodel#1=m/q.obj\nwidth#1=wide\ndepth#1=1\nheight#1=1\n")
    write_sh3f(tmp_path / "good.sh3f", "name#1=Mug\nmodel#1=m/q.obj\n" + size)
    (tmp_path / "afile").write_text("")
    table, _ = read_table(out / "descriptors.parquet")
    table.drop(columns=["label"]).to_parquet(tmp_path / "nolabel.parquet")
    capsys.readouterr()
    argv = [a.format(model=box, tmp=tmp_path) for a in args]
    if code == 2:
        with pytest.raises(SystemExit) as usage:
            main(argv)
        assert usage.value.code == 2 and message in capsys.readouterr().err
    else:
        assert main(argv) == 1
        assert message in caplog.text and "Traceback" not in caplog.text
    assert not (tmp_path / "a.txt.npz").exists() and not (tmp_path.parent / f"{tmp_path.name}.npz").exists()


def test_render_creates_the_output_folder(tmp_path, capsys):
    trimesh.creation.box(extents=(0.2, 0.1, 0.15)).export(tmp_path / "box.ply")
    assert main(["render", str(tmp_path / "box.ply"), "--out", str(tmp_path / "new" / "deep" / "v.npz")]) == 0
    assert capsys.readouterr().out.startswith(f"{tmp_path / 'new' / 'deep' / 'v.npz'}: ")
    with pytest.raises(hd.ModelError, match="mirrors"):
        hd.load_model(tmp_path / "box.ply", size=(-0.1, 0.1, 0.1))


def test_the_command_spares_open3d_its_web_viewer_and_still_segments():
    code = (
        "import sys; from heatdata.cli import _without_open3d_viewer; _without_open3d_viewer(); import open3d; "
        "import numpy as np; cloud = open3d.geometry.PointCloud(open3d.utility.Vector3dVector("
        "np.random.default_rng(0).random((200, 3)) * [1, 1, 0])); "
        "plane = np.abs(cloud.segment_plane(0.01, 3, 50)[0]); "
        "print('dash' in sys.modules, 'plotly' in sys.modules, np.round(plane, 3))"
    )
    out = subprocess.run([sys.executable, "-c", code], capture_output=True, text=True, check=True).stdout
    assert out.split()[:2] == ["False", "False"] and "1." in out, out
    viewer = subprocess.run(
        [sys.executable, "-c", "from heatdata.cli import _without_open3d_viewer; _without_open3d_viewer(); "
         "import open3d; open3d.visualization.draw_plotly([])"],
        capture_output=True, text=True, check=False,
    )  # fmt: skip
    assert viewer.returncode != 0 and "not loaded in the heatdata command" in viewer.stderr


def test_every_command_takes_verbose_after_it_and_render_takes_o():
    from heatdata.cli import build_parser

    parser = build_parser()
    assert parser.parse_args(["kinds", "-v"]).verbose and parser.parse_args(["-v", "kinds"]).verbose
    assert not parser.parse_args(["kinds"]).verbose
    assert parser.parse_args(["recognize", "frame.png", "--library", "l.parquet", "--verbose"]).verbose
    assert str(parser.parse_args(["render", "m.obj", "-o", "v.npz"]).out) == "v.npz"


def test_recognize_reads_the_main_jobs_library_by_default_and_lists_those_there_when_it_is_missing(
    tmp_path, monkeypatch, caplog
):
    monkeypatch.chdir(tmp_path)
    assert main(["recognize", "frame.png"]) == 1
    assert (
        "results/libraries/hgd_color=hue-saturation-40.parquet: no --library given, and the main job's library of the "
        "default descriptor is not there; build the libraries with snakemake --cores 2" in caplog.text
    )
    (tmp_path / "results" / "libraries").mkdir(parents=True)
    (tmp_path / "results" / "libraries" / "esf-8.parquet").write_bytes(b"")
    caplog.clear()
    assert main(["recognize", "frame.png", "--library", "results/libraries/esf-40.parquet"]) == 1
    assert "esf-40.parquet: no such library (did you mean esf-8.parquet?); results/libraries holds esf-8.parquet" in (
        caplog.text
    )

"""A mistyped library, descriptor, kind or object name is answered with the nearest one."""

import pytest

from heatdata.cli import main
from heatdata.descriptors import kind_of
from heatdata.errors import SpecError, did_you_mean


def test_the_nearest_choice_is_named_and_a_far_one_is_not():
    assert did_you_mean("hdg", ["pvhk", "hgd", "esf"]) == " (did you mean hgd?)"
    assert did_you_mean("beer_mug", ["beer-mug", "coffee-cup"]) == " (did you mean beer-mug?)"
    assert did_you_mean("zzzz", ["pvhk", "hgd"]) == ""
    assert did_you_mean(None, ["pvhk"]) == "" and did_you_mean("pvhk", []) == ""


def test_a_kind_library_and_descriptor_typo_each_suggest_the_name(tmp_path, capsys, caplog):
    with pytest.raises(SpecError, match=r"did you mean ft-pvhk\?"):
        kind_of("ft_pvhk")
    with pytest.raises(SystemExit):
        main(["describe", str(tmp_path / "view.npz"), "--kind", "hdg"])
    assert "did you mean hgd?" in capsys.readouterr().err
    (tmp_path / "hgd_color=hue-saturation-40.parquet").write_bytes(b"")
    frame = tmp_path / "frame.png"
    frame.write_bytes(b"")
    assert main(["recognize", str(frame), "--library", str(tmp_path / "hgd_color=hue-saturaton-40.parquet")]) == 1
    assert "did you mean hgd_color=hue-saturation-40.parquet?" in caplog.text

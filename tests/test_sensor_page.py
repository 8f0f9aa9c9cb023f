"""The guide page "From your sensor to heatdata": its commands on the test data's real frame run as written, and
print what the page quotes."""

import json
import re
import shlex

from conftest import ROOT

from heatdata.cli import main

PAGE = ROOT / "docs/guide/from_your_sensor.md"


def page_commands(text: str) -> list[list[str]]:
    """The ``heatdata`` commands of the page's shell blocks that read the test data, continuation lines joined."""
    blocks = re.findall(r"```sh\n(.*?)```", text, re.S)
    lines = " ".join(blocks).replace("\\\n", " ").splitlines()
    commands = [shlex.split(line.split("#")[0]) for line in lines if "tests/data/mosd/" in line]
    return [c[1:] for c in commands if c and c[0] == ".venv/bin/heatdata"]


def test_the_pages_commands_run_on_the_real_frame_and_print_what_it_quotes(tmp_path, monkeypatch, capsys):
    text = PAGE.read_text()
    commands = page_commands(text)
    assert commands and all(c[0] == "segment" for c in commands)
    monkeypatch.chdir(tmp_path)
    (tmp_path / "tests").symlink_to(ROOT / "tests")
    for command in commands:
        assert main(command) == 0, command
    out, err = capsys.readouterr()
    quoted = re.search(r"prints the two boxes and `([^`]*)`", text).group(1)
    assert quoted in out and out.count("px at") == 2 and "overlay written to objects.png" in err
    intrinsics = json.loads((ROOT / "tests/data/mosd/intrinsics.json").read_text())
    (tmp_path / "long.json").write_text(
        json.dumps({**intrinsics, "fx": 3 * intrinsics["fx"], "fy": 3 * intrinsics["fy"]})
    )
    frame = commands[0][commands[0].index("segment") + 1]
    assert main(["segment", frame, "--intrinsics", "long.json", "-o", "long.png"]) == 0
    note = re.search(r"with fx three times too\s+long it adds `([^`]*)`", text).group(1)
    assert " ".join(note.split()) in capsys.readouterr().out

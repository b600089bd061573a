"""The documents' Python blocks run as written from any directory, with the shared data
named by PSH_DATA_DIR: docs/python.md's quickstart (and the picture it promises) and
README.md's snippet."""

import re

import pytest

from support import DATA, ROOT


def blocks_of(name):
    return re.findall(r"```python\n(.*?)```", (ROOT / name).read_text(), flags=re.S)


def test_readme_snippet_runs_from_any_directory(tmp_path, monkeypatch, data, capsys):
    (block,) = blocks_of("README.md")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PSH_DATA_DIR", str(DATA.parent))
    scope = {}
    exec(compile(block, "README.md", "exec"), scope)
    assert "[[" in capsys.readouterr().out  # the (channels, 4) array printed
    assert scope["s"].shape == (3, 4)
    # What README says of it: a DoP of 1.01, above 1 (PSH (70) broken by the band limit).
    assert all(1.005 < d < 1.015 for d in scope["dop"]), scope["dop"]


def test_quickstart_runs_as_written(tmp_path, monkeypatch, data):
    pytest.importorskip("matplotlib")
    (block,) = blocks_of("docs/python.md")
    monkeypatch.chdir(tmp_path)
    monkeypatch.setenv("PSH_DATA_DIR", str(DATA.parent))
    scope = {}
    exec(compile(block, "docs/python.md", "exec"), scope)
    assert (tmp_path / "psh-python-quickstart.png").stat().st_size > 10_000
    # The projection from the 64^2 cube map agrees with polarsh's coefficients (from a
    # 1024^2 map) at low degrees.
    assert scope["gap"] < 1e-3  # measured 1.2e-4
    assert scope["reflected"].argument == "travel"

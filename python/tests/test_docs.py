"""docs/python.md runs as written: its Python block is executed from the repository root
(with the shared data) and makes the picture it promises."""

import os
import re

import pytest

from support import DATA, ROOT


def test_quickstart_runs_as_written(tmp_path, monkeypatch, data):
    pytest.importorskip("matplotlib")
    text = (ROOT / "docs" / "python.md").read_text()
    blocks = re.findall(r"```python\n(.*?)```", text, flags=re.S)
    assert len(blocks) == 1
    monkeypatch.chdir(ROOT)
    monkeypatch.setenv("PSH_DATA_DIR", str(DATA.parent))
    picture = ROOT / "psh-python-quickstart.png"
    scope = {}
    try:
        exec(compile(blocks[0], "docs/python.md", "exec"), scope)
        assert picture.stat().st_size > 10_000
    finally:
        if picture.exists():
            os.replace(picture, tmp_path / picture.name)
    # The projection from the 64^2 cube map agrees with polarsh's coefficients (from a
    # 1024^2 map) at low degrees.
    assert scope["gap"] < 1e-3  # measured 1.2e-4
    assert scope["reflected"].argument == "travel"

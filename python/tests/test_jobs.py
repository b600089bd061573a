"""The whole pipeline from Python: `render` (the PPRT job) and `verify` (psh's checks)."""

import inspect
import json
import pathlib

import numpy as np
import pytest

import psh


def test_render_returns_the_image_and_the_report(tmp_path, cli):
    stokes, report = psh.render(out=tmp_path / "py", width=24, height=18, l_low=2, l_high=4,
                                rays=8, polarizers=[0.0, 90.0])
    assert stokes.shape == (18, 24, 3, 4) and np.isfinite(stokes).all()
    assert report["counts"]["primary_rays"] == 24 * 18
    assert report["settings"]["l_low"] == 2 and report["settings"]["polarizers_deg"] == [0.0, 90.0]
    assert json.loads((tmp_path / "py" / "report.json").read_text()) == report
    assert all(pathlib.Path(f).is_file() for f in report["pictures"])
    # The same job as `psh render` with the same arguments: settings, counts and plan.
    cli("render", "--out", "cli", "--size", "24x18", "--l-low", 2, "--l-high", 4, "--rays", 8,
        "--polarizer", 0, "--polarizer", 90)
    ref = json.loads((tmp_path / "cli" / "report.json").read_text())
    for key in ("settings", "counts", "plan", "high_order_projection_residual_per_material"):
        assert report[key] == ref[key], key


def test_verify_runs_psh_checks():
    results = psh.verify("swsh.")
    assert results and all(r["id"].startswith("swsh.") for r in results)
    assert all(r["passed"] for r in results), [r for r in results if not r["passed"]]
    assert {"id", "source", "description", "max_error", "tolerance", "passed"} <= set(results[0])
    # A filter no check matches is a mistake (as `psh verify --filter` says), not [].
    with pytest.raises(ValueError, match="no-such-check"):
        psh.verify("no-such-check")


def test_render_signature_shows_the_defaults_it_uses(tmp_path):
    """`help(psh.render)` shows values (no `...`), and they are the ones the job applies."""
    defaults = {k: p.default for k, p in inspect.signature(psh.render).parameters.items()}
    assert Ellipsis not in defaults.values()
    stokes, report = psh.render(out=tmp_path, l_low=2, l_high=0, rays=1)
    s = report["settings"]
    assert s["image"] == [defaults["width"], defaults["height"]]
    assert stokes.shape == (defaults["height"], defaults["width"], 3, 4)
    assert s["polarizers_deg"] == defaults["polarizers"]
    # None: the scene's window; the built-in scene has none.
    assert defaults["window"] is None and s["window"] == "none"
    assert s["valid_range_projection"] == defaults["valid_range"]
    assert s["shadows"] == defaults["shadows"]
    assert report["plan"]["tolerance"] == defaults["tolerance"]


def test_render_takes_the_scene_files_window(tmp_path):
    """A scene file's `[settings] window` is the render's unless `window=` says another."""
    scene = tmp_path / "scene.toml"
    scene.write_text(
        '[environment]\ntype = "sky"\nsun_elevation_deg = 30.0\nsun_azimuth_deg = 20.0\n\n'
        '[camera]\nposition = [0.0, -4.0, 1.0]\ntarget = [0.0, 0.0, 0.0]\nfov_deg = 40.0\n'
        'width = 12\nheight = 8\n\n[settings]\nl_low = 2\nl_high = 0\nrays = 8\n'
        'window = "hann"\n\n[[material]]\nname = "m"\ntype = "plastic"\nalpha = 0.3\n'
        'ior = 1.5\nalbedo = 0.5\n\n[[mesh]]\ntype = "sphere"\ncenter = [0.0, 0.0, 0.0]\n'
        'radius = 0.5\nrings = 6\nsegments = 12\nmaterial = "m"\n')
    _, report = psh.render(scene, out=tmp_path / "a")
    assert report["settings"]["window"] == "hann"
    _, report = psh.render(scene, out=tmp_path / "b", window="lanczos")
    assert report["settings"]["window"] == "lanczos"

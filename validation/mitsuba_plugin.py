"""psh's Mitsuba 3 emitter `psh_stokes_envmap` (src/io/psh_stokes_envmap.py, written beside
a Mitsuba export of a polarized environment) for the validation suite: loading it, and
whether Dr.Jit's LLVM backend runs here (the fast `llvm_ad_*` variants)."""

import functools
import importlib.util
import pathlib
import subprocess
import sys

PLUGIN = pathlib.Path(__file__).resolve().parent.parent / "src" / "io" / "psh_stokes_envmap.py"


def load_plugin(path=PLUGIN):
    """The plugin file `path` under the name psh's export gives it beside a scene."""
    spec = importlib.util.spec_from_file_location("psh_stokes_envmap", path)
    module = importlib.util.module_from_spec(spec)
    spec.loader.exec_module(module)
    return module


_PROBE = """
import sys, tempfile, importlib.util, numpy as np, drjit as dr, mitsuba as mi
mi.set_variant("llvm_ad_mono_polarized")
spec = importlib.util.spec_from_file_location("psh_stokes_envmap", sys.argv[1])
m = importlib.util.module_from_spec(spec); spec.loader.exec_module(m); m.register()
with tempfile.TemporaryDirectory() as d:
    for p in range(4):
        mi.Bitmap(np.full((2, 4, 3), 1.0 - 0.3 * p, dtype=np.float32)).write(f"{d}/e_s{p}.exr")
    scene = mi.load_dict({"type": "scene",
        "integrator": {"type": "stokes", "nested": {"type": "path", "max_depth": 2}},
        "sensor": {"type": "perspective", "film": {"type": "hdrfilm", "width": 4, "height": 4,
                                                  "pixel_format": "luminance"}},
        "shape": {"type": "sphere", "center": [0, 0, 5]},
        "emitter": {"type": "psh_stokes_envmap", "filename": f"{d}/e_s%d.exr"}})
    print(float(np.array(mi.render(scene, spp=4)).mean()))
"""


@functools.cache
def llvm_problem():
    """None if the LLVM variants render here, else the probe's first line naming an
    error (else its last line)."""
    p = subprocess.run([sys.executable, "-c", _PROBE, str(PLUGIN)], capture_output=True,
                       text=True, timeout=600)
    if p.returncode == 0:
        return None
    lines = (p.stderr or p.stdout).strip().splitlines() or [f"exit status {p.returncode}"]
    return next((x.strip() for x in lines if "error" in x.lower()), lines[-1])[:200]

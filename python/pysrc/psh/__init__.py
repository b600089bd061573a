"""Polarized spherical harmonics (Yi et al., SIGGRAPH 2024): the Rust crate psh from numpy.

Every computation is the compiled module's (`psh.psh`, re-exported here); `psh.plot`
(matplotlib, `pip install "polarized-sh[plot]"`) draws its results.
"""

from .psh import *  # noqa: F401,F403
from .psh import __all__, __version__  # noqa: F401

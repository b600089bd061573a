"""Type stubs of psh, polarized spherical harmonics (Yi et al., SIGGRAPH 2024), from numpy.

Conventions (docs/conventions.md): flat coefficient index ``l*l + l + m``; directions are
unit vectors ``(x, y, z)`` with theta from +z and phi from +x towards +y; Stokes
components ``[s0, s1, s2, s3]`` are measured in the frames of a frame field (theta-phi
PSH (28) by default). Arrays passed in may be any array-like; float64 C-contiguous arrays
are read without a copy. Bad values raise ``ValueError`` (or ``TypeError`` for the wrong
type), unreadable or malformed files ``OSError``, work over psh's memory budget (4 GiB, or
``PSH_MAX_MEMORY``) ``MemoryError``.
"""

from os import PathLike
from typing import Any, Callable, Optional, Sequence, Tuple, Union, final

import numpy as np
import numpy.typing as npt

__version__: str
__all__ = [
    "__version__",
    "Rotation",
    "FrameField",
    "PshVector",
    "ConvolutionKernel",
    "KernelCoefficients",
    "Conductor",
    "PolarizedPlastic",
    "PshMatrix",
    "IsotropicMatrix",
    "TripleTable",
    "sh_real",
    "sh_complex",
    "swsh",
    "wigner_d",
    "wigner_d_real",
    "read_stokes_map",
    "write_stokes_map",
    "project_map",
    "reconstruct_map",
    "reconstruct_perspective",
    "isotropic_pairs",
    "project_pbrdf",
    "visibility_transfer",
    "MeasuredPbrdf",
    "read_measured_pbrdf",
    "render",
    "verify",
]

_ArrayLike = npt.ArrayLike
_FloatArray = npt.NDArray[np.float64]
_ComplexArray = npt.NDArray[np.complex128]
_Path = Union[str, PathLike]
# A psh.Rotation, one scipy.spatial.transform.Rotation or one quaternionic.array.
_RotationLike = Any

@final
class Rotation:
    """A rotation of R^3; fields turn as ``R_F[f](w) = f(R^-1 w)`` (PSH (8))."""

    @staticmethod
    def from_rotvec(v: _ArrayLike) -> Rotation:
        """Angle ``|v|`` (radians) about ``v / |v|``; zero is the identity."""
    @staticmethod
    def from_quaternion(q: _ArrayLike, scalar_first: bool = False) -> Rotation:
        """A unit quaternion, ``(x, y, z, w)`` as scipy (``(w, x, y, z)`` if scalar_first)."""
    @staticmethod
    def from_matrix(m: _ArrayLike) -> Rotation:
        """A proper orthogonal 3 x 3 matrix (checked)."""
    @staticmethod
    def from_euler_zyz(alpha: float, beta: float, gamma: float) -> Rotation:
        """``Rz(alpha) Ry(beta) Rz(gamma)``."""
    def matrix(self) -> _FloatArray:
        """The 3 x 3 matrix."""
    def euler_zyz(self) -> Tuple[float, float, float]:
        """ZYZ Euler angles, beta in [0, pi]."""
    def inverse(self) -> Rotation: ...
    def __mul__(self, other: Rotation, /) -> Rotation:
        """``a * b`` applies ``b`` first."""
    def __rmul__(self, other: Rotation, /) -> Rotation: ...

@final
class FrameField:
    """The Stokes frame assigned to each direction (PSH Sec. 5.1)."""

    @staticmethod
    def theta_phi() -> FrameField:
        """PSH (28): x = e_theta, y = e_phi."""
    @staticmethod
    def cube_map() -> FrameField:
        """Per cube face, the 90-degree camera's frame (x image-right, y image-down)."""
    @staticmethod
    def perspective(forward: _ArrayLike, up: _ArrayLike) -> FrameField:
        """A pinhole camera's frames (x image-right, y image-down, z the pixel direction)."""
    def frame(self, w: _ArrayLike) -> _FloatArray:
        """The frame at ``w``: rows x, y, z."""

@final
class PshVector:
    """PSH coefficients PSH (34): ``coeffs[channel, l*l + l + m, k]``, ``k`` over the
    codomain's Stokes components (SCALAR {s0}, POLAR2 {s1, s2}, POLAR3 {s0, s1, s2},
    POLAR4 {s0..s3}); ``argument`` "towards-source" or "travel" (polarsh's files)."""

    def __new__(
        cls, coeffs: _ArrayLike, codomain: str = "POLAR4", argument: str = "towards-source"
    ) -> PshVector: ...
    @staticmethod
    def read_npz(path: _Path) -> PshVector:
        """A polarsh ``.npz`` (argument "travel")."""
    def write_npz(self, path: _Path) -> None:
        """A polarsh ``.npz`` (converted to "travel")."""
    @staticmethod
    def from_channels(parts: Sequence[PshVector]) -> PshVector: ...
    @property
    def lmax(self) -> int: ...
    @property
    def channels(self) -> int: ...
    @property
    def codomain(self) -> str: ...
    @property
    def components(self) -> list[int]: ...
    @property
    def argument(self) -> str: ...
    @property
    def coeffs(self) -> _FloatArray:
        """A read-only copy ``(channels, (lmax+1)^2, components)``."""
    def evaluate(self, dirs: _ArrayLike, frames: Optional[FrameField] = None) -> _FloatArray:
        """Stokes components PSH (30) at ``dirs (..., 3)``: ``(channels, ..., 4)``."""
    def rotated(self, rotation: _RotationLike) -> PshVector:
        """PSH (35)-(37)."""
    def converted(self, argument: str) -> PshVector: ...
    def truncated(self, lmax: int) -> PshVector: ...
    def channel(self, c: int) -> PshVector: ...
    def with_codomain(self, codomain: str) -> PshVector: ...
    def band_energies(self) -> _FloatArray: ...
    def __add__(self, other: PshVector, /) -> PshVector:
        """Same band limit, codomain, channels and argument, else ``ValueError``."""
    def __radd__(self, other: PshVector, /) -> PshVector: ...
    def __sub__(self, other: PshVector, /) -> PshVector: ...
    def __rsub__(self, other: PshVector, /) -> PshVector: ...
    def __mul__(self, s: float, /) -> PshVector: ...
    def __rmul__(self, s: float, /) -> PshVector: ...
    def __truediv__(self, s: float, /) -> PshVector: ...
    def __rtruediv__(self, s: float, /) -> PshVector: ...
    def __neg__(self) -> PshVector: ...

def sh_real(lmax: int, dirs: _ArrayLike) -> _FloatArray:
    """Real SH PSH (12): ``(..., (lmax+1)^2)``; within ``10 l eps`` of
    ``sqrt((2l+1)/4pi)`` at every direction, the poles included (docs/stability.md)."""

def sh_complex(lmax: int, dirs: _ArrayLike) -> _ComplexArray:
    """Complex SH PSH (1): ``(..., (lmax+1)^2)``; within ``10 l eps`` of
    ``sqrt((2l+1)/4pi)`` at every direction, the poles included (docs/stability.md)."""

def swsh(spin: int, lmax: int, dirs: _ArrayLike) -> _ComplexArray:
    """Spin-weighted SH PSH (26)-(27): ``(..., (lmax+1)^2)``, zero where l < |spin|;
    within ``10 l eps`` of ``sqrt((2l+1)/4pi)`` at every direction, the poles included."""

def wigner_d(rotation: _RotationLike, lmax: int) -> list[_ComplexArray]:
    """``D^l_{m m'}`` PSH (9) per degree, ``(2l+1, 2l+1)``, rows m, columns m'; within
    ``10 l eps`` for every rotation, tiny and near-half turns included."""

def wigner_d_real(rotation: _RotationLike, lmax: int) -> list[_FloatArray]:
    """Real Wigner blocks PSH (13) per degree, ``(2l+1, 2l+1)``."""

def read_stokes_map(pattern: _Path) -> _FloatArray:
    """EXR files (``%d`` for 0..3) or one file with layers ``S0..S3``: ``(channels, rows, columns, 4)`` in the layout's frame
    field (cube cross: ``FrameField.cube_map()``; equirect: ``FrameField.theta_phi()``)."""

def write_stokes_map(texels: _ArrayLike, pattern: _Path) -> list[str]: ...
def project_map(texels: _ArrayLike, lmax: int, codomain: str = "POLAR4") -> PshVector:
    """PSH (32) of a cube cross ``3e x 4e`` or equirect ``H x 2H`` map."""

def reconstruct_map(vector: PshVector, rows: int, columns: int) -> _FloatArray:
    """PSH (30) on a cube cross or equirect layout: ``(channels, rows, columns, 4)``."""

def reconstruct_perspective(
    vector: PshVector,
    forward: _ArrayLike,
    up: _ArrayLike,
    fov_y: float,
    width: int,
    height: int,
) -> _FloatArray:
    """PSH (30) at a pinhole camera's pixels, camera frames: ``(channels, height, width, 4)``."""

@final
class ConvolutionKernel:
    """``k(theta)``, 4 x 4 (PSH (61)-(62))."""

    @staticmethod
    def from_table(theta: _ArrayLike, values: _ArrayLike) -> ConvolutionKernel:
        """``theta (n,)`` from 0 to pi, ``values (n, 4, 4)``, linear interpolation."""
    @staticmethod
    def from_callable(f: Callable[[float], _ArrayLike]) -> ConvolutionKernel: ...
    @staticmethod
    def linear_zenith() -> ConvolutionKernel: ...
    @staticmethod
    def read_csv(path: _Path) -> ConvolutionKernel: ...
    def value(self, theta: float) -> _FloatArray: ...
    def coefficients(self, lmax: int) -> KernelCoefficients:
        """``G_l`` PSH (68a)-(68e)."""

@final
class KernelCoefficients:
    """Convolution coefficients; ``convolve`` is PSH (69a)-(69c)."""

    @staticmethod
    def from_real_form(g: _ArrayLike) -> KernelCoefficients: ...
    @property
    def lmax(self) -> int: ...
    @property
    def error_estimate(self) -> float: ...
    def real_form(self) -> _FloatArray:
        """``(lmax+1, 4, 4)``."""
    def synthesize(self, theta: float) -> _FloatArray: ...
    def convolve(self, f: PshVector) -> PshVector: ...

@final
class Conductor:
    """GGX microfacet conductor (PF Table 1 material at a channel, or ``n + i k``)."""

    def __new__(
        cls,
        alpha: float,
        material: Optional[str] = None,
        channel: str = "red",
        n: Optional[float] = None,
        k: Optional[float] = None,
    ) -> Conductor: ...

@final
class PolarizedPlastic:
    """GGX dielectric specular of index ``n`` over a Lambertian base of ``albedo``."""

    def __new__(cls, alpha: float, n: float, albedo: float) -> PolarizedPlastic: ...

@final
class PshMatrix:
    """PSH (40): entries ``[j_o, j_i, p_o, p_i]``."""

    @staticmethod
    def from_data(
        data: _ArrayLike, input: str = "towards-source", output: str = "travel"
    ) -> PshMatrix: ...
    @property
    def lmax(self) -> int: ...
    @property
    def input(self) -> str: ...
    @property
    def output(self) -> str: ...
    @property
    def data(self) -> _FloatArray:
        """``(n, n, 4, 4)``."""
    def apply(self, f: PshVector) -> PshVector:
        """PSH (41)."""
    def rotated(self, rotation: _RotationLike) -> PshMatrix: ...
    def with_input(self, input: str) -> PshMatrix: ...
    def truncated(self, lmax: int) -> PshMatrix: ...
    def __matmul__(self, f: PshVector, /) -> PshVector:
        """``apply``."""
    def __rmatmul__(self, f: PshVector, /) -> PshVector: ...

@final
class IsotropicMatrix:
    """Isotropic pBRDF matrices in polarsh's ISOBI2 layout, one per channel."""

    @staticmethod
    def read_npz(path: _Path) -> IsotropicMatrix: ...
    def write_npz(self, path: _Path) -> None: ...
    @staticmethod
    def from_dense(m: PshMatrix, tolerance: float = 1e-12) -> IsotropicMatrix: ...
    @staticmethod
    def from_channels(parts: Sequence[IsotropicMatrix]) -> IsotropicMatrix: ...
    @property
    def lmax(self) -> int: ...
    @property
    def channels(self) -> int: ...
    @property
    def input(self) -> str: ...
    @property
    def output(self) -> str: ...
    def blocks(self) -> _FloatArray:
        """``(channels, len(isotropic_pairs(lmax)), 4, 4)``."""
    def to_dense(self, c: int) -> PshMatrix: ...
    def with_input(self, input: str) -> IsotropicMatrix: ...
    def apply(self, f: PshVector) -> PshVector: ...
    def __matmul__(self, f: PshVector, /) -> PshVector:
        """``apply``."""
    def __rmatmul__(self, f: PshVector, /) -> PshVector: ...
    @staticmethod
    def from_blocks(
        blocks: _ArrayLike, input: str = "towards-source", output: str = "travel"
    ) -> IsotropicMatrix:
        """``(channels, pairs, 4, 4)`` in the order of ``isotropic_pairs(lmax)``."""

def isotropic_pairs(lmax: int) -> list[Tuple[int, int]]:
    """The ``(j_o, j_i)`` entries the isotropic layout stores, in its order."""
def project_pbrdf(
    model: Union[Conductor, PolarizedPlastic],
    lmax: int,
    grid_lmax: Optional[int] = None,
    block: str = "complex-pair",
) -> PshMatrix:
    """PSH (40) of a model (surface normal +z)."""

@final
class MeasuredPbrdf:
    """A measured pBRDF table (Mueller matrices on a Rusinkiewicz grid per wavelength)."""

    @property
    def wavelengths(self) -> list[float]: ...
    @property
    def shape(self) -> Tuple[int, int, int]: ...
    @property
    def invalid_fraction(self) -> float: ...
    def to_rgb(self) -> MeasuredPbrdf:
        """The KAIST bands 450..650 nm to linear sRGB, as the dataset's code converts them."""
    def project(
        self, lmax: int, grid_lmax: Optional[int] = None, tolerance: float = 1e-3
    ) -> IsotropicMatrix:
        """PSH (40), (52): one isotropic matrix per channel."""

def read_measured_pbrdf(path: _Path, info: Optional[_Path] = None) -> MeasuredPbrdf:
    """A Mitsuba 3 ``.pbsdf`` table, or a KAIST MAT data file with its info file's frames."""

@final
class TripleTable:
    """Couplings of PSH (54)-(56)."""

    def __new__(cls, lv: int, lmax: int, codomain: str = "POLAR4") -> TripleTable: ...
    def transfer(self, v: PshVector) -> PshMatrix: ...
    def shadow(self, v: PshVector, f: PshVector) -> PshVector: ...

def visibility_transfer(v: PshVector, lmax: int) -> PshMatrix: ...
def render(
    scene: Optional[_Path] = None,
    out: _Path = "psh-out",
    width: int = 480,
    height: int = 360,
    l_low: Optional[int] = None,
    l_high: Optional[int] = None,
    rays: Optional[int] = None,
    shadows: bool = True,
    tolerance: Optional[float] = 1e-3,
    polarizers: Sequence[float] = [0.0, 45.0, 90.0, 135.0],
    valid_range: bool = True,
    window: Optional[str] = None,
    sun: Optional[str] = None,
) -> Tuple[_FloatArray, dict]:
    """PPRT (PSH Sec. 7): ``(stokes (height, width, 3, 4), report)``, channels R, G, B,
    components s0..s3 (``stokes[..., 0]`` is the radiance image ``imshow`` takes)."""

def verify(filter: Optional[str] = None) -> list[dict]:
    """The checks of ``psh verify`` whose id contains ``filter`` (ValueError when none
    does)."""

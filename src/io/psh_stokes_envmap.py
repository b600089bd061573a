"""Mitsuba 3 emitter ``psh_stokes_envmap``: a polarized environment map stored in psh's
map-file format, emitted with its Stokes vectors turned into Mitsuba's polarization frames
and importance-sampled by intensity.

Mitsuba's own ``envmap`` emits unpolarized light only. This module is self-contained
(numpy, mitsuba, drjit and the standard library; not the psh package), so that psh's
Mitsuba export can write it beside a scene as ``psh_stokes_envmap.py``.

Usage::

    import mitsuba as mi
    mi.set_variant("scalar_spectral_polarized")   # or llvm_ad_mono_polarized, ...
    import psh_stokes_envmap                       # or: from psh import mitsuba_envmap
    psh_stokes_envmap.register()                   # for the variant now set; idempotent
    scene = mi.load_file("scene.xml")

with, in ``scene.xml``::

    <emitter type="psh_stokes_envmap">
        <string name="filename" value="environment_s%d.exr"/>
        <float name="scale" value="1"/>                    <!-- optional -->
        <transform name="to_world"> ... </transform>       <!-- optional rotation -->
    </emitter>

``emitter_class()`` (also the module attribute ``PshStokesEnvmap``) is the plugin class of
the variant now set. Mitsuba does not hand a Python emitter its scene: call
``emitter.set_scene(scene)`` on the loaded emitter (``scene.emitters()``) to give it the
scene's bounding sphere, which ``sample_ray`` (light tracing) needs; before that it uses
the unit sphere, and shadow rays towards sampled directions reach ``FAR`` units.

File format (psh's ``docs/conventions.md``, "Maps and files"):

- Four EXR files, one per Stokes component, named by a pattern with one ``%d`` (replaced by
  0..3) or by one of them (the last ``_s`` of the name followed by 0..3, as psh's
  ``io::component_paths``); channels ``R, G, B`` or one channel ``Y``. Any other name is
  one EXR file with the layers ``S0..S3`` (the layout of Mitsuba's ``stokes`` output).
- Equirectangular, ``H`` rows by ``W = 2H`` columns: row ``i`` spans
  ``theta in [pi i/H, pi (i+1)/H]``, column ``j`` spans ``phi in [2 pi j/W, 2 pi (j+1)/W]``,
  ``theta`` from ``+z`` and ``phi`` from ``+x`` towards ``+y`` of the map's coordinates, at
  the direction ``w`` towards the light's source. psh's cube crosses (``3e x 4e``) are not
  read: psh's export resamples them to this layout.
- The map is piecewise constant over texels (psh's ``Equirect::texel_at``; no filtering).
- A texel's components are measured in the frame ``[e_theta, -e_phi, -w]`` at the exact
  direction ``w``: ``z`` along the light's travel, ``e_theta, e_phi`` the spherical unit
  vectors (at the poles their limit along ``phi = 0``).

Conventions (derivation: psh's ``proofs/mitsuba-stokes-environment.md``):

- ``to_world`` (a rotation) takes the map's coordinates to Mitsuba's world, directions and
  frames alike; psh's exports use psh's world, so a map in psh's orientation needs none
  (this mapping is not that of Mitsuba's ``envmap``, which is ``y``-up).
- Light arriving along a ray travels along ``d = -(to_world w)``; Mitsuba expects its Stokes
  vector in the frame ``[b, d x b, d]``, ``b = mueller.stokes_basis(d)``
  (``include/mitsuba/render/mueller.h``), as the first column of the ``Spectrum``'s
  Mueller matrix (its other columns zero) in polarized variants. The stored components are
  turned by ``mueller.rotator(vartheta)``, ``vartheta`` the angle from
  ``to_world e_theta`` to ``b`` about ``d``; other variants emit ``s0``.
- Colour as Mitsuba's ``envmap`` (``src/emitters/envmap.cpp``): spectral variants upsample
  an RGB triple ``c >= 0`` by ``srgb_model_fetch(c / (2 max c))``, times ``2 max c`` and the
  D65 illuminant (an unpolarized map emits what ``envmap`` emits given the same texels, to
  the bit); a component with negative channels is the upsampled positive part minus the
  upsampled negative part; monochrome variants take ``luminance``, RGB variants the triple.
  Texels with ``s0 <= 0`` emit what they store and are never sampled.

Sampling: a texel with probability proportional to ``max(luminance(s0), 0)`` times its
solid angle, then a direction uniform in ``cos theta`` and ``phi`` over the texel; the pdf
per solid angle is ``P(texel) / Omega(texel)``, ``Omega = (cos t0 - cos t1) 2 pi / W``.

Variants: polarized ones emit the Stokes vector, the others ``s0``. Scalar variants call
this Python code once per ray under the GIL (a 64 x 64 image at 64 samples per pixel takes
seconds); the ``llvm_ad_*`` variants trace it once and run it vectorized (hundreds of times
faster), given Dr.Jit's LLVM backend (libLLVM 16 or newer; LLVM 15 aborts).
"""

import importlib
import math
import os

import drjit as dr  # type: ignore[import-not-found, unused-ignore]
import mitsuba as mi  # type: ignore[import-not-found, unused-ignore]
import numpy as np

#: The plugin's name in scene files.
NAME = "psh_stokes_envmap"
#: Length of shadow rays towards sampled directions before `set_scene`.
FAR = 1e10

_CLASSES: dict = {}
_REGISTERED: set = set()


def component_files(filename):
    """The files of a map: four for a ``%d`` pattern or a name with ``_s0``..``_s3`` (psh's
    ``io::component_paths``), else the one multilayer file."""
    if "%d" in filename:
        if filename.count("%d") != 1:
            raise ValueError(f"{filename}: exactly one %d (the Stokes component) is allowed")
        return [filename.replace("%d", str(p)) for p in range(4)]
    head, name = os.path.split(filename)
    at = name.rfind("_s")
    if at >= 0 and name[at + 2:at + 3] in ("0", "1", "2", "3"):
        return [os.path.join(head, f"{name[:at + 2]}{p}{name[at + 3:]}") for p in range(4)]
    return [filename]


def _rgb(bitmap, what):
    """A bitmap's linear float32 RGB ``[H, W, 3]`` (a ``Y`` channel repeated)."""
    channels = bitmap.channel_count()
    if channels not in (1, 3):
        raise ValueError(f"{what}: {channels} channels, expected R, G, B or Y")
    return np.array(bitmap.convert(mi.Bitmap.PixelFormat.RGB, mi.Struct.Type.Float32, False))


def read_map(files):
    """The components ``[4, H, W, 3]`` (float32), as stored, of the map in ``files``
    (``component_files``), checked for an equirectangular shape and finite values."""
    filename = files[0]
    if len(files) == 4:
        images = [_rgb(mi.Bitmap(f), f) for f in files]
    else:
        layers = dict(mi.Bitmap(filename).split())
        missing = [f"S{p}" for p in range(4) if f"S{p}" not in layers]
        if missing:
            raise ValueError(f"{filename}: no layers {', '.join(missing)} (expected one file "
                             "per component, named with %d or _s0, or layers S0..S3)")
        images = [_rgb(layers[f"S{p}"], f"{filename} layer S{p}") for p in range(4)]
    shapes = {im.shape for im in images}
    if len(shapes) != 1:
        raise ValueError(f"{filename}: the components differ in size {sorted(shapes)}")
    height, width = images[0].shape[:2]
    if width != 2 * height:
        raise ValueError(f"{filename}: {height} x {width} (rows x columns) is not "
                         "equirectangular (H x 2H); cube crosses are not read")
    stokes = np.stack(images)
    if not np.isfinite(stokes).all():
        raise ValueError(f"{filename}: non-finite values")
    return stokes


def _check_rotation(r):
    """Refuses a ``to_world`` whose 3 x 3 part is no rotation (``R^T R = I``, det 1)."""
    if np.abs(r.T @ r - np.eye(3)).max() > 1e-5 or np.linalg.det(r) <= 0:
        raise ValueError(f"to_world must be a rotation, got\n{r}")


def emitter_class():
    """The plugin class for the Mitsuba variant now set."""
    variant = mi.variant()
    if variant is None:
        raise RuntimeError("set a Mitsuba variant (mi.set_variant) first")
    if variant not in _CLASSES:
        _CLASSES[variant] = _make_class(importlib.import_module(f"mitsuba.{variant}"))
    return _CLASSES[variant]


def register():
    """Registers ``psh_stokes_envmap`` for the variant now set (once per variant)."""
    variant = mi.variant()
    if variant not in _REGISTERED:
        cls = emitter_class()
        mi.register_emitter(NAME, lambda props: cls(props))
        _REGISTERED.add(variant)


def __getattr__(name):
    if name == "PshStokesEnvmap":
        return emitter_class()
    raise AttributeError(f"module {__name__!r} has no attribute {name!r}")


def _make_class(mv):
    """The emitter class of the variant module ``mv``."""
    jit = dr.is_jit_v(mv.Float)
    polarized, spectral, mono = mv.is_polarized, mv.is_spectral, mv.is_monochromatic
    ncomp = 4 if polarized else 1

    def first(x):
        """The value of a scalar, or of a JIT array of width 1."""
        return float(x[0] if jit else x)

    class PshStokesEnvmap(mv.Emitter):
        """A polarized environment map in psh's format (see the module's docstring)."""

        def __init__(self, props):
            mv.Emitter.__init__(self, props)
            self.filename = props.get("filename")
            # Each file found as Mitsuba finds its own (beside the scene file first).
            stokes = read_map([str(mi.file_resolver().resolve(f))
                               for f in component_files(self.filename)])
            self.height, self.width = stokes.shape[1:3]
            self.scale = float(props.get("scale", 1.0))
            matrix = np.array(props.get("to_world", mv.ScalarTransform4f()).matrix,
                              dtype=np.float64).reshape(4, 4)
            _check_rotation(matrix[:3, :3])
            self.to_world = mv.AffineTransform4f(mv.ScalarTransform4f(matrix.tolist()))
            self.to_local = self.to_world.inverse()
            self.m_flags = mi.EmitterFlags.Infinite | mi.EmitterFlags.SpatiallyVarying
            self.bsphere = (mv.ScalarPoint3f(0.0), 1.0)
            self.bounded = False
            self.d65 = mv.Texture.D65(1.0)

            # Rows: 1 - cos t0, 1 + cos t1, cos t0 - cos t1 and the texel's solid angle,
            # each without cancellation (psh's Equirect::solid_angle).
            h, w = self.height, self.width
            t = np.pi * np.arange(h + 1) / h
            delta = 2 * np.sin(0.5 * (t[:-1] + t[1:])) * np.sin(0.5 * (t[1:] - t[:-1]))
            rows = np.stack([2 * np.sin(0.5 * t[:-1]) ** 2, 2 * np.cos(0.5 * t[1:]) ** 2,
                             delta, delta * 2 * np.pi / w], axis=1)
            self.rows = self._table(rows)

            weights = np.array([first(mv.luminance(mv.ScalarColor3f(*e)))
                                for e in np.eye(3)])
            lum = np.maximum(stokes[0].astype(np.float64) @ weights, 0) * rows[:, 3:4]
            self.distr = None
            if lum.sum() > 0:
                pmf = lum.ravel()
                self.distr = mv.DiscreteDistribution(mv.Float(pmf) if jit else pmf)

            comps = stokes[:ncomp].reshape(ncomp, h * w, 3).transpose(1, 0, 2)
            if spectral:
                texels = _spectral_parts(comps, self.scale)
            elif mono:
                texels = comps.astype(np.float64) @ weights * self.scale
            else:
                texels = comps * self.scale
            self.texels = self._table(texels.reshape(h * w, -1))

        # -- tables ---------------------------------------------------------------

        def _table(self, rows):
            """Rows of numbers (float32), looked up by ``_lookup``: a flat ``Float`` in JIT
            variants, else an array."""
            rows = np.asarray(rows, dtype=np.float32)
            return (mv.Float(rows.ravel()), rows.shape[1]) if jit else rows

        @staticmethod
        def _lookup(table, index, active):
            if jit:
                flat, n = table
                return [dr.gather(mv.Float, flat, index * n + k, active) for k in range(n)]
            return table[index].tolist()

        # -- geometry -------------------------------------------------------------

        def _texel(self, w):
            """Texel index and row of the unit direction ``w`` (map coordinates):
            psh's ``Equirect::texel_at``."""
            rho = dr.sqrt(w.x * w.x + w.y * w.y)
            theta = dr.atan2(rho, w.z)
            phi = dr.atan2(w.y, w.x)
            phi = dr.select(phi < 0, phi + 2 * math.pi, phi)
            row = dr.minimum(mv.UInt32(theta * (self.height / math.pi)), self.height - 1)
            col = dr.minimum(mv.UInt32(phi * (self.width / (2 * math.pi))), self.width - 1)
            return row * self.width + col, row

        def _rotation(self, w, travel):
            """``(cos 2 vartheta, sin 2 vartheta)``, ``vartheta`` the angle about the
            travel direction from the stored frame's ``x = e_theta(w)`` to Mitsuba's
            ``stokes_basis(travel)`` (proofs/mitsuba-stokes-environment.md, section 4)."""
            b = self.to_local @ mv.mueller.stokes_basis(travel)
            rho = dr.sqrt(w.x * w.x + w.y * w.y)
            pole = rho == 0
            cos_phi = dr.select(pole, 1.0, w.x) / dr.select(pole, 1.0, rho)
            sin_phi = dr.select(pole, 0.0, w.y) / dr.select(pole, 1.0, rho)
            c = w.z * (cos_phi * b.x + sin_phi * b.y) - rho * b.z  # e_theta . b
            s = sin_phi * b.x - cos_phi * b.y  # -e_phi . b
            n = c * c + s * s
            return (c * c - s * s) / n, 2 * c * s / n

        # -- radiance -------------------------------------------------------------

        def _whitepoint(self, wavelengths):
            """The D65 illuminant at ``wavelengths`` in spectral variants (Mitsuba's
            ``envmap::eval_spectrum``), else 1."""
            if not spectral:
                return 1.0
            si = dr.zeros(mv.SurfaceInteraction3f)
            si.wavelengths = wavelengths
            return self.d65.eval(si)

        def _components(self, texel, wavelengths):
            """The ``ncomp`` components of a row of ``self.texels`` as
            ``UnpolarizedSpectrum``; in spectral variants each the sum over its two parts of
            ``srgb_model_eval`` times the signed size (``_spectral_parts``)."""
            out = []
            for k in range(ncomp):
                if spectral:
                    s = mv.UnpolarizedSpectrum(0.0)
                    for part in (texel[8 * k:8 * k + 4], texel[8 * k + 4:8 * k + 8]):
                        if jit or part[3] != 0:  # scalar variants skip empty parts
                            s = s + mv.srgb_model_eval(mv.Color3f(*part[:3]), wavelengths) * part[3]
                    out.append(s)
                elif mono:
                    out.append(mv.UnpolarizedSpectrum(texel[k]))
                else:
                    out.append(mv.UnpolarizedSpectrum(*texel[3 * k:3 * k + 3]))
            return out

        def _emission(self, w, travel, index, wavelengths, factor, active):
            """The light of texel ``index`` at the unit local direction ``w``, travelling
            along ``travel`` (world), times ``factor``, in Mitsuba's frame (section 4 of
            the proof)."""
            texel = self._lookup(self.texels, index, active)
            s = [x * factor for x in self._components(texel, wavelengths)]
            if not polarized:
                return s[0]
            cos2, sin2 = self._rotation(w, travel)
            m = dr.zeros(mv.Spectrum)
            m[0, 0] = s[0]
            m[1, 0] = cos2 * s[1] + sin2 * s[2]  # mueller::rotator(vartheta)
            m[2, 0] = cos2 * s[2] - sin2 * s[1]
            m[3, 0] = s[3]
            return m

        def _density(self, w, active):
            """Texel of the unit local direction ``w`` and the pdf per solid angle there,
            ``P(texel) / Omega(texel)``."""
            index, row = self._texel(w)
            omega = self._lookup(self.rows, row, active)[3]
            return index, self.distr.eval_pmf_normalized(index, active) / omega

        def _sample(self, sample, active):
            """A texel by ``self.distr`` and a direction uniform in it: (local direction,
            texel, pdf per solid angle), the last two those of the direction (``_density``:
            a direction rounded onto a neighbouring texel is evaluated as ``eval`` does)."""
            index, u, _ = self.distr.sample_reuse_pmf(sample.x, active)
            row = index // self.width
            col = index - row * self.width
            one_minus, one_plus, delta, _ = self._lookup(self.rows, row, active)
            m = one_minus + u * delta  # 1 - cos theta
            p = one_plus + (1 - u) * delta  # 1 + cos theta
            z = dr.select(m < p, 1 - m, p - 1)
            sin_theta = dr.sqrt(dr.maximum(m * p, 0))
            sin_phi, cos_phi = dr.sincos((col + sample.y) * (2 * math.pi / self.width))
            w = mv.Vector3f(sin_theta * cos_phi, sin_theta * sin_phi, z)
            return (w, *self._density(w, active))

        # -- Mitsuba's interface --------------------------------------------------

        def set_scene(self, scene):
            """The scene's bounding sphere, enlarged as Mitsuba's ``envmap::set_scene``."""
            box = scene.bbox()
            if box.valid():
                sphere = box.bounding_sphere()
                radius = max(mv.math.RayEpsilon, sphere.radius * (1 + mv.math.RayEpsilon))
                self.bsphere = (mv.ScalarPoint3f(sphere.center), radius)
            else:
                self.bsphere = (mv.ScalarPoint3f(0.0), mv.math.RayEpsilon)
            self.bounded = True

        def eval(self, si, active=True):
            w = self.to_local @ -si.wi
            index, _ = self._texel(w)
            return self._emission(w, si.wi, index, si.wavelengths,
                                  self._whitepoint(si.wavelengths), active)

        def sample_direction(self, it, sample, active=True):
            if self.distr is None:
                w, index, pdf = mv.Vector3f(0, 0, 1), 0, 0.0
                active = False
            else:
                w, index, pdf = self._sample(sample, active)
            d = self.to_world @ w
            if self.bounded:
                center, radius = self.bsphere
                dist = 2 * dr.maximum(radius, dr.norm(it.p - mv.Point3f(center)))
            else:
                dist = mv.Float(FAR)
            pdf = dr.select(active, pdf, 0.0)
            ds = mv.DirectionSample3f(it.p + d * dist, -d, mv.Point2f(0.0), it.time, pdf,
                                      mv.Bool(False), d, dist,
                                      mv.EmitterPtr(self) if jit else self)
            factor = self._whitepoint(it.wavelengths) * self._inverse(pdf, active)
            return ds, self._emission(w, -d, index, it.wavelengths, factor, active)

        @staticmethod
        def _inverse(pdf, active):
            """``1 / pdf``, 0 where ``pdf`` is 0 or ``active`` false."""
            return dr.select(active & (pdf > 0), dr.rcp(dr.select(pdf > 0, pdf, 1.0)), 0.0)

        def pdf_direction(self, it, ds, active=True):
            if self.distr is None:
                return mv.Float(0.0)
            return dr.select(active, self._density(self.to_local @ ds.d, active)[1], 0.0)

        def eval_direction(self, it, ds, active=True):
            w = self.to_local @ ds.d
            index, _ = self._texel(w)
            return self._emission(w, -ds.d, index, it.wavelengths,
                                  self._whitepoint(it.wavelengths), active)

        def _wavelengths(self, si, sample, active):
            """Wavelengths by the D65 illuminant and their weight, as Mitsuba's
            ``envmap::sample_wavelengths``; ``si``'s (none) in non-spectral variants."""
            if spectral:
                return self.d65.sample_spectrum(si, mv.sample_shifted(sample), active)
            return si.wavelengths, 1.0

        def sample_wavelengths(self, si, sample, active=True):
            w = self.to_local @ -si.wi
            index, _ = self._texel(w)
            wavelengths, weight = self._wavelengths(si, sample, active)
            return wavelengths, self._emission(w, si.wi, index, wavelengths, weight, active)

        def sample_ray(self, time, wavelength_sample, sample2, sample3, active=True):
            """A ray from the disk of the bounding sphere facing the sampled direction, as
            Mitsuba's ``envmap::sample_ray``."""
            if self.distr is None:
                return dr.zeros(mv.Ray3f), dr.zeros(mv.Spectrum)
            w, index, pdf = self._sample(sample3, active)
            d = self.to_world @ w
            center, radius = self.bsphere
            disk = mv.warp.square_to_uniform_disk_concentric(sample2)
            offset = mv.Frame3f(-d).to_world(mv.Vector3f(disk.x, disk.y, 0))
            origin = mv.Point3f(center) + (offset + d) * radius
            si = dr.zeros(mv.SurfaceInteraction3f)
            si.time = time
            wavelengths, weight = self._wavelengths(si, wavelength_sample, active)
            factor = weight * (math.pi * radius ** 2) * self._inverse(pdf, active)
            ray = mv.Ray3f(origin, -d, time, wavelengths)
            return ray, self._emission(w, -d, index, wavelengths, factor, active)

        def bbox(self):
            return mv.ScalarBoundingBox3f()

        def to_string(self):
            return (f"PshStokesEnvmap[filename={self.filename!r}, "
                    f"res={self.height}x{self.width}, scale={self.scale}]")

    return PshStokesEnvmap


def _spectral_parts(rgb, scale):
    """Spectral upsampling of the RGB triples ``rgb`` ``[N, K, 3]`` times ``scale``: per
    triple ``[2, 4]``, its positive and its negative part ``c`` (``rgb = c+ - c-``) as the
    coefficients ``srgb_model_fetch(c / max(1e-8, 2 max c))`` and the signed size
    ``+-2 max c scale``, as Mitsuba's ``envmap`` constructor (``src/emitters/envmap.cpp``).
    Its compiled division of a colour by a scalar is a float32 product with the reciprocal:
    done so here, so that the coefficients are the same to the bit. The coefficients come
    from a ``bitmap`` texture, which applies ``srgb_model_fetch`` to every texel at once
    (``src/textures/bitmap.cpp``, ``upsample_spectral``) and exposes them as ``data``."""
    parts = np.stack([np.maximum(rgb, 0), np.maximum(-rgb, 0)], axis=-2).astype(np.float32)
    size = np.float32(2) * parts.max(axis=-1)
    inverse = np.float32(1) / np.maximum(np.float32(1e-8), size)
    normalized = parts * inverse[..., None]
    texture = mi.load_dict({"type": "bitmap", "filter_type": "nearest", "format": "variant",
                            "bitmap": mi.Bitmap(np.ascontiguousarray(
                                normalized.reshape(len(rgb), -1, 3)))})
    coeff = np.array(mi.traverse(texture)["data"]).reshape(normalized.shape)
    signed = size * np.array([1, -1], dtype=np.float32) * np.float32(scale)
    return np.concatenate([coeff, signed[..., None]], axis=-1)

"""Pictures of psh's results with matplotlib (`pip install "polarized-sh[plot]"`), sized for
a paper's column (3.4 inches wide by default, 8-point text), every panel labelled.

- `stokes_image`: a Stokes image as s0, degree of linear polarization, angle of linear
  polarization (cyclic colour map) and views through linear polarizers, with colour bars.
- `coefficients`: a coefficient vector's magnitudes as (l, m) triangles, one per Stokes
  component.
- `matrix`: a coefficient matrix's magnitudes by (l_o, l_i) blocks, one panel per
  (p_o, p_i) spin block.
- `sphere`: a field on the visible hemisphere with angle-of-polarization glyphs (the static
  counterpart of polarsh's sphere viewer).

Conventions. Images are `(height, width, 4)` or `(height, width, channels, 4)` (what
`psh.render` returns), Stokes components in frames with `x` image-right and `y` image-up
(psh's renders); angles are measured from image-right towards image-up. The AoLP is
`0.5 atan2(s2, s1)` in degrees, in (-90, 90]; the DoLP `sqrt(s1^2 + s2^2) / s0`.
"""

from __future__ import annotations

from typing import Any, Optional, Sequence, Tuple

import matplotlib.pyplot as plt
import numpy as np

import psh

#: Column width of a two-column paper, inches.
COLUMN = 3.4
#: Rec. 709 luminance weights of R, G, B (Stokes vectors add, so the luminance's Stokes
#: vector is the weighted sum of the channels').
LUMINANCE = np.array([0.2126, 0.7152, 0.0722])

_TEXT: Any = {"font.size": 8, "axes.titlesize": 8, "axes.labelsize": 8,
         "xtick.labelsize": 7, "ytick.labelsize": 7, "legend.fontsize": 7}


def _luminance(stokes: np.ndarray) -> np.ndarray:
    """`(H, W, 4)` from `(H, W, 4)` or `(H, W, 3, 4)` (R, G, B weighted by Rec. 709)."""
    s = np.asarray(stokes, dtype=float)
    if s.ndim == 4 and s.shape[2] == 3 and s.shape[3] == 4:
        return np.tensordot(s, LUMINANCE, axes=([2], [0]))
    if s.ndim == 3 and s.shape[2] == 4:
        return s
    raise ValueError(f"invalid stokes: shape {s.shape}, expected (H, W, 4) or (H, W, 3, 4)")


def dolp(s: np.ndarray) -> np.ndarray:
    """Degree of linear polarization of `(..., 4)`; NaN where `s0 <= 0`."""
    with np.errstate(divide="ignore", invalid="ignore"):
        d = np.hypot(s[..., 1], s[..., 2]) / s[..., 0]
    return np.where(s[..., 0] > 0, d, np.nan)


def aolp_deg(s: np.ndarray) -> np.ndarray:
    """Angle of linear polarization of `(..., 4)` in degrees, (-90, 90]."""
    return np.degrees(0.5 * np.arctan2(s[..., 2], s[..., 1]))


def through_polarizer(s: np.ndarray, angle_deg: float) -> np.ndarray:
    """Intensity behind an ideal linear polarizer at `angle_deg` (PF (8)):
    `(s0 + s1 cos 2a + s2 sin 2a) / 2`, on `(..., 4)` or `(..., channels, 4)`."""
    a = np.radians(angle_deg)
    return 0.5 * (s[..., 0] + s[..., 1] * np.cos(2 * a) + s[..., 2] * np.sin(2 * a))


def _tone(x: np.ndarray, white: float) -> np.ndarray:
    """Linear radiance to display values: divided by `white`, clipped, gamma 1/2.2."""
    return np.clip(np.nan_to_num(x) / white, 0, 1) ** (1 / 2.2)


def stokes_image(stokes: np.ndarray, title: Optional[str] = None,
                 polarizers: Sequence[float] = (0.0, 45.0, 90.0, 135.0),
                 width: float = 2 * COLUMN, min_s0: float = 1e-3):
    """A Stokes image in two rows: s0 (RGB when the image has three channels), DoLP and
    AoLP (cyclic map, hidden where the DoLP is below 1% or s0 below `min_s0` of its 99th
    percentile) with colour bars; then the views through `polarizers` (degrees from
    image-right towards image-up) on s0's scale. Returns `(fig, axes)`, `axes` the list
    of panels in that order."""
    s = np.asarray(stokes, dtype=float)
    lum = _luminance(s)
    white = np.nanpercentile(lum[..., 0], 99) if np.isfinite(lum[..., 0]).any() else 1.0
    white = white if white > 0 else 1.0  # a dark or empty image: the scale of 1
    rgb = s.ndim == 4
    h, w = lum.shape[:2]
    k = max(3, len(polarizers))
    with plt.rc_context(_TEXT):
        fig = plt.figure(figsize=(width, 2 * width / k * h / w + 0.6), layout="constrained")
        rows: Any = fig.subfigures(2, 1)
        top, bottom = rows[0], rows[1]
        first = top.subplots(1, 3)
        views = bottom.subplots(1, len(polarizers), squeeze=False)[0] if polarizers else []
        if rgb:
            first[0].imshow(_tone(s[..., 0], white))
            first[0].set_title("s0 (R, G, B)")
        else:
            im = first[0].imshow(lum[..., 0], cmap="gray", vmin=0, vmax=white)
            top.colorbar(im, ax=first[0], shrink=0.8)
            first[0].set_title("s0")
        d = dolp(lum)
        im = first[1].imshow(d, cmap="viridis", vmin=0, vmax=1)
        top.colorbar(im, ax=first[1], shrink=0.8)
        first[1].set_title("DoLP")
        angle = np.where((d > 0.01) & (lum[..., 0] > min_s0 * white), aolp_deg(lum), np.nan)
        im = first[2].imshow(angle, cmap="twilight", vmin=-90, vmax=90)
        bar = top.colorbar(im, ax=first[2], shrink=0.8, ticks=[-90, -45, 0, 45, 90])
        bar.set_label("degrees")
        first[2].set_title("AoLP")
        for a, deg in zip(views, polarizers):
            view = through_polarizer(s, deg)
            if rgb:
                a.imshow(_tone(view, white))
            else:
                a.imshow(view, cmap="gray", vmin=0, vmax=white)
            a.set_title(f"polarizer {deg:g} deg")
        panels = list(first) + list(views)
        for a in panels:
            a.set_xticks([])
            a.set_yticks([])
        if title:
            fig.suptitle(title)
    return fig, panels


def _triangle(c: np.ndarray, lmax: int) -> np.ndarray:
    """`(lmax + 1, 2 lmax + 1)` of `c` at flat index `l*l + l + m`, NaN outside `|m| <= l`."""
    t = np.full((lmax + 1, 2 * lmax + 1), np.nan)
    for l in range(lmax + 1):
        t[l, lmax - l:lmax + l + 1] = c[l * l:(l + 1) * (l + 1)]
    return t


def coefficients(v: psh.PshVector, channel: int = 0, floor: float = 1e-12,
                 width: float = COLUMN):
    """`log10 |c_lm|` of one channel of a coefficient vector, an (l, m) triangle per Stokes
    component (rows l from 0 at the top, columns m from -l to l). Returns `(fig, axes)`."""
    c = v.coeffs[channel]
    names = [f"s{k}" for k in v.components]
    logs = [np.log10(np.maximum(np.abs(_triangle(c[:, k], v.lmax)), floor))
            for k in range(c.shape[1])]
    top = max(np.nanmax(x) for x in logs)
    with plt.rc_context(_TEXT):
        fig, axes = plt.subplots(1, len(logs), figsize=(width, width / len(logs) * 0.75 + 0.5),
                                 squeeze=False, layout="constrained")
        for a, x, name in zip(axes[0], logs, names):
            im = a.imshow(x, cmap="magma", vmin=max(np.log10(floor), top - 8), vmax=top,
                          extent=(-v.lmax - 0.5, v.lmax + 0.5, v.lmax + 0.5, -0.5),
                          aspect="auto")
            a.set_title(name)
            a.set_xlabel("m")
            a.set_xticks(_integer_ticks(-v.lmax, v.lmax))
            a.set_yticks(_integer_ticks(0, v.lmax))
        axes[0, 0].set_ylabel("l")
        bar = fig.colorbar(im, ax=list(axes[0]), shrink=0.8)
        bar.set_label("log10 |coefficient|")
    return fig, axes


def _integer_ticks(lo: int, hi: int, most: int = 5) -> list:
    """At most `most` integer ticks from `lo` to `hi`, evenly spaced, ends included."""
    step = max(1, int(np.ceil((hi - lo) / (most - 1))))
    ticks = list(range(lo, hi + 1, step))
    return ticks if ticks[-1] == hi or len(ticks) < most else ticks[:-1] + [hi]


def matrix(m, channel: int = 0, floor: float = 1e-12, width: float = COLUMN):
    """`log10` of the Frobenius norm of each `(l_o, l_i)` block of a coefficient matrix
    (a `PshMatrix`, or an `IsotropicMatrix`'s channel), one panel per spin block: 0 <- 0
    (`p in {0, 3}`), 0 <- 2, 2 <- 0 and 2 <- 2 (`p in {1, 2}`). Returns `(fig, axes)`."""
    dense = m.to_dense(channel) if isinstance(m, psh.IsotropicMatrix) else m
    data = dense.data
    lmax = dense.lmax
    ls = np.repeat(np.arange(lmax + 1), 2 * np.arange(lmax + 1) + 1)
    spins = {"0": [0, 3], "2": [1, 2]}
    blocks = [("0", "0"), ("0", "2"), ("2", "0"), ("2", "2")]
    with plt.rc_context(_TEXT):
        fig, axes = plt.subplots(2, 2, figsize=(width, width * 0.9), squeeze=False,
                                 layout="constrained")
        tops = []
        images = []
        for (so, si) in blocks:
            sub = data[:, :, spins[so]][:, :, :, spins[si]]
            sq = np.sum(sub ** 2, axis=(2, 3))
            b = np.zeros((lmax + 1, lmax + 1))
            np.add.at(b, (ls[:, None], ls[None, :]), sq)
            x = np.log10(np.maximum(np.sqrt(b), floor))
            images.append(x)
            tops.append(x.max())
        top = max(tops)
        for a, x, (so, si) in zip(axes.flat, images, blocks):
            im = a.imshow(x, cmap="magma", vmin=max(np.log10(floor), top - 8), vmax=top,
                          origin="upper")
            a.set_title(f"spin {so} <- {si}")
            a.set_xlabel("l_i")
            a.set_ylabel("l_o")
            a.set_xticks(_integer_ticks(0, lmax))
            a.set_yticks(_integer_ticks(0, lmax))
        bar = fig.colorbar(im, ax=list(axes.flat), shrink=0.8)
        bar.set_label("log10 |block|")
    return fig, axes


def sphere(v: psh.PshVector, channel: int = 0, n: int = 256, glyphs: int = 15,
           width: float = COLUMN * 0.75, ax=None) -> Tuple:
    """The field of a coefficient vector on the hemisphere facing the viewer (+z towards
    the viewer, x right, y up: orthographic), s0 in grey from 0, with angle-of-polarization
    glyphs on a `glyphs x glyphs` lattice: segments along the polarization direction in
    the tangent plane (theta-phi frames, PSH (28)), seen in projection, their length the
    DoLP. Returns `(fig, ax)`."""
    xs = np.linspace(-1, 1, n)
    X, Y = np.meshgrid(xs, -xs)
    inside = X ** 2 + Y ** 2 < 1
    Z = np.sqrt(np.clip(1 - X ** 2 - Y ** 2, 0, 1))
    dirs = np.stack([X[inside], Y[inside], Z[inside]], axis=-1)
    s0 = np.full(X.shape, np.nan)
    s0[inside] = v.evaluate(dirs)[channel, :, 0]
    with plt.rc_context(_TEXT):
        if ax is None:
            fig, ax = plt.subplots(figsize=(width, width), layout="constrained")
        else:
            fig = ax.figure
        im = ax.imshow(s0, cmap="gray", extent=(-1, 1, -1, 1), vmin=min(0.0, np.nanmin(s0)),
                       vmax=np.nanmax(s0))
        fig.colorbar(im, ax=ax, shrink=0.7, label="s0")
        g = (np.arange(glyphs) + 0.5) / glyphs * 2 - 1
        GX, GY = np.meshgrid(g, g)
        keep = GX ** 2 + GY ** 2 < 0.95
        w = np.stack([GX[keep], GY[keep], np.sqrt(1 - GX[keep] ** 2 - GY[keep] ** 2)], -1)
        s = v.evaluate(w)[channel]
        chi = 0.5 * np.arctan2(s[:, 2], s[:, 1])
        theta = np.arccos(np.clip(w[:, 2], -1, 1))
        phi = np.arctan2(w[:, 1], w[:, 0])
        e_theta = np.stack([np.cos(theta) * np.cos(phi), np.cos(theta) * np.sin(phi),
                            -np.sin(theta)], -1)
        e_phi = np.stack([-np.sin(phi), np.cos(phi), np.zeros_like(phi)], -1)
        t = np.cos(chi)[:, None] * e_theta + np.sin(chi)[:, None] * e_phi
        length = np.clip(dolp(s), 0, 1) * (1.6 / glyphs)
        half = 0.5 * length[:, None] * t[:, :2]
        for (x, y), dx in zip(w[:, :2], half):
            ax.plot([x - dx[0], x + dx[0]], [y - dx[1], y + dx[1]], color="tab:orange",
                    linewidth=1.0, solid_capstyle="round")
        ax.set_xlim(-1.02, 1.02)
        ax.set_ylim(-1.02, 1.02)
        ax.set_aspect("equal")
        ax.set_xticks([])
        ax.set_yticks([])
        ax.set_title("s0 and AoLP (length: DoLP)")
    return fig, ax

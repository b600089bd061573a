//! Stokes maps: polarized environment maps as Stokes fields on pixel grids, the values
//! together with their frame field, so that a texel's components never lose their frame.
//!
//! A map indexes light by the direction `w` towards its source. Its layout is a cube
//! cross (`3e x 4e`) or an equirectangular image (`H x 2H`), and its components are in
//! psh's frame field of that layout ([`MapFrameField`]): the cube-map frame field, or the
//! theta-phi frame field PSH (28). Files store them in another frame, see [`crate::io`].

use crate::error::{Error, Result};
use crate::geometry::frame::{CubeMapFrameField, Frame, FrameField, ThetaPhiFrameField};
use crate::geometry::image_grid::{CubeCross, Equirect, PixelGrid};
use crate::polarized::{
    project_cube_map, project_image, reconstruct_image, Codomain, FieldArgument, PshVector,
};
use crate::stokes::{StokesComponents, StokesVector};

/// The pixel layout of a map.
#[derive(Clone, Debug, PartialEq, Eq)]
pub enum MapLayout {
    /// A cube map stored as a 3 x 4 cross ([`CubeCross`]).
    CubeCross(CubeCross),
    /// A latitude-longitude image ([`Equirect`]).
    Equirect(Equirect),
}

impl MapLayout {
    /// The layout of an image of `height x width`: `3e x 4e` is a cube cross, `H x 2H`
    /// equirectangular; any other shape is an error naming it.
    pub fn from_image_size(height: usize, width: usize) -> Result<Self> {
        if height > 0 && width == 2 * height {
            Ok(Self::Equirect(Equirect::new(height, width)?))
        } else if height > 0 && height.is_multiple_of(3) && 3 * width == 4 * height {
            Ok(Self::CubeCross(CubeCross::new(height / 3)?))
        } else {
            Err(Error::invalid(
                "map size",
                format!("{height} x {width} (rows x columns)"),
                "a cube cross is 3e x 4e, an equirectangular map H x 2H",
            ))
        }
    }

    /// Image rows.
    pub fn height(&self) -> usize {
        match self {
            Self::CubeCross(g) => g.height(),
            Self::Equirect(g) => g.height,
        }
    }

    /// Image columns.
    pub fn width(&self) -> usize {
        match self {
            Self::CubeCross(g) => g.width(),
            Self::Equirect(g) => g.width,
        }
    }

    /// PSH coefficients of `l <= lmax` of images on this layout (one slice of texels per
    /// channel, row-major, components in [`Self::frame_field`]), for the components of
    /// `codomain`: by [`project_image`], for cube crosses by [`project_cube_map`].
    pub fn project(
        &self,
        channels: &[&[[f64; 4]]],
        codomain: Codomain,
        lmax: usize,
    ) -> Result<PshVector> {
        match self {
            Self::CubeCross(g) => project_cube_map(g, channels, codomain, lmax),
            Self::Equirect(g) => project_image(g, &self.frame_field(), channels, codomain, lmax),
        }
    }

    /// The texel containing the direction `w` (`None` for zero or non-finite `w`):
    /// [`CubeCross::texel_at`], [`Equirect::texel_at`].
    pub fn texel_at(&self, w: [f64; 3]) -> Option<usize> {
        match self {
            Self::CubeCross(g) => g.texel_at(w),
            Self::Equirect(g) => g.texel_at(w),
        }
    }

    /// psh's frame field of the layout.
    pub fn frame_field(&self) -> MapFrameField {
        match self {
            Self::CubeCross(_) => MapFrameField::CubeMap,
            Self::Equirect(_) => MapFrameField::ThetaPhi,
        }
    }
}

impl PixelGrid for MapLayout {
    fn len(&self) -> usize {
        match self {
            Self::CubeCross(g) => g.len(),
            Self::Equirect(g) => g.len(),
        }
    }

    fn direction(&self, i: usize) -> [f64; 3] {
        match self {
            Self::CubeCross(g) => g.direction(i),
            Self::Equirect(g) => g.direction(i),
        }
    }

    fn solid_angle(&self, i: usize) -> f64 {
        match self {
            Self::CubeCross(g) => g.solid_angle(i),
            Self::Equirect(g) => g.solid_angle(i),
        }
    }

    fn angles(&self, i: usize) -> Result<(f64, f64)> {
        match self {
            Self::CubeCross(g) => g.angles(i),
            Self::Equirect(g) => g.angles(i),
        }
    }
}

/// The frame field of a map's components: z along `w` in both.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum MapFrameField {
    /// [`CubeMapFrameField`]: x image-right, y image-down on each face.
    CubeMap,
    /// [`ThetaPhiFrameField`] of PSH (28): x = e_theta, y = e_phi.
    ThetaPhi,
}

impl FrameField for MapFrameField {
    fn frame(&self, w: [f64; 3]) -> Result<Frame> {
        match self {
            Self::CubeMap => CubeMapFrameField.frame(w),
            Self::ThetaPhi => ThetaPhiFrameField::new().frame(w),
        }
    }
}

/// A polarized map: per channel (e.g. R, G, B), the Stokes components `[s0, s1, s2, s3]`
/// of every texel (row-major) in the layout's [`MapFrameField`].
///
/// # Example
///
/// A band-limited field reconstructed on an equirectangular map (PSH (30)) and projected
/// back (PSH (32)) returns its coefficients up to the texel quadrature error.
///
/// ```
/// use psh::map::{MapLayout, StokesMap};
/// use psh::polarized::{Codomain, PshVector};
///
/// // Flat layout `[(l*l + l + m) * 4 + p]`: f_000 = 1, f_{2,0,1} = 0.3, f_{2,2,2} = -0.2,
/// // f_{1,-1,3} = 0.1.
/// let mut data = vec![0.0; 9 * 4];
/// data[0] = 1.0;
/// data[6 * 4 + 1] = 0.3;
/// data[8 * 4 + 2] = -0.2;
/// data[1 * 4 + 3] = 0.1;
/// let v = PshVector::from_data(2, Codomain::Full, 1, data)?;
///
/// let map = StokesMap::reconstruct(&v, MapLayout::from_image_size(32, 64)?)?;
/// assert_eq!((map.channels().len(), map.channels()[0].len()), (1, 32 * 64));
/// let back = map.project(Codomain::Full, 2)?;
/// let err = v.data().iter().zip(back.data()).fold(0.0f64, |e, (a, b)| e.max((a - b).abs()));
/// assert!(err < 5e-3, "{err}");
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct StokesMap {
    layout: MapLayout,
    channels: Vec<Vec<[f64; 4]>>,
}

impl StokesMap {
    /// A map from its texels. Errors: no channel, a channel whose length is not the
    /// layout's, a NaN or infinite component on a texel of the map (named).
    pub fn new(layout: MapLayout, channels: Vec<Vec<[f64; 4]>>) -> Result<Self> {
        if channels.is_empty() {
            return Err(Error::invalid(
                "Stokes map channels",
                "0",
                "a map needs at least one channel",
            ));
        }
        for (c, ch) in channels.iter().enumerate() {
            crate::error::check_len("Stokes map channel", layout.len(), ch.len())?;
            for (i, s) in ch.iter().enumerate() {
                if layout.solid_angle(i) > 0.0 && s.iter().any(|x| !x.is_finite()) {
                    return Err(Error::invalid(
                        "Stokes texel",
                        format!(
                            "channel {c}, row {}, column {}: {s:?}",
                            i / layout.width(),
                            i % layout.width()
                        ),
                        "components must be finite",
                    ));
                }
            }
        }
        Ok(Self { layout, channels })
    }

    /// The band-limited map of `v` on `layout`: reconstruction PSH (30) at every texel.
    pub fn reconstruct(v: &PshVector, layout: MapLayout) -> Result<Self> {
        FieldArgument::TowardsSource.expect(v.argument(), "PSH vector", "a map")?;
        let channels = reconstruct_image(v, &layout, &layout.frame_field())?;
        Ok(Self { layout, channels })
    }

    /// The layout.
    pub fn layout(&self) -> &MapLayout {
        &self.layout
    }

    /// The frame field of the components.
    pub fn frame_field(&self) -> MapFrameField {
        self.layout.frame_field()
    }

    /// The channels, `[channel][texel] = [s0, s1, s2, s3]`.
    pub fn channels(&self) -> &[Vec<[f64; 4]>] {
        &self.channels
    }

    /// The map at its own resolution, as a field piecewise constant over texels: per
    /// channel the components of the texel containing the unit direction `w`, in the
    /// layout's frame at `w`. Error: `w` zero or not finite.
    pub fn incident(&self, w: [f64; 3]) -> Result<Vec<StokesVector>> {
        let texel = self.layout.texel_at(w).ok_or_else(|| {
            Error::invalid(
                "map direction",
                format!("{w:?}"),
                "a finite non-zero direction",
            )
        })?;
        let frame = self.frame_field().frame(w)?;
        self.channels
            .iter()
            .map(|c| Ok(StokesVector::new(StokesComponents::new(c[texel])?, frame)))
            .collect()
    }

    /// The same map with `s1`, `s2`, `s3` set to zero (its intensity alone).
    pub fn unpolarized(&self) -> StokesMap {
        let channels = self
            .channels
            .iter()
            .map(|c| c.iter().map(|s| [s[0], 0.0, 0.0, 0.0]).collect())
            .collect();
        Self {
            layout: self.layout.clone(),
            channels,
        }
    }

    /// PSH coefficients of `l <= lmax` (projection PSH (32) by the texel-wise quadrature of
    /// [`project_image`]; for cube crosses by [`project_cube_map`]) of the components of
    /// `codomain`.
    pub fn project(&self, codomain: Codomain, lmax: usize) -> Result<PshVector> {
        let refs: Vec<&[[f64; 4]]> = self.channels.iter().map(|c| c.as_slice()).collect();
        self.layout.project(&refs, codomain, lmax)
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn layouts_from_sizes() {
        assert!(matches!(
            MapLayout::from_image_size(192, 256).unwrap(),
            MapLayout::CubeCross(CubeCross { edge: 64 })
        ));
        assert!(matches!(
            MapLayout::from_image_size(32, 64).unwrap(),
            MapLayout::Equirect(Equirect {
                height: 32,
                width: 64
            })
        ));
        for (h, w) in [(0, 0), (190, 256), (192, 255), (3, 5)] {
            let e = MapLayout::from_image_size(h, w).unwrap_err().to_string();
            assert!(e.contains(&format!("{h} x {w}")), "{e}");
        }
    }

    /// A band-limited map reconstructed on an image and projected back returns its
    /// coefficients up to the texel quadrature error, in both layouts; and a NaN texel is
    /// an error naming it.
    #[test]
    fn reconstruct_then_project() {
        let lmax = 3;
        let v = crate::testing::random_psh(lmax, Codomain::Full, 2, 23).unwrap();
        for layout in [
            MapLayout::from_image_size(96, 128).unwrap(),
            MapLayout::from_image_size(64, 128).unwrap(),
        ] {
            let map = StokesMap::reconstruct(&v, layout.clone()).unwrap();
            let back = map.project(Codomain::Full, lmax).unwrap();
            let err = v
                .data()
                .iter()
                .zip(back.data())
                .fold(0.0f64, |m, (a, b)| m.max((a - b).abs()));
            assert!(err < 5e-3, "{layout:?}: {err}");
            let mut bad = map.channels().to_vec();
            let i = layout.len() / 2 + layout.width() / 2;
            bad[1][i][2] = f64::NAN;
            let e = StokesMap::new(layout.clone(), bad).unwrap_err().to_string();
            assert!(e.contains("channel 1") && e.contains("NaN"), "{e}");
        }
    }
}

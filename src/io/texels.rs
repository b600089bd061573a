//! The Stokes images the writers take, read in place: per channel the components of every
//! texel, in the stored frames or in psh's frames ([`super::reverse_frame`] applied on
//! the fly, no copy of the image); and the memory that writing them needs beside the
//! image, checked against [`crate::budget`] before anything is written.

use crate::error::{check_len, Result};

/// Bytes per texel and channel that the EXR files need beside the image: the 32-bit
/// values of one component and the encoder's copy of them.
const EXR_BYTES_PER_TEXEL_CHANNEL: usize = 8;

/// Bytes per texel that the PNG pictures need beside the image: the luminance of the four
/// components, one component's values and their sorted copy (the percentile), the mask
/// and the 8-bit RGB picture.
const PNG_BYTES_PER_TEXEL: usize = 32 + 8 + 8 + 1 + 3;

/// Channels of `texels` texels each, components `[s0, s1, s2, s3]` per texel.
#[derive(Clone, Copy)]
pub(crate) struct StokesTexels<'a> {
    channels: &'a [Vec<[f64; 4]>],
    reversed: bool,
    texels: usize,
}

impl<'a> StokesTexels<'a> {
    /// Components as stored (the frames of the files). Error: a channel not of `texels`.
    pub(crate) fn stored(channels: &'a [Vec<[f64; 4]>], texels: usize) -> Result<Self> {
        for c in channels {
            check_len("Stokes image channel", texels, c.len())?;
        }
        Ok(Self {
            channels,
            reversed: false,
            texels,
        })
    }

    /// Components in psh's frames, written in the stored frames (`reverse_frame`).
    pub(crate) fn in_psh_frames(channels: &'a [Vec<[f64; 4]>], texels: usize) -> Result<Self> {
        Ok(Self {
            reversed: true,
            ..Self::stored(channels, texels)?
        })
    }

    /// Number of channels.
    pub(crate) fn channels(&self) -> usize {
        self.channels.len()
    }

    /// Number of texels per channel.
    pub(crate) fn len(&self) -> usize {
        self.texels
    }

    /// The stored components of texel `t` of channel `c`.
    pub(crate) fn get(&self, c: usize, t: usize) -> [f64; 4] {
        let s = self.channels[c][t];
        if self.reversed {
            super::reverse_frame(s)
        } else {
            s
        }
    }
}

/// Checks that an image of `texels` texels and `channels` channels (four 64-bit
/// components each), its EXR files and its PNG pictures fit in the memory budget
/// together: before an image is made to be written (`psh reconstruct`), and by the
/// writers. Error: [`crate::Error::MemoryBudget`].
pub fn check_stokes_output(texels: usize, channels: usize) -> Result<()> {
    let per_texel = channels
        .checked_mul(32 + EXR_BYTES_PER_TEXEL_CHANNEL)
        .and_then(|b| b.checked_add(PNG_BYTES_PER_TEXEL))
        .unwrap_or(usize::MAX);
    crate::budget::check(
        "a Stokes image with its EXR files and pictures",
        &[texels, per_texel],
        1,
    )
    .map(|_| ())
}

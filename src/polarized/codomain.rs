//! Which Stokes components a PSH field or coefficient vector carries (polarsh's
//! `cod_type`).

/// Whether flat SH index `j = l*l + l + m` with Stokes component `p` lies in the index
/// set PSH (31): `l >= 0` for `p = 0, 3`, `l >= 2` for the spin-2 components `p = 1, 2`.
#[inline]
pub fn in_index_set(j: usize, p: usize) -> bool {
    j >= 4 || !(p == 1 || p == 2)
}

/// Which Stokes components a field or coefficient vector carries (polarsh `cod_type`).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Codomain {
    /// Intensity only, `{s0}`: scalar SH (`SCALAR`).
    Intensity,
    /// Linear polarization only, `{s1, s2}` (`POLAR2`).
    Linear,
    /// `{s0, s1, s2}` (`POLAR3`).
    NoCircular,
    /// The full Stokes vector `{s0, s1, s2, s3}` (`POLAR4`).
    Full,
}

impl Codomain {
    /// The Stokes components present, in storage order.
    pub fn components(self) -> &'static [usize] {
        match self {
            Codomain::Intensity => &[0],
            Codomain::Linear => &[1, 2],
            Codomain::NoCircular => &[0, 1, 2],
            Codomain::Full => &[0, 1, 2, 3],
        }
    }

    /// Whether the linear (spin-2) components `s1, s2` are present.
    pub fn has_spin2(self) -> bool {
        self != Codomain::Intensity
    }
}

crate::named_enum!(Codomain, "codomain", {
    Intensity => "SCALAR",
    Linear => "POLAR2",
    NoCircular => "POLAR3",
    Full => "POLAR4",
});

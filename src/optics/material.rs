//! The material table of the PF paper (Enfeldt & Goswami, Table 1): complex indices of
//! refraction and specular colours of common conductors and dielectrics.
//!
//! As transcribed in `PF-enfeldt-polarizing-filter-function.txt`: values of `n` and `k`
//! for red, green and blue defined as 650, 550 and 450 nm, from refractiveindex.info's
//! "selected data for 3D artists"; `R_0` rounded to two decimals. What the transcription
//! lost (see `proofs/optics.md` §6): the column separators (rebuilt from the groups of
//! three numbers); whether the printed table had more (e.g. a colour swatch) cannot be
//! told from the text. The footnote marks survive as `*`
//! (soda-lime glass, clear) and `†` (polycarbonate). Every printed `R_0` agrees with
//! PF (3) evaluated on the printed `n`, `k` to the printed rounding, except that Quartz
//! green (`R_0 = 0.03497`) is printed as 0.04. A first rounding to three decimals would
//! explain that entry but contradicts Quartz red (0.03460, printed 0.03) and Titanium
//! blue (0.54452, printed 0.54): a single discrepancy of the printed table
//! (`proofs/polarizing-filter.md` §6, check `filter.r0_table`).

use super::ior::ComplexIor;
use crate::error::{Error, Result};

/// The wavelengths (nm) of the red, green and blue channels of the table.
pub const WAVELENGTHS_NM: [f64; 3] = [650.0, 550.0, 450.0];

/// A colour channel of the table.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Channel {
    /// 650 nm.
    Red,
    /// 550 nm.
    Green,
    /// 450 nm.
    Blue,
}

impl Channel {
    /// All three, in the table's order.
    pub const ALL: [Channel; 3] = [Channel::Red, Channel::Green, Channel::Blue];

    /// The index 0, 1, 2 of red, green, blue.
    pub fn index(self) -> usize {
        self as usize
    }

    /// The wavelength in nm.
    pub fn wavelength_nm(self) -> f64 {
        WAVELENGTHS_NM[self.index()]
    }
}

/// A material of PF Table 1.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Material {
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.91, 0.91, 0.92.
    Aluminum,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.89, 0.79, 0.43.
    Brass,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.93, 0.72, 0.50.
    Copper,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.94, 0.78, 0.37.
    Gold,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.53, 0.51, 0.50.
    Iron,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.63, 0.63, 0.64.
    Lead,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.68, 0.64, 0.59.
    Platinum,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.96, 0.95, 0.92.
    Silver,
    /// Conductor (`k > 0`); printed `R_0` (R, G, B): 0.62, 0.58, 0.54.
    Titanium,
    /// Dielectric (`k = 0`); printed `R_0` (R, G, B): 0.17, 0.17, 0.19.
    Diamond,
    /// Soda-lime glass, clear (the table's footnote `*`).
    Glass,
    /// Dielectric (`k = 0`); printed `R_0` 0.02 in each channel.
    Ice,
    /// Polycarbonate (PC; the table's footnote `†`).
    Plastic,
    /// Dielectric (`k = 0`); printed `R_0` (R, G, B): 0.03, 0.04, 0.04.
    Quartz,
    /// Dielectric (`k = 0`); printed `R_0` 0.02 in each channel.
    Water,
}

/// One row: name, `n` RGB, `k` RGB, `R_0` RGB (as printed).
type Row = (&'static str, [f64; 3], [f64; 3], [f64; 3]);

const TABLE: [Row; 15] = [
    (
        "Aluminum",
        [1.346, 0.965, 0.617],
        [7.475, 6.400, 5.303],
        [0.91, 0.91, 0.92],
    ),
    (
        "Brass",
        [0.444, 0.527, 1.094],
        [3.695, 2.765, 1.829],
        [0.89, 0.79, 0.43],
    ),
    (
        "Copper",
        [0.271, 0.677, 1.316],
        [3.609, 2.625, 2.292],
        [0.93, 0.72, 0.50],
    ),
    (
        "Gold",
        [0.183, 0.421, 1.373],
        [3.424, 2.346, 1.770],
        [0.94, 0.78, 0.37],
    ),
    (
        "Iron",
        [2.911, 2.950, 2.585],
        [3.089, 2.932, 2.767],
        [0.53, 0.51, 0.50],
    ),
    (
        "Lead",
        [1.910, 1.830, 1.440],
        [3.510, 3.400, 3.180],
        [0.63, 0.63, 0.64],
    ),
    (
        "Platinum",
        [2.376, 2.085, 1.845],
        [4.266, 3.715, 3.137],
        [0.68, 0.64, 0.59],
    ),
    (
        "Silver",
        [0.159, 0.145, 0.135],
        [3.929, 3.190, 2.381],
        [0.96, 0.95, 0.92],
    ),
    (
        "Titanium",
        [2.741, 2.542, 2.267],
        [3.814, 3.435, 3.039],
        [0.62, 0.58, 0.54],
    ),
    (
        "Diamond",
        [2.409, 2.423, 2.539],
        [0.0, 0.0, 0.0],
        [0.17, 0.17, 0.19],
    ),
    (
        "Glass",
        [1.521, 1.525, 1.532],
        [0.0, 0.0, 0.0],
        [0.04, 0.04, 0.04],
    ),
    (
        "Ice",
        [1.308, 1.311, 1.316],
        [0.0, 0.0, 0.0],
        [0.02, 0.02, 0.02],
    ),
    (
        "Plastic",
        [1.579, 1.589, 1.608],
        [0.0, 0.0, 0.0],
        [0.05, 0.05, 0.05],
    ),
    (
        "Quartz",
        [1.457, 1.460, 1.466],
        [0.0, 0.0, 0.0],
        [0.03, 0.04, 0.04],
    ),
    (
        "Water",
        [1.331, 1.333, 1.337],
        [0.0, 0.0, 0.0],
        [0.02, 0.02, 0.02],
    ),
];

impl Material {
    /// All materials in the table's order.
    pub const ALL: [Material; 15] = [
        Material::Aluminum,
        Material::Brass,
        Material::Copper,
        Material::Gold,
        Material::Iron,
        Material::Lead,
        Material::Platinum,
        Material::Silver,
        Material::Titanium,
        Material::Diamond,
        Material::Glass,
        Material::Ice,
        Material::Plastic,
        Material::Quartz,
        Material::Water,
    ];

    fn row(self) -> &'static Row {
        &TABLE[self as usize]
    }

    /// The table's name ("Gold", "Glass", ...).
    pub fn name(self) -> &'static str {
        self.row().0
    }

    /// The material of a name, ignoring ASCII case and surrounding spaces, also accepting
    /// "aluminium", "soda-lime glass", "polycarbonate" and "pc". Error
    /// ([`Error::InvalidArgument`]) naming the unknown name and listing the known ones.
    pub fn from_name(name: &str) -> Result<Self> {
        let key = name.trim().to_ascii_lowercase();
        let alias = match key.as_str() {
            "aluminium" => "aluminum",
            "soda-lime glass" | "soda lime glass" => "glass",
            "polycarbonate" | "pc" => "plastic",
            k => k,
        };
        Self::ALL
            .into_iter()
            .find(|m| m.name().eq_ignore_ascii_case(alias))
            .ok_or_else(|| {
                Error::invalid(
                    "material name",
                    crate::error::clip(name),
                    format!(
                        "not in PF Table 1 ({})",
                        Self::ALL.map(|m| m.name()).join(", ")
                    ),
                )
            })
    }

    /// `n` for red, green, blue.
    pub fn n(self) -> [f64; 3] {
        self.row().1
    }

    /// `k` for red, green, blue.
    pub fn k(self) -> [f64; 3] {
        self.row().2
    }

    /// The specular colour `R_0` for red, green, blue, as printed (two decimals).
    pub fn specular_color(self) -> [f64; 3] {
        self.row().3
    }

    /// Whether the table lists `k > 0` (a conductor).
    pub fn is_conductor(self) -> bool {
        self.k().iter().any(|&k| k > 0.0)
    }

    /// The relative index `n + i k` in one channel (against air, index 1).
    pub fn ior(self, channel: Channel) -> ComplexIor {
        let i = channel.index();
        ComplexIor::new(self.n()[i], self.k()[i]).expect("table values are valid")
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn names_round_trip() {
        for m in Material::ALL {
            assert_eq!(Material::from_name(m.name()).unwrap(), m);
            assert_eq!(Material::from_name(&m.name().to_uppercase()).unwrap(), m);
        }
        assert_eq!(
            Material::from_name(" aluminium ").unwrap(),
            Material::Aluminum
        );
        assert_eq!(Material::from_name("PC").unwrap(), Material::Plastic);
        let e = Material::from_name("unobtainium").unwrap_err().to_string();
        assert!(e.contains("unobtainium") && e.contains("Gold"), "{e}");
    }

    #[test]
    fn printed_specular_color_matches_pf_3() {
        // R_0 = ((n-1)^2 + k^2)/((n+1)^2 + k^2) (PF (3)) to the printed two decimals; the
        // one discrepancy (Quartz green, 0.03497 printed 0.04) needs 0.0051.
        for m in Material::ALL {
            for c in Channel::ALL {
                let r0 = m.ior(c).normal_reflectance();
                let printed = m.specular_color()[c.index()];
                assert!((r0 - printed).abs() <= 0.0051, "{} {c:?}: {r0}", m.name());
            }
        }
        assert!(Material::Gold.is_conductor() && !Material::Water.is_conductor());
    }
}

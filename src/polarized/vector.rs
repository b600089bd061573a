//! PSH coefficient vectors PSH (34): real coefficients `f_lmp` in the layout
//! `[channel][l*l + l + m][p]` of polarsh's `.npz`, with their codomain and the meaning
//! of their argument ([`FieldArgument`]).

use super::{in_index_set, Codomain, FieldArgument, PshEvaluator};
use crate::error::{check_len, finite_all, Error, Result};
use crate::sh::{lm_index, num_coeffs, Window};
use crate::stokes::StokesVector;
use num_complex::Complex64;

/// A PSH coefficient vector PSH (34): real coefficients `f_lmp` for `l <= lmax`, the
/// components of `codomain`, and `channels` colour channels, of a field whose argument
/// means what [`FieldArgument`] says.
///
/// # Example
///
/// A rotation (PSH (35)-(37)) keeps every degree's energy, keeps `l = 0`, and `R^-1`
/// undoes `R`.
///
/// ```
/// use psh::geometry::rotation_from_rotvec;
/// use psh::polarized::{Codomain, PshVector};
///
/// // Flat layout `[(l*l + l + m) * 4 + p]`: f_000 = 0.5, f_{2,1,1} = 1, f_{3,-2,2} = -0.3,
/// // f_{1,0,3} = 0.2 (spin 2 starts at l = 2, PSH (31)).
/// let mut data = vec![0.0; 16 * 4];
/// data[0] = 0.5;
/// data[7 * 4 + 1] = 1.0;
/// data[10 * 4 + 2] = -0.3;
/// data[2 * 4 + 3] = 0.2;
/// let f = PshVector::from_data(3, Codomain::Full, 1, data)?;
///
/// let r = rotation_from_rotvec([0.3, -0.2, 0.9])?;
/// let g = f.rotated(&r)?;
/// assert!((g.get(0, 0, 0, 0)? - 0.5).abs() < 1e-15);
/// for (a, b) in f.band_energies()?.iter().zip(g.band_energies()?) {
///     assert!((a - b).abs() < 1e-13);
/// }
/// let back = g.rotated(&r.inverse())?;
/// assert!(back.data().iter().zip(f.data()).all(|(a, b)| (a - b).abs() < 1e-13));
/// # Ok::<(), psh::Error>(())
/// ```
#[derive(Clone, Debug, PartialEq)]
pub struct PshVector {
    lmax: usize,
    codomain: Codomain,
    channels: usize,
    argument: FieldArgument,
    /// `[channel][l*l + l + m][p]`.
    data: Vec<f64>,
}

impl PshVector {
    /// All-zero coefficients of a field indexed by the direction towards the source
    /// (psh's convention; [`Self::labelled`] declares another).
    pub fn zeros(lmax: usize, codomain: Codomain, channels: usize) -> Result<Self> {
        crate::sh::check_lmax(lmax)?;
        if channels == 0 {
            return Err(Error::invalid("channels", "0", "at least one channel"));
        }
        let n = crate::budget::check(
            "PSH coefficients",
            &[channels, num_coeffs(lmax), codomain.components().len()],
            8,
        )?;
        Ok(Self {
            lmax,
            codomain,
            channels,
            argument: FieldArgument::TowardsSource,
            data: vec![0.0; n],
        })
    }

    /// From data in the layout `[channel][l*l + l + m][p]` of a field indexed by the
    /// direction towards the source ([`Self::labelled`] declares another); coefficients
    /// outside the index set PSH (31) must be zero, and every value finite.
    pub fn from_data(
        lmax: usize,
        codomain: Codomain,
        channels: usize,
        data: Vec<f64>,
    ) -> Result<Self> {
        let mut v = Self::zeros(lmax, codomain, channels)?;
        check_len("PSH coefficients", v.data.len(), data.len())?;
        finite_all("PSH coefficient", &data)?;
        v.data = data;
        for c in 0..channels {
            for i in 0..4.min(num_coeffs(lmax)) {
                for (k, &p) in codomain.components().iter().enumerate() {
                    let x = v.data[v.offset(c, i) + k];
                    if !in_index_set(i, p) && x != 0.0 {
                        return Err(Error::invalid(
                            "PSH coefficient",
                            format!("f[{c}][{i}][{p}] = {x}"),
                            "spin-2 coefficients start at l = 2 (PSH (31))",
                        ));
                    }
                }
            }
        }
        Ok(v)
    }

    /// A one-channel scalar field (e.g. a visibility) from its real SH coefficients
    /// `l*l + l + m`, `l <= lmax`, indexed by the direction towards the source
    /// ([`Self::labelled`] declares another). Errors: as [`Self::from_data`].
    pub fn scalar(lmax: usize, coefficients: Vec<f64>) -> Result<Self> {
        Self::from_data(lmax, Codomain::Intensity, 1, coefficients)
    }

    /// The band limit.
    pub fn lmax(&self) -> usize {
        self.lmax
    }

    /// The codomain.
    pub fn codomain(&self) -> Codomain {
        self.codomain
    }

    /// Number of channels.
    pub fn channels(&self) -> usize {
        self.channels
    }

    /// What the field's argument means.
    pub fn argument(&self) -> FieldArgument {
        self.argument
    }

    /// The same coefficients declared to index a field by `argument`, without changing
    /// them: for coefficients made outside psh's readers and projections. To express the
    /// same field in the other convention use [`Self::converted`].
    pub fn labelled(mut self, argument: FieldArgument) -> PshVector {
        self.argument = argument;
        self
    }

    /// The same light field indexed by `argument`: itself when it already is; otherwise
    /// the map between the direction `w` towards the source and the direction of travel
    /// `v = -w`, both in the theta-phi frames at their argument (`docs/conventions.md`):
    /// `f'_lm0 = (-1)^l f_lm0`, `f'_lm3 = -(-1)^l f_lm3`, `a'_lm = (-1)^{l+m} conj(a_{l,-m})`
    /// for `a = f_lm1 + i f_lm2` (derived in `proofs/travel-convention.md`; an involution).
    pub fn converted(&self, argument: FieldArgument) -> PshVector {
        PshVector {
            data: self.data_in(argument).collect(),
            argument,
            ..*self
        }
    }

    /// The data of [`Self::converted`] (layout of [`Self::data`]), entry by entry, without
    /// a copy of the vector.
    pub fn data_in(&self, argument: FieldArgument) -> impl Iterator<Item = f64> + '_ {
        let comps = self.codomain.components();
        let same = argument == self.argument;
        (0..self.data.len()).map(move |i| {
            if same {
                return self.data[i];
            }
            let (k, lm) = (i % comps.len(), i / comps.len());
            let c = lm / num_coeffs(self.lmax);
            let (l, m) = crate::sh::lm_of_index(lm % num_coeffs(self.lmax));
            let l = l as i64;
            match comps[k] {
                0 => parity(l) * self.data[i],
                3 => -parity(l) * self.data[i],
                // Re and Im of (-1)^{l+m} conj(a_{l,-m}).
                p => {
                    let j = self.offset(c, lm_index(l as usize, -m)) + k;
                    let sign = if p == 1 { 1.0 } else { -1.0 };
                    sign * parity(l + m) * self.data[j]
                }
            }
        })
    }

    /// The data, `[channel][l*l + l + m][p]`.
    pub fn data(&self) -> &[f64] {
        &self.data
    }

    /// The same coefficients with another codomain: components it lacks are zero,
    /// components this vector lacks are dropped.
    pub fn with_codomain(&self, codomain: Codomain) -> PshVector {
        let (from, to) = (self.codomain.components(), codomain.components());
        let n = num_coeffs(self.lmax);
        let mut data = vec![0.0; self.channels * n * to.len()];
        for (o, x) in data
            .chunks_exact_mut(to.len())
            .zip(self.data.chunks_exact(from.len()))
        {
            for (k, p) in to.iter().enumerate() {
                if let Some(i) = from.iter().position(|q| q == p) {
                    o[k] = x[i];
                }
            }
        }
        PshVector {
            lmax: self.lmax,
            codomain,
            channels: self.channels,
            argument: self.argument,
            data,
        }
    }

    /// Channel `c` alone, as a one-channel vector. Error: `c` out of range.
    pub fn channel(&self, c: usize) -> Result<PshVector> {
        self.check_index(c, 0, 0)?;
        let len = num_coeffs(self.lmax) * self.codomain.components().len();
        let data = self.data[self.offset(c, 0)..][..len].to_vec();
        Ok(PshVector::from_data(self.lmax, self.codomain, 1, data)?.labelled(self.argument))
    }

    /// The channels of `parts` side by side (each may hold several). Errors: no parts, or
    /// parts of different band limits, codomains or arguments, naming the first that
    /// differs.
    pub fn from_channels(parts: &[PshVector]) -> Result<PshVector> {
        let first = parts
            .first()
            .ok_or_else(|| Error::invalid("PSH vectors", "[]", "at least one vector to stack"))?;
        if let Some((k, v)) = parts.iter().enumerate().find(|(_, v)| {
            v.lmax != first.lmax || v.codomain != first.codomain || v.argument != first.argument
        }) {
            return Err(Error::invalid(
                "PSH vector",
                format!(
                    "#{k}: lmax {}, {}, {}",
                    v.lmax,
                    v.codomain.name(),
                    v.argument
                ),
                format!(
                    "the first has lmax {}, {}, {}",
                    first.lmax,
                    first.codomain.name(),
                    first.argument
                ),
            ));
        }
        let data = parts.iter().flat_map(|v| v.data.iter().copied()).collect();
        let channels = parts.iter().map(|v| v.channels).sum();
        Ok(
            PshVector::from_data(first.lmax, first.codomain, channels, data)?
                .labelled(first.argument),
        )
    }

    /// The coefficients of degrees `l <= lmax` (band-limiting). Error: `lmax` above this
    /// vector's.
    pub fn truncated(&self, lmax: usize) -> Result<PshVector> {
        if lmax > self.lmax {
            return Err(Error::invalid(
                "lmax",
                lmax.to_string(),
                format!("the vector has lmax {}", self.lmax),
            ));
        }
        let len = num_coeffs(lmax) * self.codomain.components().len();
        let data = (0..self.channels)
            .flat_map(|c| self.data[self.offset(c, 0)..][..len].iter().copied())
            .collect();
        Ok(PshVector::from_data(lmax, self.codomain, self.channels, data)?.labelled(self.argument))
    }

    /// The same coefficients with every degree `l <= l_low` zeroed (a high pass).
    pub fn without_bands_through(&self, l_low: usize) -> PshVector {
        let mut out = self.clone();
        let len = num_coeffs(l_low.min(self.lmax)) * self.codomain.components().len();
        for c in 0..self.channels {
            let o = self.offset(c, 0);
            out.data[o..o + len].fill(0.0);
        }
        out
    }

    /// The coefficients tapered by `window` over this vector's degrees, `w_l f_lmp`
    /// ([`Window`]; the same band limit): ringing traded for blur, commuting with
    /// rotations and convolutions (`proofs/windowed-band-limits.md`).
    pub fn windowed(&self, window: Window) -> PshVector {
        let mut out = self.clone();
        out.apply_window(window);
        out
    }

    /// [`Self::windowed`] in place.
    pub fn apply_window(&mut self, window: Window) {
        let w = window.factors(self.lmax);
        let np = self.codomain.components().len();
        for x in self.data.chunks_exact_mut(num_coeffs(self.lmax) * np) {
            for (j, f) in x.chunks_exact_mut(np).enumerate() {
                let wl = w[crate::sh::lm_of_index(j).0];
                f.iter_mut().for_each(|v| *v *= wl);
            }
        }
    }

    /// The energy of each degree, `E_l = sum_{c, m, p} f_lmp^2` (`l <= lmax`): by
    /// Parseval, the squared L2 norm over the sphere of the band `l` of the field. Error:
    /// an energy beyond the range of `f64` (coefficients near `1e154` or larger), named
    /// rather than returned as infinity.
    pub fn band_energies(&self) -> Result<Vec<f64>> {
        let np = self.codomain.components().len();
        let mut e = vec![0.0; self.lmax + 1];
        for x in self.data.chunks_exact(num_coeffs(self.lmax) * np) {
            for (j, f) in x.chunks_exact(np).enumerate() {
                e[crate::sh::lm_of_index(j).0] += f.iter().map(|v| v * v).sum::<f64>();
            }
        }
        crate::error::finite_all("band energy", &e)?;
        Ok(e)
    }

    /// `a self + b other`, the field's linear combination (PSH (34) is linear in the
    /// field). Errors: `a`, `b` or a result not finite; a band limit, codomain, channel
    /// count or argument convention that differs, named (truncate, convert or relabel
    /// one first: the combination does not guess).
    pub fn combined(&self, a: f64, other: &PshVector, b: f64) -> Result<PshVector> {
        crate::error::finite("coefficient a", a)?;
        crate::error::finite("coefficient b", b)?;
        self.check_alike(other)?;
        let data: Vec<f64> = self
            .data
            .iter()
            .zip(&other.data)
            .map(|(x, y)| a * x + b * y)
            .collect();
        finite_all("combined coefficient", &data)?;
        Ok(self.with_data(data))
    }

    /// `self + b other` in place, as [`Self::combined`] with `a = 1` (the same values)
    /// without a new vector. Errors: as [`Self::combined`]; on error `self` may hold
    /// the partial sum.
    pub fn accumulate(&mut self, b: f64, other: &PshVector) -> Result<()> {
        crate::error::finite("coefficient b", b)?;
        self.check_alike(other)?;
        for (x, y) in self.data.iter_mut().zip(&other.data) {
            *x += b * y;
        }
        finite_all("combined coefficient", &self.data)
    }

    /// Error unless `other` has the same band limit, codomain, channel count and
    /// argument convention, naming the one that differs.
    fn check_alike(&self, other: &PshVector) -> Result<()> {
        let differs = |what: &str, x: String, y: String| {
            Err(Error::invalid(
                "vectors combined",
                format!("{what} {x} and {y}"),
                format!("the same {what}"),
            ))
        };
        if self.lmax != other.lmax {
            return differs("band limit", self.lmax.to_string(), other.lmax.to_string());
        }
        if self.codomain != other.codomain {
            let n = |c: Codomain| c.name().to_string();
            return differs("codomain", n(self.codomain), n(other.codomain));
        }
        if self.channels != other.channels {
            let c = |v: &PshVector| v.channels.to_string();
            return differs("channel count", c(self), c(other));
        }
        if self.argument != other.argument {
            let n = |v: &PshVector| v.argument.name().to_string();
            return differs("argument convention", n(self), n(other));
        }
        Ok(())
    }

    /// This vector's labels with `data` (of its layout) as the coefficients.
    fn with_data(&self, data: Vec<f64>) -> PshVector {
        PshVector {
            lmax: self.lmax,
            codomain: self.codomain,
            channels: self.channels,
            argument: self.argument,
            data,
        }
    }

    /// `s self`. Error: `s` or a result not finite.
    pub fn scaled(&self, s: f64) -> Result<PshVector> {
        crate::error::finite("scale", s)?;
        let data: Vec<f64> = self.data.iter().map(|x| s * x).collect();
        finite_all("scaled coefficient", &data)?;
        Ok(self.with_data(data))
    }

    pub(super) fn offset(&self, channel: usize, lm: usize) -> usize {
        (channel * num_coeffs(self.lmax) + lm) * self.codomain.components().len()
    }

    /// `f_lmp` (0 outside the codomain or the index set), or an error for an index out of
    /// range.
    pub fn get(&self, channel: usize, l: usize, m: i64, p: usize) -> Result<f64> {
        self.check_index(channel, l, m)?;
        Ok(
            match self.codomain.components().iter().position(|&q| q == p) {
                Some(k) => self.data[self.offset(channel, lm_index(l, m)) + k],
                None => 0.0,
            },
        )
    }

    fn check_index(&self, channel: usize, l: usize, m: i64) -> Result<()> {
        crate::sh::check_lm(l as i64, m)?;
        if l > self.lmax || channel >= self.channels {
            return Err(Error::invalid(
                "PSH index",
                format!("channel {channel}, l {l}"),
                format!("{} channels, lmax {}", self.channels, self.lmax),
            ));
        }
        Ok(())
    }

    /// The Stokes vector of channel `c` at the unit direction `w` by PSH (30), in the
    /// theta-phi frame there (tables built per call; loops use a [`PshEvaluator`]); `w`
    /// means what [`Self::argument`] says.
    pub fn evaluate(&self, c: usize, w: [f64; 3]) -> Result<StokesVector> {
        if c >= self.channels {
            return Err(Error::invalid(
                "channel",
                c.to_string(),
                format!("{} channels", self.channels),
            ));
        }
        Ok(self.evaluate_all(w)?.swap_remove(c))
    }

    /// The Stokes vectors of every channel at `w` ([`Self::evaluate`], the basis evaluated
    /// once; a [`PshEvaluator`] keeps its tables across calls).
    pub fn evaluate_all(&self, w: [f64; 3]) -> Result<Vec<StokesVector>> {
        PshEvaluator::new(self.lmax)?.evaluate_all(self, w)
    }

    /// The coefficients, mutable (layout of [`Self::data`]).
    pub(super) fn data_mut(&mut self) -> &mut [f64] {
        &mut self.data
    }

    /// Component `p` of channel `c` as a flat SH vector (`l*l + l + m`).
    pub(super) fn component(&self, c: usize, k: usize) -> Vec<f64> {
        (0..num_coeffs(self.lmax))
            .map(|i| self.data[self.offset(c, i) + k])
            .collect()
    }

    /// Sets component slot `k` of coefficient `lm` (flat index) of channel `c`.
    pub(super) fn set_coefficient(&mut self, c: usize, lm: usize, k: usize, x: f64) {
        let o = self.offset(c, lm) + k;
        self.data[o] = x;
    }

    pub(super) fn set_component(&mut self, c: usize, k: usize, v: &[f64]) {
        for (i, &x) in v.iter().enumerate() {
            let o = self.offset(c, i) + k;
            self.data[o] = x;
        }
    }

    /// The spin-2 coefficients `f_lm1 + i f_lm2` of channel `c` (flat order; zero for `l < 2`
    /// and for a codomain without them).
    pub(super) fn spin2(&self, c: usize) -> Vec<Complex64> {
        if !self.codomain.has_spin2() {
            return vec![Complex64::default(); num_coeffs(self.lmax)];
        }
        let comps = self.codomain.components();
        let k1 = comps
            .iter()
            .position(|&p| p == 1)
            .expect("checked: the codomain has s1");
        let (re, im) = (self.component(c, k1), self.component(c, k1 + 1));
        re.iter()
            .zip(&im)
            .map(|(&a, &b)| Complex64::new(a, b))
            .collect()
    }

    /// Sets the spin-2 coefficients of channel `c` (a codomain without them drops `z`).
    pub(super) fn set_spin2(&mut self, c: usize, z: &[Complex64]) {
        if !self.codomain.has_spin2() {
            return;
        }
        let comps = self.codomain.components();
        let k1 = comps
            .iter()
            .position(|&p| p == 1)
            .expect("checked: the codomain has s1");
        let re: Vec<f64> = z.iter().map(|v| v.re).collect();
        let im: Vec<f64> = z.iter().map(|v| v.im).collect();
        self.set_component(c, k1, &re);
        self.set_component(c, k1 + 1, &im);
    }
}

/// `(-1)^n`.
fn parity(n: i64) -> f64 {
    if n % 2 == 0 {
        1.0
    } else {
        -1.0
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `a v + b w` evaluates to `a v(w) + b w(w)` (the field is linear in its
    /// coefficients), and vectors that differ in band limit, codomain, channels or
    /// convention are refused, naming what differs.
    #[test]
    fn combinations_are_linear_and_checked() {
        let v = crate::testing::random_psh(4, Codomain::Full, 2, 1).unwrap();
        let w = crate::testing::random_psh(4, Codomain::Full, 2, 2).unwrap();
        let sum = v.combined(2.0, &w, -0.5).unwrap();
        let dir = [0.36, -0.48, 0.8];
        for c in 0..2 {
            let (a, b, s) = (
                v.evaluate(c, dir).unwrap(),
                w.evaluate(c, dir).unwrap(),
                sum.evaluate(c, dir).unwrap(),
            );
            let want = a.components().vector() * 2.0 - b.components().vector() * 0.5;
            assert!((s.components().vector() - want).amax() < 1e-12);
        }
        assert_eq!(v.scaled(3.0).unwrap().data()[5], 3.0 * v.data()[5]);
        let e = |x: &PshVector| v.combined(1.0, x, 1.0).unwrap_err().to_string();
        assert!(e(&v.truncated(3).unwrap()).contains("band limit"));
        assert!(e(&v.with_codomain(Codomain::NoCircular)).contains("codomain"));
        assert!(e(&v.channel(0).unwrap()).contains("channel count"));
        assert!(e(&v.converted(FieldArgument::Travel)).contains("argument convention"));
        assert!(v.scaled(f64::NAN).is_err());
        assert!(v.combined(f64::INFINITY, &w, 1.0).is_err());
    }

    #[test]
    fn index_set_and_bad_input() {
        let mut data = vec![0.0; num_coeffs(3) * 4];
        // (l, m) = (1, -1) is flat index 1; its s1 slot (p = 1) is outside PSH (31).
        data[4 + 1] = 1.0;
        assert!(PshVector::from_data(3, Codomain::Full, 1, data.clone()).is_err());
        data[4 + 1] = 0.0;
        data[0] = f64::NAN;
        assert!(PshVector::from_data(3, Codomain::Full, 1, data).is_err());
        assert!(PshVector::zeros(3, Codomain::Linear, 0).is_err());
        assert!(Codomain::from_name("POLAR5").is_err());
        assert_eq!(Codomain::from_name("POLAR3").unwrap(), Codomain::NoCircular);
        let v = PshVector::zeros(3, Codomain::Linear, 2).unwrap();
        assert_eq!(v.get(1, 3, -3, 0).unwrap(), 0.0);
        assert!(v.get(2, 1, 0, 1).is_err());
        assert!(v.get(0, 1, 2, 1).is_err());
    }

    /// The travel convention against its definition: at `u`, in the theta-phi frame
    /// there, the field is the original one at `w = -u` read in `[e_theta, -e_phi, -w]`
    /// of the theta-phi frame at `w`, i.e. `(s0, s1, -s2, -s3)`; and it is an involution.
    #[test]
    fn travel_convention_reverses_directions() {
        let v = crate::testing::random_psh(6, Codomain::Full, 2, 3).unwrap();
        let t = v.converted(FieldArgument::Travel);
        assert_eq!(t.argument(), FieldArgument::Travel);
        assert_eq!(t.converted(FieldArgument::Travel), t);
        let back = t.converted(FieldArgument::TowardsSource);
        assert_eq!(back, v);
        for (i, u) in [[0.0, 0.0, 1.0], [0.6, 0.0, -0.8], [0.48, -0.6, 0.64]]
            .into_iter()
            .enumerate()
        {
            let c = i % 2;
            let got = t.evaluate(c, u).unwrap().components().to_array();
            let w = u.map(|x| -x);
            let s = v.evaluate(c, w).unwrap().components().to_array();
            let want = [s[0], s[1], -s[2], -s[3]];
            for p in 0..4 {
                assert!((got[p] - want[p]).abs() < 1e-13, "{u:?} s{p}");
            }
        }
    }
}

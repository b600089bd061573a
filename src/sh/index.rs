//! The flat coefficient index `l*l + l + m` and the degree checks every routine of the
//! SH layer (and the layers above) shares.

use crate::error::{Error, Result};

/// Largest degree any routine of this module accepts. Tables of recursion
/// coefficients take `O(MAX_DEGREE^2)` memory (about 270 MB at this limit).
pub const MAX_DEGREE: usize = 8192;

/// Flat index of `(l, m)`: `l*l + l + m`.
#[inline]
pub const fn lm_index(l: usize, m: i64) -> usize {
    (l * l + l).wrapping_add_signed(m as isize)
}

/// Number of coefficients of degrees `l <= lmax`: `(lmax + 1)^2`.
#[inline]
pub const fn num_coeffs(lmax: usize) -> usize {
    (lmax + 1) * (lmax + 1)
}

/// `(l, m)` of a flat index (inverse of [`lm_index`]).
#[inline]
pub fn lm_of_index(i: usize) -> (usize, i64) {
    let mut l = (i as f64).sqrt() as usize;
    while l * l > i {
        l -= 1;
    }
    while (l + 1) * (l + 1) <= i {
        l += 1;
    }
    (l, i as i64 - (l * l + l) as i64)
}

/// Checks `lmax <= MAX_DEGREE`.
pub fn check_lmax(lmax: usize) -> Result<()> {
    check_degree_limit("lmax", lmax, MAX_DEGREE, "the largest supported degree")
}

/// Checks `lmax <= limit`; the error names `name`, `lmax` and says `what` the limit is.
pub fn check_degree_limit(name: &'static str, lmax: usize, limit: usize, what: &str) -> Result<()> {
    if lmax > limit {
        return Err(Error::DegreeOutOfRange {
            name,
            value: lmax as i128,
            reason: format!("{what} is {limit}"),
        });
    }
    Ok(())
}

/// Checks `0 <= l` and `|m| <= l`.
pub fn check_lm(l: i64, m: i64) -> Result<()> {
    if l < 0 {
        return Err(Error::DegreeOutOfRange {
            name: "l",
            value: l.into(),
            reason: "degrees are non-negative".into(),
        });
    }
    if m.abs() > l {
        return Err(Error::OrderOutOfRange { name: "m", l, m });
    }
    Ok(())
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn flat_index_round_trips() {
        let mut i = 0;
        for l in 0..40usize {
            for m in -(l as i64)..=l as i64 {
                assert_eq!(lm_index(l, m), i);
                assert_eq!(lm_of_index(i), (l, m));
                i += 1;
            }
        }
        assert_eq!(i, num_coeffs(39));
    }
}

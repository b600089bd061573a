//! Complex pair separation of the spin 2-to-2 block of a Mueller matrix (PSH Sec. 6.3.2):
//! the 2 x 2 block `M` (rows and columns `s1, s2`) as the isomorphic and conjugation parts
//! `m_iso = C_iso(M)`, `m_conj = C_conj(M)` (PSH (44)), with
//! `M R2(z) = R2(m_iso z + m_conj conj(z))` (PSH (47a)) and back by PSH (45).

use num_complex::Complex64;

/// `(C_iso(M), C_conj(M))` of PSH (44) for `M = [[M11, M12], [M21, M22]]`.
pub fn complex_pair(m: [[f64; 2]; 2]) -> (Complex64, Complex64) {
    let [[m11, m12], [m21, m22]] = m;
    (
        Complex64::new(0.5 * (m11 + m22), 0.5 * (m21 - m12)),
        Complex64::new(0.5 * (m11 - m22), 0.5 * (m21 + m12)),
    )
}

/// The 2 x 2 block `R(m_iso) + R(m_conj) J` of PSH (45), `R(a + ib) = [[a, -b], [b, a]]`,
/// `J = diag(1, -1)`.
pub fn from_complex_pair(iso: Complex64, conj: Complex64) -> [[f64; 2]; 2] {
    [
        [iso.re + conj.re, -iso.im + conj.im],
        [iso.im + conj.im, iso.re - conj.re],
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    /// PSH (45) inverts PSH (44), and PSH (47a) holds.
    #[test]
    fn separation_round_trips_and_multiplies() {
        let m = [[0.3, -1.2], [0.7, 2.5]];
        let (iso, conj) = complex_pair(m);
        let back = from_complex_pair(iso, conj);
        for r in 0..2 {
            for c in 0..2 {
                assert!((back[r][c] - m[r][c]).abs() < 1e-15);
            }
        }
        let z = Complex64::new(-0.4, 1.9);
        let w = iso * z + conj * z.conj();
        let mz = [
            m[0][0] * z.re + m[0][1] * z.im,
            m[1][0] * z.re + m[1][1] * z.im,
        ];
        assert!((w.re - mz[0]).abs() < 1e-15 && (w.im - mz[1]).abs() < 1e-15);
    }
}

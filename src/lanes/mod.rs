//! Kernels compiled for several instruction sets and chosen at run time, and the four
//! `f64` lanes they compute in.
//!
//! A crate that depends on psh, and psh's wheel, are built for baseline x86-64 (SSE2):
//! code compiled once runs SSE2 whatever the CPU. A dispatched kernel carries
//! `#[multiversion(targets = "simd")]` (the `multiversion` crate: x86-64-v4 (AVX-512), v3
//! (AVX2, FMA) and v2 (SSE4.2) besides the baseline), around a body whose callees are
//! inlined into it, so that its loops are vectorized for the CPU it runs on. [`F64x4`]
//! is a plain array whose operations are inlined lane-by-lane expressions: in such a
//! kernel the compiler turns them into that set's vector instructions (`wide`'s lanes fix
//! theirs when psh is compiled). Every version performs the same IEEE operations in the
//! same order: `mul_add` is a product then a sum (no fused multiply-add; the compiler may
//! not contract them), so the kernels give the same bits on every CPU, which a test
//! checks kernel by kernel against the baseline bodies ([`dispatch!`]).
//!
//! Loops over many four-lane vectors (the transforms' order sums, the Cartesian SH kernel)
//! use [`LaneSet`] instead ([`sets`]): vector registers by type, AVX's chosen at run time
//! through `pulp`'s token, under the same rule of no fused multiply-adds. Written with
//! [`F64x4`] and dispatched, the sums' syntheses ran 1.3-1.9x slower: the loop vectorizer
//! turned the accumulation into ring vectors into gathers and scatters
//! (`docs/performance.md`).

mod sets;
pub(crate) use sets::{with_lanes, LaneSet, WithLanes};

/// Four `f64` lanes; arithmetic lane by lane.
#[derive(Clone, Copy, Debug, Default, PartialEq)]
#[repr(C, align(32))]
pub(crate) struct F64x4(pub(crate) [f64; 4]);

impl F64x4 {
    /// Every lane 0.
    pub(crate) const ZERO: F64x4 = F64x4([0.0; 4]);

    /// The lanes `v`.
    #[inline(always)]
    pub(crate) const fn new(v: [f64; 4]) -> Self {
        F64x4(v)
    }

    /// Every lane `x`.
    #[inline(always)]
    pub(crate) const fn splat(x: f64) -> Self {
        F64x4([x; 4])
    }

    /// The lanes as an array.
    #[inline(always)]
    pub(crate) const fn to_array(self) -> [f64; 4] {
        self.0
    }

    /// `self * m + a`, rounded twice (not fused: the same bits on every CPU).
    #[inline(always)]
    pub(crate) fn mul_add(self, m: Self, a: Self) -> Self {
        let (x, m, a) = (self.0, m.0, a.0);
        F64x4([
            x[0] * m[0] + a[0],
            x[1] * m[1] + a[1],
            x[2] * m[2] + a[2],
            x[3] * m[3] + a[3],
        ])
    }
}

/// Calls a kernel: `dispatch!(simd | body(args))` calls `simd(args)`, the kernel compiled
/// per instruction set (`#[multiversion(targets = "simd")]` around `body`), or, on a
/// thread of the unit tests that asked for it ([`baseline`]), `body(args)` compiled for
/// the baseline, which the tests compare with it bit for bit.
macro_rules! dispatch {
    ($simd:ident | $body:ident ($($arg:expr),* $(,)?)) => {
        if $crate::lanes::baseline() {
            $body($($arg),*)
        } else {
            $simd($($arg),*)
        }
    };
}
pub(crate) use dispatch;

#[cfg(test)]
thread_local! {
    static BASELINE: std::cell::Cell<bool> = const { std::cell::Cell::new(false) };
}

/// Whether this thread runs the kernels' baseline bodies ([`dispatch!`]): set by the unit
/// tests only (`on_baseline`); `false` in every other build.
#[inline(always)]
pub(crate) fn baseline() -> bool {
    #[cfg(test)]
    return BASELINE.with(std::cell::Cell::get);
    #[cfg(not(test))]
    false
}

/// `f` run on a one-thread pool whose thread takes the kernels' baseline bodies when
/// `baseline` (the dispatched versions otherwise): the same operation both ways, for a
/// bit-for-bit comparison.
#[cfg(test)]
pub(crate) fn on_baseline<T: Send>(baseline: bool, f: impl FnOnce() -> T + Send) -> T {
    let pool = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .unwrap();
    pool.install(|| {
        BASELINE.with(|b| b.set(baseline));
        f()
    })
}

#[cfg(test)]
mod tests {
    use super::*;

    /// `mul_add` is the scalar product then sum, lane by lane, not fused: `0.1 * 10 - 1`
    /// rounds to 0 unfused and to 5.55e-17 fused.
    #[test]
    fn mul_add_is_not_fused() {
        let a = F64x4::new([0.1, -2.0, 3.5, 1e300]);
        let b = F64x4::new([10.0, 0.25, -1.0, 1e10]);
        let c = F64x4::splat(-1.0);
        assert_ne!(0.1f64.mul_add(10.0, -1.0), 0.0);
        assert_eq!(a.mul_add(b, c).to_array(), [0.0, -1.5, -4.5, f64::INFINITY]);
        assert_eq!(F64x4::ZERO.mul_add(b, c), c);
    }

    /// Bits of `f` in the kernels' dispatched versions (AVX-512 or AVX2 on the machines
    /// that have them) and in their baseline bodies.
    fn both<T: Send>(f: impl Fn() -> T + Send + Sync) -> (T, T) {
        (on_baseline(false, &f), on_baseline(true, &f))
    }

    /// Every dispatched kernel gives the bits of its baseline body: the batch SH (the
    /// Cartesian kernel, and the polar lanes above its band limit, with the exponent scaling
    /// near the poles), the transforms' sweeps, the PSH evaluator's sums (one direction and batches), the Wigner blocks (Risbo's steps and the complex rows) and the PSH
    /// rotation's products, on random input and at the poles. A version that fused its
    /// multiply-adds or summed in another order would differ in the last bits.
    #[test]
    fn dispatched_kernels_give_the_baseline_bits() {
        use crate::polarized::{in_index_set, Codomain, PshRotation, PshVector};
        use crate::random::pseudo_random;
        use crate::sh::{for_each_block, num_coeffs, ShEvaluator};

        let dirs: Vec<[f64; 3]> = pseudo_random(3 * 103, 7)
            .chunks_exact(3)
            .map(|v| {
                let n = (v[0] * v[0] + v[1] * v[1] + v[2] * v[2]).sqrt();
                [v[0] / n, v[1] / n, v[2] / n]
            })
            .chain([[0.0, 0.0, 1.0], [0.0, 0.0, -1.0], [1.0, 0.0, -0.0]])
            .collect();
        // The Cartesian kernel (l <= 24) and the polar lanes above it.
        for l in [4, 24, 40, 90] {
            let sh = ShEvaluator::new(l).unwrap();
            let (a, b) = both(|| {
                let mut out = vec![0.0; dirs.len() * sh.len()];
                sh.real_batch(&dirs, &mut out).unwrap();
                out
            });
            assert!(
                a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
                "SH l {l}"
            );
        }

        // A generic rotation, the identity, a tiny one and a half turn (beta = 0, ~0, pi).
        let bits = |z: &num_complex::Complex64| (z.re.to_bits(), z.im.to_bits());
        for (roll, pitch, yaw) in [
            (0.3, -1.1, 2.0),
            (0.0, 0.0, 0.0),
            (1e-9, 0.0, 0.0),
            (std::f64::consts::PI, 0.0, 0.5),
        ] {
            let r = nalgebra::Rotation3::from_euler_angles(roll, pitch, yaw);
            let (a, b) = both(|| {
                let mut all = Vec::new();
                for_each_block(&r, 60, |_, block| all.extend_from_slice(block)).unwrap();
                all
            });
            assert!(
                a.iter().zip(&b).all(|(x, y)| bits(x) == bits(y)),
                "Wigner D blocks at {roll}, {pitch}, {yaw}"
            );
        }
        // The transforms' sweeps (AVX lanes against the compiled ones): real and spin-2
        // synthesis and analysis at a band limit whose rings near the poles start below the
        // f64 range (the exponent scaling) and are left out while negligible.
        let lmax = 300;
        let real = crate::sh::ShTransform::new(lmax).unwrap();
        let coeffs = pseudo_random(num_coeffs(lmax), 3);
        let (a, b) = both(|| {
            let mut field = vec![0.0; real.grid().len()];
            real.synthesis_real(&coeffs, &mut field).unwrap();
            let mut back = vec![0.0; coeffs.len()];
            real.analysis_real(&field, &mut back).unwrap();
            [field, back].concat()
        });
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "real transforms"
        );
        let spin = crate::swsh::SpinTransform::new(2, lmax).unwrap();
        let coeffs: Vec<_> = coeffs
            .iter()
            .map(|&x| num_complex::Complex64::new(x, 0.5 - x))
            .collect();
        let (a, b) = both(|| {
            let mut field = vec![num_complex::Complex64::default(); spin.grid().len()];
            spin.synthesis(&coeffs, &mut field).unwrap();
            let mut back = vec![num_complex::Complex64::default(); coeffs.len()];
            spin.analysis(&field, &mut back).unwrap();
            [field, back].concat()
        });
        assert!(
            a.iter().zip(&b).all(|(x, y)| bits(x) == bits(y)),
            "spin-2 transforms"
        );

        // The PSH evaluator's sums (the PPRT frame's per-vertex evaluation).
        let v = crate::testing::random_psh(9, Codomain::Full, 3, 5).unwrap();
        let (a, b) = both(|| {
            let mut eval = crate::polarized::PshEvaluator::new(9).unwrap();
            let mut out = vec![[0.0; 4]; 3];
            let mut all = Vec::new();
            for &w in &dirs {
                eval.evaluate_into(&v, w, &mut out).unwrap();
                all.extend(out.iter().flatten().copied());
            }
            // And the batch's sums over four directions in lanes (a partial block too).
            let mut batch = vec![[0.0; 4]; 3 * dirs.len()];
            eval.evaluate_batch(&v, &dirs, &mut batch).unwrap();
            all.extend(batch.iter().flatten().copied());
            all
        });
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "PSH evaluation"
        );

        let r = nalgebra::Rotation3::from_euler_angles(0.3, -1.1, 2.0);
        let l = 12;
        let mut data = pseudo_random(2 * num_coeffs(l) * 4, 11);
        for (j, x) in data.iter_mut().enumerate() {
            let (i, p) = ((j / 4) % num_coeffs(l), j % 4);
            if !in_index_set(i, Codomain::Full.components()[p]) {
                *x = 0.0;
            }
        }
        let v = PshVector::from_data(l, Codomain::Full, 2, data).unwrap();
        let rotation = PshRotation::new(&r, l).unwrap();
        let (a, b) = both(|| rotation.rotate(&v).unwrap().data().to_vec());
        assert!(
            a.iter().zip(&b).all(|(x, y)| x.to_bits() == y.to_bits()),
            "PSH rotation"
        );
    }
}

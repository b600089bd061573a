//! Four `f64` lanes as one vector of an instruction set chosen at run time: the lanes
//! compiled into psh ([`Compiled`], `wide`'s: SSE2 in a portable build) or AVX's 256-bit
//! registers ([`Avx`]) on a CPU with x86-64-v3, proven by `pulp`'s token. A kernel
//! written once over [`LaneSet`] is compiled for both; [`with_lanes`] runs it on the best
//! set of the CPU. Every operation is one IEEE operation per lane and a product is
//! rounded before its sum is taken (no fused multiply-add), so both sets give the same
//! bits, which `lanes::tests` checks kernel by kernel.
//!
//! Unlike [`super::F64x4`], whose array lanes the compiler vectorizes as it sees fit
//! (across a loop's iterations, with gathers, if it judges that cheaper), these are
//! vector registers by type: a loop over ring vectors stays a loop over vectors.

use super::F64x4;
use std::ops::{Add, Div, Mul, Neg, Sub};

/// An instruction set's four-lane `f64` vector `V` and the operations of the kernels.
pub(crate) trait LaneSet: Copy {
    /// Four lanes in one register (or two) of the set.
    type V: Copy
        + Add<Output = Self::V>
        + Sub<Output = Self::V>
        + Mul<Output = Self::V>
        + Div<Output = Self::V>
        + Neg<Output = Self::V>;

    /// Every lane `x`.
    fn splat(self, x: f64) -> Self::V;

    /// The lanes of `v`.
    fn load(self, v: &F64x4) -> Self::V;

    /// The lanes of `v` as an array.
    fn store(self, v: Self::V) -> F64x4;

    /// `|v|` lane by lane.
    fn abs(self, v: Self::V) -> Self::V;

    /// The larger of `a`, `b` lane by lane (`b` where either is NaN).
    fn max(self, a: Self::V, b: Self::V) -> Self::V;

    /// `sqrt(v)` lane by lane (correctly rounded).
    fn sqrt(self, v: Self::V) -> Self::V;

    /// `-1` where `v < 0`, else `1` (`+1` at `-0` and NaN), lane by lane.
    fn sign_of_negative(self, v: Self::V) -> Self::V;

    /// The 4 x 4 transpose: lane `j` of `v[i]` to lane `i` of the result's `j`.
    #[inline(always)]
    fn transpose(self, v: [Self::V; 4]) -> [Self::V; 4] {
        let a = v.map(|v| self.store(v).0);
        std::array::from_fn(|j| self.load(&F64x4(std::array::from_fn(|i| a[i][j]))))
    }

    /// Every lane 0.
    #[inline(always)]
    fn zero(self) -> Self::V {
        self.splat(0.0)
    }

    /// `a * m + c`, rounded twice.
    #[inline(always)]
    fn mul_add(self, a: Self::V, m: Self::V, c: Self::V) -> Self::V {
        a * m + c
    }

    /// `c - a * m`, rounded twice.
    #[inline(always)]
    fn mul_neg_add(self, a: Self::V, m: Self::V, c: Self::V) -> Self::V {
        c - a * m
    }

    /// `(v0 + v1) + (v2 + v3)`.
    #[inline(always)]
    fn reduce_add(self, v: Self::V) -> f64 {
        let [a, b, c, d] = self.store(v).0;
        (a + b) + (c + d)
    }
}

/// The lanes compiled into psh: `wide`'s `f64x4` (SSE2 pairs in a portable build).
#[derive(Clone, Copy, Debug)]
pub(crate) struct Compiled;

impl LaneSet for Compiled {
    type V = wide::f64x4;

    #[inline(always)]
    fn splat(self, x: f64) -> Self::V {
        wide::f64x4::splat(x)
    }

    #[inline(always)]
    fn load(self, v: &F64x4) -> Self::V {
        wide::f64x4::new(v.0)
    }

    #[inline(always)]
    fn store(self, v: Self::V) -> F64x4 {
        F64x4(v.to_array())
    }

    #[inline(always)]
    fn abs(self, v: Self::V) -> Self::V {
        v.abs()
    }

    #[inline(always)]
    fn max(self, a: Self::V, b: Self::V) -> Self::V {
        a.fast_max(b)
    }

    #[inline(always)]
    fn sqrt(self, v: Self::V) -> Self::V {
        v.sqrt()
    }

    #[inline(always)]
    fn sign_of_negative(self, v: Self::V) -> Self::V {
        use wide::CmpLt;
        let one = wide::f64x4::ONE;
        v.cmp_lt(wide::f64x4::ZERO).blend(-one, one)
    }
}

/// AVX's 256-bit lanes, on a CPU with x86-64-v3 (the token is its proof).
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct Avx(pulp::x86::V3);

/// A vector of [`Avx`].
#[cfg(target_arch = "x86_64")]
#[derive(Clone, Copy, Debug)]
pub(crate) struct AvxV {
    v: std::arch::x86_64::__m256d,
    set: pulp::x86::V3,
}

#[cfg(target_arch = "x86_64")]
impl AvxV {
    #[inline(always)]
    fn with(self, v: std::arch::x86_64::__m256d) -> Self {
        AvxV { v, set: self.set }
    }
}

#[cfg(target_arch = "x86_64")]
impl Add for AvxV {
    type Output = AvxV;
    #[inline(always)]
    fn add(self, o: AvxV) -> AvxV {
        self.with(self.set.avx._mm256_add_pd(self.v, o.v))
    }
}

#[cfg(target_arch = "x86_64")]
impl Sub for AvxV {
    type Output = AvxV;
    #[inline(always)]
    fn sub(self, o: AvxV) -> AvxV {
        self.with(self.set.avx._mm256_sub_pd(self.v, o.v))
    }
}

#[cfg(target_arch = "x86_64")]
impl Mul for AvxV {
    type Output = AvxV;
    #[inline(always)]
    fn mul(self, o: AvxV) -> AvxV {
        self.with(self.set.avx._mm256_mul_pd(self.v, o.v))
    }
}

#[cfg(target_arch = "x86_64")]
impl Div for AvxV {
    type Output = AvxV;
    #[inline(always)]
    fn div(self, o: AvxV) -> AvxV {
        self.with(self.set.avx._mm256_div_pd(self.v, o.v))
    }
}

#[cfg(target_arch = "x86_64")]
impl Neg for AvxV {
    type Output = AvxV;
    #[inline(always)]
    fn neg(self) -> AvxV {
        let sign = self.set.avx._mm256_set1_pd(-0.0);
        self.with(self.set.avx._mm256_xor_pd(self.v, sign))
    }
}

#[cfg(target_arch = "x86_64")]
impl LaneSet for Avx {
    type V = AvxV;

    #[inline(always)]
    fn splat(self, x: f64) -> AvxV {
        AvxV {
            v: self.0.avx._mm256_set1_pd(x),
            set: self.0,
        }
    }

    #[inline(always)]
    fn load(self, v: &F64x4) -> AvxV {
        AvxV {
            v: pulp::cast(v.0),
            set: self.0,
        }
    }

    #[inline(always)]
    fn store(self, v: AvxV) -> F64x4 {
        F64x4(pulp::cast(v.v))
    }

    #[inline(always)]
    fn abs(self, v: AvxV) -> AvxV {
        let sign = self.0.avx._mm256_set1_pd(-0.0);
        v.with(self.0.avx._mm256_andnot_pd(sign, v.v))
    }

    #[inline(always)]
    fn max(self, a: AvxV, b: AvxV) -> AvxV {
        a.with(self.0.avx._mm256_max_pd(a.v, b.v))
    }

    #[inline(always)]
    fn transpose(self, [a, b, c, d]: [AvxV; 4]) -> [AvxV; 4] {
        let avx = self.0.avx;
        // [a0 b0 a2 b2], [a1 b1 a3 b3], [c0 d0 c2 d2], [c1 d1 c3 d3]
        let (ab0, ab1) = (
            avx._mm256_unpacklo_pd(a.v, b.v),
            avx._mm256_unpackhi_pd(a.v, b.v),
        );
        let (cd0, cd1) = (
            avx._mm256_unpacklo_pd(c.v, d.v),
            avx._mm256_unpackhi_pd(c.v, d.v),
        );
        [
            a.with(avx._mm256_permute2f128_pd::<0x20>(ab0, cd0)),
            a.with(avx._mm256_permute2f128_pd::<0x20>(ab1, cd1)),
            a.with(avx._mm256_permute2f128_pd::<0x31>(ab0, cd0)),
            a.with(avx._mm256_permute2f128_pd::<0x31>(ab1, cd1)),
        ]
    }

    #[inline(always)]
    fn sqrt(self, v: AvxV) -> AvxV {
        v.with(self.0.avx._mm256_sqrt_pd(v.v))
    }

    #[inline(always)]
    fn sign_of_negative(self, v: AvxV) -> AvxV {
        use std::arch::x86_64::_CMP_LT_OQ;
        let avx = self.0.avx;
        let negative = avx._mm256_cmp_pd::<_CMP_LT_OQ>(v.v, avx._mm256_setzero_pd());
        let one = avx._mm256_set1_pd(1.0);
        v.with(avx._mm256_blendv_pd(one, avx._mm256_set1_pd(-1.0), negative))
    }
}

/// A kernel over any [`LaneSet`], run by [`with_lanes`].
pub(crate) trait WithLanes {
    /// What the kernel returns.
    type Output;

    /// The kernel on the lanes of `set` (inlined into the caller compiled for the set).
    fn run<L: LaneSet>(self, set: L) -> Self::Output;
}

/// Runs `kernel` on [`Avx`] where the CPU has x86-64-v3 (compiled for it), else (and on a
/// thread of the unit tests that asked for the baseline bodies, [`super::baseline`]) on
/// [`Compiled`].
#[inline]
pub(crate) fn with_lanes<W: WithLanes>(kernel: W) -> W::Output {
    #[cfg(target_arch = "x86_64")]
    if !super::baseline() {
        if let Some(v3) = pulp::x86::V3::try_new() {
            return v3.vectorize(OnAvx(kernel, Avx(v3)));
        }
    }
    kernel.run(Compiled)
}

/// A kernel bound to the AVX lanes: what `pulp` runs compiled for them. Not a closure: a
/// closure's body is a function of its own that the compiler may leave out of line, and
/// out of line the lanes' instructions are calls.
#[cfg(target_arch = "x86_64")]
struct OnAvx<W>(W, Avx);

#[cfg(target_arch = "x86_64")]
impl<W: WithLanes> pulp::NullaryFnOnce for OnAvx<W> {
    type Output = W::Output;

    #[inline(always)]
    fn call(self) -> W::Output {
        self.0.run(self.1)
    }
}

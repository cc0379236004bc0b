//! Lanes of `f64` for tracing several rays at once.
//!
//! The packet tracer (sv-trace's `packet` module) is written once, generic over
//! [`Simd`], and compiled for each instruction set found at run time:
//! AVX-512 (eight lanes) and AVX2 (four), on x86-64. [`Portable`] is the
//! same lanes in plain arrays, for the tests on any machine.
//!
//! Every operation is the IEEE operation of the scalar code lane by lane
//! (no fused multiply-add, no approximate reciprocal or root), so a lane
//! computes bit for bit what the scalar tracer computes for its ray.
//!
//! The methods take the instruction set's token by value: a token exists
//! only once its instructions were found on the processor
//! ([`Avx512::detect`], [`Avx2::detect`]), which is what makes the
//! intrinsics inside them sound to call.

/// A vector instruction set: `LANES` values of `f64` and masks over them.
pub trait Simd: Copy {
    /// Lanes per vector.
    const LANES: usize;
    /// `LANES` values.
    type F: Copy;
    /// A mask: one flag per lane.
    type M: Copy;

    /// Every lane `v`.
    fn splat(self, v: f64) -> Self::F;
    /// The first `LANES` values of `v`.
    fn load(self, v: &[f64]) -> Self::F;
    /// Into the first `LANES` places of `out`.
    fn store(self, x: Self::F, out: &mut [f64]);
    /// `a + b`.
    fn add(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a - b`.
    fn sub(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a * b`.
    fn mul(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a / b`.
    fn div(self, a: Self::F, b: Self::F) -> Self::F;
    /// Correctly rounded square root.
    fn sqrt(self, a: Self::F) -> Self::F;
    /// `-a` (the sign flipped, as the scalar unary minus).
    fn neg(self, a: Self::F) -> Self::F;
    /// `|a|`.
    fn abs(self, a: Self::F) -> Self::F;
    /// The greatest whole number not above `a`.
    fn floor(self, a: Self::F) -> Self::F;
    /// The magnitude of `mag` with the sign of `sign`.
    fn copysign(self, mag: Self::F, sign: Self::F) -> Self::F;
    /// `if a < b { a } else { b }`, lane by lane.
    fn min(self, a: Self::F, b: Self::F) -> Self::F;
    /// `if a > b { a } else { b }`, lane by lane.
    fn max(self, a: Self::F, b: Self::F) -> Self::F;
    /// `a < b`.
    fn lt(self, a: Self::F, b: Self::F) -> Self::M;
    /// `a <= b`.
    fn le(self, a: Self::F, b: Self::F) -> Self::M;
    /// `a == b`.
    fn eq(self, a: Self::F, b: Self::F) -> Self::M;
    /// Lanes set in both.
    fn and(self, a: Self::M, b: Self::M) -> Self::M;
    /// Lanes set in either.
    fn or(self, a: Self::M, b: Self::M) -> Self::M;
    /// Lanes set in `a` and not in `b`.
    fn andnot(self, a: Self::M, b: Self::M) -> Self::M;
    /// `if m { a } else { b }`, lane by lane.
    fn select(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F;
    /// Bit `i` set for lane `i`.
    fn bits(self, m: Self::M) -> u32;
    /// The mask of the low `LANES` bits of `b`.
    fn mask(self, b: u32) -> Self::M;
    /// The lanes (bit `j`) whose value in `a` is not lane `j - 1`'s, to
    /// the bit (`-0` is not `+0`; the same NaN is the same); bit 0 clear.
    fn differ_from_lane_before(self, a: Self::F) -> u32;
    /// The least lane. Its answer with a lane that is not a number differs
    /// from one instruction set to another: give it numbers.
    fn min_lane(self, a: Self::F) -> f64;
    /// Lane `i` is `v[first + i * stride]`; `v` must hold them all.
    fn gather(self, v: &[f64], first: usize, stride: usize) -> Self::F;

    /// `a > b`.
    #[inline(always)]
    fn gt(self, a: Self::F, b: Self::F) -> Self::M {
        self.lt(b, a)
    }
    /// `a >= b`.
    #[inline(always)]
    fn ge(self, a: Self::F, b: Self::F) -> Self::M {
        self.le(b, a)
    }
    /// True when any lane is set.
    #[inline(always)]
    fn any(self, m: Self::M) -> bool {
        self.bits(m) != 0
    }
    /// True when every lane is set.
    #[inline(always)]
    fn all(self, m: Self::M) -> bool {
        self.bits(m) == (1 << Self::LANES) - 1
    }
    /// The mask with no lane set.
    #[inline(always)]
    fn none(self) -> Self::M {
        self.mask(0)
    }
}

/// `P` lanes in plain arrays: the packet tracer's reference form, which
/// runs anywhere (the tests hold the vector forms to it and to the scalar
/// tracer, with four lanes as AVX2 has and eight as AVX-512 has).
#[derive(Clone, Copy, Debug, Default)]
pub struct Portable<const P: usize>;

/// One lane at a time.
#[inline(always)]
fn lanes<T: Copy, const P: usize>(f: impl Fn(usize) -> T) -> [T; P] {
    std::array::from_fn(f)
}

impl<const P: usize> Simd for Portable<P> {
    const LANES: usize = P;
    type F = [f64; P];
    type M = [bool; P];

    #[inline(always)]
    fn splat(self, v: f64) -> Self::F {
        [v; P]
    }
    #[inline(always)]
    fn load(self, v: &[f64]) -> Self::F {
        lanes(|i| v[i])
    }
    #[inline(always)]
    fn store(self, x: Self::F, out: &mut [f64]) {
        out[..P].copy_from_slice(&x);
    }
    #[inline(always)]
    fn add(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| a[i] + b[i])
    }
    #[inline(always)]
    fn sub(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| a[i] - b[i])
    }
    #[inline(always)]
    fn mul(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| a[i] * b[i])
    }
    #[inline(always)]
    fn div(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| a[i] / b[i])
    }
    #[inline(always)]
    fn sqrt(self, a: Self::F) -> Self::F {
        lanes(|i| a[i].sqrt())
    }
    #[inline(always)]
    fn neg(self, a: Self::F) -> Self::F {
        lanes(|i| -a[i])
    }
    #[inline(always)]
    fn abs(self, a: Self::F) -> Self::F {
        lanes(|i| a[i].abs())
    }
    #[inline(always)]
    fn floor(self, a: Self::F) -> Self::F {
        lanes(|i| a[i].floor())
    }
    #[inline(always)]
    fn copysign(self, mag: Self::F, sign: Self::F) -> Self::F {
        lanes(|i| mag[i].copysign(sign[i]))
    }
    #[inline(always)]
    fn min(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| if a[i] < b[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn max(self, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| if a[i] > b[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn lt(self, a: Self::F, b: Self::F) -> Self::M {
        lanes(|i| a[i] < b[i])
    }
    #[inline(always)]
    fn le(self, a: Self::F, b: Self::F) -> Self::M {
        lanes(|i| a[i] <= b[i])
    }
    #[inline(always)]
    fn eq(self, a: Self::F, b: Self::F) -> Self::M {
        lanes(|i| a[i] == b[i])
    }
    #[inline(always)]
    fn and(self, a: Self::M, b: Self::M) -> Self::M {
        lanes(|i| a[i] & b[i])
    }
    #[inline(always)]
    fn or(self, a: Self::M, b: Self::M) -> Self::M {
        lanes(|i| a[i] | b[i])
    }
    #[inline(always)]
    fn andnot(self, a: Self::M, b: Self::M) -> Self::M {
        lanes(|i| a[i] & !b[i])
    }
    #[inline(always)]
    fn select(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F {
        lanes(|i| if m[i] { a[i] } else { b[i] })
    }
    #[inline(always)]
    fn bits(self, m: Self::M) -> u32 {
        (0..P).fold(0, |b, i| b | (u32::from(m[i]) << i))
    }
    #[inline(always)]
    fn mask(self, b: u32) -> Self::M {
        lanes(|i| b & (1 << i) != 0)
    }
    #[inline(always)]
    fn differ_from_lane_before(self, a: Self::F) -> u32 {
        (1..P).fold(0, |b, i| {
            b | u32::from(a[i].to_bits() != a[i - 1].to_bits()) << i
        })
    }
    #[inline(always)]
    fn min_lane(self, a: Self::F) -> f64 {
        a.iter().fold(f64::INFINITY, |m, &v| m.min(v))
    }
    #[inline(always)]
    fn gather(self, v: &[f64], first: usize, stride: usize) -> Self::F {
        lanes(|i| v[first + i * stride])
    }
}

#[cfg(target_arch = "x86_64")]
pub use x86::{Avx2, Avx512};

#[cfg(target_arch = "x86_64")]
mod x86 {
    use super::Simd;
    use std::arch::x86_64::*;

    /// AVX-512 (the foundation set): eight lanes, masks in mask registers.
    #[derive(Clone, Copy, Debug)]
    pub struct Avx512(());

    impl Avx512 {
        /// The token, when this processor has AVX-512F.
        pub fn detect() -> Option<Avx512> {
            is_x86_feature_detected!("avx512f").then_some(Avx512(()))
        }
    }

    // SAFETY (every `unsafe` block below): a token exists only when the
    // processor has the instructions (`detect`), and every pointer access
    // is bounds-checked by the slice indexing before it.
    impl Simd for Avx512 {
        const LANES: usize = 8;
        type F = __m512d;
        type M = __mmask8;

        #[inline(always)]
        fn splat(self, v: f64) -> Self::F {
            unsafe { _mm512_set1_pd(v) }
        }
        #[inline(always)]
        fn load(self, v: &[f64]) -> Self::F {
            let v = &v[..8];
            unsafe { _mm512_loadu_pd(v.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, x: Self::F, out: &mut [f64]) {
            let out = &mut out[..8];
            unsafe { _mm512_storeu_pd(out.as_mut_ptr(), x) }
        }
        #[inline(always)]
        fn add(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_mul_pd(a, b) }
        }
        #[inline(always)]
        fn div(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_div_pd(a, b) }
        }
        #[inline(always)]
        fn sqrt(self, a: Self::F) -> Self::F {
            unsafe { _mm512_sqrt_pd(a) }
        }
        #[inline(always)]
        fn neg(self, a: Self::F) -> Self::F {
            unsafe {
                _mm512_castsi512_pd(_mm512_xor_si512(
                    _mm512_castpd_si512(a),
                    _mm512_set1_epi64(i64::MIN),
                ))
            }
        }
        #[inline(always)]
        fn abs(self, a: Self::F) -> Self::F {
            unsafe { _mm512_abs_pd(a) }
        }
        #[inline(always)]
        fn floor(self, a: Self::F) -> Self::F {
            unsafe { _mm512_roundscale_pd::<{ _MM_FROUND_TO_NEG_INF | _MM_FROUND_NO_EXC }>(a) }
        }
        #[inline(always)]
        fn copysign(self, mag: Self::F, sign: Self::F) -> Self::F {
            unsafe {
                let s = _mm512_set1_epi64(i64::MIN);
                _mm512_castsi512_pd(_mm512_or_si512(
                    _mm512_andnot_si512(s, _mm512_castpd_si512(mag)),
                    _mm512_and_si512(s, _mm512_castpd_si512(sign)),
                ))
            }
        }
        #[inline(always)]
        fn min(self, a: Self::F, b: Self::F) -> Self::F {
            // `vminpd a, b` gives `b` unless `a < b`, as the scalar code.
            unsafe { _mm512_min_pd(a, b) }
        }
        #[inline(always)]
        fn max(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_max_pd(a, b) }
        }
        #[inline(always)]
        fn lt(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LT_OQ>(a, b) }
        }
        #[inline(always)]
        fn le(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm512_cmp_pd_mask::<_CMP_LE_OQ>(a, b) }
        }
        #[inline(always)]
        fn eq(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm512_cmp_pd_mask::<_CMP_EQ_OQ>(a, b) }
        }
        #[inline(always)]
        fn and(self, a: Self::M, b: Self::M) -> Self::M {
            a & b
        }
        #[inline(always)]
        fn or(self, a: Self::M, b: Self::M) -> Self::M {
            a | b
        }
        #[inline(always)]
        fn andnot(self, a: Self::M, b: Self::M) -> Self::M {
            a & !b
        }
        #[inline(always)]
        fn select(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm512_mask_blend_pd(m, b, a) }
        }
        #[inline(always)]
        fn bits(self, m: Self::M) -> u32 {
            u32::from(m)
        }
        #[inline(always)]
        fn mask(self, b: u32) -> Self::M {
            b as u8
        }
        #[inline(always)]
        fn differ_from_lane_before(self, a: Self::F) -> u32 {
            unsafe {
                // Lane j of `before` is lane j - 1 of `a` (lane 0, lane 0).
                let before = _mm512_permutexvar_pd(_mm512_set_epi64(6, 5, 4, 3, 2, 1, 0, 0), a);
                let differ =
                    _mm512_cmpneq_epi64_mask(_mm512_castpd_si512(a), _mm512_castpd_si512(before));
                u32::from(differ)
            }
        }
        #[inline(always)]
        fn gather(self, v: &[f64], first: usize, stride: usize) -> Self::F {
            let last = stride.checked_mul(7).and_then(|s| s.checked_add(first));
            assert!(last.is_some_and(|l| l < v.len()));
            let s = stride as i64;
            unsafe {
                let at = _mm512_setr_epi64(0, s, 2 * s, 3 * s, 4 * s, 5 * s, 6 * s, 7 * s);
                _mm512_i64gather_pd::<8>(at, v.as_ptr().add(first).cast())
            }
        }
        #[inline(always)]
        fn min_lane(self, a: Self::F) -> f64 {
            unsafe {
                let m = _mm256_min_pd(_mm512_castpd512_pd256(a), _mm512_extractf64x4_pd::<1>(a));
                let m = _mm_min_pd(_mm256_castpd256_pd128(m), _mm256_extractf128_pd::<1>(m));
                _mm_cvtsd_f64(_mm_min_sd(m, _mm_unpackhi_pd(m, m)))
            }
        }
    }

    /// AVX2: four lanes, masks as all-ones lanes.
    #[derive(Clone, Copy, Debug)]
    pub struct Avx2(());

    impl Avx2 {
        /// The token, when this processor has AVX2.
        pub fn detect() -> Option<Avx2> {
            is_x86_feature_detected!("avx2").then_some(Avx2(()))
        }
    }

    // SAFETY: as for `Avx512`.
    impl Simd for Avx2 {
        const LANES: usize = 4;
        type F = __m256d;
        type M = __m256d;

        #[inline(always)]
        fn splat(self, v: f64) -> Self::F {
            unsafe { _mm256_set1_pd(v) }
        }
        #[inline(always)]
        fn load(self, v: &[f64]) -> Self::F {
            let v = &v[..4];
            unsafe { _mm256_loadu_pd(v.as_ptr()) }
        }
        #[inline(always)]
        fn store(self, x: Self::F, out: &mut [f64]) {
            let out = &mut out[..4];
            unsafe { _mm256_storeu_pd(out.as_mut_ptr(), x) }
        }
        #[inline(always)]
        fn add(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_add_pd(a, b) }
        }
        #[inline(always)]
        fn sub(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_sub_pd(a, b) }
        }
        #[inline(always)]
        fn mul(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_mul_pd(a, b) }
        }
        #[inline(always)]
        fn div(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_div_pd(a, b) }
        }
        #[inline(always)]
        fn sqrt(self, a: Self::F) -> Self::F {
            unsafe { _mm256_sqrt_pd(a) }
        }
        #[inline(always)]
        fn neg(self, a: Self::F) -> Self::F {
            unsafe { _mm256_xor_pd(a, _mm256_set1_pd(-0.0)) }
        }
        #[inline(always)]
        fn abs(self, a: Self::F) -> Self::F {
            unsafe { _mm256_andnot_pd(_mm256_set1_pd(-0.0), a) }
        }
        #[inline(always)]
        fn floor(self, a: Self::F) -> Self::F {
            unsafe { _mm256_floor_pd(a) }
        }
        #[inline(always)]
        fn copysign(self, mag: Self::F, sign: Self::F) -> Self::F {
            unsafe {
                let s = _mm256_set1_pd(-0.0);
                _mm256_or_pd(_mm256_andnot_pd(s, mag), _mm256_and_pd(s, sign))
            }
        }
        #[inline(always)]
        fn min(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_min_pd(a, b) }
        }
        #[inline(always)]
        fn max(self, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_max_pd(a, b) }
        }
        #[inline(always)]
        fn lt(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm256_cmp_pd::<_CMP_LT_OQ>(a, b) }
        }
        #[inline(always)]
        fn le(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm256_cmp_pd::<_CMP_LE_OQ>(a, b) }
        }
        #[inline(always)]
        fn eq(self, a: Self::F, b: Self::F) -> Self::M {
            unsafe { _mm256_cmp_pd::<_CMP_EQ_OQ>(a, b) }
        }
        #[inline(always)]
        fn and(self, a: Self::M, b: Self::M) -> Self::M {
            unsafe { _mm256_and_pd(a, b) }
        }
        #[inline(always)]
        fn or(self, a: Self::M, b: Self::M) -> Self::M {
            unsafe { _mm256_or_pd(a, b) }
        }
        #[inline(always)]
        fn andnot(self, a: Self::M, b: Self::M) -> Self::M {
            unsafe { _mm256_andnot_pd(b, a) }
        }
        #[inline(always)]
        fn select(self, m: Self::M, a: Self::F, b: Self::F) -> Self::F {
            unsafe { _mm256_blendv_pd(b, a, m) }
        }
        #[inline(always)]
        fn bits(self, m: Self::M) -> u32 {
            unsafe { _mm256_movemask_pd(m) as u32 }
        }
        #[inline(always)]
        fn gather(self, v: &[f64], first: usize, stride: usize) -> Self::F {
            let last = stride.checked_mul(3).and_then(|s| s.checked_add(first));
            assert!(last.is_some_and(|l| l < v.len()));
            let s = stride as i64;
            unsafe {
                let at = _mm256_setr_epi64x(0, s, 2 * s, 3 * s);
                _mm256_i64gather_pd::<8>(v.as_ptr().add(first), at)
            }
        }
        #[inline(always)]
        fn min_lane(self, a: Self::F) -> f64 {
            unsafe {
                let m = _mm_min_pd(_mm256_castpd256_pd128(a), _mm256_extractf128_pd::<1>(a));
                _mm_cvtsd_f64(_mm_min_sd(m, _mm_unpackhi_pd(m, m)))
            }
        }
        #[inline(always)]
        fn mask(self, b: u32) -> Self::M {
            unsafe {
                let lane = _mm256_setr_epi64x(1, 2, 4, 8);
                let set = _mm256_and_si256(_mm256_set1_epi64x(i64::from(b)), lane);
                _mm256_castsi256_pd(_mm256_cmpeq_epi64(set, lane))
            }
        }
        #[inline(always)]
        fn differ_from_lane_before(self, a: Self::F) -> u32 {
            unsafe {
                // Lane j of `before` is lane j - 1 of `a` (lane 0, lane 0).
                let before = _mm256_permute4x64_pd::<0b10_01_00_00>(a);
                let same = _mm256_cmpeq_epi64(_mm256_castpd_si256(a), _mm256_castpd_si256(before));
                !(_mm256_movemask_pd(_mm256_castsi256_pd(same)) as u32) & 0b1110
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Values whose neighbours are equal as numbers but not to the bit
    /// (`-0` and `+0`), the same NaN, and plain neighbours equal and not.
    const ROWS: [[f64; 8]; 4] = [
        [1.0, 1.0, 2.0, 2.0, 2.0, 3.0, 3.0, 3.0],
        [0.0, -0.0, -0.0, 0.0, 0.0, 5.0, 5.0, -5.0],
        [
            f64::NAN,
            f64::NAN,
            1.0,
            f64::NAN,
            -0.0,
            -0.0,
            f64::INFINITY,
            f64::INFINITY,
        ],
        [7.0, 6.0, 5.0, 4.0, 3.0, 2.0, 1.0, 0.0],
    ];

    /// Lane by lane, as the lanes' bits compare.
    fn expected(row: &[f64], lanes: usize) -> u32 {
        (1..lanes).fold(0, |b, j| {
            b | u32::from(row[j].to_bits() != row[j - 1].to_bits()) << j
        })
    }

    #[test]
    fn lanes_differ_from_the_lane_before_to_the_bit() {
        for row in &ROWS {
            let portable = Portable::<8>;
            let got = portable.differ_from_lane_before(portable.load(row));
            assert_eq!(got, expected(row, 8), "{row:?}");
            let portable = Portable::<4>;
            let got = portable.differ_from_lane_before(portable.load(row));
            assert_eq!(got, expected(row, 4), "{row:?}");
            #[cfg(target_arch = "x86_64")]
            {
                if let Some(s) = Avx512::detect() {
                    assert_eq!(s.differ_from_lane_before(s.load(row)), expected(row, 8));
                }
                if let Some(s) = Avx2::detect() {
                    assert_eq!(s.differ_from_lane_before(s.load(row)), expected(row, 4));
                }
            }
        }
        // The rows above hold every case in some lane.
        assert_eq!(expected(&ROWS[1], 8), 0b1010_1010);
    }
}

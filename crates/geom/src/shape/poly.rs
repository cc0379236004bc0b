//! Real roots of polynomials of degree ≤ 4 inside an interval, for the torus
//! and the general TGC. Follows Yuksel 2022 ("High-performance polynomial
//! root finding for graphics"): the roots of the derivative split the
//! interval into monotonic pieces, each of which holds at most one root,
//! found by safeguarded Newton–bisection started from the chord's zero.
//! A quadratic's roots come in closed form.

/// Evaluate `c[0] + c[1] t + … + c[n] tⁿ`. Cubics and quartics by
/// Estrin's scheme: each Newton step waits on the value, and pairing the
/// terms halves the chain of dependent operations that Horner's rule is.
#[inline]
fn eval(c: &[f64], t: f64) -> f64 {
    if let [c0, c1, c2, c3, c4] = *c {
        let t2 = t * t;
        return (c0 + c1 * t) + ((c2 + c3 * t) + c4 * t2) * t2;
    }
    if let [c0, c1, c2, c3] = *c {
        let t2 = t * t;
        return (c0 + c1 * t) + (c2 + c3 * t) * t2;
    }
    c.iter().rev().fold(0.0, |acc, &k| acc * t + k)
}

/// Roots of the polynomial `c` (ascending powers, degree ≤ 4) in
/// `[lo, hi]`, ascending, written to `out`; returns how many.
pub fn roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
    roots_to(c, lo, hi, ROOT_PRECISION, out)
}

/// Relative precision of the roots returned.
const ROOT_PRECISION: f64 = 1e-15;

/// Relative precision of the critical points, which only bound the
/// monotonic pieces. Newton's step falls below this once the iterate is
/// within about its square of the root, and a critical point off by even
/// 1e-9 could only hide a pair of roots that close to a tangency, a
/// chord far below any tolerance the tracer works to.
const CRITICAL_PRECISION: f64 = 1e-9;

/// [`roots_in`] to the given relative precision.
fn roots_to(c: &[f64], lo: f64, hi: f64, precision: f64, out: &mut [f64; 4]) -> usize {
    let mut deg = c.len() - 1;
    while deg > 0 && c[deg] == 0.0 {
        deg -= 1;
    }
    let c = &c[..=deg];
    match deg {
        0 => 0,
        1 => {
            let t = -c[0] / c[1];
            if t >= lo && t <= hi {
                out[0] = t;
                1
            } else {
                0
            }
        }
        2 => quadratic_roots_in(c, lo, hi, out),
        3 => roots_by_pieces::<4, 3>(c, lo, hi, precision, out),
        4 => roots_by_pieces::<5, 4>(c, lo, hi, precision, out),
        _ => unreachable!("roots_in takes polynomials of degree 4 at most"),
    }
}

/// The roots of `c` (`N` coefficients, the last not zero; `M` = `N` - 1)
/// in `[lo, hi]`, one from each monotonic piece between the roots of its
/// derivative where it changes sign. Fixed sizes let the evaluations
/// unroll.
fn roots_by_pieces<const N: usize, const M: usize>(
    c: &[f64],
    lo: f64,
    hi: f64,
    precision: f64,
    out: &mut [f64; 4],
) -> usize {
    let c: [f64; N] = std::array::from_fn(|i| c[i]);
    let d: [f64; M] = std::array::from_fn(|i| c[i + 1] * (i + 1) as f64);
    let mut crit = [0.0; 4];
    let nc = roots_to(&d, lo, hi, CRITICAL_PRECISION, &mut crit);
    let mut n = 0;
    let mut a = lo;
    let mut fa = eval(&c, a);
    for b in crit[..nc].iter().copied().chain(std::iter::once(hi)) {
        let fb = eval(&c, b);
        if fa == 0.0 {
            if n == 0 || out[n - 1] != a {
                out[n] = a;
                n += 1;
            }
        } else if fa.signum() != fb.signum() && n < 4 {
            out[n] = monotone_root(&c, &d, (a, b), (fa, fb), precision);
            n += 1;
        }
        a = b;
        fa = fb;
    }
    if fa == 0.0 && (n == 0 || out[n - 1] != a) && n < 4 {
        out[n] = a;
        n += 1;
    }
    n
}

/// Roots of `c[0] + c[1] t + c[2] t²` (`c[2] ≠ 0`) in `[lo, hi]`,
/// ascending. Each root is computed without cancellation (one from `q`,
/// the other from the product of the roots), so a near-double root is as
/// good as the discriminant, which is what a search on the polynomial
/// itself would also be limited by.
fn quadratic_roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
    let discriminant = c[1] * c[1] - 4.0 * c[2] * c[0];
    if discriminant < 0.0 {
        return 0;
    }
    let q = -0.5 * (c[1] + discriminant.sqrt().copysign(c[1]));
    let (r0, r1) = if q == 0.0 {
        // c[1] and c[0] are both zero: a double root at 0.
        (0.0, 0.0)
    } else {
        let (x, y) = (q / c[2], c[0] / q);
        (x.min(y), x.max(y))
    };
    let mut n = 0;
    for r in [r0, r1] {
        if r >= lo && r <= hi && (n == 0 || out[n - 1] != r) {
            out[n] = r;
            n += 1;
        }
    }
    n
}

/// The one root of `c` between `a` and `b`, where `c` is monotonic and
/// takes the values `fa` and `fb` of opposite signs. The first guess is
/// where the chord between the ends crosses zero, which for the smooth
/// pieces between critical points is usually close; Newton's steps that
/// would leave the shrinking bracket are replaced by bisection.
fn monotone_root<const N: usize, const M: usize>(
    c: &[f64; N],
    d: &[f64; M],
    (mut a, mut b): (f64, f64),
    (fa, fb): (f64, f64),
    precision: f64,
) -> f64 {
    let rising = fa < 0.0;
    let chord = a - fa * (b - a) / (fb - fa);
    let mut t = if chord > a && chord < b {
        chord
    } else {
        0.5 * (a + b)
    };
    for _ in 0..100 {
        let f = eval(c, t);
        if f == 0.0 {
            return t;
        }
        if (f < 0.0) == rising {
            a = t;
        } else {
            b = t;
        }
        let df = eval(d, t);
        let nt = t - f / df;
        let tolerance = precision * t.abs().max(1.0);
        // Newton's step is within the precision: done. This comes before
        // the bracket's test, which refuses such a step whenever `t` has
        // just become an end of the bracket, and bisection would then
        // creep back to `t` from the far end a halving at a time.
        if (nt - t).abs() <= tolerance {
            return nt.clamp(a, b);
        }
        let next = if df != 0.0 && nt > a && nt < b {
            nt
        } else {
            0.5 * (a + b)
        };
        if (next - t).abs() <= tolerance || b - a <= tolerance {
            return next;
        }
        t = next;
    }
    t
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn quartic_with_four_known_roots() {
        // (t-1)(t-2)(t-3)(t-4) = t⁴ - 10t³ + 35t² - 50t + 24
        let mut r = [0.0; 4];
        let n = roots_in(&[24.0, -50.0, 35.0, -10.0, 1.0], -10.0, 10.0, &mut r);
        assert_eq!(n, 4);
        for (i, &x) in r.iter().enumerate() {
            assert!((x - (i + 1) as f64).abs() < 1e-12, "{r:?}");
        }
        assert_eq!(
            roots_in(&[24.0, -50.0, 35.0, -10.0, 1.0], 2.5, 3.5, &mut r),
            1
        );
        assert!((r[0] - 3.0).abs() < 1e-12);
    }

    #[test]
    fn no_roots_and_double_roots() {
        let mut r = [0.0; 4];
        assert_eq!(roots_in(&[1.0, 0.0, 1.0], -5.0, 5.0, &mut r), 0);
        // (t-2)² touches zero at the critical point.
        let n = roots_in(&[4.0, -4.0, 1.0], -5.0, 5.0, &mut r);
        assert!(n >= 1 && (r[0] - 2.0).abs() < 1e-7);
    }

    #[test]
    fn quadratic_roots_in_closed_form() {
        let mut r = [0.0; 4];
        // (t-1)(t-3), whole and clipped to either end.
        assert_eq!(roots_in(&[3.0, -4.0, 1.0], -5.0, 5.0, &mut r), 2);
        assert_eq!(r[..2], [1.0, 3.0]);
        assert_eq!(roots_in(&[3.0, -4.0, 1.0], 2.0, 5.0, &mut r), 1);
        assert_eq!(r[0], 3.0);
        assert_eq!(roots_in(&[3.0, -4.0, 1.0], 1.0, 2.0, &mut r), 1);
        assert_eq!(r[0], 1.0);
        // No linear term, and a leading coefficient below zero.
        assert_eq!(roots_in(&[4.0, 0.0, -1.0], -5.0, 5.0, &mut r), 2);
        assert_eq!(r[..2], [-2.0, 2.0]);
        // Roots 1e-8 and 1e8: the small one survives the large one.
        let n = roots_in(&[1.0, -(1e8 + 1e-8), 1.0], 0.0, 1e9, &mut r);
        assert_eq!(n, 2);
        assert!(
            (r[0] - 1e-8).abs() < 1e-22 && (r[1] - 1e8).abs() < 1e-6,
            "{r:?}"
        );
        // A double root at zero.
        assert_eq!(roots_in(&[0.0, 0.0, 2.0], -1.0, 1.0, &mut r), 1);
        assert_eq!(r[0], 0.0);
    }

    proptest::proptest! {
        /// A quartic built from four roots apart from one another gives
        /// them all back, to a precision far finer than any tolerance of
        /// the tracer, whatever its scale and sign: within 1e-9, or
        /// within what the rounding of its coefficients moves a root by
        /// where the roots crowd together.
        #[test]
        fn quartic_gives_back_its_roots(
            roots in proptest::array::uniform4(-20.0..20.0f64),
            scale in proptest::prop_oneof![-1e3..-1e-3f64, 1e-3..1e3f64],
        ) {
            let mut sorted = roots;
            sorted.sort_by(f64::total_cmp);
            proptest::prop_assume!(sorted.windows(2).all(|w| w[1] - w[0] > 1e-2));
            // scale·(t - r0)(t - r1)(t - r2)(t - r3), ascending powers.
            let mut c = vec![scale];
            for root in sorted {
                let mut next = vec![0.0; c.len() + 1];
                for (i, &k) in c.iter().enumerate() {
                    next[i + 1] += k;
                    next[i] -= root * k;
                }
                c = next;
            }
            let mut found = [0.0; 4];
            let n = roots_in(&c, -25.0, 25.0, &mut found);
            proptest::prop_assert_eq!(n, 4, "{:?} {:?}", sorted, found);
            for (i, (root, found)) in sorted.iter().zip(found).enumerate() {
                // The coefficients are rounded products: the roots of the
                // quartic they make lie about ε·Σ|c_k r^k| / |p'(r)| from
                // the roots it was built from (the roots' condition).
                let slope: f64 = sorted
                    .iter()
                    .enumerate()
                    .filter(|&(j, _)| j != i)
                    .map(|(_, other)| root - other)
                    .product::<f64>()
                    * scale;
                let size: f64 = c
                    .iter()
                    .enumerate()
                    .map(|(k, ck)| ck.abs() * root.abs().powi(k as i32))
                    .sum();
                let moved = 16.0 * f64::EPSILON * size / slope.abs();
                proptest::prop_assert!(
                    (root - found).abs() < 1e-9 + moved,
                    "{:?} {:?} (rounding moves the roots by up to {:e})",
                    sorted,
                    found,
                    moved
                );
            }
        }
    }
}

//! Real roots of polynomials of degree ≤ 4 inside an interval, for the torus
//! and the general TGC. Follows Yuksel 2022 ("High-performance polynomial
//! root finding for graphics"): the roots of the derivative split the
//! interval into monotonic pieces, each of which holds at most one root,
//! found by safeguarded Newton–bisection started from the chord's zero.
//! A quadratic's roots come in closed form.

use sv_math::lanes::{clamp, max_num, min_num, nan, not};
use sv_math::simd::Simd;

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

/// [`roots_in`] over `[0, hi]` in every lane of `m`, operation for
/// operation, for quartics whose leading coefficient `c[4]` is not zero
/// (the torus's is one): the roots, ascending, and how many each lane has
/// (a whole number in `f64`). Where [`roots_in`] branches, the lanes take
/// both ways and each lane keeps its own; a piece's search runs while any
/// lane still needs it.
#[inline(always)]
pub(crate) fn quartic_roots_lanes<S: Simd>(
    s: S,
    c: [S::F; 5],
    hi: S::F,
    m: S::M,
) -> ([S::F; 4], S::F) {
    let zero = s.splat(0.0);
    // The derivatives' coefficients, `c[i + 1] * (i + 1)` as `roots_by_pieces` has them.
    let mut d = [zero; 4];
    for (i, d) in d.iter_mut().enumerate() {
        *d = s.mul(c[i + 1], s.splat((i + 1) as f64));
    }
    let mut dd = [zero; 3];
    for (i, dd) in dd.iter_mut().enumerate() {
        *dd = s.mul(d[i + 1], s.splat((i + 1) as f64));
    }
    // The critical points of the derivative, in closed form.
    let mut inflections = Pushed::new(s);
    quadratic_roots_lanes(s, dd, hi, m, &mut inflections);
    // The critical points of the quartic: the roots of its derivative.
    let mut critical = Pushed::new(s);
    roots_by_pieces_lanes(
        s,
        (&d, &dd),
        (zero, hi),
        (&inflections, 3),
        m,
        &mut critical,
    );
    let mut roots = Pushed::new(s);
    roots_by_pieces_lanes(s, (&c, &d), (zero, hi), (&critical, 5), m, &mut roots);
    (roots.out, roots.n)
}

/// [`roots_in`] over `[0, hi]` in every lane of `m`, operation for
/// operation, for quadratics whose `c[2]` is not zero: the roots,
/// ascending, and how many each lane has (a whole number in `f64`).
#[inline(always)]
pub(crate) fn quadratic_roots_in_lanes<S: Simd>(
    s: S,
    c: [S::F; 3],
    hi: S::F,
    m: S::M,
) -> ([S::F; 2], S::F) {
    let mut roots = Pushed::new(s);
    quadratic_roots_lanes(s, c, hi, m, &mut roots);
    ([roots.out[0], roots.out[1]], roots.n)
}

/// Values pushed lane by lane: the first four, how many, and the last.
struct Pushed<S: Simd> {
    out: [S::F; 4],
    n: S::F,
    last: S::F,
}

impl<S: Simd> Pushed<S> {
    #[inline(always)]
    fn new(s: S) -> Pushed<S> {
        let zero = s.splat(0.0);
        Pushed {
            out: [zero; 4],
            n: zero,
            last: zero,
        }
    }

    /// Push `value` in the lanes of `m` that hold fewer than four.
    #[inline(always)]
    fn push(&mut self, s: S, m: S::M, value: S::F) {
        for (k, out) in self.out.iter_mut().enumerate() {
            *out = s.select(s.and(m, s.eq(self.n, s.splat(k as f64))), value, *out);
        }
        self.n = s.select(m, s.add(self.n, s.splat(1.0)), self.n);
        self.last = s.select(m, value, self.last);
    }

    /// The lanes with nothing pushed or whose last value is not `value`:
    /// where pushing `value` adds a root, not the last again.
    #[inline(always)]
    fn new_value(&self, s: S, value: S::F) -> S::M {
        s.or(s.eq(self.n, s.splat(0.0)), not(s, s.eq(self.last, value)))
    }
}

/// [`eval`] in every lane, operation for operation.
#[inline(always)]
fn eval_lanes<S: Simd, const N: usize>(s: S, c: &[S::F; N], t: S::F) -> S::F {
    let t2 = s.mul(t, t);
    match N {
        5 => s.add(
            s.add(c[0], s.mul(c[1], t)),
            s.mul(s.add(s.add(c[2], s.mul(c[3], t)), s.mul(c[4], t2)), t2),
        ),
        4 => s.add(
            s.add(c[0], s.mul(c[1], t)),
            s.mul(s.add(c[2], s.mul(c[3], t)), t2),
        ),
        _ => {
            let mut acc = s.splat(0.0);
            for &k in c.iter().rev() {
                acc = s.add(s.mul(acc, t), k);
            }
            acc
        }
    }
}

/// [`quadratic_roots_in`] over `[0, hi]` in every lane of `m`, for
/// quadratics whose `c[2]` is not zero, pushed to `out`.
#[inline(always)]
fn quadratic_roots_lanes<S: Simd>(s: S, c: [S::F; 3], hi: S::F, m: S::M, out: &mut Pushed<S>) {
    let zero = s.splat(0.0);
    let discriminant = s.sub(s.mul(c[1], c[1]), s.mul(s.mul(s.splat(4.0), c[2]), c[0]));
    let m = s.andnot(m, s.lt(discriminant, zero));
    let q = s.mul(
        s.splat(-0.5),
        s.add(c[1], s.copysign(s.sqrt(discriminant), c[1])),
    );
    let double = s.eq(q, zero);
    let (x, y) = (s.div(q, c[2]), s.div(c[0], q));
    let r0 = s.select(double, zero, min_num(s, x, y));
    let r1 = s.select(double, zero, max_num(s, x, y));
    for r in [r0, r1] {
        let fits = s.and(s.ge(r, zero), s.le(r, hi));
        out.push(s, s.and(s.and(m, fits), out.new_value(s, r)), r);
    }
}

/// [`roots_by_pieces`] in every lane of `m`: the roots of `c` (`N`
/// coefficients, the last not zero; `d` its derivative) in `lo..hi`, one
/// from each monotonic piece between the critical points `crit` (at most
/// `pieces - 1`), pushed to `out`.
#[inline(always)]
fn roots_by_pieces_lanes<S: Simd, const N: usize, const M: usize>(
    s: S,
    (c, d): (&[S::F; N], &[S::F; M]),
    (lo, hi): (S::F, S::F),
    (crit, pieces): (&Pushed<S>, usize),
    m: S::M,
    out: &mut Pushed<S>,
) {
    let (zero, one, four) = (s.splat(0.0), s.splat(1.0), s.splat(4.0));
    let mut a = lo;
    let mut fa = eval_lanes(s, c, a);
    for k in 0..pieces {
        let place = s.splat(k as f64);
        // The lanes with a piece `k`, and where it ends.
        let here = s.and(m, s.le(place, crit.n));
        if !s.any(here) {
            break;
        }
        let b = if k < 4 {
            s.select(s.lt(place, crit.n), crit.out[k], hi)
        } else {
            hi
        };
        let fb = eval_lanes(s, c, b);
        let at_a = s.and(here, s.eq(fa, zero));
        out.push(s, s.and(at_a, out.new_value(s, a)), a);
        // `signum` differs: either is not a number, or their signs do.
        let signs = not(s, s.eq(s.copysign(one, fa), s.copysign(one, fb)));
        let differ = s.or(s.or(nan(s, fa), nan(s, fb)), signs);
        let search = s.and(s.andnot(here, at_a), s.and(differ, s.lt(out.n, four)));
        if s.any(search) {
            let root = monotone_root_lanes(s, (c, d), (a, b), (fa, fb), PRECISIONS[N - 4], search);
            out.push(s, search, root);
        }
        a = s.select(here, b, a);
        fa = s.select(here, fb, fa);
    }
    let at_end = s.and(s.and(m, s.eq(fa, zero)), s.lt(out.n, four));
    out.push(s, s.and(at_end, out.new_value(s, a)), a);
}

/// The precision [`roots_to`] is given for a cubic (the quartic's
/// critical points) and for a quartic (its roots), by `N - 4`.
const PRECISIONS: [f64; 2] = [CRITICAL_PRECISION, ROOT_PRECISION];

/// [`monotone_root`] in every lane of `m`, each lane stopping where the
/// scalar search would.
#[inline(always)]
fn monotone_root_lanes<S: Simd, const N: usize, const M: usize>(
    s: S,
    (c, d): (&[S::F; N], &[S::F; M]),
    (mut a, mut b): (S::F, S::F),
    (fa, fb): (S::F, S::F),
    precision: f64,
    m: S::M,
) -> S::F {
    let (zero, half, one) = (s.splat(0.0), s.splat(0.5), s.splat(1.0));
    let rising = s.lt(fa, zero);
    let chord = s.sub(a, s.div(s.mul(fa, s.sub(b, a)), s.sub(fb, fa)));
    let inside = s.and(s.gt(chord, a), s.lt(chord, b));
    let mut t = s.select(inside, chord, s.mul(half, s.add(a, b)));
    let mut root = t;
    let mut running = m;
    for _ in 0..100 {
        if !s.any(running) {
            break;
        }
        let f = eval_lanes(s, c, t);
        let on = s.eq(f, zero);
        root = s.select(s.and(running, on), t, root);
        running = s.andnot(running, on);
        // `(f < 0) == rising`: the root lies beyond `t`.
        let below = s.lt(f, zero);
        let beyond = s.or(s.and(below, rising), s.andnot(not(s, below), rising));
        a = s.select(s.and(running, beyond), t, a);
        b = s.select(s.andnot(running, beyond), t, b);
        let df = eval_lanes(s, d, t);
        let nt = s.sub(t, s.div(f, df));
        let tolerance = s.mul(s.splat(precision), s.max(s.abs(t), one));
        let newton_done = s.le(s.abs(s.sub(nt, t)), tolerance);
        root = s.select(s.and(running, newton_done), clamp(s, nt, a, b), root);
        running = s.andnot(running, newton_done);
        let in_bracket = s.and(not(s, s.eq(df, zero)), s.and(s.gt(nt, a), s.lt(nt, b)));
        let next = s.select(in_bracket, nt, s.mul(half, s.add(a, b)));
        let stop = s.or(
            s.le(s.abs(s.sub(next, t)), tolerance),
            s.le(s.sub(b, a), tolerance),
        );
        root = s.select(s.and(running, stop), next, root);
        running = s.andnot(running, stop);
        t = s.select(running, next, t);
    }
    s.select(running, t, root)
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

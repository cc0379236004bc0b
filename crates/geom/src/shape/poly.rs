//! Real roots of polynomials of degree ≤ 4 inside an interval, for the torus
//! and the general TGC. Follows Yuksel 2022 ("High-performance polynomial
//! root finding for graphics"): the roots of the derivative split the
//! interval into monotonic pieces, each of which holds at most one root,
//! found by safeguarded Newton–bisection.

/// Evaluate `c[0] + c[1] t + … + c[n] tⁿ`.
#[inline]
fn eval(c: &[f64], t: f64) -> f64 {
    c.iter().rev().fold(0.0, |acc, &k| acc * t + k)
}

/// Roots of the polynomial `c` (ascending powers, degree ≤ 4) in
/// `[lo, hi]`, ascending, written to `out`; returns how many.
pub fn roots_in(c: &[f64], lo: f64, hi: f64, out: &mut [f64; 4]) -> usize {
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
        _ => {
            let mut d = [0.0; 4];
            for i in 1..=deg {
                d[i - 1] = c[i] * i as f64;
            }
            let mut crit = [0.0; 4];
            let nc = roots_in(&d[..deg], lo, hi, &mut crit);
            let mut n = 0;
            let mut a = lo;
            let mut fa = eval(c, a);
            for b in crit[..nc].iter().copied().chain(std::iter::once(hi)) {
                let fb = eval(c, b);
                if fa == 0.0 {
                    if n == 0 || out[n - 1] != a {
                        out[n] = a;
                        n += 1;
                    }
                } else if fa.signum() != fb.signum() && n < 4 {
                    out[n] = monotone_root(c, &d[..deg], a, b, fa);
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
    }
}

fn monotone_root(c: &[f64], d: &[f64], mut a: f64, mut b: f64, fa: f64) -> f64 {
    let rising = fa < 0.0;
    let mut t = 0.5 * (a + b);
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
        let next = if df != 0.0 && nt > a && nt < b {
            nt
        } else {
            0.5 * (a + b)
        };
        if (next - t).abs() <= 1e-15 * t.abs().max(1.0) || b - a <= 1e-15 * t.abs().max(1.0) {
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
}

//! MCNP numbers and the shorthand that writes many of them: Fortran reals
//! (`1.5e-3`, `1.5d-3`, and `1.5-3` with no exponent letter), and the
//! `nR` (repeat), `nI` (linear interpolates), `xM` (multiply), `nJ` (jump
//! to the default), `nLOG`/`nILOG` (logarithmic interpolates) entries.

use super::input::Word;
use super::Loc;

/// Most entries one card may expand to (`1000000000R` is refused, not
/// allocated).
pub(crate) const MAX_ENTRIES: usize = 1 << 22;

/// A real as MCNP writes it: Rust's syntax, `d`/`D` as the exponent letter,
/// or a sign that starts the exponent without a letter (`7.9-3` is 0.0079).
pub(crate) fn real(text: &str) -> Option<f64> {
    let finite = |v: f64| v.is_finite().then_some(v);
    let first = text.as_bytes().first()?;
    if !(first.is_ascii_digit() || matches!(first, b'+' | b'-' | b'.')) {
        return None;
    }
    if let Ok(v) = text.parse::<f64>() {
        return finite(v);
    }
    let normal = text.replace(['d', 'D'], "e");
    if let Ok(v) = normal.parse::<f64>() {
        return finite(v);
    }
    // A sign after the first character that does not follow an exponent
    // letter starts a letterless exponent.
    let bytes = normal.as_bytes();
    let at = (1..bytes.len())
        .find(|&i| matches!(bytes[i], b'+' | b'-') && !matches!(bytes[i - 1], b'e' | b'E'))?;
    let mantissa = &normal[..at];
    if mantissa.contains(['e', 'E']) {
        return None;
    }
    format!("{mantissa}e{}", &normal[at..])
        .parse::<f64>()
        .ok()
        .and_then(finite)
}

/// A whole number written with digits only (and a sign).
pub(crate) fn integer(text: &str) -> Option<i64> {
    let digits = text.strip_prefix(['+', '-']).unwrap_or(text);
    if digits.is_empty() || digits.len() > 15 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    text.parse().ok()
}

/// One entry after the shorthand is expanded: a value, or `None` where a
/// `J` jumped over it (the card's default).
pub(crate) type Entry = (Option<f64>, Loc);

/// A shorthand word, taken apart.
enum Shorthand {
    Repeat(usize),
    Interpolate(usize),
    LogInterpolate(usize),
    Jump(usize),
    Multiply(f64),
}

/// The count before a shorthand letter: none means one.
fn count(digits: &str) -> Option<usize> {
    if digits.is_empty() {
        return Some(1);
    }
    if digits.len() > 9 || !digits.bytes().all(|b| b.is_ascii_digit()) {
        return None;
    }
    digits.parse().ok()
}

fn shorthand(text: &str) -> Option<Shorthand> {
    let lower = text.to_ascii_lowercase();
    if let Some(n) = lower.strip_suffix("ilog") {
        return count(n).map(Shorthand::LogInterpolate);
    }
    if let Some(n) = lower.strip_suffix("log") {
        return count(n).map(Shorthand::LogInterpolate);
    }
    if let Some(n) = lower.strip_suffix('r') {
        return count(n).map(Shorthand::Repeat);
    }
    if let Some(n) = lower.strip_suffix('i') {
        return count(n).map(Shorthand::Interpolate);
    }
    if let Some(n) = lower.strip_suffix('j') {
        return count(n).map(Shorthand::Jump);
    }
    if let Some(x) = lower.strip_suffix('m') {
        return real(x).map(Shorthand::Multiply);
    }
    None
}

/// Interpolates waiting for the value that ends them.
struct Pending {
    count: usize,
    from: f64,
    log: bool,
    at: Loc,
}

/// Expands words of numbers and shorthand into entries, each located at
/// the word it came from.
#[derive(Default)]
pub(crate) struct Expander {
    pub out: Vec<Entry>,
    pending: Option<Pending>,
}

impl Expander {
    /// Take one word; `Err` names what is wrong with it.
    pub fn push(&mut self, w: &Word) -> Result<(), String> {
        if let Some(v) = real(&w.text) {
            return self.value(v, w.at);
        }
        let Some(s) = shorthand(&w.text) else {
            return Err(format!("expected a number, found `{}`", w.text));
        };
        if self.pending.is_some() {
            return Err(format!(
                "`{}` cannot follow an interpolation: a number must end it",
                w.text
            ));
        }
        let last = self.out.last().and_then(|e| e.0);
        let previous = match (last, &s) {
            (_, Shorthand::Jump(_)) => 0.0,
            (Some(v), _) => v,
            (None, _) => return Err(format!("`{}` needs a number before it", w.text)),
        };
        let added = match s {
            Shorthand::Jump(n)
            | Shorthand::Repeat(n)
            | Shorthand::Interpolate(n)
            | Shorthand::LogInterpolate(n) => n,
            Shorthand::Multiply(_) => 1,
        };
        if self.out.len() + added > MAX_ENTRIES {
            return Err(format!(
                "`{}` makes more than {MAX_ENTRIES} entries",
                w.text
            ));
        }
        match s {
            Shorthand::Jump(n) => self.out.extend(std::iter::repeat_n((None, w.at), n)),
            Shorthand::Repeat(n) => self.out.extend(std::iter::repeat_n((last, w.at), n)),
            Shorthand::Multiply(x) => self.out.push((Some(previous * x), w.at)),
            Shorthand::Interpolate(count) | Shorthand::LogInterpolate(count) => {
                let log = matches!(s, Shorthand::LogInterpolate(_));
                if log && previous <= 0.0 {
                    return Err(format!("`{}` needs a positive number before it", w.text));
                }
                self.pending = Some(Pending {
                    count,
                    from: previous,
                    log,
                    at: w.at,
                });
            }
        }
        Ok(())
    }

    fn value(&mut self, v: f64, at: Loc) -> Result<(), String> {
        if let Some(p) = self.pending.take() {
            if p.log && v <= 0.0 {
                return Err("a logarithmic interpolation must end at a positive number".into());
            }
            let steps = (p.count + 1) as f64;
            for k in 1..=p.count {
                let f = k as f64 / steps;
                let x = if p.log {
                    (p.from.ln() + f * (v.ln() - p.from.ln())).exp()
                } else {
                    p.from + f * (v - p.from)
                };
                self.out.push((Some(x), p.at));
            }
        }
        if self.out.len() >= MAX_ENTRIES {
            return Err(format!("the card has more than {MAX_ENTRIES} entries"));
        }
        self.out.push((Some(v), at));
        Ok(())
    }

    /// The entries; `Err` with the place of an interpolation left open.
    pub fn finish(self) -> Result<Vec<Entry>, (Loc, String)> {
        match self.pending {
            Some(p) => Err((p.at, "an interpolation needs a number after it".into())),
            None => Ok(self.out),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn words(text: &str) -> Vec<Word> {
        text.split_whitespace()
            .map(|t| Word {
                text: t.to_string(),
                at: Loc::default(),
            })
            .collect()
    }

    fn expand(text: &str) -> Result<Vec<Option<f64>>, String> {
        let mut e = Expander::default();
        for w in words(text) {
            e.push(&w)?;
        }
        e.finish()
            .map(|v| v.into_iter().map(|x| x.0).collect())
            .map_err(|e| e.1)
    }

    #[test]
    fn fortran_reals() {
        assert_eq!(real("7.9-3"), Some(7.9e-3));
        assert_eq!(real("-1.5+2"), Some(-150.0));
        assert_eq!(real("2.5D1"), Some(25.0));
        assert_eq!(real(".5"), Some(0.5));
        assert_eq!(real("5."), Some(5.0));
        assert_eq!(real("1e-3"), Some(1e-3));
        assert_eq!(real("1e-3-4"), None);
        assert_eq!(real("inf"), None);
        assert_eq!(real("1e999"), None);
        assert_eq!(real("px"), None);
        assert_eq!(integer("-12"), Some(-12));
        assert_eq!(integer("1.0"), None);
    }

    #[test]
    fn shorthand_expands() {
        let s = |v: &[f64]| v.iter().map(|x| Some(*x)).collect::<Vec<_>>();
        assert_eq!(expand("1 2R 3").unwrap(), s(&[1.0, 1.0, 1.0, 3.0]));
        assert_eq!(expand("1 3I 5").unwrap(), s(&[1.0, 2.0, 3.0, 4.0, 5.0]));
        assert_eq!(expand("2 3M").unwrap(), s(&[2.0, 6.0]));
        assert_eq!(
            expand("1 2j 3").unwrap(),
            vec![Some(1.0), None, None, Some(3.0)]
        );
        let log = expand("1 1log 100").unwrap();
        assert!((log[1].unwrap() - 10.0).abs() < 1e-9);
        assert_eq!(expand("1 r").unwrap(), s(&[1.0, 1.0]));
        assert!(expand("R").is_err());
        assert!(expand("1 2I").is_err());
        assert!(expand("1 4000000000R").is_err());
        assert!(expand("1 x").is_err());
    }
}

//! Coefficient algebra: sums of monomials `lit · Π atom^power` in the parameters and Ω
//! (powers may be negative), like terms merged. A coefficient is what multiplies the
//! signals inside `D(e, n)` and in outputs; it is constant over a period, so `D` can pull
//! it outside and outputs can require it to be a bare literal.

use std::collections::BTreeMap;

/// A coefficient factor that is not a literal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Atom {
    Param(usize),
    Omega,
}

/// A coefficient monomial: `lit * Π atom^power`; no power is 0.
#[derive(Debug, Clone, PartialEq)]
pub struct Monomial {
    pub lit: f64,
    pub atoms: BTreeMap<Atom, i32>,
}

/// A sum of coefficient monomials, like terms merged and none with `lit == 0`.
#[derive(Debug, Clone, Default, PartialEq)]
pub struct CoefPoly(Vec<Monomial>);

/// Why a coefficient has no reciprocal in the algebra.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum NoRecip {
    /// It is zero.
    Zero,
    /// It is a sum of several monomials (the quotient would not be polynomial).
    Sum,
}

impl CoefPoly {
    pub fn constant(v: f64) -> Self {
        CoefPoly(vec![Monomial { lit: v, atoms: BTreeMap::new() }]).clean()
    }

    pub fn atom(a: Atom) -> Self {
        CoefPoly(vec![Monomial { lit: 1.0, atoms: BTreeMap::from([(a, 1)]) }])
    }

    /// The monomials, in order of first appearance.
    pub fn monomials(&self) -> &[Monomial] {
        &self.0
    }

    fn clean(self) -> Self {
        let mut out: Vec<Monomial> = Vec::new();
        for c in self.0 {
            match out.iter_mut().find(|o| o.atoms == c.atoms) {
                Some(o) => o.lit += c.lit,
                None => out.push(c),
            }
        }
        out.retain(|c| c.lit != 0.0);
        CoefPoly(out)
    }

    pub fn add(mut self, other: CoefPoly) -> Self {
        self.0.extend(other.0);
        self.clean()
    }

    pub fn neg(self) -> Self {
        CoefPoly(self.0.into_iter().map(|c| Monomial { lit: -c.lit, ..c }).collect())
    }

    pub fn mul(&self, other: &CoefPoly) -> Self {
        let mut out = Vec::new();
        for a in &self.0 {
            for b in &other.0 {
                let mut atoms = a.atoms.clone();
                for (k, v) in &b.atoms {
                    *atoms.entry(*k).or_insert(0) += v;
                }
                atoms.retain(|_, v| *v != 0);
                out.push(Monomial { lit: a.lit * b.lit, atoms });
            }
        }
        CoefPoly(out).clean()
    }

    /// `self^k`, `k >= 0`.
    pub fn powi(&self, k: u32) -> Self {
        let mut c = CoefPoly::constant(1.0);
        for _ in 0..k {
            c = c.mul(self);
        }
        c
    }

    /// `1 / self`, defined for a single monomial only.
    pub fn recip(&self) -> Result<Self, NoRecip> {
        match self.0.as_slice() {
            [c] => Ok(CoefPoly(vec![Monomial {
                lit: 1.0 / c.lit,
                atoms: c.atoms.iter().map(|(a, p)| (*a, -p)).collect(),
            }])),
            [] => Err(NoRecip::Zero),
            _ => Err(NoRecip::Sum),
        }
    }

    /// The value if it is a bare literal (0 for the zero coefficient).
    pub fn literal(&self) -> Option<f64> {
        match self.0.as_slice() {
            [] => Some(0.0),
            [c] if c.atoms.is_empty() => Some(c.lit),
            _ => None,
        }
    }

    pub fn is_zero(&self) -> bool {
        self.0.is_empty()
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// The value at parameters `p` and frequency `omega`.
    fn eval(c: &CoefPoly, p: &[f64], omega: f64) -> f64 {
        c.monomials()
            .iter()
            .map(|m| {
                m.atoms.iter().fold(m.lit, |acc, (a, pow)| {
                    let base = match a {
                        Atom::Param(i) => p[*i],
                        Atom::Omega => omega,
                    };
                    acc * base.powi(*pow)
                })
            })
            .sum()
    }

    const P: [f64; 2] = [1.7, -0.6];
    const OMEGA: f64 = 2.3;

    fn a() -> CoefPoly {
        CoefPoly::atom(Atom::Param(0))
    }
    fn b() -> CoefPoly {
        CoefPoly::atom(Atom::Param(1))
    }
    fn w() -> CoefPoly {
        CoefPoly::atom(Atom::Omega)
    }
    /// `(a + 2 Ω) (3 - b)` and `b² - 0.5 a Ω`: sums with shared atoms.
    fn samples() -> [CoefPoly; 3] {
        let s1 =
            a().add(CoefPoly::constant(2.0).mul(&w())).mul(&CoefPoly::constant(3.0).add(b().neg()));
        let s2 = b().mul(&b()).add(CoefPoly::constant(-0.5).mul(&a()).mul(&w()));
        [s1, s2, CoefPoly::constant(-4.0)]
    }

    fn close(x: f64, y: f64) -> bool {
        (x - y).abs() <= 1e-12 * (1.0 + x.abs().max(y.abs()))
    }

    #[test]
    fn ring_operations_agree_with_arithmetic_on_values() {
        for x in samples() {
            for y in samples() {
                let (vx, vy) = (eval(&x, &P, OMEGA), eval(&y, &P, OMEGA));
                assert!(close(eval(&x.mul(&y), &P, OMEGA), vx * vy));
                assert!(close(eval(&x.clone().add(y.clone()), &P, OMEGA), vx + vy));
                assert!(close(eval(&x.clone().neg(), &P, OMEGA), -vx));
            }
            for k in 0..5 {
                let v = eval(&x, &P, OMEGA).powi(k as i32);
                assert!(close(eval(&x.powi(k), &P, OMEGA), v));
            }
        }
    }

    #[test]
    fn like_terms_merge_and_cancel() {
        // a + a = 2a: one monomial.
        let two_a = a().add(a());
        assert_eq!(two_a.monomials().len(), 1);
        assert_eq!(two_a.monomials()[0].lit, 2.0);
        // x - x = 0 exactly, for sums too.
        for x in samples() {
            assert!(x.clone().add(x.neg()).is_zero());
        }
        assert!(CoefPoly::constant(0.0).is_zero());
        // a · a⁻¹ = 1 with no atom left at power 0.
        let one = a().mul(&a().recip().unwrap());
        assert_eq!(one, CoefPoly::constant(1.0));
    }

    #[test]
    fn only_monomials_have_reciprocals() {
        // 2 a² / Ω → 0.5 Ω / a².
        let m = CoefPoly::constant(2.0).mul(&a()).mul(&a()).mul(&w().recip().unwrap());
        let r = m.recip().unwrap();
        assert!(close(eval(&r, &P, OMEGA), OMEGA / (2.0 * P[0] * P[0])));
        assert_eq!(CoefPoly::default().recip(), Err(NoRecip::Zero));
        assert_eq!(a().add(CoefPoly::constant(1.0)).recip(), Err(NoRecip::Sum));
    }

    #[test]
    fn literal_reads_bare_numbers_only() {
        assert_eq!(CoefPoly::constant(-1.5).literal(), Some(-1.5));
        assert_eq!(CoefPoly::default().literal(), Some(0.0));
        assert_eq!(a().literal(), None);
        assert_eq!(a().add(CoefPoly::constant(1.0)).literal(), None);
    }
}

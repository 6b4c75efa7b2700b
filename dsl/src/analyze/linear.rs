//! Linear forms in the DOFs, `Σ cᵢ·xᵢ + c₀` with coefficient polynomials `cᵢ`: what the
//! argument of `D(e, n)` and an output must be. A form read from an expression expands
//! aliases by their definitions; `D` then splits it into signals with literal
//! coefficients, coefficient factors pulled outside (`signal_groups`), so that
//! `D(2 x - 2 y, p)` and `D(x - y, p)` read the same signal.

use super::coeff::{Atom, CoefPoly, NoRecip};
use super::diag::{err, Sp};
use super::scope::{Name, Scope};
use super::syntax::{ident_of, mentions_t, powi_exponent, show};
use super::tree::{Func, Terms};
use crate::parse::{literal_value, LetDecl};
use std::collections::BTreeMap;
use syn::{BinOp, Expr, UnOp};

/// A linear form in the DOFs with coefficient polynomials, plus a constant part.
#[derive(Debug, Clone, Default)]
pub struct Lin {
    pub dofs: BTreeMap<usize, CoefPoly>,
    pub konst: CoefPoly,
    /// Where a constant term came from (for the error message).
    pub konst_span: Option<Sp>,
}

/// DOF terms of a form sharing one non-literal coefficient factor: the form holds
/// `scale · Π atom^power · Σ terms`, the first of `terms` with coefficient 1.
#[derive(Debug, Clone, PartialEq)]
pub struct Group {
    pub atoms: BTreeMap<Atom, i32>,
    pub scale: f64,
    pub terms: Terms,
}

impl Lin {
    /// The constant form `c`, which came from `span`.
    pub fn konst(c: CoefPoly, span: Sp) -> Lin {
        Lin { dofs: BTreeMap::new(), konst: c, konst_span: Some(span) }
    }

    /// The form `x_i`.
    pub fn dof(i: usize) -> Lin {
        Lin { dofs: BTreeMap::from([(i, CoefPoly::constant(1.0))]), ..Lin::default() }
    }

    pub fn has_dofs(&self) -> bool {
        self.dofs.values().any(|c| !c.is_zero())
    }

    pub fn scale(mut self, c: &CoefPoly) -> Self {
        for v in self.dofs.values_mut() {
            *v = v.mul(c);
        }
        self.konst = self.konst.mul(c);
        self
    }

    pub fn neg(mut self) -> Self {
        for v in self.dofs.values_mut() {
            *v = std::mem::take(v).neg();
        }
        self.konst = self.konst.neg();
        self
    }

    pub fn add(mut self, other: Lin) -> Self {
        for (d, c) in other.dofs {
            let e = self.dofs.remove(&d).unwrap_or_default();
            self.dofs.insert(d, e.add(c));
        }
        self.konst = self.konst.add(other.konst);
        self.konst_span = self.konst_span.or(other.konst_span);
        self
    }

    /// The DOF terms grouped by their non-literal coefficient factor, groups and terms
    /// in order of first appearance, each group normalised so that its first
    /// coefficient is 1 (`D(2y)` and `D(y)` share a signal).
    pub fn signal_groups(&self) -> Vec<Group> {
        let mut groups: Vec<(BTreeMap<Atom, i32>, Terms)> = Vec::new();
        for (dof, poly) in &self.dofs {
            for coef in poly.monomials() {
                match groups.iter_mut().find(|(a, _)| *a == coef.atoms) {
                    Some((_, terms)) => terms.push((*dof, coef.lit)),
                    None => groups.push((coef.atoms.clone(), vec![(*dof, coef.lit)])),
                }
            }
        }
        groups
            .into_iter()
            .map(|(atoms, terms)| {
                let scale = terms[0].1;
                let terms = terms.into_iter().map(|(d, v)| (d, v / scale)).collect();
                Group { atoms, scale, terms }
            })
            .collect()
    }
}

/// Reads expressions as linear forms, given the names declared so far.
pub struct LinearReader<'a> {
    pub scope: &'a Scope,
    pub lets: &'a [LetDecl],
}

/// The error for a form that is not linear, saying why.
fn not_linear<T>(e: &Expr, why: &str) -> syn::Result<T> {
    err(
        Sp::of(&e),
        format!(
            "`{}` is not linear in the DOFs ({why}): here only a DOF, a `let` alias of a \
             linear combination, or a linear combination with parameter/literal \
             coefficients is allowed",
            show(e)
        ),
    )
}

/// The error for a coefficient function inside a linear form: the factors a signal
/// is split by are monomials, so a function must stand outside `D`.
fn function_inside<T>(e: &Expr) -> syn::Result<T> {
    err(
        Sp::of(&e),
        format!(
            "`{}`: inside `D(...)` and outputs a coefficient must be a product of \
             parameters, literals and powers of omega; write a function of coefficients \
             outside, e.g. `cos(omega * tau) * D(x, 1)` rather than \
             `D(cos(omega * tau) * x, 1)`",
            show(e)
        ),
    )
}

impl LinearReader<'_> {
    /// The linear form of `e` in the DOFs (for `D` arguments and outputs).
    pub fn read(&self, e: &Expr) -> syn::Result<Lin> {
        match e {
            Expr::Paren(p) => self.read(&p.expr),
            Expr::Group(g) => self.read(&g.expr),
            Expr::Lit(l) => Ok(Lin::konst(CoefPoly::constant(literal_value(&l.lit)?), Sp::of(&l))),
            Expr::Path(_) => {
                let Some(ident) = ident_of(e) else {
                    return err(Sp::of(&e), format!("unknown name `{}`", show(e)));
                };
                if ident == "omega" {
                    return Ok(Lin::konst(CoefPoly::atom(Atom::Omega), Sp::of(&ident)));
                }
                match self.scope.lookup(ident)? {
                    Name::Param(i) => {
                        Ok(Lin::konst(CoefPoly::atom(Atom::Param(i)), Sp::of(&ident)))
                    }
                    Name::Dof(i) => Ok(Lin::dof(i)),
                    Name::Alias(i) => self.read(&self.lets[i].expr),
                }
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => Ok(self.read(&u.expr)?.neg()),
            Expr::Binary(b) => self.binary(e, b),
            Expr::MethodCall(m) if m.method == "powi" => {
                let k = powi_exponent(m)?;
                let base = self.read(&m.receiver)?;
                if base.has_dofs() {
                    match k {
                        0 => Ok(Lin::konst(CoefPoly::constant(1.0), Sp::of(&m))),
                        1 => Ok(base),
                        _ => not_linear(e, "a power of a DOF term"),
                    }
                } else {
                    Ok(Lin::konst(base.konst.powi(k), Sp::of(&m)))
                }
            }
            Expr::Call(c) if ident_of(&c.func).is_some_and(|i| i == "D") => {
                not_linear(e, "nested derivatives are not supported")
            }
            Expr::Call(c)
                if ident_of(&c.func).is_some_and(|i| i == "cos" || i == "sin") && mentions_t(e) =>
            {
                not_linear(e, "forcing is not a DOF term")
            }
            Expr::Call(c)
                if ident_of(&c.func).is_some_and(|i| Func::named(&i.to_string()).is_some()) =>
            {
                function_inside(e)
            }
            Expr::MethodCall(m)
                if m.method == "powf" || Func::named(&m.method.to_string()).is_some() =>
            {
                function_inside(e)
            }
            other => not_linear(other, "unsupported expression"),
        }
    }

    /// `e` is `b`: sums and differences of forms, products and quotients by coefficients.
    fn binary(&self, e: &Expr, b: &syn::ExprBinary) -> syn::Result<Lin> {
        let l = self.read(&b.left)?;
        let r = self.read(&b.right)?;
        match b.op {
            BinOp::Add(_) => Ok(l.add(r)),
            BinOp::Sub(_) => Ok(l.add(r.neg())),
            BinOp::Mul(_) => match (l.has_dofs(), r.has_dofs()) {
                (true, true) => not_linear(e, "a product of DOF terms"),
                (false, _) => Ok(r.scale(&l.konst)),
                (true, false) => Ok(l.scale(&r.konst)),
            },
            BinOp::Div(_) => {
                if r.has_dofs() {
                    return not_linear(e, "division by a DOF term");
                }
                match r.konst.recip() {
                    Ok(inv) => Ok(l.scale(&inv)),
                    Err(NoRecip::Zero) => err(Sp::of(&b.right), "division by zero"),
                    Err(NoRecip::Sum) => err(
                        Sp::of(&b.right),
                        "inside `D(...)` and outputs, divide only by a product of \
                         parameters and literals",
                    ),
                }
            }
            _ => not_linear(e, "unsupported operator"),
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn scope() -> Scope {
        let mut s = Scope::default();
        let id = |n: &str| syn::Ident::new(n, proc_macro2::Span::call_site());
        s.declare(&id("a"), Name::Param(0)).unwrap();
        s.declare(&id("x"), Name::Dof(0)).unwrap();
        s.declare(&id("y"), Name::Dof(1)).unwrap();
        s
    }

    fn read(src: &str) -> syn::Result<Lin> {
        let scope = scope();
        LinearReader { scope: &scope, lets: &[] }.read(&syn::parse_str(src).unwrap())
    }

    #[test]
    fn signal_groups_pull_coefficient_factors_out() {
        // 2a x - 2a y + 3 x = 2a (x - y) + 3 (x).
        let groups = read("2.0 * a * x - (2.0 * a) * y + 3.0 * x").unwrap().signal_groups();
        let a1 = BTreeMap::from([(Atom::Param(0), 1)]);
        assert_eq!(
            groups,
            [
                Group { atoms: a1, scale: 2.0, terms: vec![(0, 1.0), (1, -1.0)] },
                Group { atoms: BTreeMap::new(), scale: 3.0, terms: vec![(0, 1.0)] },
            ]
        );
        // A literal multiple of a form has the same terms: one signal.
        let g1 = read("x - y").unwrap().signal_groups();
        let g2 = read("-(2.0 * y - 2.0 * x) / 4.0").unwrap().signal_groups();
        assert_eq!(g1[0].terms, g2[0].terms);
        assert_eq!((g1[0].scale, g2[0].scale), (1.0, 0.5));
    }

    #[test]
    fn constants_cancel_and_nonlinear_terms_are_rejected() {
        let l = read("(x + 1.0) - 1.0").unwrap();
        assert!(l.konst.is_zero() && l.has_dofs());
        assert!(!read("x - x").unwrap().has_dofs());
        assert!(read("x / a.powi(2)").unwrap().has_dofs());
        for bad in [
            "x * y",
            "x.powi(2)",
            "x / y",
            "x / (a + 1.0)",
            "cos(omega * t)",
            "cos(omega * a) * x",
            "a.sqrt() * x",
            "x * a.powf(0.5)",
        ] {
            assert!(read(bad).is_err(), "{bad}");
        }
        let e = read("x / (a - a)").unwrap_err().to_string();
        assert_eq!(e, "division by zero");
    }
}

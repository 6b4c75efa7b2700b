//! Coefficient expressions: smooth functions (`sqrt`, `exp`, `ln`, `sin`, `cos`, `tan`,
//! `abs`), real powers `.powf(q)` and negative integer powers of parameters, literals
//! and Ω. They never take a DOF or forcing (the residual stays polynomial in the
//! signals), and each one that can fail to be finite (a function, a real power, a
//! quotient) is recorded as a [`Check`] for the generated `check_coefficients`.

use super::diag::{err, Sp};
use super::lower::{Info, Lower};
use super::syntax::{show, strip};
use super::tree::{Check, Func, Kink, Node};
use syn::Expr;

impl Lower<'_> {
    /// `f(arg)` (written `f(arg)` or `arg.f()`, the whole call `e`): `arg` must be a
    /// coefficient.
    pub(super) fn function(&mut self, e: &Expr, f: Func, arg: &Expr) -> syn::Result<(Node, Info)> {
        let node = Node::Func(f, Box::new(self.coefficient(e, arg)?));
        // sin, cos and abs of a finite number are finite: only the others can fail.
        if matches!(f, Func::Sin | Func::Cos | Func::Abs) {
            return Ok((node, Info::default()));
        }
        self.checked(e, node)
    }

    /// `base.powf(exponent)` (the whole call `e`), both coefficients.
    pub(super) fn powf(
        &mut self,
        e: &Expr,
        base: &Expr,
        args: &[&Expr],
    ) -> syn::Result<(Node, Info)> {
        let [exponent] = args else {
            return err(Sp::of(&e), "`.powf(q)` takes one argument, a coefficient");
        };
        let b = self.coefficient(e, base)?;
        let q = self.coefficient(e, exponent)?;
        self.checked(e, Node::Powf(Box::new(b), Box::new(q)))
    }

    /// `base.powi(-k)` (the whole call `e`) of a coefficient: `1 / base^k`.
    pub(super) fn negative_powi(
        &mut self,
        e: &Expr,
        base: &Expr,
        k: u32,
    ) -> syn::Result<(Node, Info)> {
        let (b, info) = self.value(base)?;
        if info.dof.is_some() || info.forcing.is_some() {
            return err(
                Sp::of(&e),
                format!(
                    "`{}`: a negative power is a division, allowed for coefficients \
                     (parameters, literals, omega) only; a DOF term or forcing needs \
                     `.powi(k)` with a literal k >= 0",
                    show(e)
                ),
            );
        }
        self.checked(e, Node::Div(Box::new(Node::Lit(1.0)), Box::new(Node::Powi(Box::new(b), k))))
    }

    /// A division `whole` = `node` by `d` (lowered to `dn`) may divide by zero: check
    /// the quotient if it is a coefficient (`left_coefficient`), else `1 / d`.
    pub(super) fn check_division(
        &mut self,
        whole: &Expr,
        d: &Expr,
        node: &Node,
        dn: &Node,
        left_coefficient: bool,
    ) {
        if matches!(dn, Node::Lit(_)) {
            return;
        }
        if left_coefficient {
            self.check(show(whole), node);
        } else {
            let recip = Node::Div(Box::new(Node::Lit(1.0)), Box::new(dn.clone()));
            let text = match strip(d) {
                d @ (Expr::Path(_) | Expr::Lit(_) | Expr::MethodCall(_) | Expr::Call(_)) => {
                    format!("1 / {}", show(d))
                }
                d => format!("1 / ({})", show(d)),
            };
            self.check(text, &recip);
        }
    }

    /// `arg`, an operand of the coefficient function `e`, lowered: it must hold neither
    /// DOFs nor forcing.
    fn coefficient(&mut self, e: &Expr, arg: &Expr) -> syn::Result<Node> {
        let (node, info) = self.value(arg)?;
        if info.dof.is_some() {
            return err(
                Sp::of(&e),
                format!(
                    "`{}` is not allowed: `{}` depends on the DOFs, and a function of a DOF \
                     is not polynomial; {} apply to coefficients (parameters, literals, \
                     omega) only, `cos`/`sin` also give forcing `cos(k * omega * t)` / \
                     `sin(k * omega * t)`, and the non-smooth {} to anything",
                    show(e),
                    show(arg),
                    Func::list(),
                    Kink::list()
                ),
            );
        }
        if let Some(at) = info.forcing {
            return err(
                at,
                format!(
                    "`{}` is not allowed: a function of forcing is not a sum of harmonics; \
                     {} apply to coefficients (parameters, literals, omega) only",
                    show(e),
                    Func::list()
                ),
            );
        }
        Ok(node)
    }

    /// `node`, the coefficient `e`, recorded for the run-time check.
    fn checked(&mut self, e: &Expr, node: Node) -> syn::Result<(Node, Info)> {
        self.check(show(e), &node);
        Ok((node, Info::default()))
    }

    /// Record `node` (a coefficient) for the run-time check, aliases expanded.
    fn check(&mut self, text: String, node: &Node) {
        let node = self.expand(node);
        self.checks.push((self.lowering_alias, Check { text, node }));
    }

    /// `n` with every alias replaced by its tree (for coefficients, which hold no
    /// signals, so the check needs nothing but parameters and Ω).
    fn expand(&self, n: &Node) -> Node {
        match n {
            Node::Alias(i) => self.expand(&self.aliases[*i].0),
            other => {
                let mut out = other.clone();
                out.for_each_child_mut(|c| *c = self.expand(c));
                out
            }
        }
    }
}

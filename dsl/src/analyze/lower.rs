//! Lowering: each equation and alias, read in value context, becomes a [`Node`] tree
//! over numbered signals, with the checks that keep the model polynomial in the signals
//! and its time dependence `cos/sin(k * omega * t)` times coefficients or DOF terms
//! (forcing, and parametric excitation). Coefficient functions are read by
//! `function`. Signals are interned as they are met (`D(e, n)` splits `e` through
//! `Lin::signal_groups`).

use super::coeff::Atom;
use super::diag::{err, Sp};
use super::forcing::harmonic;
use super::linear::{Group, LinearReader};
use super::scope::{Name, Scope};
use super::syntax::{ident_of, mentions_t, negative_powi_exponent, powi_exponent, show, strip};
use super::tree::{Alias, Check, Func, Kink, Node, OrderKey, SignalKey, Trig};
use crate::parse::{literal_value, Equation, LetDecl};
use quote::ToTokens;
use std::collections::BTreeMap;
use syn::{BinOp, Expr, Lit, UnOp};

/// What the polynomial allows, repeated in several messages.
const ALLOWED: &str = "allowed are parameters, DOFs, `let` aliases, numeric literals, `omega`, \
     `+ - *`, division by coefficients, `.powi(k)` with a literal k >= 0, `D(e, n)`, \
     forcing `cos(k * omega * t)` / `sin(k * omega * t)`, functions of coefficients \
     (`sqrt`, `exp`, `ln`, `sin`, `cos`, `tan`, `.powf(q)`), and the non-smooth \
     `max(a, b)`, `min(a, b)`, `abs(e)`, `sign(e)` of anything";

/// Where a subexpression holds a DOF-dependent and a forcing term, if it does: what the
/// checks of products, quotients and powers look at, and where their messages point.
#[derive(Debug, Clone, Copy, Default)]
pub(super) struct Info {
    pub(super) dof: Option<Sp>,
    pub(super) forcing: Option<Sp>,
}

/// The signals met, the aliases lowered (none marked used yet), and the coefficient
/// checks with the alias each came from (`None`: an equation).
pub struct Lowered {
    pub signals: Vec<SignalKey>,
    pub aliases: Vec<Alias>,
    pub checks: Vec<(Option<usize>, Check)>,
}

/// The lowering of one model: the names declared so far, the signals met so far, the
/// lowered aliases, and the coefficient checks (with the alias they came from).
pub struct Lower<'a> {
    lets: &'a [LetDecl],
    scope: Scope,
    signals: Vec<SignalKey>,
    pub(super) aliases: Vec<(Node, Info)>,
    pub(super) checks: Vec<(Option<usize>, Check)>,
    /// The alias being lowered, if any (checks found in it count only if it is used).
    pub(super) lowering_alias: Option<usize>,
    /// Lower a use of an alias as its definition (in an output, whose signals are
    /// numbered apart from the residual's).
    expand_aliases: bool,
}

impl<'a> Lower<'a> {
    /// Lowering with `scope` (parameters and DOFs declared); aliases come from `lets`.
    pub fn new(lets: &'a [LetDecl], scope: Scope) -> Self {
        Lower {
            lets,
            scope,
            signals: Vec::new(),
            aliases: Vec::new(),
            checks: Vec::new(),
            lowering_alias: None,
            expand_aliases: false,
        }
    }

    /// An output's tree, over the output signals `signals` (met signals are added to
    /// it) with every alias expanded. Its coefficient checks are not kept: the solvers
    /// check what the residual needs, and an output that is not finite shows as such.
    pub fn output(&mut self, e: &Expr, signals: &mut Vec<SignalKey>) -> syn::Result<Node> {
        std::mem::swap(&mut self.signals, signals);
        let checks = self.checks.len();
        self.expand_aliases = true;
        let lowered = self.value(e);
        self.expand_aliases = false;
        self.checks.truncate(checks);
        std::mem::swap(&mut self.signals, signals);
        Ok(lowered?.0)
    }

    /// Lower alias `i`, then declare its name (so it sees only earlier names).
    pub fn alias(&mut self, i: usize) -> syn::Result<()> {
        let lets = self.lets;
        let l = &lets[i];
        self.lowering_alias = Some(i);
        let converted = self.value(&l.expr);
        self.lowering_alias = None;
        let converted = converted?;
        self.aliases.push(converted);
        self.scope.declare(&l.name, Name::Alias(i))
    }

    /// The residual tree `lhs - rhs` of an equation, which must involve some DOF.
    pub fn equation(&mut self, eq: &Equation) -> syn::Result<Node> {
        let (l, li) = self.value(&eq.lhs)?;
        let (r, ri) = self.value(&eq.rhs)?;
        if li.dof.is_none() && ri.dof.is_none() {
            return err(
                Sp::of(&eq.lhs),
                format!(
                    "equation `{} = {}` does not involve any DOF",
                    show(&eq.lhs),
                    show(&eq.rhs)
                ),
            );
        }
        Ok(match r {
            Node::Lit(0.0) => l,
            r => Node::Sub(Box::new(l), Box::new(r)),
        })
    }

    /// What was lowered besides the equations.
    pub fn finish(self) -> Lowered {
        let aliases = self.aliases.into_iter().map(|(node, _)| Alias { node, used: false });
        Lowered { signals: self.signals, aliases: aliases.collect(), checks: self.checks }
    }

    /// Reads linear forms with the names declared so far.
    pub fn linear(&self) -> LinearReader<'_> {
        LinearReader { scope: &self.scope, lets: self.lets }
    }

    fn signal(&mut self, key: SignalKey) -> usize {
        if let Some(i) = self.signals.iter().position(|s| *s == key) {
            return i;
        }
        self.signals.push(key);
        self.signals.len() - 1
    }

    /// `D(e, n)`: split the linear form of `e` into signals with literal coefficients,
    /// parameter factors pulled outside.
    fn derivative(&mut self, c: &syn::ExprCall) -> syn::Result<(Node, Info)> {
        if c.args.len() != 2 {
            return err(
                Sp::of(&c),
                "`D` takes two arguments: `D(e, n)` with e linear in the DOFs and n an \
                 integer literal or a parameter name",
            );
        }
        let (e, n) = (&c.args[0], &c.args[1]);
        if let Some((at, k)) = kink_in(e) {
            return err(
                at,
                format!(
                    "`{}` is not allowed inside `D(e, n)`: e must be linear in the DOFs; a \
                     non-smooth function of a derivative is written outside it, e.g. \
                     `abs(D(y, 1))` or `max(0.0, D(y, 1))`",
                    k.usage()
                ),
            );
        }
        let order = self.order(n)?;
        let lin = self.linear().read(e)?;
        if !lin.konst.is_zero() {
            return err(
                lin.konst_span.unwrap_or_else(|| Sp::of(&e)),
                format!(
                    "`D(e, n)` needs e to be a linear combination of DOFs without a constant \
                     term; `{}` has one",
                    show(e)
                ),
            );
        }
        let mut node: Option<Node> = None;
        for Group { atoms, scale, terms } in lin.signal_groups() {
            let s = Node::Signal(self.signal(SignalKey { terms, order }));
            let term = scaled(s, &atoms, scale);
            node = Some(match node {
                Some(n) => Node::Add(Box::new(n), Box::new(term)),
                None => term,
            });
        }
        let Some(node) = node else {
            return err(Sp::of(&e), format!("`D({}, ...)` has no DOF term", show(e)));
        };
        Ok((node, Info { dof: Some(Sp::of(&c)), forcing: None }))
    }

    /// The order `n` of `D(e, n)`: an integer literal or a parameter.
    fn order(&self, n: &Expr) -> syn::Result<OrderKey> {
        let order_msg = "the order of `D(e, n)` must be an integer literal (0, 1, 2, ...) or a \
                         parameter name (a fractional order)";
        match strip(n) {
            Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => match i.base10_parse::<u32>() {
                Ok(k) => Ok(OrderKey::Int(k)),
                Err(_) => err(Sp::of(&i), order_msg),
            },
            Expr::Lit(syn::ExprLit { lit: Lit::Float(f), .. }) => err(
                Sp::of(&f),
                format!(
                    "{order_msg}; for a fractional order declare a parameter, e.g. \
                     `p = {}`, and write `D(e, p)`",
                    f.base10_digits()
                ),
            ),
            other => match ident_of(other) {
                Some(ident) if ident == "omega" => err(
                    Sp::of(&ident),
                    format!(
                        "{order_msg}; `omega` is not: the order of a signal is fixed while \
                         omega varies along a curve"
                    ),
                ),
                Some(ident) => match self.scope.lookup(ident)? {
                    Name::Param(i) => Ok(OrderKey::Param(i)),
                    name => {
                        err(Sp::of(&ident), format!("{order_msg}; `{ident}` is {}", name.kind()))
                    }
                },
                None => err(Sp::of(&other), order_msg),
            },
        }
    }

    /// Convert an expression in value context, checking that it is polynomial.
    pub(super) fn value(&mut self, e: &Expr) -> syn::Result<(Node, Info)> {
        match e {
            Expr::Paren(p) => self.value(&p.expr),
            Expr::Group(g) => self.value(&g.expr),
            Expr::Lit(l) => Ok((Node::Lit(literal_value(&l.lit)?), Info::default())),
            Expr::Path(_) => self.name(e),
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                let (n, i) = self.value(&u.expr)?;
                Ok((Node::Neg(Box::new(n)), i))
            }
            Expr::Binary(b) => self.binary(b),
            Expr::MethodCall(m) => self.method(e, m),
            Expr::Call(c) => self.call(e, c),
            other => err(
                Sp::of(&other),
                format!("`{}` is not allowed in oscillator!: {ALLOWED}", show(other)),
            ),
        }
    }

    /// A name in value context: `omega`, a parameter, a DOF (its signal of order 0) or
    /// an alias.
    fn name(&mut self, e: &Expr) -> syn::Result<(Node, Info)> {
        let Some(ident) = ident_of(e) else {
            return err(
                Sp::of(&e),
                format!("unknown name `{}`: use plain names declared above", show(e)),
            );
        };
        if ident == "omega" {
            return Ok((Node::Omega, Info::default()));
        }
        match self.scope.lookup(ident)? {
            Name::Param(i) => Ok((Node::Param(i), Info::default())),
            Name::Dof(i) => {
                let s = self.signal(SignalKey { terms: vec![(i, 1.0)], order: OrderKey::Int(0) });
                Ok((Node::Signal(s), Info { dof: Some(Sp::of(&ident)), forcing: None }))
            }
            Name::Alias(i) if self.expand_aliases => {
                let lets = self.lets;
                self.value(&lets[i].expr)
            }
            Name::Alias(i) => {
                let info = self.aliases[i].1;
                // Point messages at this use, not at the alias's definition.
                let at = Sp::of(&ident);
                let info = Info { dof: info.dof.map(|_| at), forcing: info.forcing.map(|_| at) };
                Ok((Node::Alias(i), info))
            }
        }
    }

    /// `e` is `m`: `.powi(k)`, forcing written `(k * omega * t).cos()`, or a function
    /// of a coefficient (`omega.sqrt()`, `tau.powf(0.5)`, `omega.powi(-1)`).
    fn method(&mut self, e: &Expr, m: &syn::ExprMethodCall) -> syn::Result<(Node, Info)> {
        let name = m.method.to_string();
        if name == "powi" {
            if let Some(k) = negative_powi_exponent(m) {
                return self.negative_powi(e, &m.receiver, k);
            }
            let k = powi_exponent(m)?;
            let (n, i) = self.value(&m.receiver)?;
            if k >= 2 {
                if let Some(f) = i.forcing {
                    return err(
                        f,
                        format!(
                            "`{}` raises forcing to a power: forcing may only be \
                             multiplied by coefficients; write products of harmonics \
                             as a sum of harmonics",
                            show(e)
                        ),
                    );
                }
            }
            if k == 0 {
                return Ok((Node::Lit(1.0), Info::default()));
            }
            return Ok((Node::Powi(Box::new(n), k), i));
        }
        if (name == "cos" || name == "sin") && m.args.is_empty() && mentions_t(&m.receiver) {
            let k = harmonic(&m.receiver, Sp::of(&e), &show(e))?;
            return self.forcing(&name, k, Sp::of(&e));
        }
        if name == "powf" {
            let args: Vec<&Expr> = m.args.iter().collect();
            return self.powf(e, &m.receiver, &args);
        }
        if let Some(k) = Kink::named(&name).filter(|k| k.arity() == m.args.len() + 1) {
            let mut args = vec![&*m.receiver];
            args.extend(m.args.iter());
            return self.kink(e, k, &args);
        }
        match Func::named(&name) {
            Some(f) if m.args.is_empty() => self.function(e, f, &m.receiver),
            _ => err(
                Sp::of(&m.method),
                format!(
                    "`.{name}(...)` is not allowed: DOF terms take only `.powi(k)` with an \
                     integer literal k >= 0 (which keeps the model polynomial); \
                     coefficients also take {}",
                    Func::list()
                ),
            ),
        }
    }

    /// `e` is `c`: `D(e, n)`, forcing `cos/sin(k * omega * t)`, or a function of a
    /// coefficient (`cos(omega * tau)`, `sqrt(k / m)`).
    fn call(&mut self, e: &Expr, c: &syn::ExprCall) -> syn::Result<(Node, Info)> {
        let Some(f) = ident_of(&c.func) else {
            return err(Sp::of(&c.func), format!("unsupported function: {ALLOWED}"));
        };
        let fname = f.to_string();
        if let Some(k) = Kink::named(&fname) {
            let args: Vec<&Expr> = c.args.iter().collect();
            return self.kink(e, k, &args);
        }
        match fname.as_str() {
            "D" => self.derivative(c),
            _ => match Func::named(&fname) {
                Some(_) if c.args.len() != 1 => {
                    err(Sp::of(&c), format!("`{fname}` takes one argument"))
                }
                Some(func) => {
                    let arg = &c.args[0];
                    if matches!(func, Func::Cos | Func::Sin) && mentions_t(arg) {
                        let k = harmonic(arg, Sp::of(&c), &show(e))?;
                        self.forcing(&fname, k, Sp::of(&c))
                    } else {
                        self.function(e, func, arg)
                    }
                }
                None => err(
                    Sp::of(&f),
                    format!(
                        "unknown function `{fname}`: the functions are `D(e, n)`, forcing \
                         `cos(k * omega * t)` / `sin(k * omega * t)`, {} and `abs` of \
                         coefficients, and the non-smooth {} of anything",
                        Func::list(),
                        Kink::list()
                    ),
                ),
            },
        }
    }

    /// A non-smooth function `k` of `args` (the whole call `e`). Of coefficients only it
    /// is a coefficient (`abs(k)` as before, `sign(k - 1.0)`); of anything with DOFs or
    /// forcing it is a kink of the residual.
    fn kink(&mut self, e: &Expr, k: Kink, args: &[&Expr]) -> syn::Result<(Node, Info)> {
        if args.len() != k.arity() {
            let count = if k.arity() == 1 { "one argument" } else { "two arguments" };
            return err(Sp::of(&e), format!("`{}` takes {count}: `{}`", k.name(), k.usage()));
        }
        let mut nodes = Vec::with_capacity(args.len());
        let mut info = Info::default();
        for a in args {
            let (n, i) = self.value(a)?;
            info = Info { dof: info.dof.or(i.dof), forcing: info.forcing.or(i.forcing) };
            nodes.push(n);
        }
        if k == Kink::Abs && info.dof.is_none() && info.forcing.is_none() {
            // A coefficient: the smooth-function path, which records its check.
            return self.function(e, Func::Abs, args[0]);
        }
        Ok((Node::Kink(k, nodes), info))
    }

    fn forcing(&self, name: &str, k: u32, span: Sp) -> syn::Result<(Node, Info)> {
        let trig = if name == "cos" { Trig::Cos } else { Trig::Sin };
        Ok((Node::Forcing(trig, k), Info { dof: None, forcing: Some(span) }))
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> syn::Result<(Node, Info)> {
        let (l, li) = self.value(&b.left)?;
        let (r, ri) = self.value(&b.right)?;
        let sum = Info { dof: li.dof.or(ri.dof), forcing: li.forcing.or(ri.forcing) };
        let (l, r) = (Box::new(l), Box::new(r));
        match b.op {
            BinOp::Add(_) => Ok((Node::Add(l, r), sum)),
            BinOp::Sub(_) => Ok((Node::Sub(l, r), sum)),
            // Forcing times a DOF term is parametric excitation (a stiffness or damping
            // that varies over the period): still polynomial in the signals.
            BinOp::Mul(_) => {
                if let (Some(f), Some(_)) = (li.forcing, ri.forcing) {
                    return err(
                        f,
                        format!(
                            "product of two forcing terms in `{}`: write it as a sum of \
                             harmonics `cos(k * omega * t)` / `sin(k * omega * t)`",
                            show(&Expr::Binary(b.clone()))
                        ),
                    );
                }
                Ok((Node::Mul(l, r), sum))
            }
            BinOp::Div(_) => {
                if ri.dof.is_some() || ri.forcing.is_some() {
                    return err(
                        Sp::of(&b.right),
                        format!(
                            "division by `{}` is not allowed: divide only by coefficients \
                             (parameters, literals, omega) to keep the model polynomial",
                            show(&b.right)
                        ),
                    );
                }
                if matches!(*r, Node::Lit(v) if v == 0.0) {
                    return err(Sp::of(&b.right), "division by zero");
                }
                let divisor = (*r).clone();
                let node = Node::Div(l, r);
                let left_coefficient = li.dof.is_none() && li.forcing.is_none();
                let whole = Expr::Binary(b.clone());
                self.check_division(&whole, &b.right, &node, &divisor, left_coefficient);
                Ok((node, sum))
            }
            BinOp::BitXor(_) => err(
                Sp::of(&b.op),
                format!(
                    "`^` is XOR in Rust, not a power (and it binds looser than `+` and `*`): \
                     write `base.powi(k)`, e.g. `y.powi({})`",
                    show(&b.right)
                ),
            ),
            _ => err(
                Sp::of(&b.op),
                format!("operator `{}` is not allowed: {ALLOWED}", b.op.to_token_stream()),
            ),
        }
    }
}

/// The first non-smooth function called in `e`, with where it is written.
fn kink_in(e: &Expr) -> Option<(Sp, Kink)> {
    match e {
        Expr::Paren(p) => kink_in(&p.expr),
        Expr::Group(g) => kink_in(&g.expr),
        Expr::Unary(u) => kink_in(&u.expr),
        Expr::Binary(b) => kink_in(&b.left).or_else(|| kink_in(&b.right)),
        Expr::Call(c) => {
            let k = ident_of(&c.func).and_then(|f| Kink::named(&f.to_string()));
            match k {
                Some(k) => Some((Sp::of(&c), k)),
                None => c.args.iter().find_map(kink_in),
            }
        }
        Expr::MethodCall(m) => match Kink::named(&m.method.to_string()) {
            Some(k) if k.arity() == m.args.len() + 1 => Some((Sp::of(&m), k)),
            _ => kink_in(&m.receiver).or_else(|| m.args.iter().find_map(kink_in)),
        },
        _ => None,
    }
}

/// `scale · Π atom^power · s` as a tree: positive powers multiply, negative ones divide,
/// and a scale of ±1 writes no literal.
fn scaled(s: Node, atoms: &BTreeMap<Atom, i32>, scale: f64) -> Node {
    let mut factor: Option<Node> = None;
    let mut divisor: Option<Node> = None;
    for (atom, pow) in atoms {
        let base = match atom {
            Atom::Param(i) => Node::Param(*i),
            Atom::Omega => Node::Omega,
        };
        let p = Node::Powi(Box::new(base), pow.unsigned_abs());
        let slot = if *pow > 0 { &mut factor } else { &mut divisor };
        *slot = Some(match slot.take() {
            Some(f) => Node::Mul(Box::new(f), Box::new(p)),
            None => p,
        });
    }
    let mut term = match factor {
        Some(f) => Node::Mul(Box::new(f), Box::new(s)),
        None => s,
    };
    if let Some(d) = divisor {
        term = Node::Div(Box::new(term), Box::new(d));
    }
    if scale == -1.0 {
        term = Node::Neg(Box::new(term));
    } else if scale != 1.0 {
        term = Node::Mul(Box::new(Node::Lit(scale)), Box::new(term));
    }
    term
}

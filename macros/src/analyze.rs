//! Symbolic analysis: resolve names, expand `let` aliases, check that every equation is
//! polynomial in the signals with forcing only as `cos/sin(k * omega * t)` times
//! coefficients, and collect the distinct signals.
//!
//! Every rejection is a `syn::Error` spanned on the offending token, with a message that
//! says what is allowed instead.

use crate::parse::{literal_value, ModelDef};
use proc_macro2::{Span, TokenStream};
use quote::ToTokens;
use std::collections::{BTreeMap, BTreeSet, HashMap};
use syn::{BinOp, Expr, Lit, UnOp};

/// Names the DSL keeps for itself.
const RESERVED: [&str; 3] = ["omega", "t", "D"];

/// What the polynomial allows, repeated in several messages.
const ALLOWED: &str = "allowed are parameters, DOFs, `let` aliases, numeric literals, `omega`, \
     `+ - *`, division by coefficients, `.powi(k)` with a literal k >= 0, `D(e, n)`, and \
     forcing `cos(k * omega * t)` / `sin(k * omega * t)`";

/// A coefficient factor that is not a literal.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Atom {
    Param(usize),
    Omega,
}

/// A coefficient monomial: `lit * Π atom^power` (powers may be negative).
#[derive(Debug, Clone, PartialEq)]
struct Coef {
    lit: f64,
    atoms: BTreeMap<Atom, i32>,
}

/// A sum of coefficient monomials, like terms merged.
#[derive(Debug, Clone, Default, PartialEq)]
struct CoefPoly(Vec<Coef>);

impl CoefPoly {
    fn constant(v: f64) -> Self {
        CoefPoly(vec![Coef { lit: v, atoms: BTreeMap::new() }]).clean()
    }
    fn atom(a: Atom) -> Self {
        CoefPoly(vec![Coef { lit: 1.0, atoms: BTreeMap::from([(a, 1)]) }])
    }
    fn clean(self) -> Self {
        let mut out: Vec<Coef> = Vec::new();
        for c in self.0 {
            match out.iter_mut().find(|o| o.atoms == c.atoms) {
                Some(o) => o.lit += c.lit,
                None => out.push(c),
            }
        }
        out.retain(|c| c.lit != 0.0);
        CoefPoly(out)
    }
    fn add(mut self, other: CoefPoly) -> Self {
        self.0.extend(other.0);
        self.clean()
    }
    fn neg(self) -> Self {
        CoefPoly(self.0.into_iter().map(|c| Coef { lit: -c.lit, ..c }).collect())
    }
    fn mul(&self, other: &CoefPoly) -> Self {
        let mut out = Vec::new();
        for a in &self.0 {
            for b in &other.0 {
                let mut atoms = a.atoms.clone();
                for (k, v) in &b.atoms {
                    *atoms.entry(*k).or_insert(0) += v;
                }
                atoms.retain(|_, v| *v != 0);
                out.push(Coef { lit: a.lit * b.lit, atoms });
            }
        }
        CoefPoly(out).clean()
    }
    fn is_zero(&self) -> bool {
        self.0.is_empty()
    }
}

/// A linear form in the DOFs with coefficient polynomials, plus a constant part.
#[derive(Debug, Clone, Default)]
struct Lin {
    dofs: BTreeMap<usize, CoefPoly>,
    konst: CoefPoly,
    /// Where a constant term came from (for the error message).
    konst_span: Option<Sp>,
}

impl Lin {
    fn has_dofs(&self) -> bool {
        self.dofs.values().any(|c| !c.is_zero())
    }
    fn scale(mut self, c: &CoefPoly) -> Self {
        for v in self.dofs.values_mut() {
            *v = v.mul(c);
        }
        self.konst = self.konst.mul(c);
        self
    }
    fn add(mut self, other: Lin, sign: f64) -> Self {
        for (d, c) in other.dofs {
            let c = if sign < 0.0 { c.neg() } else { c };
            let e = self.dofs.remove(&d).unwrap_or_default();
            self.dofs.insert(d, e.add(c));
        }
        let k = if sign < 0.0 { other.konst.neg() } else { other.konst };
        self.konst = self.konst.add(k);
        self.konst_span = self.konst_span.or(other.konst_span);
        self
    }
}

/// DOF terms sharing one non-literal coefficient factor (atoms with powers).
type Group = (BTreeMap<Atom, i32>, Vec<(usize, f64)>);

/// The derivative order of a signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OrderKey {
    Int(u32),
    Param(usize),
}

/// `D^order (Σ coef · x_dof)`, literal coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalKey {
    pub terms: Vec<(usize, f64)>,
    pub order: OrderKey,
}

/// Forcing functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Trig {
    Cos,
    Sin,
}

/// The resolved expression tree the residual is generated from.
#[derive(Debug, Clone)]
pub enum Node {
    Lit(f64),
    Param(usize),
    Omega,
    Signal(usize),
    Alias(usize),
    Forcing(Trig, u32),
    Add(Box<Node>, Box<Node>),
    Sub(Box<Node>, Box<Node>),
    Mul(Box<Node>, Box<Node>),
    Div(Box<Node>, Box<Node>),
    Neg(Box<Node>),
    Powi(Box<Node>, u32),
}

/// What a subexpression is, for the polynomial checks.
#[derive(Debug, Clone, Copy, Default)]
pub struct Info {
    /// Polynomial degree in the signals.
    pub degree: u32,
    /// Span of a DOF-dependent subterm, if any.
    dof: Option<Sp>,
    /// Span of a forcing subterm, if any.
    forcing: Option<Sp>,
    /// Highest forcing harmonic inside.
    pub max_k: u32,
}

/// How a name resolves.
#[derive(Debug, Clone, Copy)]
enum Name {
    Param(usize),
    Dof(usize),
    Alias(usize),
}

impl Name {
    fn kind(self) -> &'static str {
        match self {
            Name::Param(_) => "a parameter",
            Name::Dof(_) => "a DOF",
            Name::Alias(_) => "a `let` alias",
        }
    }
}

/// The analysed model.
pub struct Analysis {
    pub signals: Vec<SignalKey>,
    /// Converted aliases (declaration order) and whether the residual uses them.
    pub aliases: Vec<(Node, Info, bool)>,
    /// One residual tree per equation (`lhs - rhs`).
    pub equations: Vec<Node>,
    /// `(name, terms)` per output.
    pub outputs: Vec<(String, Vec<(usize, f64)>)>,
    pub degree: u32,
    pub max_k: u32,
}

struct Ctx<'a> {
    def: &'a ModelDef,
    names: HashMap<String, Name>,
    signals: Vec<SignalKey>,
    aliases: Vec<(Node, Info, bool)>,
}

/// A source range: the first and last token of the offending code. (`Span::join` is
/// nightly-only; `syn::Error::new_spanned` underlines from the first to the last token.)
#[derive(Debug, Clone, Copy)]
pub struct Sp(Span, Span);

impl Sp {
    /// The range covered by `t`.
    pub fn of(t: &impl ToTokens) -> Sp {
        let mut it = t.to_token_stream().into_iter();
        let first = it.next().map_or_else(Span::call_site, |t| t.span());
        let last = it.last().map_or(first, |t| t.span());
        Sp(first, last)
    }
}

impl From<Span> for Sp {
    fn from(s: Span) -> Sp {
        Sp(s, s)
    }
}

impl ToTokens for Sp {
    fn to_tokens(&self, tokens: &mut TokenStream) {
        tokens.extend([
            proc_macro2::TokenTree::Ident(proc_macro2::Ident::new("a", self.0)),
            proc_macro2::TokenTree::Ident(proc_macro2::Ident::new("b", self.1)),
        ]);
    }
}

fn err<T>(span: impl Into<Sp>, msg: impl std::fmt::Display) -> syn::Result<T> {
    Err(syn::Error::new_spanned(span.into(), msg))
}

/// Source text of an expression, for messages and `equations()`.
pub fn show(e: &Expr) -> String {
    match e {
        Expr::Binary(b) => {
            format!("{} {} {}", show(&b.left), b.op.to_token_stream(), show(&b.right))
        }
        Expr::Unary(u) => format!("{}{}", u.op.to_token_stream(), show(&u.expr)),
        Expr::Paren(p) => format!("({})", show(&p.expr)),
        Expr::Group(g) => show(&g.expr),
        Expr::Lit(l) => l.lit.to_token_stream().to_string(),
        Expr::Path(p) => p.path.to_token_stream().to_string().replace(' ', ""),
        Expr::Call(c) => {
            let args: Vec<String> = c.args.iter().map(show).collect();
            format!("{}({})", show(&c.func), args.join(", "))
        }
        Expr::MethodCall(m) => {
            let args: Vec<String> = m.args.iter().map(show).collect();
            format!("{}.{}({})", show(&m.receiver), m.method, args.join(", "))
        }
        Expr::Assign(a) => format!("{} = {}", show(&a.left), show(&a.right)),
        other => other.to_token_stream().to_string(),
    }
}

/// Strip parentheses and invisible groups.
fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        other => other,
    }
}

/// The single identifier of a path expression, if it is one.
fn ident_of(e: &Expr) -> Option<&syn::Ident> {
    match strip(e) {
        Expr::Path(p) if p.qself.is_none() => p.path.get_ident(),
        _ => None,
    }
}

/// `k` of `cos(k * omega * t)`, or an error saying what forcing may look like.
fn harmonic(arg: &Expr, call_span: Sp, call_text: &str) -> syn::Result<u32> {
    let bad = || {
        err(
            call_span,
            format!(
                "`{call_text}` is not allowed: `cos`/`sin` may only be forcing \
                 `cos(k * omega * t)` / `sin(k * omega * t)` with k a positive integer \
                 literal (`k *` optional), times coefficients; a trigonometric function of \
                 DOFs is not polynomial, and a phase shift is written \
                 `A * cos(omega * t) + B * sin(omega * t)`"
            ),
        )
    };
    let is = |e: &Expr, name: &str| ident_of(e).is_some_and(|i| i == name);
    let omega_t = |e: &Expr| match strip(e) {
        Expr::Binary(b) if matches!(b.op, BinOp::Mul(_)) => {
            is(&b.left, "omega") && is(&b.right, "t")
        }
        _ => false,
    };
    let literal_k = |e: &Expr| -> syn::Result<u32> {
        let e = strip(e);
        let not_int = |span: Sp, text: String| {
            err(
                span,
                format!(
                    "the forcing harmonic must be a positive integer literal (1, 2, 3, ...), \
                     not `{text}`: only integer multiples of omega keep the response periodic \
                     with period 2π/omega"
                ),
            )
        };
        match e {
            Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => match i.base10_parse::<u32>() {
                Ok(k) if k > 0 => Ok(k),
                _ => not_int(Sp::of(&i), i.base10_digits().to_string()),
            },
            Expr::Lit(syn::ExprLit { lit: Lit::Float(f), .. }) => {
                let v: f64 = f.base10_parse()?;
                if v.fract() == 0.0 && v >= 1.0 && v <= u32::MAX as f64 {
                    Ok(v as u32)
                } else {
                    not_int(Sp::of(&f), f.base10_digits().to_string())
                }
            }
            other => not_int(Sp::of(&other), show(other)),
        }
    };
    let arg = strip(arg);
    if omega_t(arg) {
        return Ok(1);
    }
    if let Expr::Binary(b) = arg {
        if matches!(b.op, BinOp::Mul(_)) {
            // k * (omega * t)
            if omega_t(&b.right) {
                return literal_k(&b.left);
            }
            // (k * omega) * t
            if is(&b.right, "t") {
                if let Expr::Binary(inner) = strip(&b.left) {
                    if matches!(inner.op, BinOp::Mul(_)) && is(&inner.right, "omega") {
                        return literal_k(&inner.left);
                    }
                }
            }
        }
    }
    bad()
}

impl<'a> Ctx<'a> {
    fn declare(&mut self, ident: &syn::Ident, name: Name) -> syn::Result<()> {
        let s = ident.to_string();
        if RESERVED.contains(&s.as_str()) {
            return err(
                Sp::of(&ident),
                format!(
                    "`{s}` is a reserved name in oscillator! (`omega` is the forcing frequency, \
                     `t` the time, `D` the derivative); choose another name"
                ),
            );
        }
        if let Some(prev) = self.names.get(&s) {
            return err(
                Sp::of(&ident),
                format!("duplicate name `{s}`: already declared as {}", prev.kind()),
            );
        }
        self.names.insert(s, name);
        Ok(())
    }

    fn lookup(&self, ident: &syn::Ident) -> syn::Result<Name> {
        let s = ident.to_string();
        if let Some(n) = self.names.get(&s) {
            return Ok(*n);
        }
        if s == "t" {
            return err(
                Sp::of(&ident),
                "`t` may only appear inside forcing `cos(k * omega * t)` / `sin(k * omega * t)`",
            );
        }
        let list = |f: &dyn Fn(&Name) -> bool| {
            let mut v: Vec<&String> =
                self.names.iter().filter(|(_, n)| f(n)).map(|(k, _)| k).collect();
            v.sort();
            v.into_iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        };
        err(
            Sp::of(&ident),
            format!(
                "unknown name `{s}`: not a parameter ({}), DOF ({}) or `let` alias declared \
                 above ({})",
                list(&|n| matches!(n, Name::Param(_))),
                list(&|n| matches!(n, Name::Dof(_))),
                list(&|n| matches!(n, Name::Alias(_))),
            ),
        )
    }

    fn signal(&mut self, key: SignalKey) -> usize {
        if let Some(i) = self.signals.iter().position(|s| *s == key) {
            return i;
        }
        self.signals.push(key);
        self.signals.len() - 1
    }

    /// The linear form of `e` in the DOFs (for `D` arguments and outputs).
    fn linear(&self, e: &Expr) -> syn::Result<Lin> {
        let konst =
            |c: CoefPoly, span: Sp| Lin { dofs: BTreeMap::new(), konst: c, konst_span: Some(span) };
        let not_linear = |e: &Expr, why: &str| {
            err(
                Sp::of(&e),
                format!(
                    "`{}` is not linear in the DOFs ({why}): here only a DOF, a `let` alias of a \
                     linear combination, or a linear combination with parameter/literal \
                     coefficients is allowed",
                    show(e)
                ),
            )
        };
        match e {
            Expr::Paren(p) => self.linear(&p.expr),
            Expr::Group(g) => self.linear(&g.expr),
            Expr::Lit(l) => Ok(konst(CoefPoly::constant(literal_value(&l.lit)?), Sp::of(&l))),
            Expr::Path(_) => {
                let Some(ident) = ident_of(e) else {
                    return err(Sp::of(&e), format!("unknown name `{}`", show(e)));
                };
                if ident == "omega" {
                    return Ok(konst(CoefPoly::atom(Atom::Omega), Sp::of(&ident)));
                }
                match self.lookup(ident)? {
                    Name::Param(i) => Ok(konst(CoefPoly::atom(Atom::Param(i)), Sp::of(&ident))),
                    Name::Dof(i) => Ok(Lin {
                        dofs: BTreeMap::from([(i, CoefPoly::constant(1.0))]),
                        ..Lin::default()
                    }),
                    Name::Alias(i) => self.linear(&self.def.lets[i].expr),
                }
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                Ok(Lin::default().add(self.linear(&u.expr)?, -1.0))
            }
            Expr::Binary(b) => {
                let l = self.linear(&b.left)?;
                let r = self.linear(&b.right)?;
                match b.op {
                    BinOp::Add(_) => Ok(l.add(r, 1.0)),
                    BinOp::Sub(_) => Ok(l.add(r, -1.0)),
                    BinOp::Mul(_) => match (l.has_dofs(), r.has_dofs()) {
                        (true, true) => not_linear(e, "a product of DOF terms"),
                        (false, _) => Ok(r.scale(&l.konst)),
                        (true, false) => Ok(l.scale(&r.konst)),
                    },
                    BinOp::Div(_) => {
                        if r.has_dofs() {
                            return not_linear(e, "division by a DOF term");
                        }
                        match r.konst.0.as_slice() {
                            [c] => {
                                let inv = Coef {
                                    lit: 1.0 / c.lit,
                                    atoms: c.atoms.iter().map(|(a, p)| (*a, -p)).collect(),
                                };
                                Ok(l.scale(&CoefPoly(vec![inv])))
                            }
                            [] => err(Sp::of(&b.right), "division by zero"),
                            _ => err(
                                Sp::of(&b.right),
                                "inside `D(...)` and outputs, divide only by a product of \
                                 parameters and literals",
                            ),
                        }
                    }
                    _ => not_linear(e, "unsupported operator"),
                }
            }
            Expr::MethodCall(m) if m.method == "powi" => {
                let k = self.powi_exponent(m)?;
                let base = self.linear(&m.receiver)?;
                if base.has_dofs() {
                    match k {
                        0 => Ok(konst(CoefPoly::constant(1.0), Sp::of(&m))),
                        1 => Ok(base),
                        _ => not_linear(e, "a power of a DOF term"),
                    }
                } else {
                    let mut c = CoefPoly::constant(1.0);
                    for _ in 0..k {
                        c = c.mul(&base.konst);
                    }
                    Ok(konst(c, Sp::of(&m)))
                }
            }
            Expr::Call(c) if ident_of(&c.func).is_some_and(|i| i == "D") => {
                not_linear(e, "nested derivatives are not supported")
            }
            Expr::Call(c) if ident_of(&c.func).is_some_and(|i| i == "cos" || i == "sin") => {
                not_linear(e, "forcing is not a DOF term")
            }
            other => not_linear(other, "unsupported expression"),
        }
    }

    fn powi_exponent(&self, m: &syn::ExprMethodCall) -> syn::Result<u32> {
        let msg = "`.powi(k)` needs an integer literal k >= 0 (negative or non-literal powers \
                   are not polynomial)";
        if m.args.len() != 1 {
            return err(Sp::of(&m.method), msg);
        }
        match strip(&m.args[0]) {
            Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => {
                i.base10_parse::<u32>().or_else(|_| err(Sp::of(&i), msg))
            }
            other => err(Sp::of(&other), msg),
        }
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
        let order_msg = "the order of `D(e, n)` must be an integer literal (0, 1, 2, ...) or a \
                         parameter name (a fractional order)";
        let order = match strip(n) {
            Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => match i.base10_parse::<u32>() {
                Ok(k) => OrderKey::Int(k),
                Err(_) => return err(Sp::of(&i), order_msg),
            },
            Expr::Lit(syn::ExprLit { lit: Lit::Float(f), .. }) => {
                return err(
                    Sp::of(&f),
                    format!(
                        "{order_msg}; for a fractional order declare a parameter, e.g. \
                         `p = {}`, and write `D(e, p)`",
                        f.base10_digits()
                    ),
                )
            }
            other => match ident_of(other) {
                Some(ident) => match self.lookup(ident)? {
                    Name::Param(i) => OrderKey::Param(i),
                    name => {
                        return err(
                            Sp::of(&ident),
                            format!("{order_msg}; `{ident}` is {}", name.kind()),
                        )
                    }
                },
                None => return err(Sp::of(&other), order_msg),
            },
        };
        let lin = self.linear(e)?;
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
        // Group the DOF terms by their non-literal coefficient factor.
        let mut groups: Vec<Group> = Vec::new();
        for (dof, poly) in &lin.dofs {
            for coef in &poly.0 {
                match groups.iter_mut().find(|(a, _)| *a == coef.atoms) {
                    Some((_, terms)) => terms.push((*dof, coef.lit)),
                    None => groups.push((coef.atoms.clone(), vec![(*dof, coef.lit)])),
                }
            }
        }
        let mut node: Option<Node> = None;
        for (atoms, terms) in groups {
            // Normalise so that the first coefficient is 1: D(2y) and D(y) share a signal.
            let c0 = terms[0].1;
            let terms = terms.into_iter().map(|(d, v)| (d, v / c0)).collect();
            let s = Node::Signal(self.signal(SignalKey { terms, order }));
            let mut factor: Option<Node> = None;
            let mut divisor: Option<Node> = None;
            for (atom, pow) in atoms {
                let base = match atom {
                    Atom::Param(i) => Node::Param(i),
                    Atom::Omega => Node::Omega,
                };
                let p = Node::Powi(Box::new(base), pow.unsigned_abs());
                let slot = if pow > 0 { &mut factor } else { &mut divisor };
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
            if c0 == -1.0 {
                term = Node::Neg(Box::new(term));
            } else if c0 != 1.0 {
                term = Node::Mul(Box::new(Node::Lit(c0)), Box::new(term));
            }
            node = Some(match node {
                Some(n) => Node::Add(Box::new(n), Box::new(term)),
                None => term,
            });
        }
        let Some(node) = node else {
            return err(Sp::of(&e), format!("`D({}, ...)` has no DOF term", show(e)));
        };
        Ok((node, Info { degree: 1, dof: Some(Sp::of(&c)), forcing: None, max_k: 0 }))
    }

    /// Convert an expression in value context, checking that it is polynomial.
    fn value(&mut self, e: &Expr) -> syn::Result<(Node, Info)> {
        let coef = |n: Node| Ok((n, Info::default()));
        match e {
            Expr::Paren(p) => self.value(&p.expr),
            Expr::Group(g) => self.value(&g.expr),
            Expr::Lit(l) => coef(Node::Lit(literal_value(&l.lit)?)),
            Expr::Path(_) => {
                let Some(ident) = ident_of(e) else {
                    return err(
                        Sp::of(&e),
                        format!("unknown name `{}`: use plain names declared above", show(e)),
                    );
                };
                if ident == "omega" {
                    return coef(Node::Omega);
                }
                match self.lookup(ident)? {
                    Name::Param(i) => coef(Node::Param(i)),
                    Name::Dof(i) => {
                        let s = self
                            .signal(SignalKey { terms: vec![(i, 1.0)], order: OrderKey::Int(0) });
                        Ok((
                            Node::Signal(s),
                            Info { degree: 1, dof: Some(Sp::of(&ident)), forcing: None, max_k: 0 },
                        ))
                    }
                    Name::Alias(i) => {
                        let info = self.aliases[i].1;
                        // Point messages at this use, not at the alias's definition.
                        let at = Sp::of(&ident);
                        Ok((
                            Node::Alias(i),
                            Info {
                                dof: info.dof.map(|_| at),
                                forcing: info.forcing.map(|_| at),
                                ..info
                            },
                        ))
                    }
                }
            }
            Expr::Unary(u) if matches!(u.op, UnOp::Neg(_)) => {
                let (n, i) = self.value(&u.expr)?;
                Ok((Node::Neg(Box::new(n)), i))
            }
            Expr::Binary(b) => self.binary(b),
            Expr::MethodCall(m) => {
                let name = m.method.to_string();
                if name == "powi" {
                    let k = self.powi_exponent(m)?;
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
                        return coef(Node::Lit(1.0));
                    }
                    let info = Info { degree: i.degree * k, ..i };
                    return Ok((Node::Powi(Box::new(n), k), info));
                }
                if (name == "cos" || name == "sin") && m.args.is_empty() {
                    let k = harmonic(&m.receiver, Sp::of(&e), &show(e))?;
                    return self.forcing(&name, k, Sp::of(&e));
                }
                err(
                    Sp::of(&m.method),
                    format!(
                        "`.{name}(...)` is not allowed: only `.powi(k)` with an integer literal \
                         k >= 0 keeps the model polynomial"
                    ),
                )
            }
            Expr::Call(c) => {
                let Some(f) = ident_of(&c.func) else {
                    return err(Sp::of(&c.func), format!("unsupported function: {ALLOWED}"));
                };
                let fname = f.to_string();
                match fname.as_str() {
                    "D" => self.derivative(c),
                    "cos" | "sin" => {
                        if c.args.len() != 1 {
                            return err(Sp::of(&c), format!("`{fname}` takes one argument"));
                        }
                        let k = harmonic(&c.args[0], Sp::of(&c), &show(e))?;
                        self.forcing(&fname, k, Sp::of(&c))
                    }
                    _ => err(
                        Sp::of(&f),
                        format!(
                            "unknown function `{fname}`: the only functions are `D(e, n)`, \
                             `cos(k * omega * t)` and `sin(k * omega * t)`"
                        ),
                    ),
                }
            }
            other => err(
                Sp::of(&other),
                format!("`{}` is not allowed in oscillator!: {ALLOWED}", show(other)),
            ),
        }
    }

    fn forcing(&self, name: &str, k: u32, span: Sp) -> syn::Result<(Node, Info)> {
        let trig = if name == "cos" { Trig::Cos } else { Trig::Sin };
        Ok((Node::Forcing(trig, k), Info { degree: 0, dof: None, forcing: Some(span), max_k: k }))
    }

    fn binary(&mut self, b: &syn::ExprBinary) -> syn::Result<(Node, Info)> {
        let (l, li) = self.value(&b.left)?;
        let (r, ri) = self.value(&b.right)?;
        let sum = Info {
            degree: li.degree.max(ri.degree),
            dof: li.dof.or(ri.dof),
            forcing: li.forcing.or(ri.forcing),
            max_k: li.max_k.max(ri.max_k),
        };
        let (l, r) = (Box::new(l), Box::new(r));
        match b.op {
            BinOp::Add(_) => Ok((Node::Add(l, r), sum)),
            BinOp::Sub(_) => Ok((Node::Sub(l, r), sum)),
            BinOp::Mul(_) => {
                for (f, d) in [(li.forcing, ri.dof), (ri.forcing, li.dof)] {
                    if let (Some(f), Some(d)) = (f, d) {
                        let _ = d;
                        return err(
                            f,
                            format!(
                                "forcing multiplied by a DOF-dependent term in `{}`: forcing \
                                 `cos(k * omega * t)` / `sin(k * omega * t)` may only be \
                                 multiplied by coefficients (parameters, literals, omega)",
                                show(&Expr::Binary(b.clone()))
                            ),
                        );
                    }
                }
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
                Ok((Node::Mul(l, r), Info { degree: li.degree + ri.degree, ..sum }))
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
                Ok((Node::Div(l, r), sum))
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

    /// Output `name = expr` (or a bare DOF/alias name): literal linear combination.
    fn output(&self, name: &syn::Ident, expr: Option<&Expr>) -> syn::Result<Vec<(usize, f64)>> {
        let lin = match expr {
            Some(e) => self.linear(e)?,
            None => {
                let n = self.lookup(name)?;
                match n {
                    Name::Dof(i) => return Ok(vec![(i, 1.0)]),
                    Name::Alias(i) => self.linear(&self.def.lets[i].expr)?,
                    Name::Param(_) => {
                        return err(
                            Sp::of(&name),
                            format!("output `{name}` is a parameter: outputs are DOFs or aliases"),
                        )
                    }
                }
            }
        };
        let span = expr.map_or(Sp::of(&name), |e| Sp::of(&e));
        let msg = "outputs must be linear combinations of DOFs with literal coefficients \
                   (their terms are fixed at compile time)";
        if !lin.konst.is_zero() {
            return err(span, format!("{msg}; output `{name}` has a constant term"));
        }
        let mut terms = Vec::new();
        for (dof, poly) in lin.dofs {
            match poly.0.as_slice() {
                [] => {}
                [c] if c.atoms.is_empty() => terms.push((dof, c.lit)),
                _ => {
                    return err(
                        span,
                        format!("{msg}; output `{name}` has a parameter or omega coefficient"),
                    )
                }
            }
        }
        if terms.is_empty() {
            return err(span, format!("output `{name}` has no DOF term"));
        }
        Ok(terms)
    }
}

/// Mark used aliases and list signals in order of first use, then renumber.
fn compact(a: &mut Analysis) {
    fn walk(n: &Node, aliases: &mut [(Node, Info, bool)], order: &mut Vec<usize>) {
        match n {
            Node::Signal(s) => {
                if !order.contains(s) {
                    order.push(*s);
                }
            }
            Node::Alias(i) => {
                if !aliases[*i].2 {
                    aliases[*i].2 = true;
                    let inner = aliases[*i].0.clone();
                    walk(&inner, aliases, order);
                }
            }
            Node::Add(x, y) | Node::Sub(x, y) | Node::Mul(x, y) | Node::Div(x, y) => {
                walk(x, aliases, order);
                walk(y, aliases, order);
            }
            Node::Neg(x) | Node::Powi(x, _) => walk(x, aliases, order),
            Node::Lit(_) | Node::Param(_) | Node::Omega | Node::Forcing(..) => {}
        }
    }
    fn renumber(n: &mut Node, map: &[Option<usize>]) {
        match n {
            Node::Signal(s) => {
                if let Some(Some(new)) = map.get(*s) {
                    *s = *new;
                }
            }
            Node::Add(x, y) | Node::Sub(x, y) | Node::Mul(x, y) | Node::Div(x, y) => {
                renumber(x, map);
                renumber(y, map);
            }
            Node::Neg(x) | Node::Powi(x, _) => renumber(x, map),
            _ => {}
        }
    }
    let mut order = Vec::new();
    for eq in &a.equations {
        walk(eq, &mut a.aliases, &mut order);
    }
    let mut map = vec![None; a.signals.len()];
    for (new, old) in order.iter().enumerate() {
        map[*old] = Some(new);
    }
    a.signals = order.iter().map(|i| a.signals[*i].clone()).collect();
    for eq in &mut a.equations {
        renumber(eq, &map);
    }
    for (n, _, used) in &mut a.aliases {
        if *used {
            renumber(n, &map);
        }
    }
}

/// Run every check and build the residual trees.
pub fn analyze(def: &ModelDef) -> syn::Result<Analysis> {
    let mut cx = Ctx { def, names: HashMap::new(), signals: Vec::new(), aliases: Vec::new() };
    for (i, p) in def.params.iter().enumerate() {
        cx.declare(&p.name, Name::Param(i))?;
    }
    for (i, d) in def.dofs.iter().enumerate() {
        cx.declare(d, Name::Dof(i))?;
    }
    for (i, l) in def.lets.iter().enumerate() {
        let converted = cx.value(&l.expr)?;
        cx.aliases.push((converted.0, converted.1, false));
        cx.declare(&l.name, Name::Alias(i))?;
    }
    let ndof = def.dofs.len();
    if def.equations.len() != ndof {
        let dofs: Vec<String> = def.dofs.iter().map(|d| d.to_string()).collect();
        return err(
            def.equations_span,
            format!(
                "{} equation(s) for {ndof} DOF(s) ({}): oscillator! needs exactly one \
                 equation per DOF",
                def.equations.len(),
                dofs.join(", ")
            ),
        );
    }
    let mut equations = Vec::new();
    let (mut degree, mut max_k) = (1, 0);
    for eq in &def.equations {
        let (l, li) = cx.value(&eq.lhs)?;
        let (r, ri) = cx.value(&eq.rhs)?;
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
        degree = degree.max(li.degree).max(ri.degree);
        max_k = max_k.max(li.max_k).max(ri.max_k);
        let node = match r {
            Node::Lit(0.0) => l,
            r => Node::Sub(Box::new(l), Box::new(r)),
        };
        equations.push(node);
    }
    let mut outputs = Vec::new();
    match &def.outputs {
        Some(list) => {
            let mut seen: Vec<String> = Vec::new();
            for o in list {
                let name = o.name.to_string();
                if seen.contains(&name) {
                    return err(Sp::of(&o.name), format!("duplicate output name `{name}`"));
                }
                seen.push(name.clone());
                outputs.push((name, cx.output(&o.name, o.expr.as_ref())?));
            }
        }
        None => {
            for (i, d) in def.dofs.iter().enumerate() {
                outputs.push((d.to_string(), vec![(i, 1.0)]));
            }
        }
    }
    let mut a =
        Analysis { signals: cx.signals, aliases: cx.aliases, equations, outputs, degree, max_k };
    compact(&mut a);
    Ok(a)
}

/// Which signals a subtree contains, which of them it is not affine in (with a
/// coefficient free of signals and time), and whether it varies in time or uses Ω.
#[derive(Debug, Clone, Default)]
struct Shape {
    present: BTreeSet<usize>,
    nonaffine: BTreeSet<usize>,
    timed: bool,
    omega: bool,
}

impl Shape {
    fn union(mut self, o: &Shape) -> Shape {
        self.present.extend(&o.present);
        self.nonaffine.extend(&o.nonaffine);
        self.timed |= o.timed;
        self.omega |= o.omega;
        self
    }
}

/// The shape of `n`, conservatively: a signal multiplied by anything that holds a
/// signal or varies in time counts as non-affine even if terms cancel (that only costs
/// speed; the converse would give wrong Jacobians).
fn shape(n: &Node, aliases: &[Shape]) -> Shape {
    match n {
        Node::Lit(_) | Node::Param(_) => Shape::default(),
        Node::Omega => Shape { omega: true, ..Shape::default() },
        Node::Forcing(..) => Shape { timed: true, ..Shape::default() },
        Node::Signal(s) => Shape { present: BTreeSet::from([*s]), ..Shape::default() },
        Node::Alias(i) => aliases[*i].clone(),
        Node::Neg(a) => shape(a, aliases),
        Node::Add(a, b) | Node::Sub(a, b) => shape(a, aliases).union(&shape(b, aliases)),
        Node::Mul(a, b) | Node::Div(a, b) => {
            let (sa, sb) = (shape(a, aliases), shape(b, aliases));
            let mut out = sa.clone().union(&sb);
            for (x, y) in [(&sa, &sb), (&sb, &sa)] {
                if !y.present.is_empty() || y.timed {
                    out.nonaffine.extend(&x.present);
                }
            }
            out
        }
        Node::Powi(a, k) => match *k {
            0 => Shape::default(),
            1 => shape(a, aliases),
            _ => {
                let mut s = shape(a, aliases);
                let p = s.present.clone();
                s.nonaffine.extend(p);
                s
            }
        },
    }
}

impl Analysis {
    fn shapes(&self) -> Shape {
        let mut aliases: Vec<Shape> = Vec::with_capacity(self.aliases.len());
        for (n, _, _) in &self.aliases {
            let s = shape(n, &aliases);
            aliases.push(s);
        }
        self.equations.iter().fold(Shape::default(), |acc, e| acc.union(&shape(e, &aliases)))
    }

    /// Per signal: every equation is affine in it with a signal- and time-free
    /// coefficient (its gradient is constant over a period).
    pub fn affine_signals(&self) -> Vec<bool> {
        let s = self.shapes();
        (0..self.signals.len()).map(|i| !s.nonaffine.contains(&i)).collect()
    }

    /// Whether some equation uses `omega` other than inside `cos/sin(k * omega * t)`.
    pub fn explicit_omega(&self) -> bool {
        self.shapes().omega
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn analyze_str(src: &str) -> syn::Result<Analysis> {
        let def: ModelDef = syn::parse_str(src)?;
        analyze(&def)
    }

    #[test]
    fn literal_factors_and_parameter_coefficients_split_signals() {
        let a = analyze_str(
            "struct S { params { a = 1.0, p = 0.5 } dofs { x, y }
               equations {
                 D(x, 2) + D(2.0 * x - 2.0 * y, p) + D(x - y, p) + D(a * x + y, 1) = 0.0;
                 D(y, 2) + x.powi(2) * y = cos(3 * omega * t);
               } }",
        )
        .unwrap();
        let keys: Vec<(Vec<(usize, f64)>, OrderKey)> =
            a.signals.iter().map(|s| (s.terms.clone(), s.order)).collect();
        // D(2x - 2y, p) and D(x - y, p) share one signal; D(a x + y, 1) = a Dx + Dy.
        assert_eq!(
            keys,
            vec![
                (vec![(0, 1.0)], OrderKey::Int(2)),
                (vec![(0, 1.0), (1, -1.0)], OrderKey::Param(1)),
                (vec![(0, 1.0)], OrderKey::Int(1)),
                (vec![(1, 1.0)], OrderKey::Int(1)),
                (vec![(1, 1.0)], OrderKey::Int(2)),
                (vec![(0, 1.0)], OrderKey::Int(0)),
                (vec![(1, 1.0)], OrderKey::Int(0)),
            ]
        );
        assert_eq!((a.degree, a.max_k), (3, 3));
    }

    #[test]
    fn unused_aliases_add_no_signals() {
        let a = analyze_str(
            "struct S { params { k = 1.0 } dofs { x } let v = D(x, 1);
               equations { D(x, 2) + k * x = cos(omega * t); } }",
        )
        .unwrap();
        assert_eq!(a.signals.len(), 2);
        assert!(!a.aliases[0].2);
    }
}

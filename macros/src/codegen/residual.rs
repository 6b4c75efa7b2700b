//! The residual: emitted from the alias-expanded trees as straight-line code over locals
//! (parameters, signals, `cos/sin(k·phase)` in f64, each used alias computed once), so
//! one sample costs what a hand-written residual costs and allocates nothing.

use super::float;
use ihbm_dsl::analyze::{Analysis, Node, Trig};
use proc_macro2::TokenStream;
use quote::{format_ident, quote, ToTokens};

/// Whether a generated expression is a plain `f64` or the dual type.
#[derive(Clone, Copy, PartialEq)]
pub(super) enum Kind {
    Const,
    Dual,
}

/// `fn residual`, generic over the dual type.
pub fn residual(a: &Analysis) -> TokenStream {
    let used = a.aliases.iter().filter(|x| x.used).map(|x| &x.node);
    let locals = locals(&uses(a.equations.iter().chain(used)));
    let (alias_kinds, alias_lets) = aliases(a);
    let body = assignments(&a.equations, &alias_kinds);
    sample_fn(quote!(residual), a.equations.len(), quote!(#locals #(#alias_lets)* #body))
}

/// `fn output_values` (the expression outputs, aliases expanded), generic over the
/// dual type; nothing when every output is a combination of DOFs.
pub fn output_values(a: &Analysis) -> TokenStream {
    if a.output_exprs.is_empty() {
        return TokenStream::new();
    }
    let locals = locals(&uses(a.output_exprs.iter()));
    let body = assignments(&a.output_exprs, &[]);
    sample_fn(quote!(output_values), a.output_exprs.len(), quote!(#locals #body))
}

/// A method evaluated at one sample (the residual's signature), writing `nout` values.
fn sample_fn(name: TokenStream, nout: usize, body: TokenStream) -> TokenStream {
    quote! {
        #[inline]
        #[allow(unused_variables, unused_parens, clippy::all)]
        fn #name<__IhbmD: ::ihbm::num_dual::DualNum<Primitive = f64> + Copy>(
            &self,
            __params: &[__IhbmD],
            __omega: __IhbmD,
            __phase: f64,
            __signals: &[__IhbmD],
            __out: &mut [__IhbmD],
        ) {
            let __out = &mut __out[..#nout];
            #body
        }
    }
}

/// `__out[i] = <tree i>;` for each tree.
fn assignments(trees: &[Node], alias_kinds: &[Kind]) -> TokenStream {
    let outs = trees.iter().enumerate().map(|(i, n)| {
        let (code, kind) = expr(n, alias_kinds);
        if kind == Kind::Const {
            quote!(__out[#i] = __IhbmD::from(#code);)
        } else {
            quote!(__out[#i] = #code;)
        }
    });
    quote!(#(#outs)*)
}

/// What the residual body needs declared up front.
#[derive(Default)]
struct Uses {
    params: Vec<usize>,
    signals: Vec<usize>,
    forcing: Vec<(Trig, u32)>,
}

/// The parameters, signals and forcing terms `trees` read (aliases are leaves), sorted.
fn uses<'a>(trees: impl Iterator<Item = &'a Node>) -> Uses {
    fn collect(n: &Node, u: &mut Uses) {
        fn add<T: PartialEq>(v: &mut Vec<T>, x: T) {
            if !v.contains(&x) {
                v.push(x)
            }
        }
        match n {
            Node::Param(i) => add(&mut u.params, *i),
            Node::Signal(i) => add(&mut u.signals, *i),
            Node::Forcing(t, k) => add(&mut u.forcing, (*t, *k)),
            other => other.for_each_child(|c| collect(c, u)),
        }
    }
    let mut uses = Uses::default();
    for tree in trees {
        collect(tree, &mut uses);
    }
    uses.params.sort_unstable();
    uses.signals.sort_unstable();
    uses.forcing.sort_unstable();
    uses
}

/// `let __p{i} = __params[i];` for each parameter in `params`.
pub(super) fn param_lets(params: &[usize]) -> TokenStream {
    let lets = params.iter().map(|i| {
        let id = format_ident!("__p{}", i);
        quote!(let #id = __params[#i];)
    });
    quote!(#(#lets)*)
}

/// `let` statements for the parameters, signals and forcing terms used.
fn locals(uses: &Uses) -> TokenStream {
    let param_lets = param_lets(&uses.params);
    let signal_lets = uses.signals.iter().map(|i| {
        let id = format_ident!("__s{}", i);
        quote!(let #id = __signals[#i];)
    });
    let forcing_lets = uses.forcing.iter().map(|(t, k)| {
        let arg = if *k == 1 {
            quote!(__phase)
        } else {
            let kf = float(*k as f64);
            quote!((#kf * __phase))
        };
        match t {
            Trig::Cos => {
                let id = format_ident!("__cos{}", k);
                quote!(let #id: f64 = #arg.cos();)
            }
            Trig::Sin => {
                let id = format_ident!("__sin{}", k);
                quote!(let #id: f64 = #arg.sin();)
            }
        }
    });
    quote!(#param_lets #(#signal_lets)* #(#forcing_lets)*)
}

/// The kind of every alias, and a `let` for each used one.
fn aliases(a: &Analysis) -> (Vec<Kind>, Vec<TokenStream>) {
    let mut alias_kinds = Vec::new();
    let mut alias_lets = Vec::new();
    for (i, alias) in a.aliases.iter().enumerate() {
        let (code, kind) = expr(&alias.node, &alias_kinds);
        alias_kinds.push(kind);
        if alias.used {
            let id = format_ident!("__a{}", i);
            alias_lets.push(quote!(let #id = #code;));
        }
    }
    (alias_kinds, alias_lets)
}

/// Code for `n` and its kind. Forcing and literals stay `f64`: `DualNum` implements
/// `dual op f64` but not `f64 op dual`, so a constant left operand is moved right.
pub(super) fn expr(n: &Node, alias_kinds: &[Kind]) -> (TokenStream, Kind) {
    type Op = fn(&TokenStream, &TokenStream) -> TokenStream;
    // `a op b` from its operands; `swapped` writes the same for a constant `a` and dual `b`.
    let bin = |x: &Node, y: &Node, plain: Op, swapped: Op| {
        let ((a, ka), (b, kb)) = (expr(x, alias_kinds), expr(y, alias_kinds));
        match (ka, kb) {
            (Kind::Const, Kind::Dual) => (swapped(&a, &b), Kind::Dual),
            (Kind::Const, Kind::Const) => (plain(&a, &b), Kind::Const),
            _ => (plain(&a, &b), Kind::Dual),
        }
    };
    match n {
        Node::Lit(v) => (float(*v), Kind::Const),
        Node::Param(i) => (format_ident!("__p{}", i).into_token_stream(), Kind::Dual),
        Node::Omega => (quote!(__omega), Kind::Dual),
        Node::Signal(i) => (format_ident!("__s{}", i).into_token_stream(), Kind::Dual),
        Node::Alias(i) => (format_ident!("__a{}", i).into_token_stream(), alias_kinds[*i]),
        Node::Forcing(t, k) => {
            let name = match t {
                Trig::Cos => format_ident!("__cos{}", k),
                Trig::Sin => format_ident!("__sin{}", k),
            };
            (name.into_token_stream(), Kind::Const)
        }
        Node::Neg(x) => {
            let (t, k) = expr(x, alias_kinds);
            (quote!((-#t)), k)
        }
        Node::Add(x, y) => bin(x, y, |a, b| quote!((#a + #b)), |a, b| quote!((#b + #a))),
        Node::Sub(x, y) => bin(x, y, |a, b| quote!((#a - #b)), |a, b| quote!((-#b + #a))),
        Node::Mul(x, y) => bin(x, y, |a, b| quote!((#a * #b)), |a, b| quote!((#b * #a))),
        Node::Div(x, y) => bin(x, y, |a, b| quote!((#a / #b)), |a, b| quote!((#b.recip() * #a))),
        // `f64` and `DualNum` name these methods alike.
        Node::Func(f, x) => {
            let (t, kind) = expr(x, alias_kinds);
            let method = format_ident!("{}", f.name());
            (quote!(#t.#method()), kind)
        }
        Node::Powf(x, q) => {
            let ((b, kb), (e, ke)) = (expr(x, alias_kinds), expr(q, alias_kinds));
            match (kb, ke) {
                (_, Kind::Const) => (quote!(#b.powf(#e)), kb),
                // A dual exponent (a parameter): `powd`, on a dual base.
                (Kind::Const, Kind::Dual) => {
                    (quote!(::ihbm::num_dual::DualNum::powd(&__IhbmD::from(#b), #e)), Kind::Dual)
                }
                (Kind::Dual, Kind::Dual) => {
                    (quote!(::ihbm::num_dual::DualNum::powd(&#b, #e)), Kind::Dual)
                }
            }
        }
        // `ihbm::model::kink` takes one scalar type: a constant operand next to a dual
        // one is lifted.
        Node::Kink(k, args) => {
            let parts: Vec<(TokenStream, Kind)> =
                args.iter().map(|a| expr(a, alias_kinds)).collect();
            let f = format_ident!("{}", k.name());
            let kind =
                if parts.iter().all(|(_, k)| *k == Kind::Const) { Kind::Const } else { Kind::Dual };
            let operands = parts.iter().map(|(t, k)| match (kind, k) {
                (Kind::Dual, Kind::Const) => quote!(__IhbmD::from(#t)),
                _ => t.clone(),
            });
            (quote!(::ihbm::model::kink::#f(#(#operands),*)), kind)
        }
        Node::Powi(x, k) => {
            let (t, kind) = expr(x, alias_kinds);
            let code = match k {
                0 => return (float(1.0), Kind::Const),
                1 => t,
                2 => quote!({ let __t = #t; __t * __t }),
                3 => quote!({ let __t = #t; __t * __t * __t }),
                4 => quote!({ let __t = #t; let __t2 = __t * __t; __t2 * __t2 }),
                _ => {
                    let k = *k as i32;
                    quote!(#t.powi(#k))
                }
            };
            (code, kind)
        }
    }
}

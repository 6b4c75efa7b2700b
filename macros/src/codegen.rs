//! Code generation: the struct, `Default`, and the `Model` impl.
//!
//! The residual is emitted from the alias-expanded tree as straight-line code over
//! locals (parameters, signals, `cos(k·phase)` in f64, aliases computed once), so one
//! sample costs what a hand-written residual costs and allocates nothing.

use crate::analyze::{show, Analysis, Node, OrderKey, Trig};
use crate::parse::ModelDef;
use proc_macro2::{Literal, TokenStream};
use quote::{format_ident, quote, ToTokens};

/// Whether a generated expression is a plain `f64` or the dual type.
#[derive(Clone, Copy, PartialEq)]
enum Kind {
    Const,
    Dual,
}

fn float(v: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(v.abs());
    if v < 0.0 {
        quote!((-#lit))
    } else {
        quote!(#lit)
    }
}

/// `QuarterCar` → `quarter-car` (underscores become dashes too).
fn kebab(name: &str) -> String {
    let mut out = String::new();
    for ch in name.chars() {
        let boundary = ch == '_' || ch.is_uppercase();
        if boundary && !out.is_empty() && !out.ends_with('-') {
            out.push('-');
        }
        if ch != '_' {
            out.extend(ch.to_lowercase());
        }
    }
    out
}

/// What the residual body needs declared up front.
#[derive(Default)]
struct Uses {
    params: Vec<usize>,
    signals: Vec<usize>,
    forcing: Vec<(Trig, u32)>,
}

fn collect(n: &Node, u: &mut Uses) {
    let add = |v: &mut Vec<usize>, i: usize| {
        if !v.contains(&i) {
            v.push(i)
        }
    };
    match n {
        Node::Param(i) => add(&mut u.params, *i),
        Node::Signal(i) => add(&mut u.signals, *i),
        Node::Forcing(t, k) => {
            if !u.forcing.contains(&(*t, *k)) {
                u.forcing.push((*t, *k));
            }
        }
        Node::Alias(_) | Node::Lit(_) | Node::Omega => {}
        Node::Add(x, y) | Node::Sub(x, y) | Node::Mul(x, y) | Node::Div(x, y) => {
            collect(x, u);
            collect(y, u);
        }
        Node::Neg(x) | Node::Powi(x, _) => collect(x, u),
    }
}

fn expr(n: &Node, alias_kinds: &[Kind]) -> (TokenStream, Kind) {
    let bin = |x: &Node, y: &Node| (expr(x, alias_kinds), expr(y, alias_kinds));
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
        Node::Add(x, y) => {
            let ((a, ka), (b, kb)) = bin(x, y);
            match (ka, kb) {
                (Kind::Const, Kind::Dual) => (quote!((#b + #a)), Kind::Dual),
                (Kind::Const, Kind::Const) => (quote!((#a + #b)), Kind::Const),
                _ => (quote!((#a + #b)), Kind::Dual),
            }
        }
        Node::Sub(x, y) => {
            let ((a, ka), (b, kb)) = bin(x, y);
            match (ka, kb) {
                (Kind::Const, Kind::Dual) => (quote!((-#b + #a)), Kind::Dual),
                (Kind::Const, Kind::Const) => (quote!((#a - #b)), Kind::Const),
                _ => (quote!((#a - #b)), Kind::Dual),
            }
        }
        Node::Mul(x, y) => {
            let ((a, ka), (b, kb)) = bin(x, y);
            match (ka, kb) {
                (Kind::Const, Kind::Dual) => (quote!((#b * #a)), Kind::Dual),
                (Kind::Const, Kind::Const) => (quote!((#a * #b)), Kind::Const),
                _ => (quote!((#a * #b)), Kind::Dual),
            }
        }
        Node::Div(x, y) => {
            let ((a, ka), (b, kb)) = bin(x, y);
            match (ka, kb) {
                (Kind::Const, Kind::Dual) => (quote!((#b.recip() * #a)), Kind::Dual),
                (Kind::Const, Kind::Const) => (quote!((#a / #b)), Kind::Const),
                _ => (quote!((#a / #b)), Kind::Dual),
            }
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

/// Everything the macro emits.
pub fn generate(def: &ModelDef, a: &Analysis) -> TokenStream {
    let ident = &def.ident;
    let vis = &def.vis;
    let attrs = &def.attrs;
    let model_name =
        def.model_name.as_ref().map_or_else(|| kebab(&ident.to_string()), |s| s.value());

    // Equation text: `lhs = rhs`, then one `where` line per alias.
    let mut eq_text: Vec<String> =
        def.equations.iter().map(|e| format!("{} = {}", show(&e.lhs), show(&e.rhs))).collect();
    for l in &def.lets {
        eq_text.push(format!("where {} = {}", l.name, show(&l.expr)));
    }

    // Struct docs: the user's, then the generated equations and parameter table.
    let mut doc = def.doc.clone();
    if !doc.is_empty() {
        doc.push_str("\n\n");
    }
    doc.push_str("# Equations\n\n```text\n");
    for e in &eq_text {
        doc.push_str(e);
        doc.push('\n');
    }
    doc.push_str("```\n\n# Parameters (name = default: doc)\n\n");
    for p in &def.params {
        doc.push_str(&format!("- `{} = {}`: {}\n", p.name, p.default, p.doc));
    }
    let doc_attrs = doc.lines().map(|l| {
        let l = format!(" {l}");
        quote!(#[doc = #l])
    });

    let fields = def.params.iter().map(|p| {
        let name = &p.name;
        let doc = format!(" {}", p.doc);
        let pattrs = &p.attrs;
        quote!(#[doc = #doc] #(#pattrs)* pub #name: f64)
    });
    let defaults = def.params.iter().map(|p| {
        let name = &p.name;
        let v = float(p.default);
        quote!(#name: #v)
    });
    let infos = def.params.iter().map(|p| {
        let name = p.name.to_string();
        let v = float(p.default);
        let doc = &p.doc;
        quote!(::ihbm::model::ParamInfo {
            name: ::std::borrow::Cow::Borrowed(#name),
            default: #v,
            doc: ::std::borrow::Cow::Borrowed(#doc),
        })
    });
    let nparams = def.params.len();
    let get_arms = def.params.iter().enumerate().map(|(i, p)| {
        let name = &p.name;
        quote!(#i => self.#name)
    });
    let set_arms = def.params.iter().enumerate().map(|(i, p)| {
        let name = &p.name;
        quote!(#i => self.#name = value)
    });
    let dofs = def.dofs.iter().map(|d| {
        let d = d.to_string();
        quote!(::std::borrow::Cow::Borrowed(#d))
    });
    let terms = |t: &[(usize, f64)]| {
        let pairs = t.iter().map(|(d, c)| {
            let c = float(*c);
            quote!((#d, #c))
        });
        quote!(::std::borrow::Cow::Borrowed(&[#(#pairs),*]))
    };
    let signals = a.signals.iter().map(|s| {
        let t = terms(&s.terms);
        let order = match s.order {
            OrderKey::Int(n) => quote!(::ihbm::model::Order::Int(#n)),
            OrderKey::Param(i) => quote!(::ihbm::model::Order::Param(#i)),
        };
        quote!(::ihbm::model::Signal { terms: #t, order: #order })
    });
    let outputs = a.outputs.iter().map(|(name, t)| {
        let t = terms(t);
        quote!(::ihbm::model::Output { name: ::std::borrow::Cow::Borrowed(#name), terms: #t })
    });
    let shape = a.shape();
    let degree = shape.degree as usize;
    let max_k = shape.max_harmonic.max(1) as usize;
    let description = &def.doc;
    let affine = shape.affine;
    let explicit_omega = shape.explicit_omega;

    // Residual body.
    let mut uses = Uses::default();
    for eq in &a.equations {
        collect(eq, &mut uses);
    }
    for alias in a.aliases.iter().filter(|x| x.used) {
        collect(&alias.node, &mut uses);
    }
    uses.params.sort_unstable();
    uses.signals.sort_unstable();
    uses.forcing.sort_unstable();
    let param_lets = uses.params.iter().map(|i| {
        let id = format_ident!("__p{}", i);
        quote!(let #id = __params[#i];)
    });
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
    let outs = a.equations.iter().enumerate().map(|(i, n)| {
        let (code, kind) = expr(n, &alias_kinds);
        if kind == Kind::Const {
            quote!(__out[#i] = __IhbmD::from(#code);)
        } else {
            quote!(__out[#i] = #code;)
        }
    });
    let nout = a.equations.len();

    quote! {
        #(#doc_attrs)*
        #[derive(Debug, Clone, PartialEq)]
        #[allow(non_snake_case)]
        #(#attrs)*
        #vis struct #ident {
            #(#fields,)*
        }

        impl ::core::default::Default for #ident {
            fn default() -> Self {
                #ident { #(#defaults,)* }
            }
        }

        #[allow(non_snake_case, clippy::all)]
        impl ::ihbm::model::Model for #ident {
            fn name(&self) -> &str {
                #model_name
            }
            fn description(&self) -> &str {
                #description
            }
            fn dofs(&self) -> &[::ihbm::model::Text] {
                const __DOFS: &[::ihbm::model::Text] = &[#(#dofs),*];
                __DOFS
            }
            fn params_info(&self) -> &[::ihbm::model::ParamInfo] {
                const __INFO: &[::ihbm::model::ParamInfo] = &[#(#infos),*];
                __INFO
            }
            fn param_value(&self, index: usize) -> f64 {
                match index {
                    #(#get_arms,)*
                    _ => ::core::panic!("parameter index {} out of range: model `{}` has {} parameters", index, #model_name, #nparams),
                }
            }
            fn set_param_value(&mut self, index: usize, value: f64) {
                match index {
                    #(#set_arms,)*
                    _ => ::core::panic!("parameter index {} out of range: model `{}` has {} parameters", index, #model_name, #nparams),
                }
            }
            fn signals(&self) -> &[::ihbm::model::Signal] {
                const __SIGNALS: &[::ihbm::model::Signal] = &[#(#signals),*];
                __SIGNALS
            }
            fn outputs(&self) -> &[::ihbm::model::Output] {
                const __OUTPUTS: &[::ihbm::model::Output] = &[#(#outputs),*];
                __OUTPUTS
            }
            fn degree(&self) -> usize {
                #degree
            }
            fn max_forcing_harmonic(&self) -> usize {
                #max_k
            }
            fn equations(&self) -> &[::ihbm::model::Text] {
                const __EQUATIONS: &[::ihbm::model::Text] =
                    &[#(::std::borrow::Cow::Borrowed(#eq_text)),*];
                __EQUATIONS
            }
            fn affine_signals(&self) -> &[bool] {
                &[#(#affine),*]
            }
            fn explicit_omega(&self) -> bool {
                #explicit_omega
            }
            #[inline]
            #[allow(unused_variables, unused_parens, clippy::all)]
            fn residual<__IhbmD: ::ihbm::num_dual::DualNum<Primitive = f64> + Copy>(
                &self,
                __params: &[__IhbmD],
                __omega: __IhbmD,
                __phase: f64,
                __signals: &[__IhbmD],
                __out: &mut [__IhbmD],
            ) {
                let __out = &mut __out[..#nout];
                #(#param_lets)*
                #(#signal_lets)*
                #(#forcing_lets)*
                #(#alias_lets)*
                #(#outs)*
            }
        }
    }
}

#[cfg(test)]
mod tests {
    #[test]
    fn kebab_case_names() {
        assert_eq!(super::kebab("QuarterCar"), "quarter-car");
        assert_eq!(super::kebab("Duffing"), "duffing");
        assert_eq!(super::kebab("FractionalDuffing"), "fractional-duffing");
        assert_eq!(super::kebab("Two_Mass"), "two-mass");
        assert_eq!(super::kebab("Chain3"), "chain3");
    }
}

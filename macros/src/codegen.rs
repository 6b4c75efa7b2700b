//! Code generation: the struct, `Default`, and the `Model` impl, each piece from a
//! function of its own; the residual, the one piece that is computed per sample, is
//! in `residual`, and the run-time check of the coefficients in `check`.

mod check;
mod residual;

use ihbm_dsl::analyze::{Analysis, OrderKey, OutputDef, SignalKey};
use ihbm_dsl::parse::{DomainDecl, ModelDef};
use ihbm_dsl::{equation_text, kebab};
use proc_macro2::{Literal, TokenStream};
use quote::quote;

/// Everything the macro emits.
pub fn generate(def: &ModelDef, a: &Analysis) -> TokenStream {
    let ident = &def.ident;
    let model_name =
        def.model_name.as_ref().map_or_else(|| kebab(&ident.to_string()), |s| s.value());
    let eq_text = equation_text(def);
    let item = struct_and_default(def, &eq_text);
    let metadata = metadata(def, a, &model_name, &eq_text);
    let params = param_access(def, &model_name);
    let residual = residual::residual(a);
    let output_values = residual::output_values(a);
    let names: Vec<String> = def.params.iter().map(|p| p.name.to_string()).collect();
    let check = check::check_coefficients(&a.checks, &names);
    quote! {
        #item

        #[allow(non_snake_case, clippy::all)]
        impl ::ihbm::model::Model for #ident {
            #metadata
            #params
            #residual
            #output_values
            #check
        }
    }
}

/// An `f64` literal (suffixed, so it never infers as another float type).
fn float(v: f64) -> TokenStream {
    let lit = Literal::f64_suffixed(v.abs());
    if v < 0.0 {
        quote!((-#lit))
    } else {
        quote!(#lit)
    }
}

/// Struct docs: the user's, then the generated equations and parameter table.
fn struct_doc(def: &ModelDef, eq_text: &[String]) -> String {
    let mut doc = def.doc.clone();
    if !doc.is_empty() {
        doc.push_str("\n\n");
    }
    doc.push_str("# Equations\n\n```text\n");
    for e in eq_text {
        doc.push_str(e);
        doc.push('\n');
    }
    doc.push_str("```\n\n# Parameters (name = default: doc)\n\n");
    for p in &def.params {
        doc.push_str(&format!("- `{} = {}`: {}\n", p.name, p.default, p.doc));
    }
    doc
}

/// The struct, one documented `pub f64` field per parameter, and `Default`.
fn struct_and_default(def: &ModelDef, eq_text: &[String]) -> TokenStream {
    let (ident, vis, attrs) = (&def.ident, &def.vis, &def.attrs);
    let doc_attrs = struct_doc(def, eq_text)
        .lines()
        .map(|l| {
            let l = format!(" {l}");
            quote!(#[doc = #l])
        })
        .collect::<Vec<_>>();
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
    }
}

/// The declared domain as a `Domain` constant (`Domain::ANY` if none is declared).
fn domain(d: Option<&DomainDecl>) -> TokenStream {
    let Some(d) = d else { return quote!(::ihbm::model::Domain::ANY) };
    let end = |e: Option<(f64, bool)>| match e {
        None => quote!(::ihbm::model::Bound::Unbounded),
        Some((v, true)) => {
            let v = float(v);
            quote!(::ihbm::model::Bound::Closed(#v))
        }
        Some((v, false)) => {
            let v = float(v);
            quote!(::ihbm::model::Bound::Open(#v))
        }
    };
    let (lower, upper) = (end(d.lower), end(d.upper));
    quote!(::ihbm::model::Domain { lower: #lower, upper: #upper })
}

/// `params_info`, `param_value` and `set_param_value`: parameter `i` is field `i`.
fn param_access(def: &ModelDef, model_name: &str) -> TokenStream {
    let infos = def.params.iter().map(|p| {
        let name = p.name.to_string();
        let v = float(p.default);
        let doc = &p.doc;
        let domain = domain(p.domain.as_ref());
        quote!(::ihbm::model::ParamInfo {
            name: ::std::borrow::Cow::Borrowed(#name),
            default: #v,
            doc: ::std::borrow::Cow::Borrowed(#doc),
            domain: #domain,
        })
    });
    let nparams = def.params.len();
    let out_of_range = quote!(_ => ::core::panic!("parameter index {} out of range: model `{}` has {} parameters", index, #model_name, #nparams));
    let get_arms = def.params.iter().enumerate().map(|(i, p)| {
        let name = &p.name;
        quote!(#i => self.#name)
    });
    let set_arms = def.params.iter().enumerate().map(|(i, p)| {
        let name = &p.name;
        quote!(#i => self.#name = value)
    });
    quote! {
        fn params_info(&self) -> &[::ihbm::model::ParamInfo] {
            const __INFO: &[::ihbm::model::ParamInfo] = &[#(#infos),*];
            __INFO
        }
        fn param_value(&self, index: usize) -> f64 {
            match index {
                #(#get_arms,)*
                #out_of_range,
            }
        }
        fn set_param_value(&mut self, index: usize, value: f64) {
            match index {
                #(#set_arms,)*
                #out_of_range,
            }
        }
    }
}

/// `Cow::Borrowed(&[(dof, coef), ...])`.
fn terms(t: &[(usize, f64)]) -> TokenStream {
    let pairs = t.iter().map(|(d, c)| {
        let c = float(*c);
        quote!((#d, #c))
    });
    quote!(::std::borrow::Cow::Borrowed(&[#(#pairs),*]))
}

/// `::ihbm::model::Signal { .. }` for `s`.
fn signal(s: &SignalKey) -> TokenStream {
    let t = terms(&s.terms);
    let order = match s.order {
        OrderKey::Int(n) => quote!(::ihbm::model::Order::Int(#n)),
        OrderKey::Param(i) => quote!(::ihbm::model::Order::Param(#i)),
    };
    quote!(::ihbm::model::Signal { terms: #t, order: #order })
}

/// Name, description, DOFs, signals, outputs, equations and the model's shape.
fn metadata(def: &ModelDef, a: &Analysis, model_name: &str, eq_text: &[String]) -> TokenStream {
    let description = &def.doc;
    let dofs = def.dofs.iter().map(|d| {
        let d = d.to_string();
        quote!(::std::borrow::Cow::Borrowed(#d))
    });
    let signals = a.signals.iter().map(signal);
    let output_signals = a.output_signals.iter().map(signal);
    let outputs = a.outputs.iter().map(|(name, def)| {
        let kind = match def {
            OutputDef::Dofs(t) => {
                let t = terms(t);
                quote!(::ihbm::model::OutputKind::Dofs(#t))
            }
            OutputDef::Expression(i) => quote!(::ihbm::model::OutputKind::Expression(#i)),
        };
        quote!(::ihbm::model::Output { name: ::std::borrow::Cow::Borrowed(#name), kind: #kind })
    });
    let output_degree = a.output_degree() as usize;
    let outputs_smooth = a.outputs_smooth();
    let shape = a.shape();
    let degree = shape.degree as usize;
    // An unforced model reports 1, as the trait does by default.
    let max_k = shape.max_harmonic.max(1) as usize;
    let parametric = shape.parametric_harmonic as usize;
    let (affine, explicit_omega, reads) = (shape.affine, shape.explicit_omega, shape.reads);
    let smooth = shape.smooth;
    quote! {
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
        fn signals(&self) -> &[::ihbm::model::Signal] {
            const __SIGNALS: &[::ihbm::model::Signal] = &[#(#signals),*];
            __SIGNALS
        }
        fn outputs(&self) -> &[::ihbm::model::Output] {
            const __OUTPUTS: &[::ihbm::model::Output] = &[#(#outputs),*];
            __OUTPUTS
        }
        fn output_signals(&self) -> &[::ihbm::model::Signal] {
            const __OUTPUT_SIGNALS: &[::ihbm::model::Signal] = &[#(#output_signals),*];
            __OUTPUT_SIGNALS
        }
        fn output_degree(&self) -> usize {
            #output_degree
        }
        fn outputs_smooth(&self) -> bool {
            #outputs_smooth
        }
        fn smooth(&self) -> bool {
            #smooth
        }
        fn equations(&self) -> &[::ihbm::model::Text] {
            const __EQUATIONS: &[::ihbm::model::Text] =
                &[#(::std::borrow::Cow::Borrowed(#eq_text)),*];
            __EQUATIONS
        }
        fn degree(&self) -> usize {
            #degree
        }
        fn max_forcing_harmonic(&self) -> usize {
            #max_k
        }
        fn parametric_harmonic(&self) -> usize {
            #parametric
        }
        fn affine_signals(&self) -> &[bool] {
            &[#(#affine),*]
        }
        fn explicit_omega(&self) -> bool {
            #explicit_omega
        }
        fn signal_reads(&self) -> &[bool] {
            const __READS: &[bool] = &[#(#reads),*];
            __READS
        }
    }
}

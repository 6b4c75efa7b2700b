//! `check_coefficients`: every coefficient subexpression that may fail to be finite
//! (a function, a real power, a quotient), evaluated in `f64` by the same code as the
//! residual's, innermost first, so that the first one that is NaN or infinite is named
//! in the error (with its value, Ω and the parameters it reads).

use super::residual::{expr, param_lets};
use ihbm_dsl::analyze::Check;
use proc_macro2::TokenStream;
use quote::quote;

/// `fn check_coefficients` (nothing if the model has no such coefficient: the trait's
/// default accepts every point).
pub fn check_coefficients(checks: &[Check], param_names: &[String]) -> TokenStream {
    if checks.is_empty() {
        return TokenStream::new();
    }
    let mut used: Vec<usize> = checks.iter().flat_map(|c| c.node.params()).collect();
    used.sort_unstable();
    used.dedup();
    let lets = param_lets(&used);
    let tests = checks.iter().map(|c| {
        let (code, _) = expr(&c.node, &[]);
        let text = &c.text;
        let reads = c.node.params();
        let fmt = if reads.is_empty() {
            "none".to_string()
        } else {
            reads
                .iter()
                .map(|&i| format!("{} = {{}}", param_names[i]))
                .collect::<Vec<_>>()
                .join(", ")
        };
        let values = reads.iter().map(|&i| quote::format_ident!("__p{}", i));
        quote! {
            let __v: f64 = #code;
            if !__v.is_finite() {
                return ::core::result::Result::Err(::ihbm::Error::NonFiniteCoefficient {
                    model: ::std::string::String::from(::ihbm::model::Model::name(self)),
                    term: ::std::string::String::from(#text),
                    value: __v,
                    omega: __omega,
                    params: ::std::format!(#fmt, #(#values),*),
                });
            }
        }
    });
    quote! {
        #[allow(unused_variables, unused_parens, clippy::all)]
        fn check_coefficients(
            &self,
            __params: &[f64],
            __omega: f64,
        ) -> ::core::result::Result<(), ::ihbm::Error> {
            // The residual's code, instantiated for plain numbers.
            type __IhbmD = f64;
            #lets
            #(#tests)*
            ::core::result::Result::Ok(())
        }
    }
}

//! The `oscillator!` proc-macro of ihbm: a model declared as equations becomes a struct
//! implementing `ihbm::model::Model`, with every symbolic check done at compile time.
//!
//! Pipeline: [`parse`] (surface syntax) → [`analyze`] (names, aliases, polynomial and
//! forcing checks, signals) → [`codegen`] (struct, `Default`, `Model` impl). See the
//! `ihbm` crate documentation for the language itself.

mod analyze;
mod codegen;
mod parse;

use proc_macro::TokenStream;

/// Declare an oscillator model; see `ihbm::oscillator` for the language.
#[proc_macro]
pub fn oscillator(input: TokenStream) -> TokenStream {
    let def = syn::parse_macro_input!(input as parse::ModelDef);
    match analyze::analyze(&def) {
        Ok(a) => codegen::generate(&def, &a).into(),
        Err(e) => e.to_compile_error().into(),
    }
}

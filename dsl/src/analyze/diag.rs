//! Diagnostics: a rejection is a `syn::Error` underlining the offending code, from its
//! first token to its last, with a message saying what is allowed instead.

use proc_macro2::{Span, TokenStream};
use quote::ToTokens;

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

/// An error spanned on `span`.
pub fn err<T>(span: impl Into<Sp>, msg: impl std::fmt::Display) -> syn::Result<T> {
    Err(syn::Error::new_spanned(span.into(), msg))
}

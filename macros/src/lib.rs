use proc_macro::TokenStream;
#[proc_macro]
pub fn oscillator(_i: TokenStream) -> TokenStream {
    TokenStream::new()
}

//! The `oscillator!` proc-macro of ihbm: a model declared as equations becomes a struct
//! implementing `ihbm::model::Model`, with every symbolic check done at compile time.
//!
//! Pipeline: `ihbm_dsl::parse` (surface syntax) → `ihbm_dsl::analyze` (names, aliases,
//! polynomial and forcing checks, signals, shape) → `codegen` (struct, `Default`,
//! `Model` impl). The first two live in `ihbm-dsl`, shared with the run-time reader of
//! model files, so both accept the same language with the same messages; only
//! `codegen` writes Rust. See the `ihbm` crate documentation for the language itself.

mod codegen;

use proc_macro::TokenStream;

/// Declare an oscillator model: a struct with one `pub f64` field per parameter,
/// `Default` with the declared values, and an implementation of `ihbm::model::Model`.
///
/// ```text
/// ihbm::oscillator! {
///     /// Docs: become the struct docs and `Model::description()`.
///     #[name = "my-model"]            // optional; default: kebab-case of the struct name
///     pub struct MyModel {
///         params {
///             /// doc (units): becomes the field doc and `ParamInfo::doc`
///             m = 1.0 in (0, inf),    // optional domain: `(`/`)` open, `[`/`]` closed,
///             c = 0.1 in "[0, inf)",  // half-open quoted (Rust brackets must pair)
///             k = 1.0, k3 = 1.0, h = 0.1, p = 0.5 in [0, 2], F = 0.5,
///         }
///         dofs { x }
///         let v = D(x, 1);            // aliases, expanded where used
///         equations {                 // one `lhs = rhs;` per DOF
///             m * D(x, 2) + c * v + k * x + k3 * x.powi(3) + h * D(x, p) = F * cos(omega * t);
///         }
///         outputs { x, v, acc = D(x, 2) } // DOFs, aliases, or `name = expression`
///     }
/// }
/// ```
///
/// The language:
/// - terms are polynomial in the DOFs and their derivatives: `+ - *`, parentheses,
///   `.powi(k)` with a literal `k >= 0`, division by coefficients only;
/// - `D(e, n)`: derivative of order `n` (an integer literal, or a parameter name for a
///   fractional order, steady-state sense) of `e`, which must be linear in the DOFs (a
///   DOF, an alias of a linear combination, or a linear combination with
///   parameter/literal coefficients). A combination with literal coefficients is one
///   signal (`D(z1 - z2, p)`); parameter coefficients are pulled outside;
/// - coefficients are smooth expressions of parameters, numeric literals and `omega`
///   (the forcing frequency Ω): `+ - * /`, `.powi(k)` (any integer literal k),
///   `.powf(q)`, and `sqrt`, `exp`, `ln`, `sin`, `cos`, `tan`, `abs`, written `f(e)` or
///   `e.f()` (an unbalance `m * e * omega.powi(2) * cos(omega * t)`, a delayed road
///   input `F * cos(omega * tau) * cos(omega * t)`). A function never takes a DOF or
///   forcing; inside `D(e, n)` coefficients stay products of parameters, literals and
///   powers of `omega`. The generated `Model::check_coefficients` names a
///   coefficient that is NaN or infinite where the solvers evaluate it;
/// - forcing is `cos(k * omega * t)` / `sin(k * omega * t)` with `k` a positive integer
///   literal (`k *` optional), multiplied by coefficients, or by DOF terms (parametric
///   excitation, `k * (1.0 + eps * cos(2 * omega * t)) * x`; one harmonic per product,
///   counted in `Model::parametric_harmonic`);
/// - outputs are DOFs, aliases, or `name = expression` with anything an equation may
///   hold (an acceleration `D(x, 2)`, a force with the forcing in it); a combination of
///   DOFs with literal coefficients is combined exactly, anything else is evaluated on
///   the transform's time grid (`Model::output_values`);
/// - `omega`, `t` and `D` are reserved names; every name is declared once.
///
/// Anything else is a compile error spanned on the offending code, saying what is
/// allowed. The generated residual is straight-line code over the signal and parameter
/// slices (no allocation per sample), generic over dual numbers so that every
/// derivative the solvers need comes from it. Generated code names only `::ihbm::...`,
/// so a user crate needs `ihbm` alone.
#[proc_macro]
pub fn oscillator(input: TokenStream) -> TokenStream {
    match ihbm_dsl::check_tokens(input.into()) {
        Ok((def, a)) => codegen::generate(&def, &a).into(),
        Err(e) => e.to_compile_error().into(),
    }
}

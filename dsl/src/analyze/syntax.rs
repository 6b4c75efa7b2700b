//! Small readings of `syn` expressions shared by every check: the source text of an
//! expression (for messages and `Model::equations()`), parentheses seen through, a plain
//! name, and the literal exponent of `.powi(k)`.

use super::diag::{err, Sp};
use quote::ToTokens;
use syn::{Expr, Lit};

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
pub fn strip(e: &Expr) -> &Expr {
    match e {
        Expr::Paren(p) => strip(&p.expr),
        Expr::Group(g) => strip(&g.expr),
        other => other,
    }
}

/// The single identifier of a path expression, if it is one.
pub fn ident_of(e: &Expr) -> Option<&syn::Ident> {
    match strip(e) {
        Expr::Path(p) if p.qself.is_none() => p.path.get_ident(),
        _ => None,
    }
}

/// Whether `e` names the time `t` anywhere: then `cos(e)` / `sin(e)` is read as forcing
/// (and must be `k * omega * t`), otherwise as a function of a coefficient.
pub fn mentions_t(e: &Expr) -> bool {
    fn scan(ts: proc_macro2::TokenStream) -> bool {
        ts.into_iter().any(|tt| match tt {
            proc_macro2::TokenTree::Ident(i) => i == "t",
            proc_macro2::TokenTree::Group(g) => scan(g.stream()),
            _ => false,
        })
    }
    scan(e.to_token_stream())
}

/// `k` of `.powi(-k)`, if the exponent is a negative integer literal (allowed on
/// coefficients, where it is a division).
pub fn negative_powi_exponent(m: &syn::ExprMethodCall) -> Option<u32> {
    match m.args.iter().map(strip).collect::<Vec<_>>().as_slice() {
        [Expr::Unary(u)] if matches!(u.op, syn::UnOp::Neg(_)) => match strip(&u.expr) {
            Expr::Lit(syn::ExprLit { lit: Lit::Int(i), .. }) => {
                i.base10_parse::<u32>().ok().filter(|&k| k > 0)
            }
            _ => None,
        },
        _ => None,
    }
}

/// `k` of `.powi(k)`: an integer literal `k >= 0`.
pub fn powi_exponent(m: &syn::ExprMethodCall) -> syn::Result<u32> {
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

#[cfg(test)]
mod tests {
    use super::*;

    fn expr(src: &str) -> Expr {
        syn::parse_str(src).unwrap()
    }

    #[test]
    fn show_gives_the_source_text_back() {
        for src in ["m * D(x, 2) + k * x.powi(3)", "-(a - b) / 2.0", "cos(2 * omega * t)"] {
            assert_eq!(show(&expr(src)), src);
        }
    }

    #[test]
    fn strip_and_ident_see_through_parentheses() {
        assert_eq!(ident_of(&expr("((x))")).map(|i| i.to_string()), Some("x".into()));
        assert!(ident_of(&expr("a::b")).is_none());
        assert!(ident_of(&expr("x + y")).is_none());
    }

    #[test]
    fn time_is_found_at_any_depth() {
        assert!(mentions_t(&expr("2 * (omega * t)")));
        assert!(mentions_t(&expr("omega * t - omega * tau")));
        assert!(!mentions_t(&expr("omega * tau")));
    }

    #[test]
    fn negative_powers_are_read_for_coefficients() {
        let m = |src: &str| match expr(src) {
            Expr::MethodCall(m) => m,
            _ => unreachable!(),
        };
        assert_eq!(negative_powi_exponent(&m("omega.powi(-2)")), Some(2));
        assert_eq!(negative_powi_exponent(&m("omega.powi((-1))")), Some(1));
        for other in ["omega.powi(2)", "omega.powi(-0)", "omega.powi(-k)", "omega.powi(-1.0)"] {
            assert_eq!(negative_powi_exponent(&m(other)), None, "{other}");
        }
    }

    #[test]
    fn powi_exponent_takes_nonnegative_integer_literals_only() {
        let m = |src: &str| match expr(src) {
            Expr::MethodCall(m) => m,
            _ => unreachable!(),
        };
        assert_eq!(powi_exponent(&m("x.powi(0)")).unwrap(), 0);
        assert_eq!(powi_exponent(&m("x.powi((3))")).unwrap(), 3);
        for bad in ["x.powi(-1)", "x.powi(2.0)", "x.powi(k)", "x.powi(1, 2)"] {
            assert!(powi_exponent(&m(bad)).is_err(), "{bad}");
        }
    }
}

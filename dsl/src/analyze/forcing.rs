//! Forcing: the argument of `cos(...)` / `sin(...)` that names `t` must be
//! `k * omega * t` with `k` a positive integer literal, so that the forcing is periodic with the period 2π/Ω the
//! harmonic balance assumes. Everything else gets a message naming what forcing may be.

use super::diag::{err, Sp};
use super::syntax::{ident_of, show, strip};
use syn::{BinOp, Expr, Lit};

/// `k` of `cos(k * omega * t)`, or an error saying what forcing may look like.
pub fn harmonic(arg: &Expr, call_span: Sp, call_text: &str) -> syn::Result<u32> {
    let bad = || {
        err(
            call_span,
            format!(
                "`{call_text}` is not allowed: with `t` in its argument `cos`/`sin` is \
                 forcing, which must be `cos(k * omega * t)` / `sin(k * omega * t)` with k a \
                 positive integer literal (`k *` optional); a phase shift or a delay is \
                 written `A * cos(omega * t) + B * sin(omega * t)` with coefficients A, B \
                 (e.g. `cos(omega * tau)`)"
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

#[cfg(test)]
mod tests {
    use super::*;

    fn k_of(arg: &str) -> syn::Result<u32> {
        let e: Expr = syn::parse_str(arg).unwrap();
        harmonic(&e, Sp::of(&e), arg)
    }

    #[test]
    fn integer_multiples_of_omega_t_are_harmonics() {
        assert_eq!(k_of("omega * t").unwrap(), 1);
        assert_eq!(k_of("(omega * t)").unwrap(), 1);
        assert_eq!(k_of("3 * omega * t").unwrap(), 3);
        assert_eq!(k_of("3 * (omega * t)").unwrap(), 3);
        assert_eq!(k_of("(2 * omega) * t").unwrap(), 2);
        assert_eq!(k_of("2.0 * omega * t").unwrap(), 2);
    }

    #[test]
    fn anything_else_is_rejected() {
        for bad in ["0 * omega * t", "1.5 * omega * t", "k * omega * t", "-1.0 * omega * t"] {
            let e = k_of(bad).unwrap_err().to_string();
            assert!(e.starts_with("the forcing harmonic must be a positive integer"), "{e}");
        }
        for bad in ["t * omega", "omega * t + 1.0", "x", "omega * t * 2"] {
            let e = k_of(bad).unwrap_err().to_string();
            assert!(e.starts_with(&format!("`{bad}` is not allowed")), "{e}");
        }
    }
}

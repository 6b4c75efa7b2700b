//! Symbolic analysis: resolve names, expand `let` aliases, check that every equation is
//! polynomial in the signals with time only in `cos/sin(k * omega * t)` (times
//! coefficients or DOF terms) and coefficients smooth functions of the parameters and
//! Ω, and collect the distinct signals and the coefficients to check at run time. This module only orchestrates; each
//! step is a module of its own.
//!
//! Every rejection is a `syn::Error` spanned on the offending token, with a message that
//! says what is allowed instead. The result, an [`Analysis`], holds no `syn` and is all
//! code generation reads.

mod coeff;
mod compact;
mod diag;
mod forcing;
mod function;
mod linear;
mod lower;
mod outputs;
mod scope;
mod shape;
mod syntax;
mod tree;

pub use shape::ModelShape;
pub use syntax::show;
pub use tree::{
    Alias, Analysis, Check, Func, Kink, Node, OrderKey, OutputDef, SignalKey, Terms, Trig,
};

use crate::parse::ModelDef;
use diag::err;
use lower::Lower;
use scope::{Name, Scope};

/// Run every check and build the residual trees.
pub fn analyze(def: &ModelDef) -> syn::Result<Analysis> {
    let mut scope = Scope::default();
    for (i, p) in def.params.iter().enumerate() {
        scope.declare(&p.name, Name::Param(i))?;
    }
    for (i, d) in def.dofs.iter().enumerate() {
        scope.declare(d, Name::Dof(i))?;
    }
    let mut lower = Lower::new(&def.lets, scope);
    for i in 0..def.lets.len() {
        lower.alias(i)?;
    }
    let ndof = def.dofs.len();
    if def.equations.len() != ndof {
        let dofs: Vec<String> = def.dofs.iter().map(|d| d.to_string()).collect();
        return err(
            def.equations_span,
            format!(
                "{} equation(s) for {ndof} DOF(s) ({}): oscillator! needs exactly one \
                 equation per DOF",
                def.equations.len(),
                dofs.join(", ")
            ),
        );
    }
    let equations = def.equations.iter().map(|eq| lower.equation(eq)).collect::<Result<_, _>>()?;
    let outputs = outputs::outputs(def, &mut lower)?;
    let lower::Lowered { signals, aliases, checks } = lower.finish();
    let mut a = Analysis {
        signals,
        aliases,
        equations,
        outputs: outputs.outputs,
        output_signals: outputs.signals,
        output_exprs: outputs.exprs,
        checks: Vec::new(),
    };
    compact::compact(&mut a);
    // Only what the residual evaluates is checked, each text once.
    for (alias, check) in checks {
        let used = alias.is_none_or(|i| a.aliases[i].used);
        if used && !a.checks.iter().any(|c| c.text == check.text) {
            a.checks.push(check);
        }
    }
    Ok(a)
}

#[cfg(test)]
mod tests {
    use super::*;

    fn analyze_str(src: &str) -> syn::Result<Analysis> {
        let def: ModelDef = syn::parse_str(src)?;
        analyze(&def)
    }

    #[test]
    fn literal_factors_and_parameter_coefficients_split_signals() {
        let a = analyze_str(
            "struct S { params { a = 1.0, p = 0.5 } dofs { x, y }
               equations {
                 D(x, 2) + D(2.0 * x - 2.0 * y, p) + D(x - y, p) + D(a * x + y, 1) = 0.0;
                 D(y, 2) + x.powi(2) * y = cos(3 * omega * t);
               } }",
        )
        .unwrap();
        let keys: Vec<(Vec<(usize, f64)>, OrderKey)> =
            a.signals.iter().map(|s| (s.terms.clone(), s.order)).collect();
        // D(2x - 2y, p) and D(x - y, p) share one signal; D(a x + y, 1) = a Dx + Dy.
        assert_eq!(
            keys,
            vec![
                (vec![(0, 1.0)], OrderKey::Int(2)),
                (vec![(0, 1.0), (1, -1.0)], OrderKey::Param(1)),
                (vec![(0, 1.0)], OrderKey::Int(1)),
                (vec![(1, 1.0)], OrderKey::Int(1)),
                (vec![(1, 1.0)], OrderKey::Int(2)),
                (vec![(0, 1.0)], OrderKey::Int(0)),
                (vec![(1, 1.0)], OrderKey::Int(0)),
            ]
        );
        let shape = a.shape();
        assert_eq!((shape.degree, shape.max_harmonic), (3, 3));
    }

    #[test]
    fn coefficient_functions_are_checked_innermost_first_once_and_only_if_used() {
        let a = analyze_str(
            "struct S { params { k = 1.0, m = 1.0, tau = 0.1 } dofs { x }
               let kd = sqrt(k - m * omega.powi(2));
               let unused = ln(tau);
               equations {
                 D(x, 2) + kd * x + k / (omega - tau) * x + omega.powi(-1) * x.powi(3)
                   + (omega * tau).cos() * x + kd.exp() * D(x, 1) + sqrt(k - m * omega.powi(2)) * x
                   = cos(omega * tau) * cos(omega * t);
               } }",
        )
        .unwrap();
        let texts: Vec<&str> = a.checks.iter().map(|c| c.text.as_str()).collect();
        // cos of a finite number needs no check; `ln(tau)` is in an unused alias; the
        // second `sqrt(...)` is the same text as the alias's.
        assert_eq!(
            texts,
            ["sqrt(k - m * omega.powi(2))", "k / (omega - tau)", "omega.powi(-1)", "kd.exp()",]
        );
        // Aliases are expanded: the check reads parameters and Ω only.
        fn has_alias(n: &Node) -> bool {
            let mut found = matches!(n, Node::Alias(_));
            n.for_each_child(|c| found |= has_alias(c));
            found
        }
        assert!(a.checks.iter().all(|c| !has_alias(&c.node)));
    }

    #[test]
    fn a_dof_quotient_checks_the_reciprocal_of_its_divisor() {
        let a = analyze_str(
            "struct S { params { k = 1.0, w = 2.0 } dofs { x }
               equations { D(x, 2) + x / (omega - w) + x / k + x / 2.0 = 0.0; } }",
        )
        .unwrap();
        let texts: Vec<&str> = a.checks.iter().map(|c| c.text.as_str()).collect();
        assert_eq!(texts, ["1 / (omega - w)", "1 / k"]);
    }

    #[test]
    fn unused_aliases_add_no_signals() {
        let a = analyze_str(
            "struct S { params { k = 1.0 } dofs { x } let v = D(x, 1);
               equations { D(x, 2) + k * x = cos(omega * t); } }",
        )
        .unwrap();
        assert_eq!(a.signals.len(), 2);
        assert!(!a.aliases[0].used);
    }
}

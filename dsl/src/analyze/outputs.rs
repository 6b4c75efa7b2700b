//! Outputs: the named quantities results are reported in, each a linear combination of
//! DOFs with literal coefficients, so that its terms are fixed at compile time. Without
//! an `outputs` section every DOF is one.

use super::diag::{err, Sp};
use super::linear::LinearReader;
use super::scope::Name;
use super::tree::Terms;
use crate::parse::ModelDef;
use syn::Expr;

/// The outputs of `def`, names unique.
pub fn outputs(def: &ModelDef, reader: &LinearReader) -> syn::Result<Vec<(String, Terms)>> {
    let mut outputs = Vec::new();
    match &def.outputs {
        Some(list) => {
            let mut seen: Vec<String> = Vec::new();
            for o in list {
                let name = o.name.to_string();
                if seen.contains(&name) {
                    return err(Sp::of(&o.name), format!("duplicate output name `{name}`"));
                }
                seen.push(name.clone());
                outputs.push((name, output(reader, &o.name, o.expr.as_ref())?));
            }
        }
        None => {
            for (i, d) in def.dofs.iter().enumerate() {
                outputs.push((d.to_string(), vec![(i, 1.0)]));
            }
        }
    }
    Ok(outputs)
}

/// Output `name = expr` (or a bare DOF/alias name): literal linear combination.
fn output(reader: &LinearReader, name: &syn::Ident, expr: Option<&Expr>) -> syn::Result<Terms> {
    let lin = match expr {
        Some(e) => reader.read(e)?,
        None => {
            let n = reader.scope.lookup(name)?;
            match n {
                Name::Dof(i) => return Ok(vec![(i, 1.0)]),
                Name::Alias(i) => reader.read(&reader.lets[i].expr)?,
                Name::Param(_) => {
                    return err(
                        Sp::of(&name),
                        format!("output `{name}` is a parameter: outputs are DOFs or aliases"),
                    )
                }
            }
        }
    };
    let span = expr.map_or(Sp::of(&name), |e| Sp::of(&e));
    let msg = "outputs must be linear combinations of DOFs with literal coefficients \
               (their terms are fixed at compile time)";
    if !lin.konst.is_zero() {
        return err(span, format!("{msg}; output `{name}` has a constant term"));
    }
    let mut terms = Vec::new();
    for (dof, poly) in lin.dofs {
        match poly.literal() {
            Some(0.0) => {}
            Some(c) => terms.push((dof, c)),
            None => {
                return err(
                    span,
                    format!("{msg}; output `{name}` has a parameter or omega coefficient"),
                )
            }
        }
    }
    if terms.is_empty() {
        return err(span, format!("output `{name}` has no DOF term"));
    }
    Ok(terms)
}

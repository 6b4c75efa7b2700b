//! Outputs: the named quantities results are reported in. A DOF, a `let` alias, or
//! `name = expression` with anything an equation may hold (derivatives of any order,
//! forcing, parameters, nonlinear terms). A linear combination of DOFs with literal
//! coefficients is kept as such (combined from the coefficients exactly); anything
//! else becomes a tree over signals of its own, evaluated on the transform's time grid.
//! Without an `outputs` section every DOF is one.

use super::diag::{err, Sp};
use super::linear::LinearReader;
use super::lower::Lower;
use super::scope::{Name, RESERVED};
use super::tree::{Node, OutputDef, SignalKey, Terms};
use crate::parse::ModelDef;
use syn::Expr;

/// The outputs of `def`, names unique, with the expression outputs' signals and trees.
pub struct Outputs {
    pub outputs: Vec<(String, OutputDef)>,
    pub signals: Vec<SignalKey>,
    pub exprs: Vec<Node>,
}

/// The outputs of `def`, lowered with the names `lower` has declared.
pub fn outputs(def: &ModelDef, lower: &mut Lower) -> syn::Result<Outputs> {
    let mut out = Outputs { outputs: Vec::new(), signals: Vec::new(), exprs: Vec::new() };
    let Some(list) = &def.outputs else {
        for (i, d) in def.dofs.iter().enumerate() {
            out.outputs.push((d.to_string(), OutputDef::Dofs(vec![(i, 1.0)])));
        }
        return Ok(out);
    };
    let mut seen: Vec<String> = Vec::new();
    for o in list {
        let name = o.name.to_string();
        if RESERVED.contains(&name.as_str()) {
            return err(
                Sp::of(&o.name),
                format!(
                    "`{name}` is a reserved name in oscillator! (`omega` is the forcing \
                     frequency, `t` the time, `D` the derivative); name the output otherwise"
                ),
            );
        }
        if seen.contains(&name) {
            return err(Sp::of(&o.name), format!("duplicate output name `{name}`"));
        }
        seen.push(name.clone());
        let expr: Expr = match &o.expr {
            Some(e) => {
                if let Some(n) = lower.linear().scope.get(&name) {
                    return err(
                        Sp::of(&o.name),
                        format!(
                            "output `{name} = ...` takes the name of {}: write `{name}` alone \
                             to report it, or give the expression another name",
                            n.kind()
                        ),
                    );
                }
                e.clone()
            }
            None => {
                if let Name::Param(_) = lower.linear().scope.lookup(&o.name)? {
                    return err(
                        Sp::of(&o.name),
                        format!(
                            "output `{name}` is a parameter, a constant: outputs are DOFs, \
                             aliases or `name = expression`"
                        ),
                    );
                }
                Expr::Path(syn::ExprPath {
                    attrs: Vec::new(),
                    qself: None,
                    path: o.name.clone().into(),
                })
            }
        };
        let def = match literal_combination(&lower.linear(), &expr) {
            Some(terms) => OutputDef::Dofs(terms),
            None => {
                let tree = lower.output(&expr, &mut out.signals)?;
                out.exprs.push(tree);
                OutputDef::Expression(out.exprs.len() - 1)
            }
        };
        out.outputs.push((name, def));
    }
    Ok(out)
}

/// `e` as a linear combination of DOFs with literal coefficients and no constant term,
/// if it is one.
fn literal_combination(reader: &LinearReader, e: &Expr) -> Option<Terms> {
    let lin = reader.read(e).ok()?;
    if !lin.konst.is_zero() {
        return None;
    }
    let mut terms = Vec::new();
    for (dof, poly) in lin.dofs {
        match poly.literal()? {
            0.0 => {}
            c => terms.push((dof, c)),
        }
    }
    (!terms.is_empty()).then_some(terms)
}

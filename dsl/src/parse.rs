//! Parsing: the surface syntax of `oscillator!` into plain declarations.
//!
//! Only the shape is checked here (sections, separators, literal defaults); what the
//! expressions mean is the business of `analyze`.

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{braced, Attribute, Expr, Ident, Lit, LitStr, Token, Visibility};

/// One declared parameter: `/// doc` `name = default`.
pub struct ParamDecl {
    pub name: Ident,
    pub default: f64,
    pub doc: String,
    pub attrs: Vec<Attribute>,
}

/// `let name = expr;`
pub struct LetDecl {
    pub name: Ident,
    pub expr: Expr,
}

/// One equation `lhs = rhs;`.
pub struct Equation {
    pub lhs: Expr,
    pub rhs: Expr,
}

/// One entry of `outputs { ... }`: a bare name or `name = expr`.
pub struct OutputDecl {
    pub name: Ident,
    pub expr: Option<Expr>,
}

/// The whole macro input.
pub struct ModelDef {
    /// Attributes other than docs and `#[name = "..."]`, passed through to the struct.
    pub attrs: Vec<Attribute>,
    pub doc: String,
    pub model_name: Option<LitStr>,
    pub vis: Visibility,
    pub ident: Ident,
    pub params: Vec<ParamDecl>,
    pub dofs: Vec<Ident>,
    pub lets: Vec<LetDecl>,
    pub equations: Vec<Equation>,
    /// Span of the `equations` keyword (for count mismatches).
    pub equations_span: Span,
    pub outputs: Option<Vec<OutputDecl>>,
}

/// The text of `///` doc attributes, one entry per line, with the leading space removed.
pub fn doc_lines(attrs: &[Attribute]) -> Vec<String> {
    let mut lines = Vec::new();
    for attr in attrs {
        if !attr.path().is_ident("doc") {
            continue;
        }
        if let syn::Meta::NameValue(nv) = &attr.meta {
            if let Expr::Lit(syn::ExprLit { lit: Lit::Str(s), .. }) = &nv.value {
                let v = s.value();
                lines.push(v.strip_prefix(' ').unwrap_or(&v).trim_end().to_string());
            }
        }
    }
    lines
}

/// A default value: a numeric literal, optionally negated.
fn parse_number(input: ParseStream) -> syn::Result<f64> {
    let neg = input.peek(Token![-]);
    if neg {
        input.parse::<Token![-]>()?;
    }
    let lit: Lit = input.parse().map_err(|e| {
        syn::Error::new(e.span(), "expected a numeric literal as the default value, e.g. `m = 1.0`")
    })?;
    let v = literal_value(&lit)?;
    Ok(if neg { -v } else { v })
}

/// The value of an integer or float literal (a finite f64), or an error naming it.
pub fn literal_value(lit: &Lit) -> syn::Result<f64> {
    let v = match lit {
        Lit::Float(f) => f.base10_parse::<f64>()?,
        Lit::Int(i) => i.base10_digits().parse::<f64>().map_err(|_| {
            syn::Error::new(i.span(), format!("`{}` is not a number", i.base10_digits()))
        })?,
        other => {
            return Err(syn::Error::new(
                other.span(),
                "expected a numeric literal (integer or float)",
            ))
        }
    };
    if !v.is_finite() {
        return Err(syn::Error::new(lit.span(), "this literal is not a finite f64"));
    }
    Ok(v)
}

impl Parse for ParamDecl {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let attrs = input.call(Attribute::parse_outer)?;
        let name: Ident = input.parse()?;
        input.parse::<Token![=]>().map_err(|e| {
            syn::Error::new(
                e.span(),
                format!("expected `=` and a default value after parameter `{name}`"),
            )
        })?;
        let default = parse_number(input)?;
        let doc = doc_lines(&attrs).join(" ").trim().to_string();
        let attrs = attrs.into_iter().filter(|a| !a.path().is_ident("doc")).collect();
        Ok(ParamDecl { name, default, doc, attrs })
    }
}

impl Parse for OutputDecl {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let name: Ident = input.parse()?;
        let expr = if input.peek(Token![=]) {
            input.parse::<Token![=]>()?;
            Some(input.parse()?)
        } else {
            None
        };
        Ok(OutputDecl { name, expr })
    }
}

fn parse_equations(input: ParseStream) -> syn::Result<Vec<Equation>> {
    let mut eqs = Vec::new();
    while !input.is_empty() {
        let expr: Expr = input.parse()?;
        match expr {
            Expr::Assign(a) => eqs.push(Equation { lhs: *a.left, rhs: *a.right }),
            other => {
                return Err(syn::Error::new_spanned(
                    other,
                    "an equation must have the form `lhs = rhs;` (use `= 0.0` for a residual)",
                ))
            }
        }
        if input.is_empty() {
            break;
        }
        input.parse::<Token![;]>()?;
    }
    Ok(eqs)
}

impl Parse for ModelDef {
    fn parse(input: ParseStream) -> syn::Result<Self> {
        let all_attrs = input.call(Attribute::parse_outer)?;
        let mut attrs = Vec::new();
        let mut model_name = None;
        let doc = doc_lines(&all_attrs).join("\n").trim().to_string();
        for attr in all_attrs {
            if attr.path().is_ident("doc") {
                continue;
            }
            if attr.path().is_ident("name") {
                let nv = attr.meta.require_name_value()?;
                match &nv.value {
                    Expr::Lit(syn::ExprLit { lit: Lit::Str(s), .. }) => {
                        model_name = Some(s.clone())
                    }
                    other => {
                        return Err(syn::Error::new_spanned(
                            other,
                            "expected a string: `#[name = \"my-model\"]`",
                        ))
                    }
                }
                continue;
            }
            attrs.push(attr);
        }
        let vis: Visibility = input.parse()?;
        input.parse::<Token![struct]>()?;
        let ident: Ident = input.parse()?;
        let body;
        braced!(body in input);

        let mut params = None;
        let mut dofs = None;
        let mut lets = Vec::new();
        let mut equations = None;
        let mut equations_span = ident.span();
        let mut outputs = None;
        while !body.is_empty() {
            if body.peek(Token![let]) {
                body.parse::<Token![let]>()?;
                let name: Ident = body.parse()?;
                body.parse::<Token![=]>()?;
                let expr: Expr = body.parse()?;
                body.parse::<Token![;]>()?;
                lets.push(LetDecl { name, expr });
                continue;
            }
            let kw: Ident = body.parse().map_err(|e| {
                syn::Error::new(
                    e.span(),
                    "expected a section (`params`, `dofs`, `equations`, `outputs`) or `let`",
                )
            })?;
            let inner;
            braced!(inner in body);
            let dup = |what: &str| {
                syn::Error::new(kw.span(), format!("the `{what}` section is given twice"))
            };
            match kw.to_string().as_str() {
                "params" => {
                    if params.is_some() {
                        return Err(dup("params"));
                    }
                    let list = Punctuated::<ParamDecl, Token![,]>::parse_terminated(&inner)?;
                    params = Some(list.into_iter().collect::<Vec<_>>());
                }
                "dofs" => {
                    if dofs.is_some() {
                        return Err(dup("dofs"));
                    }
                    let list = Punctuated::<Ident, Token![,]>::parse_terminated(&inner)?;
                    let list: Vec<Ident> = list.into_iter().collect();
                    if list.is_empty() {
                        return Err(syn::Error::new(kw.span(), "declare at least one DOF"));
                    }
                    dofs = Some(list);
                }
                "equations" => {
                    if equations.is_some() {
                        return Err(dup("equations"));
                    }
                    equations_span = kw.span();
                    equations = Some(parse_equations(&inner)?);
                }
                "outputs" => {
                    if outputs.is_some() {
                        return Err(dup("outputs"));
                    }
                    let list = Punctuated::<OutputDecl, Token![,]>::parse_terminated(&inner)?;
                    outputs = Some(list.into_iter().collect());
                }
                other => {
                    return Err(syn::Error::new(
                        kw.span(),
                        format!(
                            "unknown section `{other}`: expected `params`, `dofs`, `let`, \
                             `equations` or `outputs`"
                        ),
                    ))
                }
            }
        }
        let Some(dofs) = dofs else {
            return Err(syn::Error::new(ident.span(), "missing `dofs { ... }` section"));
        };
        let Some(equations) = equations else {
            return Err(syn::Error::new(ident.span(), "missing `equations { ... }` section"));
        };
        Ok(ModelDef {
            attrs,
            doc,
            model_name,
            vis,
            ident,
            params: params.unwrap_or_default(),
            dofs,
            lets,
            equations,
            equations_span,
            outputs,
        })
    }
}

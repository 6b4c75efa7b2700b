//! Parsing: the surface syntax of `oscillator!` into plain declarations.
//!
//! Only the shape is checked here (sections, separators, literal defaults); what the
//! expressions mean is the business of `analyze`.

use proc_macro2::Span;
use syn::parse::{Parse, ParseStream};
use syn::punctuated::Punctuated;
use syn::{braced, Attribute, Expr, Ident, Lit, LitStr, Token, Visibility};

/// One declared parameter: `/// doc` `name = default`, optionally `in (lo, hi)`.
pub struct ParamDecl {
    pub name: Ident,
    pub default: f64,
    pub doc: String,
    pub attrs: Vec<Attribute>,
    /// The declared domain, `None` if there is none (all reals).
    pub domain: Option<DomainDecl>,
}

/// A parameter's declared domain: each end `None` when unbounded (`-inf`, `inf`), else
/// its value and whether it is closed (`[`, `]`). Checked when parsed: not empty, the
/// lower end not above the upper one, infinite ends open, the default inside.
#[derive(Debug, Clone, Copy, PartialEq)]
pub struct DomainDecl {
    pub lower: Option<(f64, bool)>,
    pub upper: Option<(f64, bool)>,
}

impl DomainDecl {
    /// Whether `x` lies in the domain.
    pub fn contains(&self, x: f64) -> bool {
        let above = self.lower.is_none_or(|(a, closed)| if closed { x >= a } else { x > a });
        let below = self.upper.is_none_or(|(b, closed)| if closed { x <= b } else { x < b });
        above && below && !x.is_nan()
    }
}

impl std::fmt::Display for DomainDecl {
    /// Interval notation, as it is written: `(0, inf)`, `[0, 2]`.
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        match self.lower {
            None => write!(f, "(-inf, ")?,
            Some((a, closed)) => write!(f, "{}{a}, ", if closed { '[' } else { '(' })?,
        }
        match self.upper {
            None => write!(f, "inf)"),
            Some((b, closed)) => write!(f, "{b}{}", if closed { ']' } else { ')' }),
        }
    }
}

/// One end of a domain as written: its value (`±inf` allowed), whether its bracket is
/// closed, and where the bracket and the value are (for messages).
struct End {
    value: f64,
    closed: bool,
    bracket: Span,
    at: Span,
}

const DOMAIN_FORMS: &str = "`(0, inf)`, `[0, 2]`, or a half-open interval in quotes, \
     `\"[0, inf)\"` (brackets in Rust tokens must pair)";

/// The domain after `in`: a parenthesised or bracketed pair of bounds, or any interval
/// in a string (Rust's tokenizer refuses an unpaired `[0, inf)` before any parser sees
/// it, so a half-open interval has to be quoted).
fn parse_domain(input: ParseStream) -> syn::Result<DomainDecl> {
    let (lo, hi) = if input.peek(LitStr) {
        let lit: LitStr = input.parse()?;
        domain_text(&lit)?
    } else if input.peek(syn::token::Paren) || input.peek(syn::token::Bracket) {
        let inner;
        let (closed, delim) = if input.peek(syn::token::Paren) {
            (false, syn::parenthesized!(inner in input).span)
        } else {
            (true, syn::bracketed!(inner in input).span)
        };
        let lo = token_bound(&inner)?;
        inner.parse::<Token![,]>().map_err(|e| {
            syn::Error::new(e.span(), "expected `,` between the ends of the domain")
        })?;
        let hi = token_bound(&inner)?;
        if !inner.is_empty() {
            return Err(inner.error("expected the end of the domain: it has two bounds"));
        }
        let open = delim.open();
        let close = delim.close();
        (
            End { value: lo.0, closed, bracket: open, at: lo.1 },
            End { value: hi.0, closed, bracket: close, at: hi.1 },
        )
    } else {
        return Err(input.error(format!("expected a domain after `in`: {DOMAIN_FORMS}")));
    };
    interval(lo, hi)
}

/// One bound as tokens: a number, optionally negated, or `inf` / `-inf`.
fn token_bound(input: ParseStream) -> syn::Result<(f64, Span)> {
    let at = input.span();
    let neg = input.peek(Token![-]);
    if neg {
        input.parse::<Token![-]>()?;
    }
    let sign = if neg { -1.0 } else { 1.0 };
    if input.peek(Ident) {
        let id: Ident = input.parse()?;
        if id == "inf" {
            return Ok((sign * f64::INFINITY, at));
        }
        return Err(syn::Error::new(id.span(), not_a_bound(&id.to_string())));
    }
    match input.parse::<Lit>() {
        Ok(lit @ (Lit::Int(_) | Lit::Float(_))) => Ok((sign * literal_value(&lit)?, at)),
        Ok(other) => {
            Err(syn::Error::new(other.span(), not_a_bound(&quote::quote!(#other).to_string())))
        }
        Err(e) => Err(syn::Error::new(e.span(), not_a_bound("this"))),
    }
}

fn not_a_bound(what: &str) -> String {
    format!("`{what}` is not a bound: a bound of a domain is a number, `inf` or `-inf`")
}

/// The interval in a string, `"[0, inf)"`, read by hand. Errors point at the string:
/// a proc-macro cannot point inside a literal on stable Rust, and a model file gets the
/// macro's messages at the macro's places.
fn domain_text(lit: &LitStr) -> syn::Result<(End, End)> {
    let text = lit.value();
    let err = |msg: String| syn::Error::new(lit.span(), msg);
    let t = text.trim();
    let closed_lo = match t.chars().next() {
        Some('(') => false,
        Some('[') => true,
        _ => return Err(err(format!("expected `(` or `[` to open the domain: {DOMAIN_FORMS}"))),
    };
    let closed_hi = match t.chars().last() {
        Some(')') if t.len() > 1 => false,
        Some(']') if t.len() > 1 => true,
        _ => return Err(err("expected `)` or `]` to close the domain".into())),
    };
    let Some((lo, hi)) = t[1..t.len() - 1].split_once(',') else {
        return Err(err("expected `,` between the ends of the domain".into()));
    };
    let bound = |w: &str| -> syn::Result<f64> {
        match w.trim() {
            "inf" => Ok(f64::INFINITY),
            "-inf" => Ok(f64::NEG_INFINITY),
            w => match w.replace('_', "").parse::<f64>() {
                // "nan" and "infinity" parse, and are no bounds
                Ok(v) if v.is_finite() && !w.is_empty() => Ok(v),
                _ => Err(err(not_a_bound(w))),
            },
        }
    };
    let at = lit.span();
    Ok((
        End { value: bound(lo)?, closed: closed_lo, bracket: at, at },
        End { value: bound(hi)?, closed: closed_hi, bracket: at, at },
    ))
}

/// Check the two ends and make the domain: infinite ends open, not empty.
fn interval(lo: End, hi: End) -> syn::Result<DomainDecl> {
    for end in [&lo, &hi] {
        if end.value.is_infinite() && end.closed {
            return Err(syn::Error::new(
                end.bracket,
                "an infinite end of a domain is open: write `(-inf, ...` or `..., inf)`",
            ));
        }
    }
    if lo.value > hi.value {
        return Err(syn::Error::new(
            lo.at,
            format!("the domain's lower end {} is above its upper end {}", lo.value, hi.value),
        ));
    }
    if lo.value == f64::INFINITY || hi.value == f64::NEG_INFINITY {
        let at = if lo.value == f64::INFINITY { lo.at } else { hi.at };
        return Err(syn::Error::new(
            at,
            "the domain is empty: its lower end is `inf` or its upper end `-inf`",
        ));
    }
    if lo.value == hi.value && !(lo.closed && hi.closed) {
        return Err(syn::Error::new(
            lo.at,
            format!(
                "the domain is empty: no number lies between {} and {} (write `[{0}, {0}]` for the single value)",
                lo.value, hi.value
            ),
        ));
    }
    let end = |e: &End| e.value.is_finite().then_some((e.value, e.closed));
    Ok(DomainDecl { lower: end(&lo), upper: end(&hi) })
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
        let default_at = input.span();
        let default = parse_number(input)?;
        let domain = if input.peek(Token![in]) {
            input.parse::<Token![in]>()?;
            let domain = parse_domain(input)?;
            if !domain.contains(default) {
                return Err(syn::Error::new(
                    default_at,
                    format!(
                        "the default {default} of `{name}` is outside its declared domain {domain}"
                    ),
                ));
            }
            Some(domain)
        } else {
            None
        };
        let doc = doc_lines(&attrs).join(" ").trim().to_string();
        let attrs = attrs.into_iter().filter(|a| !a.path().is_ident("doc")).collect();
        Ok(ParamDecl { name, default, doc, attrs, domain })
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

//! The model language of ihbm: the parser and the symbolic checks of `oscillator!`,
//! shared by the proc-macro (which turns an [`analyze::Analysis`] into Rust) and the
//! run-time reader of model files (which turns it into a program evaluated over dual
//! numbers). One front end, so both accept exactly the same text with the same
//! messages.
//!
//! Pipeline: [`parse`] (surface syntax, `syn`) → [`analyze`] (names, aliases,
//! polynomial and forcing checks, signals, shape) → a plain [`analyze::Analysis`]
//! that holds no `syn`. [`read`] runs both on a string and reports errors with their
//! line and column.
//!
//! ```
//! let text = "
//!     /// m x'' + k x = F cos(Ωt)
//!     pub struct Spring {
//!         params { m = 1.0, k = 4.0, F = 0.1 }
//!         dofs { x }
//!         equations { m * D(x, 2) + k * x = F * cos(omega * t); }
//!     }";
//! let model = ihbm_dsl::read(text).unwrap();
//! assert_eq!(model.name, "spring");
//! assert_eq!(model.analysis.signals.len(), 2); // x'' and x
//!
//! let bad = ihbm_dsl::read("struct S { params { a = 1.0 } dofs { x }\n equations { sin(x) = 0.0; } }");
//! let e = &bad.err().unwrap()[0];
//! assert_eq!((e.line, e.column), (2, 14));
//! assert!(e.message.contains("`sin(x)` is not allowed"));
//! ```

pub mod analyze;
pub mod parse;

use analyze::{show, Analysis};
use parse::ModelDef;

/// A checked model: its declarations, its analysis, its name and its equations as text.
pub struct Checked {
    /// The declarations (parameters with defaults and docs, DOFs, aliases, equations).
    pub def: ModelDef,
    /// Signals, residual trees, outputs, coefficient checks.
    pub analysis: Analysis,
    /// `#[name = "..."]`, else the struct name in kebab case.
    pub name: String,
    /// `lhs = rhs` per equation, then `where alias = expr` per alias.
    pub equations: Vec<String>,
}

/// One error in a model's text: where (1-based line and column, in characters) and what.
#[derive(Debug, Clone, PartialEq)]
pub struct Diagnostic {
    /// Line, from 1.
    pub line: usize,
    /// Column, from 1, counted in characters.
    pub column: usize,
    /// What is wrong and what is allowed instead (the macro's message).
    pub message: String,
}

impl std::fmt::Display for Diagnostic {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        write!(f, "{}:{}: {}", self.line, self.column, self.message)
    }
}

/// The deepest nesting of brackets [`read`] accepts: the parser recurses per level, and
/// a file of ten thousand `(` must be an error, not a stack overflow.
pub const MAX_NESTING: usize = 200;

/// The most arithmetic operators [`read`] accepts in one expression: the parser and
/// the checks recurse once per operator of a chain `x + x + ...`, and a chain of tens
/// of thousands must be an error, not a stack overflow. Longer sums are written in
/// parts, as `let` aliases.
pub const MAX_OPERATORS: usize = 10_000;

/// The stack [`read`] needs for the longest expression it accepts (a chain of
/// [`MAX_OPERATORS`] recurses that deep in the parser and the checks, and again when
/// the result is dropped): run it on a thread with this much (only what is used is
/// touched), as `ihbm`'s reader of model files does.
pub const STACK_BYTES: usize = 256 << 20;

/// Parse and check the text of one `oscillator!` body (`pub struct Name { ... }`).
/// Run on a stack of [`STACK_BYTES`] where the text is not trusted to be short.
pub fn read(text: &str) -> Result<Checked, Vec<Diagnostic>> {
    nesting(text)?;
    operators(text)?;
    let def: ModelDef = syn::parse_str(text).map_err(diagnostics)?;
    let analysis = analyze::analyze(&def).map_err(diagnostics)?;
    let name = def.model_name.as_ref().map_or_else(|| kebab(&def.ident.to_string()), |s| s.value());
    let equations = equation_text(&def);
    Ok(Checked { def, analysis, name, equations })
}

/// Parse and check the tokens of one `oscillator!` invocation: exactly what the macro
/// runs before it writes Rust, so that its compile errors (message and span) can be
/// checked without starting a compiler.
pub fn check_tokens(tokens: proc_macro2::TokenStream) -> syn::Result<(ModelDef, Analysis)> {
    let def: ModelDef = syn::parse2(tokens)?;
    let analysis = analyze::analyze(&def)?;
    Ok((def, analysis))
}

/// Refuse nesting deeper than [`MAX_NESTING`] before the recursive parser sees it.
fn nesting(text: &str) -> Result<(), Vec<Diagnostic>> {
    let mut depth = 0usize;
    let (mut line, mut column) = (1, 0);
    for ch in text.chars() {
        column += 1;
        match ch {
            '\n' => (line, column) = (line + 1, 0),
            '(' | '[' | '{' => {
                depth += 1;
                if depth > MAX_NESTING {
                    return Err(vec![Diagnostic {
                        line,
                        column,
                        message: format!("brackets nested more than {MAX_NESTING} deep"),
                    }]);
                }
            }
            ')' | ']' | '}' => depth = depth.saturating_sub(1),
            _ => {}
        }
    }
    Ok(())
}

/// Refuse an expression (what lies between `;`, `,`, `{` and `}`) with more than
/// [`MAX_OPERATORS`] operators, comments and strings aside.
fn operators(text: &str) -> Result<(), Vec<Diagnostic>> {
    let mut count = 0usize;
    let (mut line, mut column) = (1, 0);
    let mut chars = text.chars().peekable();
    let (mut comment, mut string) = (false, false);
    while let Some(ch) = chars.next() {
        column += 1;
        if ch == '\n' {
            (line, column, comment) = (line + 1, 0, false);
            continue;
        }
        if comment {
            continue;
        }
        if string {
            string = ch != '"';
            continue;
        }
        match ch {
            '/' if chars.peek() == Some(&'/') => comment = true,
            '"' => string = true,
            ';' | ',' | '{' | '}' => count = 0,
            '+' | '-' | '*' | '/' => {
                count += 1;
                if count > MAX_OPERATORS {
                    return Err(vec![Diagnostic {
                        line,
                        column,
                        message: format!(
                            "more than {MAX_OPERATORS} operators in one expression: write a \
                             long sum in parts, as `let` aliases"
                        ),
                    }]);
                }
            }
            _ => {}
        }
    }
    Ok(())
}

/// Every error of `e`, located.
fn diagnostics(e: syn::Error) -> Vec<Diagnostic> {
    e.into_iter()
        .map(|e| {
            let start = e.span().start();
            Diagnostic { line: start.line, column: start.column + 1, message: e.to_string() }
        })
        .collect()
}

/// `QuarterCar` → `quarter-car` (underscores become dashes too).
pub fn kebab(name: &str) -> String {
    let mut out = String::new();
    for ch in name.chars() {
        let boundary = ch == '_' || ch.is_uppercase();
        if boundary && !out.is_empty() && !out.ends_with('-') {
            out.push('-');
        }
        if ch != '_' {
            out.extend(ch.to_lowercase());
        }
    }
    out
}

/// The equations as text: `lhs = rhs`, then one `where` line per alias.
pub fn equation_text(def: &ModelDef) -> Vec<String> {
    let mut eq_text: Vec<String> =
        def.equations.iter().map(|e| format!("{} = {}", show(&e.lhs), show(&e.rhs))).collect();
    for l in &def.lets {
        eq_text.push(format!("where {} = {}", l.name, show(&l.expr)));
    }
    eq_text
}

#[cfg(test)]
mod tests {
    #[test]
    fn kebab_case_names() {
        assert_eq!(super::kebab("QuarterCar"), "quarter-car");
        assert_eq!(super::kebab("Duffing"), "duffing");
        assert_eq!(super::kebab("FractionalDuffing"), "fractional-duffing");
        assert_eq!(super::kebab("Two_Mass"), "two-mass");
        assert_eq!(super::kebab("Chain3"), "chain3");
    }

    #[test]
    fn a_sum_too_long_to_recurse_on_is_an_error_a_long_one_is_not() {
        let model = |terms: usize| {
            format!(
                "struct S {{ params {{ k = 1.0 }} dofs {{ x }}\n\
                 // a comment's - and + do not count: - - - -\n\
                 equations {{ D(x, 2) + k * x{} = 0.0; }} outputs {{ s = x{} }} }}",
                " + x".repeat(terms),
                " - x".repeat(terms)
            )
        };
        // On the stack the reader asks for, the longest accepted chain is read.
        let long = model(super::MAX_OPERATORS - 5);
        let ok = std::thread::Builder::new()
            .stack_size(super::STACK_BYTES)
            .spawn(move || super::read(&long).is_ok())
            .unwrap()
            .join()
            .unwrap();
        assert!(ok);
        let e = super::read(&model(20_000)).err().unwrap();
        assert_eq!(e[0].line, 3);
        assert!(e[0].message.starts_with("more than 10000 operators in one expression"), "{e:?}");
    }

    #[test]
    fn deep_nesting_is_an_error_with_its_place() {
        let text = format!(
            "struct S {{ params {{ }} dofs {{ x }} equations {{ {}x = 0.0; }} }}",
            "(".repeat(5000)
        );
        let e = super::read(&text).err().unwrap();
        assert_eq!(e[0].line, 1);
        assert!(e[0].message.contains("nested more than"), "{}", e[0].message);
    }

    use crate::parse::DomainDecl;

    /// The domain of the one parameter `a` declared as `decl` (`a = ...`).
    fn domain(decl: &str) -> Result<Option<DomainDecl>, (usize, usize, String)> {
        let text = format!(
            "struct S {{ params {{\n{decl} }} dofs {{ x }} equations {{ a * x = 0.0; }} }}"
        );
        match super::read(&text) {
            Ok(c) => Ok(c.def.params[0].domain),
            Err(e) => Err((e[0].line, e[0].column, e[0].message.clone())),
        }
    }

    #[test]
    fn domains_in_every_form() {
        let d = |lower, upper| Ok(Some(DomainDecl { lower, upper }));
        assert_eq!(domain("a = 1.0"), Ok(None));
        assert_eq!(domain("a = 1.0 in (0, inf)"), d(Some((0.0, false)), None));
        assert_eq!(domain("a = 1.5 in [1, 2]"), d(Some((1.0, true)), Some((2.0, true))));
        assert_eq!(domain("a = -3 in (-inf, -1e-3)"), d(None, Some((-1e-3, false))));
        assert_eq!(domain("a = 0 in \"[0, inf)\""), d(Some((0.0, true)), None));
        assert_eq!(domain("a = 2 in \" ( 1.5 ,2 ] \""), d(Some((1.5, false)), Some((2.0, true))));
        assert_eq!(domain("a = 2 in [2, 2]"), d(Some((2.0, true)), Some((2.0, true))));
        assert_eq!(domain("a = 5 in \"(-inf, inf)\""), d(None, None));
    }

    #[test]
    fn domain_errors_point_at_the_offending_token() {
        let err = |decl: &str| domain(decl).unwrap_err();
        // Line 2 is the declaration; columns count from its start.
        let (l, c, m) = err("a = 0.5 in (1, 2)");
        assert_eq!((l, c), (2, 5), "{m}");
        assert!(m.contains("default 0.5 of `a` is outside its declared domain (1, 2)"), "{m}");
        let (l, c, m) = err("a = 0.5 in (2, 1)");
        assert_eq!((l, c), (2, 13), "{m}");
        assert!(m.contains("lower end 2 is above its upper end 1"), "{m}");
        let (_, c, m) = err("a = 1 in (1, 1)");
        assert_eq!(c, 11, "{m}");
        assert!(m.contains("empty"), "{m}");
        let (_, c, m) = err("a = 1 in (inf, inf)");
        assert_eq!(c, 11, "{m}");
        assert!(m.contains("its lower end is `inf`"), "{m}");
        let (_, c, m) = err("a = 1 in (0, x)");
        assert_eq!(c, 14, "{m}");
        assert!(m.contains("`x` is not a bound"), "{m}");
        let (_, c, m) = err("a = 1 in [0, inf]");
        assert_eq!(c, 17, "{m}");
        assert!(m.contains("infinite end of a domain is open"), "{m}");
        let (_, c, m) = err("a = 1 in [-inf, 2]");
        assert_eq!(c, 10, "{m}");
        assert!(m.contains("infinite end"), "{m}");
        let (_, c, m) = err("a = 1 in 0..1");
        assert_eq!(c, 10, "{m}");
        assert!(m.contains("expected a domain after `in`"), "{m}");
        // Inside a string: at the string (as the macro can only do).
        let (_, c, m) = err("a = 1 in \"[0, nan)\"");
        assert_eq!(c, 10, "{m}");
        assert!(m.contains("`nan` is not a bound"), "{m}");
        let (_, c, m) = err("a = 1 in \"[-inf, 0)\"");
        assert_eq!(c, 10, "{m}");
        assert!(m.contains("infinite end"), "{m}");
        let (_, _, m) = err("a = 1 in \"[0, 1\"");
        assert!(m.contains("expected `)` or `]`"), "{m}");
        let (_, _, m) = err("a = 1 in \"[0 1]\"");
        assert!(m.contains("expected `,`"), "{m}");
        let (_, _, m) = err("a = 1 in \"[0, 1, 2]\"");
        assert!(m.contains("`1, 2` is not a bound"), "{m}");
        let (_, _, m) = err("a = 1 in \"\"");
        assert!(m.contains("expected `(` or `[`"), "{m}");
    }
}

//! Names: what each declared identifier is (parameter, DOF, `let` alias), the names the
//! language keeps for itself, and the messages for a name declared twice or not at all.
//! An alias is declared after its expression is read, so it sees only earlier names.

use super::diag::{err, Sp};
use std::collections::HashMap;

/// Names the DSL keeps for itself.
pub(super) const RESERVED: [&str; 3] = ["omega", "t", "D"];

/// How a name resolves (the index is the declaration order within its kind).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Name {
    Param(usize),
    Dof(usize),
    Alias(usize),
}

impl Name {
    /// The kind, for messages: "a parameter", "a DOF", "a `let` alias".
    pub fn kind(self) -> &'static str {
        match self {
            Name::Param(_) => "a parameter",
            Name::Dof(_) => "a DOF",
            Name::Alias(_) => "a `let` alias",
        }
    }
}

/// The names declared so far.
#[derive(Debug, Default)]
pub struct Scope {
    names: HashMap<String, Name>,
}

impl Scope {
    /// Declare `ident`; reserved and already declared names are errors.
    pub fn declare(&mut self, ident: &syn::Ident, name: Name) -> syn::Result<()> {
        let s = ident.to_string();
        if RESERVED.contains(&s.as_str()) {
            return err(
                Sp::of(&ident),
                format!(
                    "`{s}` is a reserved name in oscillator! (`omega` is the forcing frequency, \
                     `t` the time, `D` the derivative); choose another name"
                ),
            );
        }
        if let Some(prev) = self.names.get(&s) {
            return err(
                Sp::of(&ident),
                format!("duplicate name `{s}`: already declared as {}", prev.kind()),
            );
        }
        self.names.insert(s, name);
        Ok(())
    }

    /// What `name` is, if it is declared.
    pub fn get(&self, name: &str) -> Option<Name> {
        self.names.get(name).copied()
    }

    /// What `ident` is, or an error listing the names there are.
    pub fn lookup(&self, ident: &syn::Ident) -> syn::Result<Name> {
        let s = ident.to_string();
        if let Some(n) = self.names.get(&s) {
            return Ok(*n);
        }
        if s == "t" {
            return err(
                Sp::of(&ident),
                "`t` may only appear inside forcing `cos(k * omega * t)` / `sin(k * omega * t)`",
            );
        }
        let list = |f: &dyn Fn(&Name) -> bool| {
            let mut v: Vec<&String> =
                self.names.iter().filter(|(_, n)| f(n)).map(|(k, _)| k).collect();
            v.sort();
            v.into_iter().map(|s| s.as_str()).collect::<Vec<_>>().join(", ")
        };
        err(
            Sp::of(&ident),
            format!(
                "unknown name `{s}`: not a parameter ({}), DOF ({}) or `let` alias declared \
                 above ({})",
                list(&|n| matches!(n, Name::Param(_))),
                list(&|n| matches!(n, Name::Dof(_))),
                list(&|n| matches!(n, Name::Alias(_))),
            ),
        )
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    fn id(s: &str) -> syn::Ident {
        syn::Ident::new(s, proc_macro2::Span::call_site())
    }

    #[test]
    fn declared_names_resolve_to_their_kind() {
        let mut s = Scope::default();
        s.declare(&id("k"), Name::Param(0)).unwrap();
        s.declare(&id("x"), Name::Dof(0)).unwrap();
        s.declare(&id("v"), Name::Alias(0)).unwrap();
        assert_eq!(s.lookup(&id("k")).unwrap(), Name::Param(0));
        assert_eq!(s.lookup(&id("x")).unwrap(), Name::Dof(0));
        assert_eq!(s.lookup(&id("v")).unwrap(), Name::Alias(0));
    }

    #[test]
    fn reserved_duplicate_and_unknown_names_are_rejected() {
        let mut s = Scope::default();
        for r in RESERVED {
            let e = s.declare(&id(r), Name::Param(0)).unwrap_err().to_string();
            assert!(e.starts_with(&format!("`{r}` is a reserved name")), "{e}");
        }
        s.declare(&id("b"), Name::Param(0)).unwrap();
        s.declare(&id("a"), Name::Param(1)).unwrap();
        s.declare(&id("x"), Name::Dof(0)).unwrap();
        let e = s.declare(&id("x"), Name::Alias(0)).unwrap_err().to_string();
        assert_eq!(e, "duplicate name `x`: already declared as a DOF");
        // Unknown: every declared name, sorted, by kind.
        let e = s.lookup(&id("y")).unwrap_err().to_string();
        assert_eq!(
            e,
            "unknown name `y`: not a parameter (a, b), DOF (x) or `let` alias declared above ()"
        );
        assert!(s.lookup(&id("t")).unwrap_err().to_string().starts_with("`t` may only appear"));
    }
}

//! The analysed model: one residual tree per equation over numbered signals, shared
//! alias trees, and the outputs. Checking ends here; code generation (or any other
//! reader of a model) starts here and needs no `syn`.

/// A linear combination `Σ coef · x_dof` with literal coefficients.
pub type Terms = Vec<(usize, f64)>;

/// The derivative order of a signal.
#[derive(Debug, Clone, Copy, PartialEq)]
pub enum OrderKey {
    Int(u32),
    Param(usize),
}

/// `D^order (Σ coef · x_dof)`, literal coefficients.
#[derive(Debug, Clone, PartialEq)]
pub struct SignalKey {
    pub terms: Terms,
    pub order: OrderKey,
}

/// Forcing functions.
#[derive(Debug, Clone, Copy, PartialEq, Eq, PartialOrd, Ord, Hash)]
pub enum Trig {
    Cos,
    Sin,
}

/// The smooth functions a coefficient may apply (never to a DOF or to forcing: the
/// residual stays polynomial in the signals, its coefficients need not be).
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Func {
    Sqrt,
    Exp,
    Ln,
    Sin,
    Cos,
    Tan,
    Abs,
}

impl Func {
    /// Every function, in the order messages list them.
    pub const ALL: [Func; 7] =
        [Func::Sqrt, Func::Exp, Func::Ln, Func::Sin, Func::Cos, Func::Tan, Func::Abs];

    /// The list of coefficient-only functions, for messages (`abs` applies to DOF terms
    /// too, as a [`Kink`]).
    pub fn list() -> String {
        let names: Vec<String> = Func::ALL
            .iter()
            .filter(|f| **f != Func::Abs)
            .map(|f| format!("`{}`", f.name()))
            .collect();
        format!("{} and `.powf(q)`", names.join(", "))
    }

    /// Its name in the DSL (as a function `sqrt(e)` or a method `e.sqrt()`), which is
    /// also the method of `f64` and `DualNum` that computes it.
    pub fn name(self) -> &'static str {
        match self {
            Func::Sqrt => "sqrt",
            Func::Exp => "exp",
            Func::Ln => "ln",
            Func::Sin => "sin",
            Func::Cos => "cos",
            Func::Tan => "tan",
            Func::Abs => "abs",
        }
    }

    /// The function called `name`, if there is one.
    pub fn named(name: &str) -> Option<Func> {
        Func::ALL.into_iter().find(|f| f.name() == name)
    }
}

/// The non-smooth functions, which apply to any expression (DOFs, their derivatives,
/// forcing): a bump stop `max(0, y - gap)`, an asymmetric damper, a tyre that cannot
/// pull. A model that applies one to signals or time is not smooth, and its
/// transform is sampled for accuracy rather than alias-free.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Kink {
    Max,
    Min,
    Abs,
    Sign,
}

impl Kink {
    /// Every one, in the order messages list them.
    pub const ALL: [Kink; 4] = [Kink::Max, Kink::Min, Kink::Abs, Kink::Sign];

    /// Its name in the DSL and in `ihbm::model::kink`.
    pub fn name(self) -> &'static str {
        match self {
            Kink::Max => "max",
            Kink::Min => "min",
            Kink::Abs => "abs",
            Kink::Sign => "sign",
        }
    }

    /// The number of arguments.
    pub fn arity(self) -> usize {
        match self {
            Kink::Max | Kink::Min => 2,
            Kink::Abs | Kink::Sign => 1,
        }
    }

    /// How it is written, for messages: `max(a, b)`.
    pub fn usage(self) -> &'static str {
        match self {
            Kink::Max => "max(a, b)",
            Kink::Min => "min(a, b)",
            Kink::Abs => "abs(e)",
            Kink::Sign => "sign(e)",
        }
    }

    /// The one called `name`, if there is one.
    pub fn named(name: &str) -> Option<Kink> {
        Kink::ALL.into_iter().find(|k| k.name() == name)
    }

    /// `max(a, b)`, `min(a, b)`, `abs(e)` and `sign(e)`, for messages.
    pub fn list() -> String {
        let names: Vec<String> = Kink::ALL.iter().map(|k| format!("`{}`", k.usage())).collect();
        names.join(", ")
    }

    /// Its value for plain numbers (what the generated code computes for constants).
    pub fn eval(self, args: &[f64]) -> f64 {
        let (a, b) = (args[0], args.get(1).copied().unwrap_or(0.0));
        match self {
            Kink::Max if a > b => a,
            Kink::Max if a < b => b,
            Kink::Min if a < b => a,
            Kink::Min if a > b => b,
            Kink::Max | Kink::Min => 0.5 * (a + b),
            Kink::Abs if a < 0.0 => -a,
            Kink::Abs if a == 0.0 => 0.0,
            Kink::Abs => a,
            Kink::Sign if a > 0.0 => 1.0,
            Kink::Sign if a < 0.0 => -1.0,
            Kink::Sign if a == 0.0 => 0.0,
            Kink::Sign => f64::NAN,
        }
    }
}

/// A coefficient subexpression that may not be finite at run time (a function, a
/// quotient, a real power): the generated `check_coefficients` evaluates it and names
/// it by its source text when it is not.
#[derive(Debug, Clone)]
pub struct Check {
    /// The source text, for the error message.
    pub text: String,
    /// Its tree, aliases expanded (it holds parameters, literals and Ω only).
    pub node: Node,
}

/// The resolved expression tree the residual is generated from.
#[derive(Debug, Clone)]
pub enum Node {
    Lit(f64),
    Param(usize),
    Omega,
    Signal(usize),
    /// The value of alias `i` (its tree is in `Analysis::aliases`).
    Alias(usize),
    /// `cos/sin(k * omega * t)`.
    Forcing(Trig, u32),
    Add(Box<Node>, Box<Node>),
    Sub(Box<Node>, Box<Node>),
    Mul(Box<Node>, Box<Node>),
    Div(Box<Node>, Box<Node>),
    Neg(Box<Node>),
    Powi(Box<Node>, u32),
    /// A smooth function of a coefficient.
    Func(Func, Box<Node>),
    /// `base.powf(exponent)`, both coefficients.
    Powf(Box<Node>, Box<Node>),
    /// A non-smooth function of any expressions (one or two, [`Kink::arity`]).
    Kink(Kink, Vec<Node>),
}

impl Node {
    /// Calls `f` on each direct subtree, left to right (an alias is a leaf here).
    pub fn for_each_child<'a>(&'a self, mut f: impl FnMut(&'a Node)) {
        match self {
            Node::Add(x, y)
            | Node::Sub(x, y)
            | Node::Mul(x, y)
            | Node::Div(x, y)
            | Node::Powf(x, y) => {
                f(x);
                f(y);
            }
            Node::Neg(x) | Node::Powi(x, _) | Node::Func(_, x) => f(x),
            Node::Kink(_, args) => args.iter().for_each(f),
            Node::Lit(_)
            | Node::Param(_)
            | Node::Omega
            | Node::Signal(_)
            | Node::Alias(_)
            | Node::Forcing(..) => {}
        }
    }

    /// The parameters the tree reads (aliases are leaves), sorted, each once.
    pub fn params(&self) -> Vec<usize> {
        fn collect(n: &Node, out: &mut Vec<usize>) {
            match n {
                Node::Param(i) if !out.contains(i) => out.push(*i),
                other => other.for_each_child(|c| collect(c, out)),
            }
        }
        let mut out = Vec::new();
        collect(self, &mut out);
        out.sort_unstable();
        out
    }

    /// [`Node::for_each_child`], mutably.
    pub fn for_each_child_mut(&mut self, mut f: impl FnMut(&mut Node)) {
        match self {
            Node::Add(x, y)
            | Node::Sub(x, y)
            | Node::Mul(x, y)
            | Node::Div(x, y)
            | Node::Powf(x, y) => {
                f(x);
                f(y);
            }
            Node::Neg(x) | Node::Powi(x, _) | Node::Func(_, x) => f(x),
            Node::Kink(_, args) => args.iter_mut().for_each(f),
            _ => {}
        }
    }
}

/// What an output is.
#[derive(Debug, Clone, PartialEq)]
pub enum OutputDef {
    /// A linear combination of DOFs with literal coefficients (combined from the
    /// coefficients exactly).
    Dofs(Terms),
    /// Tree `i` of [`Analysis::output_exprs`].
    Expression(usize),
}

/// A `let` alias: its tree, and whether the residual uses it.
#[derive(Debug, Clone)]
pub struct Alias {
    pub node: Node,
    pub used: bool,
}

/// The analysed model.
pub struct Analysis {
    pub signals: Vec<SignalKey>,
    /// Aliases in declaration order (an alias refers only to earlier ones).
    pub aliases: Vec<Alias>,
    /// One residual tree per equation (`lhs - rhs`).
    pub equations: Vec<Node>,
    /// `(name, what it is)` per output.
    pub outputs: Vec<(String, OutputDef)>,
    /// The signals the expression outputs read (a list of their own: the residual
    /// does not pay for them).
    pub output_signals: Vec<SignalKey>,
    /// One tree per expression output, over `output_signals`, aliases expanded.
    pub output_exprs: Vec<Node>,
    /// The coefficient subexpressions to check at run time, innermost first, from the
    /// equations and the used aliases.
    pub checks: Vec<Check>,
}

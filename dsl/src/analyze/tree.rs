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

    /// The list of coefficient functions, for messages.
    pub fn list() -> String {
        let names: Vec<String> = Func::ALL.iter().map(|f| format!("`{}`", f.name())).collect();
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

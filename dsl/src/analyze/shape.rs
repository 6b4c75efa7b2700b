//! Shape analysis of the lowered model: its polynomial degree in the signals, its
//! highest forcing harmonic and the highest harmonic of a parametric (time-varying)
//! coefficient of a signal term, the signals every equation is affine in (constant
//! gradient over a period, so the solvers may skip their sampling), and whether Ω
//! appears other than inside the forcing (a coefficient that depends on Ω does). All
//! are read off the trees, conservatively.

use super::tree::{Analysis, Node};
use std::collections::BTreeSet;

/// What a subtree is: which signals it contains, which of them it is not affine in
/// (with a coefficient free of signals and time), whether it varies in time or uses Ω,
/// its degree in the signals and its highest forcing harmonic.
#[derive(Debug, Clone, Default)]
struct Shape {
    present: BTreeSet<usize>,
    nonaffine: BTreeSet<usize>,
    timed: bool,
    omega: bool,
    degree: u32,
    max_k: u32,
    /// The highest harmonic of a time-varying factor multiplying signals.
    param_k: u32,
    /// Whether a non-smooth function of signals or time is in it.
    kinked: bool,
}

impl Shape {
    /// The shape of a sum.
    fn union(mut self, o: &Shape) -> Shape {
        self.present.extend(&o.present);
        self.nonaffine.extend(&o.nonaffine);
        self.timed |= o.timed;
        self.omega |= o.omega;
        self.degree = self.degree.max(o.degree);
        self.max_k = self.max_k.max(o.max_k);
        self.param_k = self.param_k.max(o.param_k);
        self.kinked |= o.kinked;
        self
    }
}

/// The shape of `n`, conservatively: a signal multiplied by anything that holds a
/// signal or varies in time counts as non-affine even if terms cancel (that only costs
/// speed; the converse would give wrong Jacobians), and so does the degree.
fn shape(n: &Node, aliases: &[Shape]) -> Shape {
    match n {
        Node::Lit(_) | Node::Param(_) => Shape::default(),
        Node::Omega => Shape { omega: true, ..Shape::default() },
        Node::Forcing(_, k) => Shape { timed: true, max_k: *k, ..Shape::default() },
        Node::Signal(s) => Shape { present: BTreeSet::from([*s]), degree: 1, ..Shape::default() },
        Node::Alias(i) => aliases[*i].clone(),
        // A function of a coefficient is a coefficient: degree 0, Ω if its argument has it.
        Node::Neg(a) | Node::Func(_, a) => shape(a, aliases),
        Node::Add(a, b) | Node::Sub(a, b) | Node::Powf(a, b) => {
            shape(a, aliases).union(&shape(b, aliases))
        }
        Node::Mul(a, b) | Node::Div(a, b) => {
            let (sa, sb) = (shape(a, aliases), shape(b, aliases));
            let mut out = sa.clone().union(&sb);
            for (x, y) in [(&sa, &sb), (&sb, &sa)] {
                if !y.present.is_empty() || y.timed {
                    out.nonaffine.extend(&x.present);
                }
                // Parametric excitation: `cos(kΩt) · signals` adds k to the harmonics.
                if y.timed && !x.present.is_empty() && matches!(n, Node::Mul(..)) {
                    out.param_k = out.param_k.max(y.max_k);
                }
            }
            if matches!(n, Node::Mul(..)) {
                out.degree = sa.degree + sb.degree;
            }
            out
        }
        // A kink of signals or time: non-smooth, and not affine in any signal it holds
        // (its gradient switches); its degree is its arguments' (it is homogeneous of
        // degree one in them where it is not constant).
        Node::Kink(_, args) => {
            let mut out =
                args.iter().fold(Shape::default(), |acc, a| acc.union(&shape(a, aliases)));
            if !out.present.is_empty() || out.timed {
                out.kinked = true;
                let p = out.present.clone();
                out.nonaffine.extend(p);
            }
            out
        }
        Node::Powi(a, k) => match *k {
            0 => Shape::default(),
            1 => shape(a, aliases),
            _ => {
                let mut s = shape(a, aliases);
                let p = s.present.clone();
                s.nonaffine.extend(p);
                s.degree *= k;
                s
            }
        },
    }
}

/// The model's shape, as the `Model` impl reports it.
#[derive(Debug, Clone, PartialEq)]
pub struct ModelShape {
    /// Polynomial degree in the signals (at least 1).
    pub degree: u32,
    /// Highest harmonic `k` of `cos/sin(k * omega * t)` (forcing or parametric); 0 if
    /// the equations do not depend on time.
    pub max_harmonic: u32,
    /// Highest harmonic of a time-varying factor that multiplies signals (parametric
    /// excitation, `(1 + eps * cos(2 * omega * t)) * x`); 0 if there is none.
    pub parametric_harmonic: u32,
    /// Per signal: every equation is affine in it with a signal- and time-free
    /// coefficient (its gradient is constant over a period).
    pub affine: Vec<bool>,
    /// Whether some equation uses `omega` other than inside `cos/sin(k * omega * t)`.
    pub explicit_omega: bool,
    /// Per equation and signal (`e * signals + s`): the signal appears in the
    /// equation (through its aliases too), so its derivative there may be non-zero.
    pub reads: Vec<bool>,
    /// Whether no equation applies a non-smooth function (`max`, `min`, `abs`, `sign`)
    /// to signals or time.
    pub smooth: bool,
}

impl Analysis {
    /// The polynomial degree of the expression outputs in their signals (at least 1).
    pub fn output_degree(&self) -> u32 {
        self.output_exprs.iter().map(|e| shape(e, &[]).degree).max().unwrap_or(1).max(1)
    }

    /// Whether no expression output applies a non-smooth function to signals or time.
    pub fn outputs_smooth(&self) -> bool {
        !self.output_exprs.iter().any(|e| shape(e, &[]).kinked)
    }

    /// The shape of the equations (aliases counted where they are used).
    pub fn shape(&self) -> ModelShape {
        let mut aliases: Vec<Shape> = Vec::with_capacity(self.aliases.len());
        for alias in &self.aliases {
            let s = shape(&alias.node, &aliases);
            aliases.push(s);
        }
        let each: Vec<Shape> = self.equations.iter().map(|e| shape(e, &aliases)).collect();
        let nsig = self.signals.len();
        let reads = each.iter().flat_map(|e| (0..nsig).map(|i| e.present.contains(&i))).collect();
        let s = each.iter().fold(Shape::default(), |acc, e| acc.union(e));
        ModelShape {
            degree: s.degree.max(1),
            max_harmonic: s.max_k,
            parametric_harmonic: s.param_k,
            affine: (0..self.signals.len()).map(|i| !s.nonaffine.contains(&i)).collect(),
            explicit_omega: s.omega,
            reads,
            smooth: !s.kinked,
        }
    }
}

#[cfg(test)]
mod tests {
    use crate::analyze::analyze;
    use crate::analyze::shape::ModelShape;

    /// The shape of a one- or two-DOF model with these equations (signals: x = 0, y = 1
    /// when both are used in that order).
    fn shape_of(equations: &str) -> ModelShape {
        let src = format!(
            "struct S {{ params {{ a = 1.0, p = 0.5 }} dofs {{ x, y }} let v = x * y;
               equations {{ {equations} }} }}"
        );
        analyze(&syn::parse_str(&src).unwrap()).unwrap().shape()
    }

    #[test]
    fn degree_is_the_highest_product_order() {
        assert_eq!(shape_of("a * x + y = 0.0; y = 0.0;").degree, 1);
        assert_eq!(shape_of("x * y.powi(2) = 0.0; y = x / a;").degree, 3);
        // An alias counts where it is used: v = x y, so v.powi(2) has degree 4.
        assert_eq!(shape_of("v.powi(2) + x = 0.0; y = 0.0;").degree, 4);
        // .powi(0) is the constant 1.
        assert_eq!(shape_of("x.powi(0) + x = 0.0; y = 0.0;").degree, 1);
    }

    #[test]
    fn max_harmonic_is_the_highest_forcing_k() {
        assert_eq!(shape_of("x = 0.0; y = 0.0;").max_harmonic, 0);
        let s = shape_of("x = a * cos(omega * t) + sin(3 * omega * t); y = cos(2 * omega * t);");
        assert_eq!(s.max_harmonic, 3);
    }

    #[test]
    fn parametric_harmonic_is_the_highest_k_multiplying_signals() {
        // Forcing alone is not parametric.
        assert_eq!(shape_of("x = cos(3 * omega * t); y = 0.0;").parametric_harmonic, 0);
        let s = shape_of(
            "(1.0 + a * cos(2 * omega * t)) * x + x.powi(3) = cos(3 * omega * t); y = 0.0;",
        );
        assert_eq!((s.parametric_harmonic, s.max_harmonic, s.degree), (2, 3, 3));
        // The factor may come after the signal, and through an alias (v = x y).
        let s = shape_of("v * sin(omega * t) = 0.0; y = 0.0;");
        assert_eq!((s.parametric_harmonic, s.degree), (1, 2));
        // A parametric term is not affine: its gradient varies over the period.
        assert_eq!(shape_of("cos(omega * t) * x = 0.0; y = 0.0;").affine, [false, true]);
    }

    #[test]
    fn coefficient_functions_of_omega_make_omega_explicit() {
        let s = shape_of("a * cos(omega * a) * x + y = 0.0; y = 0.0;");
        assert!(s.explicit_omega);
        // affine: the coefficient depends on parameters and Ω only
        assert_eq!((s.affine.clone(), s.degree), (vec![true, true], 1));
        let s = shape_of("a.sqrt() * x + a.powf(0.5) * y = 0.0; y = 0.0;");
        assert!(!s.explicit_omega);
    }

    #[test]
    fn reads_follow_the_equations_and_their_aliases() {
        // signals in order of appearance: x (0), D(x, 1) (1), y (2); `v` reads x and y
        let src = "struct S { params { a = 1.0 } dofs { x, y } let v = x * y;
            equations { D(x, 1) + a * x = 0.0; v + y = 0.0; } }";
        let a = analyze(&syn::parse_str(src).unwrap()).unwrap();
        let nsig = a.signals.len();
        let reads = a.shape().reads;
        assert_eq!(reads.len(), 2 * nsig);
        let read = |e: usize| (0..nsig).filter(|&s| reads[e * nsig + s]).count();
        assert_eq!(read(0), 2, "{reads:?}");
        assert_eq!(read(1), 2, "{reads:?}");
        assert!(reads.iter().zip(&reads[nsig..]).any(|(a, b)| a != b));
    }

    #[test]
    fn affine_signals_have_constant_coefficients() {
        // x multiplies y: neither is affine; D(x, 1) is scaled by a parameter and Ω.
        let s = shape_of("a * omega * D(x, 1) + x * y = cos(omega * t); y = 0.0;");
        // Signals in first use: D(x, 1), x, y.
        assert_eq!(s.affine, [true, false, false]);
        assert!(s.explicit_omega);
        // Forcing alone does not make a signal non-affine, nor is its Ω explicit.
        let s = shape_of("x + D(y, p) = cos(omega * t); y = 0.0;");
        assert_eq!(s.affine, [true, true, true]);
        assert!(!s.explicit_omega);
        // A cube is not affine.
        assert_eq!(shape_of("x.powi(3) + y = 0.0; y = 0.0;").affine, [false, true]);
    }
}

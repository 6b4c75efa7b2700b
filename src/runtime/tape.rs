//! A compiled program (tape) for expression trees of the model language, evaluated over
//! any dual number type: what the macro's straight-line code does, as data.
//!
//! Each instruction writes the register of its own index (single assignment), so a
//! program is a list of operations on earlier results. Compilation folds constant
//! subtrees, computes each used alias once, and keeps literal operands and the
//! forcing values `cos/sin(k·phase)` as `f64`, so that a product with them costs a
//! scaling instead of a dual product — the same economies as the generated code.

use crate::model::kink;
use ihbm_dsl::analyze::{Alias, Func, Kink, Node, Trig};
use num_dual::DualNum;

/// Where an operand comes from.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Arg {
    /// A register (an earlier instruction's result).
    Reg(usize),
    /// A number known when compiling.
    Lit(f64),
    /// `cos/sin(k·phase)`, slot `i` of the per-sample table (a plain number too).
    Time(usize),
}

/// One operation.
#[derive(Debug, Clone, Copy, PartialEq)]
enum Op {
    Param(usize),
    Omega,
    Signal(usize),
    /// A value that is a plain number (a literal, or a forcing term) lifted into a
    /// register: needed only where a whole result is such a number.
    Lift(Arg),
    Add(Arg, Arg),
    Sub(Arg, Arg),
    Mul(Arg, Arg),
    Div(Arg, Arg),
    Neg(usize),
    Powi(usize, i32),
    Func(Func, usize),
    Powf(usize, Arg),
    /// A non-smooth function of one or two operands (the second unused by `abs`, `sign`).
    Kink(Kink, Arg, Arg),
}

/// A compiled list of expressions over parameters, Ω, signals and time.
#[derive(Debug, Clone, Default)]
pub struct Program {
    ops: Vec<Op>,
    /// `(trig, k)` per time slot.
    time: Vec<(Trig, u32)>,
    /// The results, one per compiled root.
    outputs: Vec<Arg>,
}

/// Compiles trees into one program, sharing aliases between them.
struct Compiler<'a> {
    program: Program,
    aliases: &'a [Alias],
    /// Compiled aliases (each once, when first used).
    alias_args: Vec<Option<Arg>>,
}

impl Program {
    /// Compile `roots` (their aliases from `aliases`) into one program whose outputs
    /// are the roots' values in order.
    pub fn compile<'n>(roots: impl IntoIterator<Item = &'n Node>, aliases: &[Alias]) -> Program {
        let mut c = Compiler {
            program: Program::default(),
            aliases,
            alias_args: vec![None; aliases.len()],
        };
        for root in roots {
            let out = c.node(root);
            c.program.outputs.push(out);
        }
        c.program
    }

    /// Number of registers (instructions).
    pub fn len(&self) -> usize {
        self.ops.len()
    }

    /// Whether the program computes nothing but constants.
    pub fn is_empty(&self) -> bool {
        self.ops.is_empty()
    }

    /// Number of results.
    pub fn outputs(&self) -> usize {
        self.outputs.len()
    }

    /// Evaluate into `out` (one value per root), with `regs` as scratch of at least
    /// [`Program::len`] values.
    pub fn eval<D: DualNum<Primitive = f64> + Copy>(
        &self,
        regs: &mut [D],
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        // A model's forcing has a harmonic or two: a small table on the stack.
        let mut time = [0.0f64; 8];
        let mut heap = Vec::new();
        let time: &mut [f64] = if self.time.len() <= time.len() {
            &mut time[..self.time.len()]
        } else {
            heap.resize(self.time.len(), 0.0);
            &mut heap
        };
        for (t, &(trig, k)) in time.iter_mut().zip(&self.time) {
            let x = k as f64 * phase;
            *t = match trig {
                Trig::Cos => x.cos(),
                Trig::Sin => x.sin(),
            };
        }
        let num = |a: Arg| match a {
            Arg::Lit(v) => Some(v),
            Arg::Time(i) => Some(time[i]),
            Arg::Reg(_) => None,
        };
        for i in 0..self.ops.len() {
            let r = |a: Arg| match a {
                Arg::Reg(j) => regs[j],
                other => D::from(num(other).unwrap_or(0.0)),
            };
            let v = match self.ops[i] {
                Op::Param(j) => params[j],
                Op::Omega => omega,
                Op::Signal(j) => signals[j],
                Op::Lift(a) => r(a),
                Op::Add(a, b) => match (num(a), num(b)) {
                    (_, Some(y)) => r(a) + y,
                    (Some(x), _) => r(b) + x,
                    _ => r(a) + r(b),
                },
                Op::Sub(a, b) => match (num(a), num(b)) {
                    (_, Some(y)) => r(a) - y,
                    (Some(x), _) => -r(b) + x,
                    _ => r(a) - r(b),
                },
                Op::Mul(a, b) => match (num(a), num(b)) {
                    (_, Some(y)) => r(a) * y,
                    (Some(x), _) => r(b) * x,
                    _ => r(a) * r(b),
                },
                Op::Div(a, b) => match num(b) {
                    Some(y) => r(a) / y,
                    None => r(a) / r(b),
                },
                Op::Neg(a) => -regs[a],
                Op::Powi(a, n) => regs[a].powi(n),
                Op::Func(f, a) => {
                    let x = regs[a];
                    match f {
                        Func::Sqrt => x.sqrt(),
                        Func::Exp => x.exp(),
                        Func::Ln => x.ln(),
                        Func::Sin => x.sin(),
                        Func::Cos => x.cos(),
                        Func::Tan => x.tan(),
                        Func::Abs => x.abs(),
                    }
                }
                Op::Powf(a, b) => match num(b) {
                    Some(y) => regs[a].powf(y),
                    None => regs[a].powd(r(b)),
                },
                Op::Kink(k, a, b) => match k {
                    Kink::Max => kink::max(r(a), r(b)),
                    Kink::Min => kink::min(r(a), r(b)),
                    Kink::Abs => kink::abs(r(a)),
                    Kink::Sign => kink::sign(r(a)),
                },
            };
            regs[i] = v;
        }
        for (o, &a) in out.iter_mut().zip(&self.outputs) {
            *o = match a {
                Arg::Reg(j) => regs[j],
                other => D::from(num(other).unwrap_or(0.0)),
            };
        }
    }
}

impl Compiler<'_> {
    /// Append `op`; its register.
    fn emit(&mut self, op: Op) -> usize {
        self.program.ops.push(op);
        self.program.ops.len() - 1
    }

    /// Append `op`; its result as an operand.
    fn push(&mut self, op: Op) -> Arg {
        Arg::Reg(self.emit(op))
    }

    /// A register holding `a`.
    fn reg(&mut self, a: Arg) -> usize {
        match a {
            Arg::Reg(i) => i,
            other => self.emit(Op::Lift(other)),
        }
    }

    fn node(&mut self, n: &Node) -> Arg {
        match n {
            Node::Lit(v) => Arg::Lit(*v),
            Node::Param(i) => self.push(Op::Param(*i)),
            Node::Omega => self.push(Op::Omega),
            Node::Signal(i) => self.push(Op::Signal(*i)),
            Node::Alias(i) => {
                if let Some(a) = self.alias_args[*i] {
                    return a;
                }
                let aliases = self.aliases;
                let a = self.node(&aliases[*i].node);
                self.alias_args[*i] = Some(a);
                a
            }
            Node::Forcing(trig, k) => {
                let slot = match self.program.time.iter().position(|&t| t == (*trig, *k)) {
                    Some(s) => s,
                    None => {
                        self.program.time.push((*trig, *k));
                        self.program.time.len() - 1
                    }
                };
                Arg::Time(slot)
            }
            Node::Add(x, y) => self.binary(x, y, |a, b| a + b, Op::Add),
            Node::Sub(x, y) => self.binary(x, y, |a, b| a - b, Op::Sub),
            Node::Mul(x, y) => self.binary(x, y, |a, b| a * b, Op::Mul),
            Node::Div(x, y) => self.binary(x, y, |a, b| a / b, Op::Div),
            Node::Neg(x) => match self.node(x) {
                Arg::Lit(v) => Arg::Lit(-v),
                a => {
                    let r = self.reg(a);
                    self.push(Op::Neg(r))
                }
            },
            Node::Powi(x, n) => {
                let a = self.node(x);
                if let Arg::Lit(v) = a {
                    return Arg::Lit(v.powi(*n as i32));
                }
                // Small powers as products, as the generated code writes them.
                match n {
                    0 => Arg::Lit(1.0),
                    1 => a,
                    2 => self.push(Op::Mul(a, a)),
                    3 => {
                        let t2 = self.push(Op::Mul(a, a));
                        self.push(Op::Mul(t2, a))
                    }
                    4 => {
                        let t2 = self.push(Op::Mul(a, a));
                        self.push(Op::Mul(t2, t2))
                    }
                    _ => {
                        let r = self.reg(a);
                        self.push(Op::Powi(r, *n as i32))
                    }
                }
            }
            Node::Func(f, x) => {
                let a = self.node(x);
                let r = self.reg(a);
                self.push(Op::Func(*f, r))
            }
            Node::Powf(x, y) => {
                let (a, b) = (self.node(x), self.node(y));
                let r = self.reg(a);
                self.push(Op::Powf(r, b))
            }
            Node::Kink(k, args) => {
                let ops: Vec<Arg> = args.iter().map(|x| self.node(x)).collect();
                let (a, b) = (ops[0], ops.get(1).copied().unwrap_or(Arg::Lit(0.0)));
                match (a, b) {
                    (Arg::Lit(u), Arg::Lit(v)) => Arg::Lit(k.eval(&[u, v][..k.arity()])),
                    _ => self.push(Op::Kink(*k, a, b)),
                }
            }
        }
    }

    /// A binary operation, folded when both operands are literals.
    fn binary(
        &mut self,
        x: &Node,
        y: &Node,
        fold: fn(f64, f64) -> f64,
        op: fn(Arg, Arg) -> Op,
    ) -> Arg {
        let (a, b) = (self.node(x), self.node(y));
        match (a, b) {
            (Arg::Lit(u), Arg::Lit(v)) => Arg::Lit(fold(u, v)),
            _ => self.push(op(a, b)),
        }
    }
}

//! Models read at run time: the text of one `oscillator!` body, checked by the same
//! front end as the macro (`ihbm-dsl`, so the same language and the same messages), its
//! equations compiled once into a [`tape::Program`] evaluated over dual numbers.
//!
//! ```
//! use ihbm::runtime::RuntimeModel;
//! use ihbm::Model;
//!
//! let text = "
//!     /// Duffing oscillator.
//!     pub struct Duffing {
//!         params { m = 1.0, c = 0.1, k = 1.0, k3 = 0.5, F = 0.3 }
//!         dofs { x }
//!         equations { m * D(x, 2) + c * D(x, 1) + k * x + k3 * x.powi(3) = F * cos(omega * t); }
//!     }";
//! let mut model = RuntimeModel::from_text(text, "duffing.ihbm")?;
//! assert_eq!(model.name(), "duffing");
//! model.set_param("k3", 0.0)?;
//! // Linear now: amplitude F / |k − mΩ² + icΩ| at Ω = 1.3.
//! let sol = ihbm::corrector::solve(&model, 1.3, &Default::default(), None)?;
//! let exact = 0.3 / num_complex::Complex64::new(1.0 - 1.69, 0.13).norm();
//! assert!((sol.outputs(&model)[0].amp1 - exact).abs() < 1e-12 * exact);
//!
//! // Errors point into the text.
//! let bad = RuntimeModel::from_text("struct S { params { } dofs { x }\n  equations { x.sin() = 0.0; } }", "s.ihbm");
//! assert!(bad.unwrap_err().to_string().starts_with("s.ihbm:2:15: "));
//! # Ok::<(), ihbm::Error>(())
//! ```

pub mod tape;

use crate::error::Error;
use crate::model::{Bound, Domain, Model, Order, Output, ParamInfo, Signal, Text};
use ihbm_dsl::analyze::{OrderKey, OutputDef};
use num_dual::DualNum;
use std::borrow::Cow::Owned;
use std::path::Path;
use tape::Program;

/// The largest model file read (bytes): a model is a page of text; anything far larger
/// is a mistake, refused before it is parsed.
pub const MAX_TEXT_BYTES: usize = 1 << 20;

/// The error for a text of `len` bytes, over [`MAX_TEXT_BYTES`].
fn too_large(origin: &str, len: u64) -> Error {
    Error::ModelText {
        origin: origin.to_string(),
        diagnostics: format!(
            "{origin}: {len} bytes; a model file is at most {MAX_TEXT_BYTES} bytes"
        ),
    }
}

/// A coefficient checked for finiteness: its text and the parameters it reads.
#[derive(Debug, Clone)]
struct CheckInfo {
    text: String,
    params: Vec<usize>,
}

/// A model read from text at run time; implements [`Model`] like a generated one.
#[derive(Debug, Clone)]
pub struct RuntimeModel {
    name: String,
    description: String,
    dofs: Vec<Text>,
    params: Vec<ParamInfo>,
    values: Vec<f64>,
    signals: Vec<Signal>,
    outputs: Vec<Output>,
    output_signals: Vec<Signal>,
    output_degree: usize,
    outputs_smooth: bool,
    smooth: bool,
    equations: Vec<Text>,
    degree: usize,
    max_harmonic: usize,
    parametric_harmonic: usize,
    affine: Vec<bool>,
    reads: Vec<bool>,
    explicit_omega: bool,
    residual: Program,
    /// The expression outputs.
    output_program: Program,
    checks: Program,
    check_info: Vec<CheckInfo>,
}

/// Scratch registers on the stack up to this many; larger programs use the heap.
const INLINE_REGISTERS: usize = 96;

impl RuntimeModel {
    /// Read a model from `text`; `origin` (a file name) prefixes every error's
    /// `line:column`.
    pub fn from_text(text: &str, origin: &str) -> Result<RuntimeModel, Error> {
        if text.len() > MAX_TEXT_BYTES {
            return Err(too_large(origin, text.len() as u64));
        }
        // The reader recurses once per operator of a long sum: it runs on a stack of its
        // own, whatever thread asks (a test's, a Python worker's).
        std::thread::scope(|s| {
            let reader = std::thread::Builder::new()
                .stack_size(ihbm_dsl::STACK_BYTES)
                .spawn_scoped(s, || RuntimeModel::build(text, origin));
            match reader {
                Ok(handle) => handle.join().unwrap_or_else(|_| {
                    Err(Error::ModelText {
                        origin: origin.to_string(),
                        diagnostics: format!("{origin}: the model reader stopped unexpectedly"),
                    })
                }),
                Err(_) => RuntimeModel::build(text, origin),
            }
        })
    }

    /// [`RuntimeModel::from_text`] on the calling thread.
    fn build(text: &str, origin: &str) -> Result<RuntimeModel, Error> {
        let checked = ihbm_dsl::read(text).map_err(|d| Error::ModelText {
            origin: origin.to_string(),
            diagnostics: d.iter().map(|d| format!("{origin}:{d}")).collect::<Vec<_>>().join("\n"),
        })?;
        let (def, a) = (&checked.def, &checked.analysis);
        let shape = a.shape();
        let terms = |t: &[(usize, f64)]| -> crate::model::Terms { Owned(t.to_vec()) };
        let signal = |s: &ihbm_dsl::analyze::SignalKey| Signal {
            terms: terms(&s.terms),
            order: match s.order {
                OrderKey::Int(n) => Order::Int(n),
                OrderKey::Param(i) => Order::Param(i),
            },
        };
        let check_info = a
            .checks
            .iter()
            .map(|c| CheckInfo { text: c.text.clone(), params: c.node.params() })
            .collect();
        Ok(RuntimeModel {
            name: checked.name.clone(),
            description: def.doc.clone(),
            dofs: def.dofs.iter().map(|d| Owned(d.to_string())).collect(),
            params: def
                .params
                .iter()
                .map(|p| ParamInfo {
                    name: Owned(p.name.to_string()),
                    default: p.default,
                    doc: Owned(p.doc.clone()),
                    domain: p.domain.map_or(Domain::ANY, |d| {
                        let end = |e: Option<(f64, bool)>| match e {
                            None => Bound::Unbounded,
                            Some((v, true)) => Bound::Closed(v),
                            Some((v, false)) => Bound::Open(v),
                        };
                        Domain { lower: end(d.lower), upper: end(d.upper) }
                    }),
                })
                .collect(),
            values: def.params.iter().map(|p| p.default).collect(),
            signals: a.signals.iter().map(signal).collect(),
            outputs: a
                .outputs
                .iter()
                .map(|(n, def)| match def {
                    OutputDef::Dofs(t) => Output::dofs(n.clone(), terms(t)),
                    OutputDef::Expression(i) => Output::expression(n.clone(), *i),
                })
                .collect(),
            output_signals: a.output_signals.iter().map(signal).collect(),
            output_degree: a.output_degree() as usize,
            outputs_smooth: a.outputs_smooth(),
            smooth: shape.smooth,
            equations: checked.equations.iter().map(|e| Owned(e.clone())).collect(),
            degree: shape.degree as usize,
            max_harmonic: shape.max_harmonic.max(1) as usize,
            parametric_harmonic: shape.parametric_harmonic as usize,
            affine: shape.affine.clone(),
            reads: shape.reads.clone(),
            explicit_omega: shape.explicit_omega,
            residual: Program::compile(&a.equations, &a.aliases),
            output_program: Program::compile(&a.output_exprs, &a.aliases),
            checks: Program::compile(a.checks.iter().map(|c| &c.node), &a.aliases),
            check_info,
        })
    }

    /// Read the model file at `path` (UTF-8 text, at most [`MAX_TEXT_BYTES`]).
    pub fn from_file(path: &Path) -> Result<RuntimeModel, Error> {
        let shown = path.display().to_string();
        let io = |source| Error::Io { path: shown.clone(), source };
        let len = std::fs::metadata(path).map_err(io)?.len();
        // refused before it is read, not only before it is parsed
        if len > MAX_TEXT_BYTES as u64 {
            return Err(too_large(&shown, len));
        }
        let bytes = std::fs::read(path).map_err(io)?;
        let text = String::from_utf8(bytes).map_err(|e| {
            let at = e.utf8_error().valid_up_to();
            let before = &e.as_bytes()[..at];
            let line = before.iter().filter(|&&b| b == b'\n').count() + 1;
            let column = String::from_utf8_lossy(
                &before[before.iter().rposition(|&b| b == b'\n').map_or(0, |i| i + 1)..],
            )
            .chars()
            .count()
                + 1;
            Error::ModelText {
                origin: shown.clone(),
                diagnostics: format!("{shown}:{line}:{column}: not UTF-8 text (byte {at})"),
            }
        })?;
        RuntimeModel::from_text(&text, &shown)
    }

    /// Run `program` with scratch registers of type `D`.
    fn run<D: DualNum<Primitive = f64> + Copy>(
        program: &Program,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        if program.len() <= INLINE_REGISTERS {
            let mut regs = [D::from(0.0); INLINE_REGISTERS];
            program.eval(&mut regs, params, omega, phase, signals, out);
        } else {
            let mut regs = vec![D::from(0.0); program.len()];
            program.eval(&mut regs, params, omega, phase, signals, out);
        }
    }
}

impl Model for RuntimeModel {
    fn name(&self) -> &str {
        &self.name
    }
    fn description(&self) -> &str {
        &self.description
    }
    fn dofs(&self) -> &[Text] {
        &self.dofs
    }
    fn params_info(&self) -> &[ParamInfo] {
        &self.params
    }
    fn param_value(&self, index: usize) -> f64 {
        self.values[index]
    }
    fn set_param_value(&mut self, index: usize, value: f64) {
        self.values[index] = value;
    }
    fn signals(&self) -> &[Signal] {
        &self.signals
    }
    fn outputs(&self) -> &[Output] {
        &self.outputs
    }
    fn output_signals(&self) -> &[Signal] {
        &self.output_signals
    }
    fn output_degree(&self) -> usize {
        self.output_degree
    }
    fn degree(&self) -> usize {
        self.degree
    }
    fn smooth(&self) -> bool {
        self.smooth
    }
    fn outputs_smooth(&self) -> bool {
        self.outputs_smooth
    }
    fn max_forcing_harmonic(&self) -> usize {
        self.max_harmonic
    }
    fn parametric_harmonic(&self) -> usize {
        self.parametric_harmonic
    }
    fn equations(&self) -> &[Text] {
        &self.equations
    }
    fn affine_signals(&self) -> &[bool] {
        &self.affine
    }
    fn signal_reads(&self) -> &[bool] {
        &self.reads
    }
    fn explicit_omega(&self) -> bool {
        self.explicit_omega
    }
    fn residual<D: DualNum<Primitive = f64> + Copy>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        let n = self.dofs.len();
        RuntimeModel::run(&self.residual, params, omega, phase, signals, &mut out[..n]);
    }
    fn output_values<D: DualNum<Primitive = f64> + Copy>(
        &self,
        params: &[D],
        omega: D,
        phase: f64,
        signals: &[D],
        out: &mut [D],
    ) {
        let n = self.output_program.outputs();
        RuntimeModel::run(&self.output_program, params, omega, phase, signals, &mut out[..n]);
    }
    fn check_coefficients(&self, params: &[f64], omega: f64) -> Result<(), Error> {
        if self.check_info.is_empty() {
            return Ok(());
        }
        let mut values = vec![0.0; self.check_info.len()];
        RuntimeModel::run(&self.checks, params, omega, 0.0, &[], &mut values);
        // innermost first, as the macro's checks: the first non-finite one is the cause
        for (v, c) in values.iter().zip(&self.check_info) {
            if !v.is_finite() {
                let reads = if c.params.is_empty() {
                    "none".to_string()
                } else {
                    c.params
                        .iter()
                        .map(|&i| format!("{} = {}", self.params[i].name, params[i]))
                        .collect::<Vec<_>>()
                        .join(", ")
                };
                return Err(Error::NonFiniteCoefficient {
                    model: self.name.clone(),
                    term: c.text.clone(),
                    value: *v,
                    omega,
                    params: reads,
                });
            }
        }
        Ok(())
    }
}

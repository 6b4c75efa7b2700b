//! A user model written with `ihbm::oscillator!`, solved at one frequency and swept.
//!
//! A machine of mass m1 on a hardening mount, with a vibration absorber attached
//! through a viscoelastic element (a spring in parallel with a fractional damper of
//! order p). The book's chapter 4 declares the same model.
//!
//! Run: `cargo run --release --example user_model`

use ihbm::continuation::{sweep, SweepOptions};
use ihbm::corrector::{solve, SolveOptions};
use ihbm::Model;

// ANCHOR: model
ihbm::oscillator! {
    /// Machine on a hardening mount with a viscoelastic (fractional) vibration absorber.
    pub struct Absorber {
        params {
            /// machine mass, kg
            m1 = 10.0,
            /// absorber mass, kg
            m2 = 1.0,
            /// mount stiffness, N/m
            k1 = 1.0e4,
            /// cubic mount stiffness, N/m^3
            k3 = 1.0e7,
            /// mount damping, N s/m
            c1 = 5.0,
            /// absorber stiffness, N/m
            k2 = 1.0e3,
            /// absorber fractional damping, N s^p/m
            h = 20.0,
            /// fractional order of the absorber damping (dimensionless, in [0, 2])
            p = 0.5,
            /// force amplitude, N
            F = 20.0,
        }
        dofs { x1, x2 }
        let rel = x2 - x1;
        let fa = k2 * rel + h * D(rel, p);
        equations {
            m1 * D(x1, 2) + c1 * D(x1, 1) + k1 * x1 + k3 * x1.powi(3) - fa = F * cos(omega * t);
            m2 * D(x2, 2) + fa = 0.0;
        }
        outputs { x1, x2, rel }
    }
}
// ANCHOR_END: model

fn main() -> Result<(), ihbm::Error> {
    run(std::env::args().nth(1))
}

/// Solve and sweep the absorber; `set` is an optional `NAME=VALUE` parameter change.
pub fn run(set: Option<String>) -> Result<(), ihbm::Error> {
    let mut model = Absorber::default();
    // Parameters by name, as the CLI's --set does; an unknown name is an error.
    if let Some(arg) = set {
        let (name, value) = arg.split_once('=').ok_or_else(|| ihbm::Error::InvalidValue {
            what: "parameter change".into(),
            value: format!("'{arg}'"),
            expected: "NAME=VALUE".into(),
        })?;
        let v: f64 = value.parse().map_err(|_| ihbm::Error::InvalidValue {
            what: format!("value of {name}"),
            value: value.to_string(),
            expected: "a number".into(),
        })?;
        model.set_param(name, v)?;
    }
    println!("{}: {}", model.name(), model.description());
    for e in model.equations() {
        println!("  {e}");
    }

    // One periodic solution.
    let sol = solve(&model, 25.0, &SolveOptions::default(), None)?;
    println!(
        "\nΩ = 25 rad/s: {} Newton iterations, residual {:.1e}",
        sol.iterations, sol.residual_norm
    );
    for o in sol.outputs(&model) {
        println!("  {:>3}: max |x| = {:.6e} m, first harmonic {:.6e} m", o.name, o.max_abs, o.amp1);
    }

    // The whole curve, with folds, jumps and stability.
    let curve = sweep(&model, 10.0, 60.0, &SweepOptions::default())?;
    println!(
        "\nsweep 10..60 rad/s, N = {}: {} points, {} steps ({} rejected), {} Newton iterations",
        curve.harmonics,
        curve.points.len(),
        curve.stats.steps,
        curve.stats.rejected_steps,
        curve.stats.corrector_iterations
    );
    for s in &curve.segments {
        println!("  segment {:.3} -> {:.3} rad/s: {}", s.from, s.to, s.ended);
    }
    for f in &curve.folds {
        println!("  fold at Ω = {:.8} rad/s, x1 = {:.6e} m", f.omega, f.outputs[0].max_abs);
    }
    for j in curve.jumps.iter().filter(|j| j.output == "x1") {
        println!(
            "  {:?} sweep jumps at {:.6} rad/s: x1 {:.4e} -> {:.4e} m",
            j.direction, j.at, j.from, j.to
        );
    }
    let unstable = curve.points.iter().filter(|p| p.stability.is_unstable()).count();
    println!("  {unstable} of {} points unstable", curve.points.len());
    println!("\n  Ω (rad/s)   x1 (m)       stable");
    let every = (curve.points.len() / 25).max(1);
    for p in curve.points.iter().step_by(every) {
        println!("  {:9.4}   {:.5e}  {}", p.omega, p.outputs[0].max_abs, p.stability);
    }
    Ok(())
}

//! A user crate gets the whole `ihbm` command line for its own models in three lines.
//!
//! ```text
//! cargo run --example user_cli -- models
//! cargo run --example user_cli -- solve base-isolator --omega 3 --json
//! ```

ihbm::oscillator! {
    /// Base-isolated mass m x'' + c x' + h D^p x + k x + k3 x^3 = F cos(Ωt).
    pub struct BaseIsolator {
        params {
            /// mass, kg
            m = 1.0,
            /// viscous damping, N s/m
            c = 0.05,
            /// fractional damping coefficient, N s^p/m
            h = 0.2,
            /// fractional order
            p = 0.5,
            /// linear stiffness, N/m
            k = 4.0,
            /// cubic stiffness, N/m^3
            k3 = 0.0,
            /// force amplitude, N
            F = 1.0,
        }
        dofs { x }
        equations {
            m * D(x, 2) + c * D(x, 1) + h * D(x, p) + k * x + k3 * x.powi(3) = F * cos(omega * t);
        }
        outputs { x }
    }
}

/// The command line: this crate's model plus the paper's quarter car under a new name.
pub fn cli() -> ihbm::Cli {
    ihbm::Cli::new()
        .model::<BaseIsolator>("base-isolator")
        .model::<ihbm::models::QuarterCar>("my-quarter-car")
}

fn main() -> std::process::ExitCode {
    cli().run()
}

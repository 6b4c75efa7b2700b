//! A family of limit cycles: every output's `max |x(t)|` against the parameter, one
//! panel each, stable solid and unstable dashed, the Hopf point marked on the axis
//! (the equilibrium, amplitude 0). Drawn as the figure of a parameter sweep.

use super::{figure_svg, Figure, Panel, Series, TimeMarker};
use crate::backbone::CycleFamily;
use crate::error::{Drawable, Error};
use crate::report::FreqUnit;
use crate::results::{Curve, CurvePoint, CurveStats, Parameter};

/// Draw `f` and return the SVG document.
pub fn cycles_svg(f: &CycleFamily, title: &str) -> Result<String, Error> {
    if f.points.is_empty() {
        return Err(Error::NothingToDraw { what: Drawable::LimitCycles });
    }
    let curve = Curve {
        model: f.model.clone(),
        harmonics: f.harmonics,
        parameter: Parameter::Model { index: f.param_index, name: f.parameter.clone() },
        output_names: f.output_names.clone(),
        points: f
            .points
            .iter()
            .map(|p| CurvePoint {
                omega: p.omega,
                param: p.value,
                coeffs: Vec::new(),
                stability: p.stability.clone(),
                outputs: p.outputs.clone(),
                segment: 0,
            })
            .collect(),
        stability_checked: true,
        folds: vec![],
        jumps: vec![],
        peaks: vec![],
        segments: vec![],
        stats: CurveStats::default(),
        bifurcations: vec![],
        convergence: None,
    };
    // a marker's `omega` is its x: the parameter's value on this axis
    let markers = f
        .hopf
        .iter()
        .flat_map(|h| {
            f.output_names.iter().map(move |o| TimeMarker {
                label: format!(
                    "Hopf point ({} = {:.6}, ω = {:.6} rad/s)",
                    f.parameter, h.value, h.omega
                ),
                omega: h.value,
                output: o.clone(),
                value: 0.0,
            })
        })
        .collect();
    let fig = Figure {
        title: title.to_string(),
        unit: FreqUnit::RadPerSec,
        panels: f
            .output_names
            .iter()
            .map(|o| Panel { output: o.clone(), label: format!("max |{o}| of the cycle") })
            .collect(),
        series: vec![Series { label: format!("limit cycles (mode {})", f.mode), curve: &curve }],
        markers,
    };
    figure_svg(&fig)
}

//! The report writers on curves with known content: the closed-form linear quarter car
//! (closed form, k3 = 0) and a synthetic S-shaped curve with two folds.

use ihbm::report::{
    curve_csv, curve_facts, figure_svg, sweep_json, Figure, FreqUnit, Panel, Series, TimeMarker,
};
use ihbm::results::{
    Curve, CurvePoint, CurveStats, Direction, End, Fold, Jump, Parameter, PointOutput, Segment,
    Stability,
};
use num_complex::Complex64;

/// |Z1/F| and |Y/F| of the linear quarter car (closed form), Table 1 values.
fn linear_qc(omega: f64) -> (f64, f64) {
    let (m1, m2, k1, kt, c, h, p) = (240.0, 30.0, 16_000.0, 160_000.0, 1_000.0, 1_000.0, 0.5);
    let iw = Complex64::new(0.0, omega);
    let g = k1 + iw * c + h * iw.powf(p);
    let delta = m1 * m2 * omega.powi(4) - (kt * m1 + (m1 + m2) * g) * omega * omega + kt * g;
    ((kt * g / delta).norm(), (kt * m1 * omega * omega / delta).norm())
}

fn linear_curve(f: f64) -> Curve {
    let points = (0..=396)
        .map(|i| {
            let w = 1.0 + 0.25 * i as f64;
            let (z1, y) = linear_qc(w);
            CurvePoint {
                omega: w,
                param: w,
                coeffs: vec![],
                stability: Stability::Stable,
                outputs: vec![
                    PointOutput::harmonic(0.0, f * z1),
                    PointOutput::harmonic(0.0, f * y),
                ],
                segment: 0,
            }
        })
        .collect();
    Curve {
        model: "quarter-car".into(),
        harmonics: 5,
        parameter: Parameter::Omega,
        output_names: vec!["z1".into(), "y".into()],
        points,
        stability_checked: true,
        folds: vec![],
        jumps: vec![],
        peaks: vec![],
        segments: vec![Segment { from: 1.0, to: 100.0, ended: End::ReachedEnd }],
        stats: CurveStats::default(),
        bifurcations: vec![],
        convergence: None,
    }
}

/// An S curve Ω(s) = 10 + 8 (s - 0.5)^3 - 1.5 (s - 0.5), amplitude a = s: Ω has a local
/// max at s = 0.5 - 1/4 and a local min at s = 0.5 + 1/4; the middle branch is unstable.
fn s_curve() -> Curve {
    let omega = |s: f64| 10.0 + 8.0 * (s - 0.5).powi(3) - 1.5 * (s - 0.5);
    let n = 200;
    let (s1, s2) = (0.25, 0.75);
    let points: Vec<CurvePoint> = (0..=n)
        .map(|i| {
            let s = i as f64 / n as f64;
            CurvePoint {
                omega: omega(s),
                param: omega(s),
                coeffs: vec![],
                stability: Stability::from_verdict(!(s1..s2).contains(&s)),
                outputs: vec![PointOutput::harmonic(0.0, s)],
                segment: 0,
            }
        })
        .collect();
    let fold = |s: f64| Fold {
        omega: omega(s),
        param: omega(s),
        coeffs: vec![],
        outputs: vec![PointOutput::harmonic(0.0, s)],
        after: (s * n as f64) as usize,
        located: true,
    };
    Curve {
        model: "synthetic".into(),
        harmonics: 3,
        parameter: Parameter::Omega,
        output_names: vec!["x".into()],
        points,
        stability_checked: true,
        folds: vec![fold(s1), fold(s2)],
        jumps: vec![Jump {
            direction: Direction::Up,
            at: omega(s1),
            output: "x".into(),
            from: s1,
            to: 0.9,
        }],
        peaks: vec![],
        segments: vec![Segment { from: omega(0.0), to: omega(1.0), ended: End::ReachedEnd }],
        stats: CurveStats { folds: 2, ..CurveStats::default() },
        bifurcations: vec![],
        convergence: None,
    }
}

#[test]
fn csv_has_one_row_per_point_and_round_trips_the_closed_form() {
    let curve = linear_curve(0.01);
    let csv = curve_csv(&curve);
    let mut lines = csv.lines();
    assert_eq!(
        lines.next(),
        Some("omega,stable,z1_max_abs,z1_mean,z1_amp1,z1_rms,z1_min,z1_max,y_max_abs,y_mean,y_amp1,y_rms,y_min,y_max")
    );
    let rows: Vec<&str> = lines.collect();
    assert_eq!(rows.len(), curve.points.len());
    for row in rows {
        let cols: Vec<&str> = row.split(',').collect();
        assert_eq!(cols.len(), 2 + 2 * 6);
        let w: f64 = cols[0].parse().unwrap();
        assert_eq!(cols[1], "true");
        let (z1, y) = linear_qc(w);
        assert_eq!(cols[2].parse::<f64>().unwrap(), 0.01 * z1);
        assert_eq!(cols[8].parse::<f64>().unwrap(), 0.01 * y);
    }
}

#[test]
fn closed_form_matches_errata_at_8_rad_s() {
    // Independent check of the reference used below (closed-form numbers).
    let (z1, y) = linear_qc(8.0);
    assert!((z1 - 2.2972768).abs() < 1e-6, "{z1}");
    assert!((y - 1.7136480).abs() < 1e-6, "{y}");
}

#[test]
fn sweep_json_has_the_contract_fields_in_order() {
    let curve = s_curve();
    let v = sweep_json(&curve);
    let keys: Vec<&str> = v.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(&keys[..6], ["model", "harmonics", "points", "folds", "jumps", "segments"]);
    let p0 = &v["points"][0];
    let pk: Vec<&str> = p0.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(pk, ["omega", "stable", "outputs"]);
    let ok: Vec<&str> =
        p0["outputs"]["x"].as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(ok, ["max_abs", "mean", "amp1", "rms", "min", "max"]);
    assert_eq!(v["points"].as_array().unwrap().len(), curve.points.len());
    let f0 = &v["folds"][0];
    assert_eq!(f0["omega"].as_f64().unwrap(), curve.folds[0].omega);
    assert_eq!(f0["outputs"]["x"]["max_abs"].as_f64().unwrap(), 0.25);
    let j0 = &v["jumps"][0];
    let jk: Vec<&str> = j0.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(jk, ["direction", "omega", "output", "from", "to"]);
    assert_eq!(j0["direction"], "up");
    let s0 = &v["segments"][0];
    let sk: Vec<&str> = s0.as_object().unwrap().keys().map(|k| k.as_str()).collect();
    assert_eq!(sk, ["from_omega", "to_omega", "ended"]);
    assert_eq!(s0["ended"], "reached end");
}

#[test]
fn facts_find_the_closed_form_resonances_and_the_folds() {
    let curve = linear_curve(0.01);
    // The body resonance of the linear model lies near sqrt(k1 kt/((k1+kt) m1)) ≈ 7.8 rad/s,
    // shifted by the fractional stiffness; the wheel-hop one near sqrt((k1+kt)/m2) ≈ 77.
    let low = curve_facts(&curve, "z1", Some((1.0, 30.0))).unwrap();
    assert!(low.peak_omega > 6.0 && low.peak_omega < 11.0, "{low:?}");
    // The peak: the closed form's maximum of |Z1| F (golden section), which the
    // parabola through the largest grid point and its neighbours approaches better than
    // that grid point does.
    let amp = |w: f64| 0.01 * linear_qc(w).0;
    let grid_w =
        (0..=116).map(|i| 1.0 + 0.25 * i as f64).max_by(|a, b| amp(*a).total_cmp(&amp(*b)));
    let grid_w = grid_w.unwrap();
    let (mut lo, mut hi) = (grid_w - 0.25, grid_w + 0.25);
    let r = 0.5 * (5f64.sqrt() - 1.0);
    for _ in 0..200 {
        let (x1, x2) = (hi - r * (hi - lo), lo + r * (hi - lo));
        if amp(x1) < amp(x2) {
            lo = x1;
        } else {
            hi = x2;
        }
    }
    let (w_true, a_true) = (0.5 * (lo + hi), amp(0.5 * (lo + hi)));
    assert!((low.peak - a_true).abs() < (amp(grid_w) - a_true).abs(), "{low:?} vs {a_true}");
    assert!((low.peak_omega - w_true).abs() < (grid_w - w_true).abs(), "{low:?} vs {w_true}");
    assert!((low.peak - a_true).abs() < 1e-2 * a_true);
    let high = curve_facts(&curve, "y", Some((40.0, 100.0))).unwrap();
    assert!(high.peak_omega > 60.0 && high.peak_omega < 90.0, "{high:?}");
    assert!(curve_facts(&curve, "nope", None).is_none());
    let s = s_curve();
    let f = curve_facts(&s, "x", None).unwrap();
    assert_eq!(f.folds.len(), 2);
    assert_eq!(f.peak, 1.0);
    assert!(f.unstable_points > 90 && f.unstable_points < 110, "{f:?}");
}

/// Legend texts of an SVG (plotters writes each text as one <text> element).
fn texts(doc: &roxmltree::Document) -> Vec<String> {
    doc.descendants()
        .filter(|n| n.has_tag_name("text"))
        .map(|n| n.text().unwrap_or("").trim().to_string())
        .collect()
}

#[test]
fn svg_is_valid_xml_with_every_series_in_the_legend() {
    let family: Vec<Curve> = [0.006, 0.008, 0.01].iter().map(|&f| linear_curve(f)).collect();
    let fig = Figure {
        title: "linear quarter car".into(),
        unit: FreqUnit::Hz,
        panels: vec![
            Panel { output: "z1".into(), label: "body displacement |z1| (m)".into() },
            Panel { output: "y".into(), label: "suspension deflection |y| (m)".into() },
        ],
        series: family
            .iter()
            .zip(["F = 0.006", "F = 0.008", "F = 0.01"])
            .map(|(c, l)| Series { label: l.into(), curve: c })
            .collect(),
        markers: vec![TimeMarker {
            label: "time integration (GL)".into(),
            omega: 8.0,
            output: "z1".into(),
            value: 0.01 * linear_qc(8.0).0,
        }],
    };
    let svg = figure_svg(&fig).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let t = texts(&doc);
    for label in ["F = 0.006", "F = 0.008", "F = 0.01"] {
        // once per panel legend
        assert_eq!(t.iter().filter(|s| s.as_str() == label).count(), 2, "{label}: {t:?}");
    }
    assert_eq!(t.iter().filter(|s| s.as_str() == "time integration (GL)").count(), 2);
    assert!(t.iter().any(|s| s.contains("(Hz)")));
    assert!(t.iter().any(|s| s == "linear quarter car"));
    if let Ok(dir) = std::env::var("IHBM_REPORT_SVG_DIR") {
        std::fs::write(format!("{dir}/linear.svg"), &svg).unwrap();
    }
}

#[test]
fn svg_of_a_folding_curve_shows_unstable_fold_and_jump_legends() {
    let c = s_curve();
    let fig = Figure {
        title: "S curve".into(),
        unit: FreqUnit::RadPerSec,
        panels: vec![Panel { output: "x".into(), label: "|x| (m)".into() }],
        series: vec![Series { label: "synthetic".into(), curve: &c }],
        markers: vec![],
    };
    let svg = figure_svg(&fig).unwrap();
    let doc = roxmltree::Document::parse(&svg).unwrap();
    let t = texts(&doc);
    for label in ["synthetic", "unstable (dashed)", "fold", "jump (slow sweep)"] {
        assert_eq!(t.iter().filter(|s| s.as_str() == label).count(), 1, "{label}: {t:?}");
    }
    if let Ok(dir) = std::env::var("IHBM_REPORT_SVG_DIR") {
        std::fs::write(format!("{dir}/s_curve.svg"), &svg).unwrap();
    }
}

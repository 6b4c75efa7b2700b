//! Checking a figure's claims against what was computed: agree, disagree, or
//! inconclusive, always with the numbers.

use super::spec::{CheckKind, CheckSpec, Expect};
use crate::report::curve_facts;
use crate::results::Curve;

/// One computed curve of a family, with the family value and legend label.
pub struct Member<'a> {
    /// Legend label (`"k3 = 3e6"`).
    pub label: String,
    /// The value of the varied quantity (NaN when nothing varies).
    pub value: f64,
    /// The curve.
    pub curve: &'a Curve,
}

/// One time-domain comparison row.
#[derive(Debug, Clone, PartialEq)]
pub struct TdRow {
    /// Forcing frequency, rad/s.
    pub omega: f64,
    /// `"gl"` or `"bdf2"`.
    pub scheme: String,
    /// Output name.
    pub output: String,
    /// Harmonic-balance `max_abs`.
    pub ihbm: f64,
    /// Time-integration `max_abs` (last 10 periods).
    pub sim: f64,
}

impl TdRow {
    /// |sim - ihbm| / |ihbm|.
    pub fn rel_diff(&self) -> f64 {
        (self.sim - self.ihbm).abs() / self.ihbm.abs()
    }
}

/// The verdict of one check.
#[derive(Debug, Clone, Copy, PartialEq, Eq)]
pub enum Verdict {
    /// What we computed agrees with the claim.
    Agree,
    /// It does not.
    Disagree,
    /// Not enough results to tell (failed curves).
    Inconclusive,
}

impl std::fmt::Display for Verdict {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.write_str(match self {
            Verdict::Agree => "agree",
            Verdict::Disagree => "disagree",
            Verdict::Inconclusive => "inconclusive",
        })
    }
}

/// A short number for tables and legends: `3e6`, `0.008`, `240`.
pub fn fmt_num(v: f64) -> String {
    if v != 0.0 && (v.abs() >= 1e5 || v.abs() < 1e-3) {
        format!("{v:e}")
    } else {
        format!("{}", (v * 1e6).round() / 1e6)
    }
}

fn sig(v: f64) -> String {
    format!("{v:.4e}")
}

/// Evaluate `check` on the members; `default_output` is the figure's first panel.
/// Returns the verdict and a sentence with the numbers.
pub fn evaluate(
    check: &CheckSpec,
    members: &[Member],
    td: &[TdRow],
    default_output: &str,
) -> (Verdict, String) {
    let output = check.output.as_deref().unwrap_or(default_output);
    let band = check.band.map(|[a, b]| (a, b));
    let band_txt =
        band.map_or(String::from("whole range"), |(a, b)| format!("Ω in [{a}, {b}] rad/s"));
    let facts: Vec<(&Member, crate::report::CurveFacts)> =
        members.iter().filter_map(|m| curve_facts(m.curve, output, band).map(|f| (m, f))).collect();
    match check.kind {
        CheckKind::Peak | CheckKind::PeakOmega => {
            let peak = check.kind == CheckKind::Peak;
            let seq: Vec<(String, f64)> = facts
                .iter()
                .map(|(m, f)| (m.label.clone(), if peak { f.peak } else { f.peak_omega }))
                .collect();
            let what = if peak {
                format!("peak max|{output}|")
            } else {
                format!("frequency (rad/s) of the peak of max|{output}|")
            };
            let listed = seq
                .iter()
                .map(|(l, v)| format!("{l}: {}", if peak { sig(*v) } else { format!("{v:.3}") }))
                .collect::<Vec<_>>()
                .join("; ");
            let found = format!("{what}, {band_txt}: {listed}");
            if seq.len() < 2 || seq.len() < members.len() {
                return (Verdict::Inconclusive, found);
            }
            let vals: Vec<f64> = seq.iter().map(|s| s.1).collect();
            (trend_verdict(&vals, check.expect, check.tol.unwrap_or(0.02)), found)
        }
        CheckKind::Folds => {
            let listed = facts
                .iter()
                .map(|(m, f)| {
                    let ws =
                        f.folds.iter().map(|w| format!("{w:.4}")).collect::<Vec<_>>().join(", ");
                    format!(
                        "{}: {} fold(s){}",
                        m.label,
                        f.folds.len(),
                        if ws.is_empty() { String::new() } else { format!(" at Ω = {ws}") }
                    )
                })
                .collect::<Vec<_>>()
                .join("; ");
            let found = format!("folds, {band_txt}: {listed}");
            if facts.is_empty() || facts.len() < members.len() {
                return (Verdict::Inconclusive, found);
            }
            let ok = match (check.expect, check.from_value) {
                (Expect::Present, Some(from)) => {
                    facts.iter().all(|(m, f)| (m.value >= from) != f.folds.is_empty())
                }
                (Expect::Present, None) => facts.iter().any(|(_, f)| !f.folds.is_empty()),
                (Expect::Absent, _) => facts.iter().all(|(_, f)| f.folds.is_empty()),
                _ => {
                    return (
                        Verdict::Inconclusive,
                        format!("{found} (expect must be present or absent)"),
                    )
                }
            };
            (if ok { Verdict::Agree } else { Verdict::Disagree }, found)
        }
        CheckKind::Converges => {
            let diffs: Vec<(String, f64)> = facts
                .windows(2)
                .map(|w| {
                    (
                        format!("{} → {}", w[0].0.label, w[1].0.label),
                        (w[1].1.peak - w[0].1.peak).abs() / w[1].1.peak.abs(),
                    )
                })
                .collect();
            let listed =
                diffs.iter().map(|(l, d)| format!("{l}: {d:.2e}")).collect::<Vec<_>>().join("; ");
            let found = format!("relative change of the peak max|{output}|, {band_txt}: {listed}");
            if facts.len() < members.len() || diffs.is_empty() {
                return (Verdict::Inconclusive, found);
            }
            let vals: Vec<f64> = diffs.iter().map(|d| d.1).collect();
            (converges_verdict(&vals, check.expect, check.tol.unwrap_or(1e-5)), found)
        }
        CheckKind::Timedomain => {
            let tol = check.tol.unwrap_or(0.05);
            let rows: Vec<&TdRow> = td.iter().filter(|r| r.output == output).collect();
            let mut schemes: Vec<&str> = Vec::new();
            for r in &rows {
                if !schemes.contains(&r.scheme.as_str()) {
                    schemes.push(&r.scheme);
                }
            }
            let mut worst_all: f64 = 0.0;
            let listed = schemes
                .iter()
                .map(|s| {
                    let worst = rows
                        .iter()
                        .filter(|r| r.scheme == *s)
                        .map(|r| r.rel_diff())
                        .fold(0.0, f64::max);
                    worst_all = worst_all.max(worst);
                    format!("{s}: largest relative difference {worst:.2e}")
                })
                .collect::<Vec<_>>()
                .join("; ");
            let found = format!("time integration vs IHBM, max|{output}| at {} point(s): {listed} (tolerance {tol})", rows.len());
            if rows.is_empty() {
                return (Verdict::Inconclusive, found);
            }
            let ok = worst_all.is_finite() && worst_all <= tol;
            (
                if ok == (check.expect == Expect::Agree) {
                    Verdict::Agree
                } else {
                    Verdict::Disagree
                },
                found,
            )
        }
    }
}

/// Successive relative changes `d` along a family of increasing resolution:
/// `unchanged` means every change is at most `tol` (converged); `decreasing` means
/// "large, then small": strictly decreasing, the first above `tol`, the last at most.
fn converges_verdict(d: &[f64], expect: Expect, tol: f64) -> Verdict {
    let (Some(&first), Some(&last)) = (d.first(), d.last()) else { return Verdict::Inconclusive };
    let ok = match expect {
        Expect::Unchanged => d.iter().all(|&x| x <= tol),
        Expect::Decreasing => d.windows(2).all(|w| w[1] < w[0]) && first > tol && last <= tol,
        _ => return Verdict::Inconclusive,
    };
    if ok {
        Verdict::Agree
    } else {
        Verdict::Disagree
    }
}

/// Does the sequence follow the expected trend?
fn trend_verdict(v: &[f64], expect: Expect, tol: f64) -> Verdict {
    let ok = match expect {
        Expect::Increasing => v.windows(2).all(|w| w[1] > w[0]),
        Expect::Decreasing => v.windows(2).all(|w| w[1] < w[0]),
        Expect::Unchanged => {
            let (lo, hi) = v
                .iter()
                .fold((f64::INFINITY, f64::NEG_INFINITY), |(a, b), &x| (a.min(x), b.max(x)));
            (hi - lo) <= tol * hi.abs().max(lo.abs())
        }
        _ => return Verdict::Inconclusive,
    };
    if ok {
        Verdict::Agree
    } else {
        Verdict::Disagree
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn trends() {
        assert_eq!(trend_verdict(&[1.0, 2.0, 3.0], Expect::Increasing, 0.0), Verdict::Agree);
        assert_eq!(trend_verdict(&[1.0, 2.0, 1.5], Expect::Increasing, 0.0), Verdict::Disagree);
        assert_eq!(trend_verdict(&[3.0, 2.0, 1.0], Expect::Decreasing, 0.0), Verdict::Agree);
        assert_eq!(trend_verdict(&[1.0, 1.01, 0.995], Expect::Unchanged, 0.02), Verdict::Agree);
        assert_eq!(trend_verdict(&[1.0, 1.1], Expect::Unchanged, 0.02), Verdict::Disagree);
    }

    #[test]
    fn convergence() {
        assert_eq!(converges_verdict(&[1e-2, 1e-7], Expect::Decreasing, 1e-5), Verdict::Agree);
        assert_eq!(converges_verdict(&[1e-12, 1e-16], Expect::Decreasing, 1e-5), Verdict::Disagree);
        assert_eq!(converges_verdict(&[1e-12, 1e-16], Expect::Unchanged, 1e-5), Verdict::Agree);
        assert_eq!(converges_verdict(&[1e-2, 1e-3], Expect::Unchanged, 1e-5), Verdict::Disagree);
    }

    #[test]
    fn numbers() {
        assert_eq!(fmt_num(3e6), "3e6");
        assert_eq!(fmt_num(0.008), "0.008");
        assert_eq!(fmt_num(240.0), "240");
        assert_eq!(fmt_num(0.2), "0.2");
    }
}

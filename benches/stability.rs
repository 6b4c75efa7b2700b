//! Stability at scale: whole curves of an n-mass chain (each link a linear + cubic
//! spring with a viscous and a fractional damper of order 0.5, forcing on the last
//! mass; Ω from 0.05 to 2.5) for n = 2, 5, 10, 20 at N = 5 and 11, with Hill stability
//! at every point and without it, and the quarter car (1 → 100 rad/s, N = 5).
//!
//! Before criterion's samples, each case runs once and prints its table row (points,
//! times, ratio, full analyses). The slow cases (with stability beyond n = 5 at
//! N = 11 or n = 10 at N = 5) run only with `IHBM_BENCH_BIG=1` set; filter with
//! `cargo bench --bench stability -- chain10`.
use criterion::{criterion_group, criterion_main, Criterion};
use ihbm::continuation::{sweep, SweepOptions};
use ihbm::model::Model;
use ihbm::models::QuarterCar;
use std::hint::black_box;
use std::time::Instant;

mod chains;
use chains::{Chain10, Chain2, Chain20, Chain40, Chain5};

/// One table row for `model` on `from..to` at `nh` harmonics, then criterion's samples
/// of the curve with and without stability (`with` false: without only).
fn case<M: Model>(
    c: &mut Criterion,
    name: &str,
    model: &M,
    span: (f64, f64),
    nh: usize,
    with: bool,
) {
    let (from, to) = span;
    let on = SweepOptions { harmonics: nh, ..Default::default() };
    let off = SweepOptions { stability: None, ..on.clone() };
    // Criterion's filter, applied here too, so that the table rows of the cases left
    // out are not computed either.
    let mut filters = std::env::args().skip(1).filter(|a| !a.starts_with('-')).peekable();
    if filters.peek().is_some() && !filters.any(|a| name.contains(&a)) {
        return;
    }
    let t = Instant::now();
    let bare = sweep(model, from, to, &off).expect("curve without stability");
    let t_off = t.elapsed().as_secs_f64();
    let unknowns = model.dofs().len() * (2 * nh + 1);
    if with {
        let t = Instant::now();
        let full = sweep(model, from, to, &on).expect("curve with stability");
        let t_on = t.elapsed().as_secs_f64();
        eprintln!(
            "| {name} | {nh} | {unknowns} | {} | {t_off:.3} s | {t_on:.3} s | {:.1} | {} of {} |",
            full.points.len(),
            t_on / t_off,
            full.stats.stability_full,
            full.points.len()
        );
    } else {
        eprintln!(
            "| {name} | {nh} | {unknowns} | {} | {t_off:.3} s | (not run) | | |",
            bare.points.len()
        );
    }
    let mut g = c.benchmark_group("stability_scale");
    g.sample_size(10);
    g.bench_function(format!("{name}_N{nh}_no_stability"), |b| {
        b.iter(|| sweep(black_box(model), from, to, &off).expect("curve"))
    });
    if with {
        g.bench_function(format!("{name}_N{nh}_with_stability"), |b| {
            b.iter(|| sweep(black_box(model), from, to, &on).expect("curve"))
        });
    }
    g.finish();
}

fn chains(c: &mut Criterion) {
    let big = std::env::var("IHBM_BENCH_BIG").is_ok();
    let span = (0.05, 2.5);
    eprintln!(
        "| case | N | unknowns | points | without stability | with | ratio | full analyses |"
    );
    eprintln!("|---|---|---|---|---|---|---|---|");
    case(c, "quarter_car", &QuarterCar::default(), (1.0, 100.0), 5, true);
    for nh in [5, 11] {
        case(c, "chain2", &Chain2::default(), span, nh, true);
        case(c, "chain5", &Chain5::default(), span, nh, nh == 5 || big);
        case(c, "chain10", &Chain10::default(), span, nh, big);
        case(c, "chain20", &Chain20::default(), span, nh, big);
    }
    // The sparse-factorisation case: 920 unknowns, without stability.
    case(c, "chain40", &Chain40::default(), span, 11, false);
}

/// Pseudo-random numbers in [-1, 1) (xorshift from `seed`): matrix entries.
fn uniform(mut seed: u64) -> impl FnMut() -> f64 {
    move || {
        seed ^= seed << 13;
        seed ^= seed >> 7;
        seed ^= seed << 17;
        (seed >> 11) as f64 / (1u64 << 52) as f64 - 1.0
    }
}

/// The bordered LU of continuation on a chain's block-tridiagonal Jacobian: band
/// storage and block elimination against the dense factorisation, at the sizes the
/// choice between them (`linalg::BorderedLu`) is made for: `(blocks, block size)`.
fn factorisations(c: &mut Criterion) {
    use ihbm::linalg::{BorderedLu, Columns};
    let mut g = c.benchmark_group("bordered_lu");
    g.sample_size(20);
    for (nb, l) in [(10, 11), (20, 11), (10, 23), (20, 23), (40, 23)] {
        let na = nb * l;
        let band = (2 * l - 1, 2 * l - 1);
        for (kind, lu) in
            [("band", BorderedLu::new(na, 1, Some(band))), ("dense", BorderedLu::new(na, 1, None))]
        {
            let mut lu = lu;
            let mut rand = uniform(0x2545_f491_4f6c_dd1d);
            let name = format!("{kind}_{na}_kl{}", band.0);
            g.bench_function(name, |b| {
                b.iter(|| {
                    let mut a = lu.a_mut();
                    a.clear();
                    for j in 0..na {
                        let lo = (j / l).saturating_sub(1) * l;
                        let hi = ((j / l + 2) * l).min(na);
                        if let Some(seg) = a.segment(j, lo, hi - lo) {
                            seg.iter_mut().for_each(|v| *v = rand());
                        }
                    }
                    lu.set_border_column(0, &vec![1.0; na]);
                    lu.set_border_row(0, &vec![1.0; na]);
                    lu.set_corner(0, 0, 0.0);
                    black_box(lu.factor())
                })
            });
        }
    }
    g.finish();
}

/// One complex LU of `T(λ)` at the Hill sizes of the table (`m` = DOFs × (2N + 1)):
/// the least a point's stability costs, tracked or not, against which the curve's own
/// cost per point is set in the book's performance chapter (*The 2× goal*). Dense, and
/// for the chains also within the band of their block-tridiagonal `T` (as
/// `Hill` factorises it).
fn hill_lu(c: &mut Criterion) {
    use ihbm::linalg::{complex_band_lu_factor, complex_lu_factor};
    use num_complex::Complex64;
    let mut g = c.benchmark_group("hill_lu");
    g.sample_size(20);
    for (name, m, len) in [
        ("quarter_car_N5", 22, 0),
        ("chain2_N5", 22, 11),
        ("chain2_N11", 46, 23),
        ("chain5_N5", 55, 11),
        ("chain5_N11", 115, 23),
        ("chain10_N5", 110, 11),
        ("chain10_N11", 230, 23),
        ("chain20_N5", 220, 11),
        ("chain20_N11", 460, 23),
    ] {
        let mut rand = uniform(0x9e37_79b9_7f4a_7c15);
        let a: Vec<Complex64> = (0..m * m).map(|_| Complex64::new(rand(), rand())).collect();
        let (mut work, mut piv) = (a.clone(), vec![0; m]);
        g.bench_function(format!("{name}_m{m}"), |b| {
            b.iter(|| {
                work.copy_from_slice(&a);
                black_box(complex_lu_factor(&mut work, m, &mut piv, 0.0))
            })
        });
        if len == 0 || 2 * len >= m {
            continue; // no band narrower than the matrix
        }
        // Block-tridiagonal in blocks of `len`, zero elsewhere.
        let banded: Vec<Complex64> = a
            .iter()
            .enumerate()
            .map(|(k, &z)| {
                let (i, j) = (k / m / len, k % m / len);
                if i.abs_diff(j) <= 1 {
                    z
                } else {
                    Complex64::new(0.0, 0.0)
                }
            })
            .collect();
        let band = (2 * len - 1, 2 * len - 1);
        g.bench_function(format!("{name}_m{m}_band"), |b| {
            b.iter(|| {
                work.copy_from_slice(&banded);
                black_box(complex_band_lu_factor(&mut work, m, band, &mut piv, 0.0))
            })
        });
    }
    g.finish();
}

criterion_group!(benches, chains, factorisations, hill_lu);
criterion_main!(benches);

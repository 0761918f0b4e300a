//! Properties of `R` (DESIGN §3): identity inside, monotone, C¹ at the joins, asymptotes,
//! extreme inputs; and the rescaling the view shift relies on.

use super::*;
use proptest::prelude::*;

fn remap() -> DepthRemap {
    DepthRemap::new(10.0, 20.0, 25.0, 60.0).unwrap()
}

fn any_remap() -> impl Strategy<Value = DepthRemap> {
    (0.0..100.0f64, 0.0..100.0f64, 0.01..500.0f64, 0.01..500.0f64)
        .prop_map(|(f, b, gf, gb)| DepthRemap::new(f, b, f + gf, b + gb).unwrap())
}

#[test]
fn bad_parameters_are_refused_with_a_reason() {
    assert!(DepthRemap::new(10.0, 20.0, 10.0, 60.0).unwrap_err().contains("DF > F"));
    assert!(DepthRemap::new(-1.0, 20.0, 25.0, 60.0).unwrap_err().contains("≥ 0"));
    assert!(
        DepthRemap::new(1.0, f64::NAN, 25.0, 60.0)
            .unwrap_err()
            .contains("finite")
    );
}

#[test]
fn joins_are_continuous_with_slope_one() {
    let r = remap();
    for join in [-r.front, r.back] {
        assert_eq!(r.apply(join), join);
        // Central difference across the join: both one-sided slopes are 1.
        let h = 1e-6;
        let left = (r.apply(join) - r.apply(join - h)) / h;
        let right = (r.apply(join + h) - r.apply(join)) / h;
        assert!(
            (left - 1.0).abs() < 1e-5 && (right - 1.0).abs() < 1e-5,
            "{join}: {left} {right}"
        );
    }
}

#[test]
fn extreme_inputs_give_the_asymptotes_and_never_nan() {
    let r = remap();
    assert_eq!(r.apply(f64::INFINITY), 60.0);
    assert_eq!(r.apply(f64::NEG_INFINITY), -25.0);
    assert_eq!(r.apply(f64::NAN), 0.0);
    assert_eq!(r.apply(f64::MAX), 60.0);
    // Parallax 1 - c/w for w → 0⁺ (in front, unbounded) and w = ∞ (parallax 1).
    let s = 40.0;
    for w in [1e-300, 1e-30, 1e-6, 5.0, 1e30, f64::INFINITY] {
        let x = s * (1.0 - 5.0 / w);
        let y = r.apply(x);
        assert!(y.is_finite() && (-25.0..=60.0).contains(&y), "w = {w}: {y}");
    }
    // At w = 0 exactly, c/w = ∞: the shader's w·R(..) is then 0·(-D_F) = 0.
    assert_eq!(r.apply(s * (1.0 - 5.0 / 0.0)), -25.0);
}

#[test]
fn scaled_remap_is_r_of_k_x_over_k() {
    let r = remap();
    for k in [0.37, 12.0, -3.0, -0.01] {
        let q = r.scaled(k).unwrap();
        for x in [-1e3, -9.0, -1.0, 0.0, 0.5, 3.0, 7.0, 80.0, 1e6] {
            let want = r.apply(k * x) / k;
            let got = q.apply(x);
            assert!(
                (got - want).abs() <= 1e-9 * want.abs().max(1.0),
                "k {k} x {x}: {got} vs {want}"
            );
        }
    }
    assert!(r.scaled(0.0).is_none() && r.scaled(f64::NAN).is_none());
}

proptest! {
    #[test]
    fn identity_on_the_comfortable_range(r in any_remap(), t in 0.0..=1.0f64) {
        let x = -r.front + t * (r.front + r.back);
        prop_assert_eq!(r.apply(x), x);
    }

    #[test]
    fn monotone_and_within_the_asymptotes(r in any_remap(), a in -1e4..1e4f64, d in 0.0..1e3f64) {
        let (ya, yb) = (r.apply(a), r.apply(a + d));
        prop_assert!(yb >= ya, "R({}) = {} > R({}) = {}", a, ya, a + d, yb);
        prop_assert!(ya >= -r.front_limit && ya <= r.back_limit);
    }

    #[test]
    fn slope_is_one_at_the_joins_and_below_one_beyond(r in any_remap(), t in 0.0..1e3f64) {
        let h = 1e-4 * (1.0 + t);
        for x in [r.back + t, -r.front - t] {
            let slope = (r.apply(x + h) - r.apply(x - h)) / (2.0 * h);
            prop_assert!(slope <= 1.0 + 1e-6 && slope > 0.0, "slope {} at {}", slope, x);
        }
        // One-sided slopes at the joins, against the analytic 1 (truncation O(h/g)).
        let h = 1e-7 * (r.back_limit - r.back).min(r.front_limit - r.front);
        let up = (r.apply(r.back + h) - r.back) / h;
        let down = (-r.front - r.apply(-r.front - h)) / h;
        prop_assert!((up - 1.0).abs() < 1e-4 && (down - 1.0).abs() < 1e-4, "{} {}", up, down);
    }
}

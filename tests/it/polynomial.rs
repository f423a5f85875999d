//! Exact polynomial decisions (`core::polynomial`, the planar replay's foundation; issue 36)
//! against independent answers: root counts against the roots a polynomial was built from,
//! the minimum of a linear relative motion against its closed form, and a braking robot's
//! squared separation against exact evaluation on a dense grid.

use dashu_ratio::RBig;
use safereach::core::num::Exact;
use safereach::core::polynomial::Polynomial;

/// The cases' generator (with `int` and `rational` from `common::rational_draws`).
use crate::common::split_mix::SplitMix as Rng;

fn q(num: i64, den: i64) -> Exact {
    RBig::from(num) / RBig::from(den)
}

/// τ − r.
fn linear_factor(r: &Exact) -> Polynomial {
    Polynomial::new(vec![-r.clone(), Exact::ONE])
}

/// lead · Π (τ − rᵢ)^mᵢ.
fn from_roots(lead: &Exact, roots: &[(Exact, u32)]) -> Polynomial {
    let mut p = Polynomial::constant(lead.clone());
    for (r, m) in roots {
        for _ in 0..*m {
            p = &p * &linear_factor(r);
        }
    }
    p
}

/// A polynomial in τ from its coefficients as small fractions (num, den), constant first.
fn poly(coefficients: &[(i64, i64)]) -> Polynomial {
    Polynomial::new(coefficients.iter().map(|&(n, d)| q(n, d)).collect())
}

/// p(x) by summing cᵢ·xⁱ with powers (not Horner): the reference for `eval`.
fn eval_by_powers(p: &Polynomial, x: &Exact) -> Exact {
    p.coefficients()
        .iter()
        .enumerate()
        .map(|(i, c)| c * x.pow(i as isize))
        .fold(Exact::ZERO, |s, t| s + t)
}

/// Every bracket and decision `minimum_on`, `min_at_most` and `min_below` give on [a, b],
/// held against a true minimum known to lie in [known_lower, known_upper] (equal when it
/// is known exactly).
fn assert_minimum_consistent(
    p: &Polynomial,
    a: &Exact,
    b: &Exact,
    known_lower: &Exact,
    known_upper: &Exact,
    what: &str,
) {
    let tiny = q(1, 1_000_000_000_000);
    let width = q(1, 1_000_000_000);
    let m = p.minimum_on(a, b, &width);
    assert!(m.lower <= *known_upper, "{what}: lower above the minimum");
    assert!(m.upper >= *known_lower, "{what}: upper below the minimum");
    assert!(&m.upper - &m.lower < width, "{what}: bracket too wide");
    assert_eq!(p.eval(&m.at), m.upper, "{what}: upper not attained at `at`");
    assert!(m.at >= *a && m.at <= *b, "{what}: `at` outside [a, b]");
    assert!(p.min_at_most(&m.upper, a, b), "{what}");
    assert!(!p.min_at_most(&(&m.lower - &tiny), a, b), "{what}");
    assert!(!p.min_below(&m.lower, a, b), "{what}");
    assert!(p.min_below(&(&m.upper + &tiny), a, b), "{what}");
}

#[test]
fn distinct_roots_are_counted_once_on_half_open_intervals() {
    let mut rng = Rng(36);
    let mut repeated = 0;
    let mut at_an_end = 0;
    for case in 0..400 {
        let mut roots: Vec<(Exact, u32)> = Vec::new();
        for _ in 0..rng.int(1, 4) {
            let r = rng.rational(4);
            if roots.iter().all(|(s, _)| *s != r) {
                roots.push((r, rng.int(1, 3) as u32));
            }
        }
        let lead = match rng.int(1, 4) {
            1 => q(-3, 2),
            2 => q(1, 7),
            n => Exact::from(n),
        };
        let p = from_roots(&lead, &roots);
        // Ends drawn at random, or at one of the roots (to pin the half-open convention).
        let end = |rng: &mut Rng| {
            if rng.int(0, 2) == 0 {
                roots[rng.int(0, roots.len() as i64 - 1) as usize].0.clone()
            } else {
                rng.rational(5)
            }
        };
        let (x, y) = (end(&mut rng), end(&mut rng));
        let (a, b) = if x <= y { (x, y) } else { (y, x) };
        repeated += usize::from(roots.iter().any(|(_, m)| *m > 1));
        at_an_end += usize::from(roots.iter().any(|(r, _)| *r == a || *r == b));

        let inside = |r: &Exact| *r > a && *r <= b;
        let expected = roots.iter().filter(|(r, _)| inside(r)).count();
        assert_eq!(p.count_distinct_roots(&a, &b), expected, "case {case}");
        assert_eq!(p.count_distinct_roots(&b, &a), 0, "case {case}: reversed");

        let width = q(1, rng.int(1, 1000));
        let intervals = p.isolate_roots(&a, &b, &width);
        let closed = roots.iter().filter(|(r, _)| *r >= a && *r <= b).count();
        assert_eq!(intervals.len(), closed, "case {case}");
        for (i, (lo, hi)) in intervals.iter().enumerate() {
            assert!(a <= *lo && lo <= hi && *hi <= b, "case {case}: {lo} {hi}");
            assert!(hi - lo < width, "case {case}: too wide");
            let held = roots.iter().filter(|(r, _)| r >= lo && r <= hi).count();
            assert_eq!(held, 1, "case {case}: [{lo}, {hi}] holds {held} roots");
            if let Some((next_lo, _)) = intervals.get(i + 1) {
                assert!(hi < next_lo, "case {case}: not disjoint and sorted");
            }
        }
    }
    assert!(repeated > 100 && at_an_end > 100, "{repeated} {at_an_end}");
}

#[test]
fn arithmetic_is_the_functions_it_stands_for() {
    let mut rng = Rng(5);
    let random = |rng: &mut Rng| {
        let degree = rng.int(0, 5) as usize;
        Polynomial::new((0..=degree).map(|_| rng.rational(3)).collect())
    };
    for case in 0..200 {
        let (f, g) = (random(&mut rng), random(&mut rng));
        let x = rng.rational(3);
        let (fx, gx) = (eval_by_powers(&f, &x), eval_by_powers(&g, &x));
        assert_eq!(f.eval(&x), fx, "case {case}");
        assert_eq!((&f + &g).eval(&x), &fx + &gx, "case {case}");
        assert_eq!((&f - &g).eval(&x), &fx - &gx, "case {case}");
        assert_eq!((&f * &g).eval(&x), &fx * &gx, "case {case}");
        let (s, k) = (rng.rational(2), rng.rational(2));
        assert_eq!(
            f.compose_affine(&s, &k).eval(&x),
            eval_by_powers(&f, &(&s + &k * &x)),
            "case {case}"
        );
        // The derivative against the sum of i·cᵢ·xⁱ⁻¹.
        let derivative_by_powers = f
            .coefficients()
            .iter()
            .enumerate()
            .skip(1)
            .map(|(i, c)| c * Exact::from(i) * x.pow(i as isize - 1))
            .fold(Exact::ZERO, |s, t| s + t);
        assert_eq!(f.derivative().eval(&x), derivative_by_powers, "case {case}");
        if !g.is_zero() {
            let (quotient, remainder) = f.div_rem(&g);
            assert_eq!(&(&quotient * &g) + &remainder, f, "case {case}");
            assert!(
                remainder.is_zero() || remainder.degree() < g.degree(),
                "case {case}"
            );
        }
    }
}

#[test]
fn linear_relative_motion_reaches_its_closed_form_minimum() {
    let mut rng = Rng(11);
    let (zero, one) = (Exact::ZERO, Exact::ONE);
    let tiny = q(1, 1_000_000_000_000);
    let mut interior = 0;
    let mut through = 0;
    for case in 0..300 {
        let (vx, vy) = (rng.rational(3), rng.rational(3));
        // Some cases pass through the origin at a rational τ in [0, 1]: a double root of p at
        // its minimum 0, the touching case.
        let (dx, dy) = if rng.int(0, 3) == 0 {
            let t0 = q(rng.int(0, 8), 8);
            (-(&vx * &t0), -(&vy * &t0))
        } else {
            (rng.rational(3), rng.rational(3))
        };
        // p(τ) = |d + vτ|², built from the component motions.
        let x = Polynomial::new(vec![dx.clone(), vx.clone()]);
        let y = Polynomial::new(vec![dy.clone(), vy.clone()]);
        let p = &(&x * &x) + &(&y * &y);
        let speed2 = &vx * &vx + &vy * &vy;
        let tau = if speed2.is_zero() {
            zero.clone()
        } else {
            let t = -(&dx * &vx + &dy * &vy) / &speed2;
            if t < zero {
                zero.clone()
            } else if t > one {
                one.clone()
            } else {
                t
            }
        };
        let (ex, ey) = (&dx + &vx * &tau, &dy + &vy * &tau);
        let m = &ex * &ex + &ey * &ey;
        interior += usize::from(tau > zero && tau < one);
        through += usize::from(m.is_zero());

        assert!(p.min_at_most(&m, &zero, &one), "case {case}");
        assert!(!p.min_at_most(&(&m - &tiny), &zero, &one), "case {case}");
        assert!(!p.min_below(&m, &zero, &one), "case {case}");
        assert!(p.min_below(&(&m + &tiny), &zero, &one), "case {case}");
        assert_minimum_consistent(&p, &zero, &one, &m, &m, &format!("case {case}"));
    }
    assert!(interior > 50 && through > 30, "{interior} {through}");
}

#[test]
fn a_braking_robot_against_a_crossing_obstacle_is_bracketed_below_the_grid_minimum() {
    let mut rng = Rng(7);
    let (zero, one) = (Exact::ZERO, Exact::ONE);
    const GRID: i64 = 400;
    for case in 0..60 {
        // Robot along x: x(τ) = x0 + v0·τ − b·τ²/2; obstacle (ox + ux·τ, oy + uy·τ).
        let (x0, v0, brake) = (rng.rational(2), rng.rational(3), q(rng.int(1, 16), 4));
        let (ox, oy) = (rng.rational(3), rng.rational(1));
        let (ux, uy) = (rng.rational(3), rng.rational(3));
        let robot_x = Polynomial::new(vec![x0.clone(), v0.clone(), -(&brake / Exact::from(2))]);
        let dx = &robot_x - &Polynomial::new(vec![ox.clone(), ux.clone()]);
        let dy = Polynomial::new(vec![-oy.clone(), -uy.clone()]);
        let p = &(&dx * &dx) + &(&dy * &dy);
        assert_eq!(p.degree(), Some(4), "case {case}");

        // The squared distance evaluated directly at each grid instant, exactly.
        let separation2 = |t: &Exact| {
            let rx = &x0 + &v0 * t - &brake * t * t / Exact::from(2);
            let (sx, sy) = (rx - (&ox + &ux * t), -(&oy + &uy * t));
            &sx * &sx + &sy * &sy
        };
        let grid_min = (0..=GRID)
            .map(|k| separation2(&q(k, GRID)))
            .min()
            .expect("a grid");
        // The true minimum is at most the grid's, and not below 0.
        assert_minimum_consistent(&p, &zero, &one, &zero, &grid_min, &format!("case {case}"));
        let m = p.minimum_on(&zero, &one, &q(1, 1_000_000_000));
        assert!(m.lower <= grid_min, "case {case}");
        assert!(p.min_at_most(&grid_min, &zero, &one), "case {case}");
    }
}

#[test]
fn constants_and_zero_decide_by_their_value() {
    let (a, b) = (q(-1, 2), q(3, 1));
    let tiny = q(1, 1_000_000);
    let five = Polynomial::constant(Exact::from(5));
    assert_eq!(five.degree(), Some(0));
    assert_eq!(five.count_distinct_roots(&a, &b), 0);
    assert!(five.isolate_roots(&a, &b, &tiny).is_empty());
    assert!(five.min_at_most(&Exact::from(5), &a, &b));
    assert!(!five.min_at_most(&(Exact::from(5) - &tiny), &a, &b));
    assert!(!five.min_below(&Exact::from(5), &a, &b));
    assert!(five.min_below(&(Exact::from(5) + &tiny), &a, &b));
    let m = five.minimum_on(&a, &b, &tiny);
    assert_eq!((m.lower, m.upper), (Exact::from(5), Exact::from(5)));

    let zero = Polynomial::new(vec![Exact::ZERO, Exact::ZERO]);
    assert_eq!(zero, Polynomial::zero());
    assert_eq!(zero.degree(), None);
    assert!(zero.sturm_sequence().is_empty());
    assert!(zero.min_at_most(&Exact::ZERO, &a, &b));
    assert!(!zero.min_at_most(&-tiny.clone(), &a, &b));
    assert!(!zero.min_below(&Exact::ZERO, &a, &b));
    assert!(zero.min_below(&tiny, &a, &b));
    let m = zero.minimum_on(&a, &b, &tiny);
    assert_eq!((m.lower, m.upper), (Exact::ZERO, Exact::ZERO));
}

#[test]
#[should_panic(expected = "every point")]
fn the_zero_polynomials_roots_are_not_counted() {
    Polynomial::zero().count_distinct_roots(&Exact::ZERO, &Exact::ONE);
}

#[test]
fn roots_at_the_ends_follow_the_half_open_convention() {
    let (one, two, three) = (Exact::from(1), Exact::from(2), Exact::from(3));
    let width = q(1, 100);
    // (τ − 1)(τ − 2)(τ − 3)
    let p = from_roots(
        &Exact::ONE,
        &[(one.clone(), 1), (two.clone(), 1), (three.clone(), 1)],
    );
    assert_eq!(p.count_distinct_roots(&one, &three), 2); // 2 and 3, not 1
    assert_eq!(p.count_distinct_roots(&Exact::ZERO, &one), 1);
    assert_eq!(p.count_distinct_roots(&one, &two), 1);
    assert_eq!(p.count_distinct_roots(&three, &Exact::from(4)), 0);
    assert_eq!(p.count_distinct_roots(&one, &one), 0);
    let found = p.isolate_roots(&one, &three, &width);
    assert_eq!(found.len(), 3);
    assert_eq!(found[0], (one.clone(), one.clone()));
    assert_eq!(found[2], (three.clone(), three.clone()));
    // A repeated root at an end is one root, on the side the convention puts it.
    let r = from_roots(&Exact::ONE, &[(one.clone(), 2), (two.clone(), 3)]);
    assert_eq!(r.count_distinct_roots(&one, &two), 1);
    assert_eq!(r.count_distinct_roots(&Exact::ZERO, &one), 1);
    assert_eq!(r.count_distinct_roots(&Exact::ZERO, &two), 2);
    assert_eq!(r.isolate_roots(&one, &two, &width).len(), 2);
    // Roots at a bisection midpoint are found exactly.
    let s = from_roots(&Exact::ONE, &[(q(1, 2), 2), (q(1, 4), 1), (q(3, 4), 1)]);
    assert_eq!(
        s.isolate_roots(&Exact::ZERO, &Exact::ONE, &width)[1],
        (q(1, 2), q(1, 2))
    );
}

#[test]
fn touching_the_threshold_is_at_most_but_not_below() {
    let (zero, one) = (Exact::ZERO, Exact::ONE);
    let seven = Exact::from(7);
    // (τ − 1/3)² + 7: touches 7 at τ = 1/3 and turns back.
    let touch = &from_roots(&one, &[(q(1, 3), 2)]) + &Polynomial::constant(seven.clone());
    assert!(touch.min_at_most(&seven, &zero, &one));
    assert!(!touch.min_below(&seven, &zero, &one));
    assert!(!touch.min_at_most(&seven, &q(1, 2), &one));
    assert!(touch.min_at_most(&(&seven + q(1, 36)), &q(1, 2), &one));
    assert!(!touch.min_below(&(&seven + q(1, 36)), &q(1, 2), &one));
    let m = touch.minimum_on(&zero, &one, &q(1, 1000));
    assert!(m.lower <= seven && seven <= m.upper);
    // Two touching roots: never below. A double root beside two simple ones: below between
    // the simple ones, though f ≥ 0 at both ends. A triple root crosses.
    let two_touches = from_roots(&one, &[(q(1, 3), 2), (q(2, 3), 2)]);
    assert!(two_touches.min_at_most(&zero, &zero, &one));
    assert!(!two_touches.min_below(&zero, &zero, &one));
    let dips = from_roots(&one, &[(q(1, 4), 2), (q(1, 2), 1), (q(3, 4), 1)]);
    assert!(dips.eval(&zero) > zero && dips.eval(&one) > zero);
    assert!(dips.min_below(&zero, &zero, &one));
    assert!(!dips.min_below(&zero, &zero, &q(1, 2)));
    let crosses = from_roots(&one, &[(q(1, 3), 3), (q(2, 3), 1)]);
    assert!(crosses.eval(&zero) > zero && crosses.eval(&one) > zero);
    assert!(crosses.min_below(&zero, &zero, &one));
    // A braking robot reaching a static obstacle's centre exactly: separation² touches 0.
    let robot_x = poly(&[(0, 1), (2, 1), (-1, 1)]); // 2τ − τ², at 3/4 when τ = 1/2
    let gap = &robot_x - &Polynomial::constant(q(3, 4));
    let d2 = &gap * &gap;
    assert!(d2.min_at_most(&zero, &zero, &one));
    assert!(!d2.min_below(&zero, &zero, &one));
    assert_eq!(d2.minimum_on(&zero, &one, &q(1, 10)).upper, zero);
}

#[test]
fn a_zero_width_interval_is_its_point() {
    let p = from_roots(&Exact::ONE, &[(q(1, 2), 2), (q(2, 1), 1)]);
    let half = q(1, 2);
    let width = q(1, 10);
    assert_eq!(p.count_distinct_roots(&half, &half), 0);
    assert_eq!(
        p.isolate_roots(&half, &half, &width),
        vec![(half.clone(), half.clone())]
    );
    assert!(p.isolate_roots(&Exact::ONE, &Exact::ONE, &width).is_empty());
    let one = Exact::ONE;
    let at_one = p.eval(&one);
    assert!(p.min_at_most(&at_one, &one, &one));
    assert!(!p.min_below(&at_one, &one, &one));
    assert!(!p.min_at_most(&(&at_one - q(1, 1000)), &one, &one));
    let m = p.minimum_on(&one, &one, &width);
    assert_eq!(
        (m.lower, m.upper, m.at),
        (at_one.clone(), at_one, one.clone())
    );
    // An empty interval (a > b) holds nothing.
    assert!(!p.min_at_most(&Exact::from(1000), &one, &half));
    assert!(!p.min_below(&Exact::from(1000), &one, &half));
    assert!(p.isolate_roots(&one, &half, &width).is_empty());
}

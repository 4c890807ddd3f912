//! Every shape against brute force: the boundary sampled densely, the distance as the smallest
//! distance to a sample, the side from an independent inside test, the normal as the
//! finite-difference gradient of the signed distance.

use super::*;
use crate::Vec2;

/// Boundary samples of a polyline (closed or not), `per` points per edge.
fn sample_edges(v: &[Vec2], closed: bool, per: usize) -> Vec<Vec2> {
    let m = if closed { v.len() } else { v.len() - 1 };
    let mut out = Vec::new();
    for k in 0..m {
        let (a, b) = (v[k], v[(k + 1) % v.len()]);
        for j in 0..=per {
            out.push(a + (b - a) * (j as f64 / per as f64));
        }
    }
    out
}

/// Test points on a grid covering [-2, 2]^2, off the sample lattice.
fn probes() -> Vec<Vec2> {
    let mut out = Vec::new();
    for i in 0..41 {
        for j in 0..41 {
            out.push(Vec2::new(
                -2.0 + 0.1 * i as f64 + 0.0123,
                -2.0 + 0.1 * j as f64 - 0.0077,
            ));
        }
    }
    out
}

/// Check a shape at every probe against boundary samples (spacing `ds`) and an inside test.
fn check(shape: &dyn Shape<2>, samples: &[Vec2], ds: f64, in_solid: &dyn Fn(&Vec2) -> bool) {
    for x in probes() {
        let brute = samples
            .iter()
            .map(|s| (x - s).norm())
            .fold(f64::INFINITY, f64::min);
        let d = shape.signed_distance(&x);
        // The nearest sample is at most half a spacing along the boundary from the true
        // closest point, so the brute-force distance exceeds the true one by at most
        // (ds/2)^2 / (2 d) + ... ; ds/2 bounds it at any d.
        assert!(
            d.abs() <= brute + 1e-12 && brute - d.abs() <= 0.5 * ds,
            "{x:?}: |d| = {} vs brute force {brute}",
            d.abs()
        );
        if d.abs() > 1e-9 {
            assert_eq!(d < 0.0, in_solid(&x), "{x:?}: sign of {d}");
        }
        let c = shape.closest_point(&x);
        assert!(
            ((x - c).norm() - d.abs()).abs() < 1e-12,
            "{x:?}: closest point"
        );
        assert!(
            shape.signed_distance(&c).abs() < 1e-12,
            "{x:?}: closest point on boundary"
        );
        let n = shape.normal(&x);
        assert!((n.norm() - 1.0).abs() < 1e-12);
        if d.abs() > 1e-3 {
            let e = 1e-6;
            let g = Vec2::new(
                shape.signed_distance(&(x + Vec2::new(e, 0.0)))
                    - shape.signed_distance(&(x - Vec2::new(e, 0.0))),
                shape.signed_distance(&(x + Vec2::new(0.0, e)))
                    - shape.signed_distance(&(x - Vec2::new(0.0, e))),
            ) / (2.0 * e);
            // Away from the medial axis (where the gradient jumps) the normal is the gradient.
            if (g.norm() - 1.0).abs() < 1e-4 {
                assert!(
                    (g - n).norm() < 1e-4,
                    "{x:?}: normal {n:?} vs gradient {g:?}"
                );
            }
        }
        // Reflection across the local tangent: the boundary bisects x and its mirror.
        let m = shape.reflect(&x);
        assert!((0.5 * (x + m) - c).norm() < 1e-12);
    }
}

#[test]
fn half_plane_against_brute_force() {
    let a = 0.4f64;
    let n = Vec2::new(a.sin(), a.cos());
    let o = Vec2::new(0.1, -0.2);
    let h = HalfPlane::new(o, n);
    assert!(h.is_straight());
    let t = Vec2::new(n.y, -n.x);
    let ends = [o - 6.0 * t, o + 6.0 * t];
    let ds = 1e-3;
    check(&h, &sample_edges(&ends, false, 12000), ds, &|x| {
        (x - o).dot(&n) < 0.0
    });
    // The straight reflection keeps its closed form: x - 2 d n.
    let x = Vec2::new(0.3, 0.7);
    assert_eq!(h.reflect(&x), x - 2.0 * ((x - o).dot(&n)) * n);
}

#[test]
fn segment_against_brute_force_including_ends() {
    let s = Segment::new(Vec2::new(-1.0, -0.5), Vec2::new(1.2, 0.3));
    let ds = 1e-3;
    let samples = sample_edges(&[s.a, s.b], false, 2400);
    let n = s.line_normal();
    check(&s, &samples, ds, &|x| (x - s.a).dot(&n) < 0.0);
    // Fluid on the left going from a to b.
    let flat = Segment::new(Vec2::new(0.0, 0.0), Vec2::new(1.0, 0.0));
    assert_eq!(flat.line_normal(), Vec2::new(0.0, 1.0));
    assert!(flat.signed_distance(&Vec2::new(0.5, 0.2)) > 0.0);
    // Beyond an end the distance is to the end.
    let d = flat.signed_distance(&Vec2::new(2.0, 1.0));
    assert!((d - 2f64.sqrt()).abs() < 1e-15);
}

#[test]
fn circle_obstacle_and_container_against_brute_force() {
    let (c, r) = (Vec2::new(0.2, -0.1), 0.7);
    let ring: Vec<Vec2> = (0..20000)
        .map(|k| {
            let a = std::f64::consts::TAU * k as f64 / 20000.0;
            c + r * Vec2::new(a.cos(), a.sin())
        })
        .collect();
    let ds = std::f64::consts::TAU * r / 20000.0;
    let obstacle = Ball::obstacle(c, r);
    check(&obstacle, &ring, ds, &|x| (x - c).norm() < r);
    let container = Ball::container(c, r);
    check(&container, &ring, ds, &|x| (x - c).norm() > r);
    // Opposite signs and normals.
    let x = Vec2::new(1.5, 0.4);
    assert_eq!(obstacle.signed_distance(&x), -container.signed_distance(&x));
    assert_eq!(obstacle.normal(&x), -container.normal(&x));
}

#[test]
fn polygon_against_brute_force_with_corners() {
    // A non-convex L shape, fluid outside and inside.
    let v = vec![
        Vec2::new(-1.0, -1.0),
        Vec2::new(1.0, -1.0),
        Vec2::new(1.0, 0.0),
        Vec2::new(0.0, 0.0),
        Vec2::new(0.0, 1.0),
        Vec2::new(-1.0, 1.0),
    ];
    let samples = sample_edges(&v, true, 4000);
    let ds = 2.0 / 4000.0;
    let in_l = |x: &Vec2| {
        (x.x > -1.0 && x.x < 1.0 && x.y > -1.0 && x.y < 0.0)
            || (x.x > -1.0 && x.x < 0.0 && x.y >= 0.0 && x.y < 1.0)
    };
    let p = Polygon::new(v.clone(), Side::Outside);
    check(&p, &samples, ds, &in_l);
    let q = Polygon::new(v, Side::Inside);
    check(&q, &samples, ds, &|x| !in_l(x));
    // At an outer corner the closest point is the corner and the normal points diagonally.
    let x = Vec2::new(1.5, 0.5);
    assert_eq!(p.closest_point(&x), Vec2::new(1.0, 0.0));
    assert!((p.normal(&x) - Vec2::new(1.0, 1.0).normalize()).norm() < 1e-15);
    // On an edge the normal is the edge's, out of the solid.
    assert_eq!(p.normal(&Vec2::new(0.5, -1.0)), Vec2::new(0.0, -1.0));
    assert_eq!(q.normal(&Vec2::new(0.5, -1.0)), Vec2::new(0.0, 1.0));
}

#[test]
fn union_of_two_walls_and_a_cylinder_against_brute_force() {
    // The periodic cylinder cell: walls at y = -1.5 and y = 1.5, a cylinder at the centre.
    let bottom = HalfPlane::new(Vec2::new(0.0, -1.5), Vec2::new(0.0, 1.0));
    let top = HalfPlane::new(Vec2::new(0.0, 1.5), Vec2::new(0.0, -1.0));
    let cyl = Ball::obstacle(Vec2::zeros(), 0.5);
    let u = Union::new(vec![Box::new(bottom), Box::new(top), Box::new(cyl)]);
    let mut samples = sample_edges(&[Vec2::new(-8.0, -1.5), Vec2::new(8.0, -1.5)], false, 16000);
    samples.extend(sample_edges(
        &[Vec2::new(-8.0, 1.5), Vec2::new(8.0, 1.5)],
        false,
        16000,
    ));
    samples.extend((0..4000).map(|k| {
        let a = std::f64::consts::TAU * k as f64 / 4000.0;
        0.5 * Vec2::new(a.cos(), a.sin())
    }));
    let ds = 1e-3;
    check(&u, &samples, ds, &|x| {
        x.y < -1.5 || x.y > 1.5 || x.norm() < 0.5
    });
    assert_eq!(u.nearest(&Vec2::new(0.1, 0.7)).0, 2);
    assert_eq!(u.nearest(&Vec2::new(1.0, 1.2)).0, 1);
    assert!(!u.is_straight());
}

#[test]
fn ball_is_written_for_any_dimension() {
    let s = Ball::<3>::obstacle(crate::dim::Vector::<3>::zeros(), 1.0);
    let x = crate::dim::Vector::<3>::new(0.0, 2.0, 0.0);
    assert_eq!(s.signed_distance(&x), 1.0);
    assert_eq!(s.normal(&x), crate::dim::Vector::<3>::new(0.0, 1.0, 0.0));
    let h = HalfPlane::<3>::new(x, crate::dim::Vector::<3>::new(0.0, 0.0, 1.0));
    assert_eq!(
        h.signed_distance(&crate::dim::Vector::<3>::new(5.0, 1.0, 3.0)),
        3.0
    );
}

/// The reflection's Jacobian is the determinant of the finite-difference derivative of
/// `reflect`: (2R - r) / r around a circle (a tank's images spread out, a cylinder's crowd),
/// exactly 1 across a straight wall.
#[test]
fn reflection_jacobian_is_the_determinant_of_the_reflection() {
    let centre = Vec2::new(0.1, -0.2);
    let shapes: [Box<dyn Shape<2>>; 3] = [
        Box::new(Ball::container(centre, 0.5)),
        Box::new(Ball::obstacle(centre, 0.5)),
        Box::new(HalfPlane::new(centre, Vec2::new(0.6, 0.8))),
    ];
    let e = 1e-6;
    for shape in &shapes {
        for k in 0..24 {
            let a = 0.37 * k as f64;
            let x = centre + (0.35 + 0.3 * k as f64 / 24.0) * Vec2::new(a.cos(), a.sin());
            let col = |d: Vec2| (shape.reflect(&(x + d)) - shape.reflect(&(x - d))) / (2.0 * e);
            let (cx, cy) = (col(Vec2::new(e, 0.0)), col(Vec2::new(0.0, e)));
            let det = (cx.x * cy.y - cx.y * cy.x).abs();
            let j = shape.reflection_jacobian(&x);
            assert!(
                (det - j).abs() < 1e-6 * j,
                "{shape:?} at {x:?}: {det} vs {j}"
            );
        }
    }
    let r = 0.4;
    let x = centre + Vec2::new(r, 0.0);
    assert!((shapes[0].reflection_jacobian(&x) - (1.0 - r) / r).abs() < 1e-15);
    assert_eq!(shapes[2].reflection_jacobian(&x), 1.0);
}

//! GJK distance and EPA penetration against independent references on random shapes and poses.

mod common;

use common::*;
use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};
use proptest::prelude::*;
use rigid::physics::geometry::epa::{signed_distance, signed_distance_within};
use rigid::physics::geometry::gjk::{EXACT, GJK_MAX_ITERATIONS, SupportMap};
use rigid::physics::{ConvexHull, PosedShape, Shape, gjk_distance, gjk_intersects, penetration};

#[derive(Clone, Debug)]
enum Spec {
    Sphere(f64),
    Cuboid(DVec3),
    Capsule(f64, f64),
    Cylinder(f64, f64),
    BoxHull(DVec3),
    Octahedron(DVec3),
    /// Quickhull of a random point cloud: irregular faces, slivers, many vertices.
    Cloud(Arc<ConvexHull>),
}

impl Spec {
    fn shape(&self) -> Shape {
        match self {
            Spec::Sphere(r) => Shape::sphere(*r),
            Spec::Cuboid(h) => Shape::cuboid(*h),
            Spec::Capsule(h, r) => Shape::capsule(*h, *r),
            Spec::Cylinder(h, r) => Shape::cylinder(*h, *r),
            Spec::BoxHull(h) => hull_shape(box_hull(*h)),
            Spec::Octahedron(h) => hull_shape(octahedron_hull(*h)),
            Spec::Cloud(hull) => Shape::ConvexHull(hull.clone()),
        }
    }

    /// The shape as a polyhedron (vertices, faces' vertex lists, edges), if it is one.
    fn polyhedron(&self) -> Option<ConvexHull> {
        match self {
            Spec::Cuboid(h) | Spec::BoxHull(h) => Some(box_hull(*h)),
            Spec::Octahedron(h) => Some(octahedron_hull(*h)),
            Spec::Cloud(hull) => Some((**hull).clone()),
            _ => None,
        }
    }

    /// The core as vertices, triangles and edges, and the margin around it (used by the exact
    /// reference). A cylinder becomes a prism inscribed in it.
    fn core(&self) -> (Features, f64) {
        let hull = match self {
            Spec::Cuboid(h) | Spec::BoxHull(h) => box_hull(*h),
            Spec::Octahedron(h) => octahedron_hull(*h),
            Spec::Cloud(hull) => (**hull).clone(),
            Spec::Sphere(r) => return ((vec![DVec3::ZERO], vec![], vec![]), *r),
            Spec::Capsule(h, r) => {
                let ends = vec![DVec3::Y * *h, -DVec3::Y * *h];
                return ((ends, vec![], vec![[0, 1]]), *r);
            }
            Spec::Cylinder(h, r) => return (inscribed_prism(*h, *r), 0.0),
        };
        let triangles = hull
            .faces
            .iter()
            .flat_map(|f| {
                (1..f.vertices.len() - 1).map(move |k| {
                    [f.vertices[0], f.vertices[k], f.vertices[k + 1]].map(|i| i as usize)
                })
            })
            .collect();
        let edges = hull.edges.iter().map(|e| e.map(|i| i as usize)).collect();
        ((hull.vertices, triangles, edges), 0.0)
    }

    /// How far a cylinder's inscribed prism reaches inside it (0 for exact cores).
    fn prism_sagitta(&self) -> f64 {
        match self {
            Spec::Cylinder(_, r) => r * (1.0 - (std::f64::consts::PI / PRISM_SIDES as f64).cos()),
            _ => 0.0,
        }
    }

    /// The scale of the tolerances below: the bounding radius of a primitive, and for a hull
    /// the radius through the farthest corner of its local bounds (the hull's bounding
    /// radius was that, up to √3 times its farthest vertex, when these tolerances were set).
    fn size(&self) -> f64 {
        match self.shape() {
            Shape::ConvexHull(hull) => {
                let (min, max) = hull.bounds();
                min.abs().max(max.abs()).length()
            }
            shape => shape.bounding_radius(),
        }
    }
}

/// Vertices, triangles, edges.
type Features = (Vec<DVec3>, Vec<[usize; 3]>, Vec<[usize; 2]>);

fn extent() -> std::ops::Range<f64> {
    0.05..2.0f64
}

fn extents() -> impl Strategy<Value = DVec3> {
    (extent(), extent(), extent()).prop_map(|(x, y, z)| DVec3::new(x, y, z))
}

/// 4 to 40 random points in a random box; clouds quickhull rejects (flat ones) are redrawn.
fn cloud() -> impl Strategy<Value = Spec> {
    (
        extents(),
        prop::collection::vec((-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64), 4..40),
    )
        .prop_filter_map("degenerate cloud", |(h, points)| {
            let points: Vec<DVec3> = points
                .into_iter()
                .map(|(x, y, z)| DVec3::new(x, y, z) * h)
                .collect();
            ConvexHull::from_points(&points)
                .ok()
                .map(|hull| Spec::Cloud(Arc::new(hull)))
        })
}

/// Convex polyhedra only (boxes, octahedra, point-cloud hulls), for the SAT reference.
fn polyhedron_spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        extents().prop_map(Spec::BoxHull),
        extents().prop_map(Spec::Octahedron),
        cloud(),
    ]
}

fn spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        cloud(),
        extent().prop_map(Spec::Sphere),
        extents().prop_map(Spec::Cuboid),
        (extent(), extent()).prop_map(|(h, r)| Spec::Capsule(h, r)),
        (extent(), extent()).prop_map(|(h, r)| Spec::Cylinder(h, r)),
        extents().prop_map(Spec::BoxHull),
        extents().prop_map(Spec::Octahedron),
    ]
}

fn pose() -> impl Strategy<Value = (DVec3, DQuat)> {
    let unit = -1.0..1.0f64;
    (
        (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
        (unit.clone(), unit.clone(), unit),
    )
        .prop_map(|((x, y, z), (a, b, c))| {
            (DVec3::new(x, y, z), rotation_from(DVec3::new(a, b, c)))
        })
}

fn posed<'a>(shape: &'a Shape, (t, q): (DVec3, DQuat)) -> PosedShape<'a> {
    PosedShape::new(shape, t, DMat3::from_quat(q))
}

const PRISM_SIDES: usize = 96;

/// A regular prism around the y axis, inscribed in the cylinder.
fn inscribed_prism(h: f64, radius: f64) -> Features {
    let n = PRISM_SIDES;
    let step = std::f64::consts::TAU / n as f64;
    let mut vertices = Vec::new();
    for k in 0..n {
        let (sin, cos) = (step * k as f64).sin_cos();
        vertices.push(DVec3::new(radius * cos, h, radius * sin));
        vertices.push(DVec3::new(radius * cos, -h, radius * sin));
    }
    let (top, bottom) = (|k: usize| 2 * (k % n), |k: usize| 2 * (k % n) + 1);
    let mut triangles = Vec::new();
    let mut edges = Vec::new();
    for k in 0..n {
        triangles.push([top(k), top(k + 1), bottom(k)]);
        triangles.push([bottom(k), top(k + 1), bottom(k + 1)]);
        if k > 0 && k + 1 < n {
            triangles.push([top(0), top(k), top(k + 1)]);
            triangles.push([bottom(0), bottom(k), bottom(k + 1)]);
        }
        edges.extend([
            [top(k), top(k + 1)],
            [bottom(k), bottom(k + 1)],
            [top(k), bottom(k)],
        ]);
    }
    (vertices, triangles, edges)
}

/// Distance as the best separating plane: max over unit n of −(h_A(n) + h_B(−n)), found by
/// sampling directions and then refining the best by a shrinking pattern search.
fn support_reference(a: &impl SupportMap, b: &impl SupportMap) -> f64 {
    let gap = |n: DVec3| {
        let n = n.normalize();
        -(n.dot(a.support(n)) - n.dot(b.support(-n)))
    };
    let samples = 2000;
    let golden = std::f64::consts::PI * (3.0 - 5f64.sqrt());
    let mut best = DVec3::X;
    for k in 0..samples {
        let y = 1.0 - 2.0 * (k as f64 + 0.5) / samples as f64;
        let r = (1.0 - y * y).sqrt();
        let n = DVec3::new(
            r * (golden * k as f64).cos(),
            y,
            r * (golden * k as f64).sin(),
        );
        if gap(n) > gap(best) {
            best = n;
        }
    }
    let mut step = 0.05;
    while step > 1e-9 {
        let (u, v) = best.any_orthonormal_pair();
        let improved = [u, -u, v, -v, u + v, u - v, -u + v, -u - v]
            .into_iter()
            .map(|d| (best + d * step).normalize())
            .find(|&n| gap(n) > gap(best));
        match improved {
            Some(n) => best = n,
            None => step *= 0.5,
        }
    }
    gap(best)
}

fn transform(points: &[DVec3], (t, q): (DVec3, DQuat)) -> Vec<DVec3> {
    points.iter().map(|p| q * *p + t).collect()
}

fn point_segment(p: DVec3, a: DVec3, b: DVec3) -> f64 {
    let e = b - a;
    let t = ((p - a).dot(e) / e.length_squared()).clamp(0.0, 1.0);
    p.distance(a + e * t)
}

fn point_triangle(p: DVec3, [a, b, c]: [DVec3; 3]) -> f64 {
    let n = (b - a).cross(c - a).normalize();
    let q = p - n * n.dot(p - a);
    let inside = [(a, b), (b, c), (c, a)]
        .iter()
        .all(|&(u, v)| (v - u).cross(q - u).dot(n) >= 0.0);
    if inside {
        return n.dot(p - a).abs();
    }
    point_segment(p, a, b)
        .min(point_segment(p, b, c))
        .min(point_segment(p, c, a))
}

fn segment_segment(a0: DVec3, a1: DVec3, b0: DVec3, b1: DVec3) -> f64 {
    let boundary = point_segment(a0, b0, b1)
        .min(point_segment(a1, b0, b1))
        .min(point_segment(b0, a0, a1))
        .min(point_segment(b1, a0, a1));
    let (d1, d2, r) = (a1 - a0, b1 - b0, a0 - b0);
    let (aa, ee, bb) = (d1.dot(d1), d2.dot(d2), d1.dot(d2));
    let denom = aa * ee - bb * bb;
    if denom <= 1e-14 * aa * ee {
        return boundary;
    }
    let (c, f) = (d1.dot(r), d2.dot(r));
    let s = (bb * f - c * ee) / denom;
    let t = (aa * f - bb * c) / denom;
    if (0.0..=1.0).contains(&s) && (0.0..=1.0).contains(&t) {
        boundary.min((a0 + d1 * s).distance(b0 + d2 * t))
    } else {
        boundary
    }
}

/// Exact distance between two separated convex cores: the nearest pair of features is a
/// vertex and a triangle, two edges, or two vertices.
fn core_reference((va, ta, ea): &Features, (vb, tb, eb): &Features) -> f64 {
    let mut best = f64::INFINITY;
    for (verts, tris, others) in [(va, ta, vb), (vb, tb, va)] {
        for tri in tris {
            for p in others {
                best = best.min(point_triangle(*p, tri.map(|i| verts[i])));
            }
        }
    }
    for p in va {
        for q in vb {
            best = best.min(p.distance(*q));
        }
    }
    for (verts, edges, others) in [(va, ea, vb), (vb, eb, va)] {
        for e in edges {
            for p in others {
                best = best.min(point_segment(*p, verts[e[0]], verts[e[1]]));
            }
        }
    }
    for e in ea {
        for f in eb {
            best = best.min(segment_segment(va[e[0]], va[e[1]], vb[f[0]], vb[f[1]]));
        }
    }
    best
}

/// Separating-axis test on the 15 axes of two boxes; returns the largest separation found
/// (positive: a separating axis exists).
fn box_sat(ha: DVec3, pa: (DVec3, DQuat), hb: DVec3, pb: (DVec3, DQuat)) -> f64 {
    let ra = DMat3::from_quat(pa.1);
    let rb = DMat3::from_quat(pb.1);
    let axes_a = [ra.x_axis, ra.y_axis, ra.z_axis];
    let axes_b = [rb.x_axis, rb.y_axis, rb.z_axis];
    let mut axes: Vec<DVec3> = axes_a.iter().chain(&axes_b).copied().collect();
    for u in axes_a {
        for v in axes_b {
            let c = u.cross(v);
            if c.length() > 1e-6 {
                axes.push(c.normalize());
            }
        }
    }
    let radius = |axes: [DVec3; 3], h: DVec3, n: DVec3| {
        h.x * axes[0].dot(n).abs() + h.y * axes[1].dot(n).abs() + h.z * axes[2].dot(n).abs()
    };
    axes.iter()
        .map(|&n| (pb.0 - pa.0).dot(n).abs() - radius(axes_a, ha, n) - radius(axes_b, hb, n))
        .fold(f64::NEG_INFINITY, f64::max)
}

/// A support map that hides its core segment and its nearest surface point, so that GJK
/// (and EPA) iterate on it instead of taking the closed forms.
struct Iterated<'a>(PosedShape<'a>);

impl SupportMap for Iterated<'_> {
    fn core_support(&self, direction: DVec3) -> DVec3 {
        self.0.core_support(direction)
    }
    fn margin(&self) -> f64 {
        self.0.margin()
    }
    fn inner_point(&self) -> DVec3 {
        self.0.inner_point()
    }
}

fn round_spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        extent().prop_map(Spec::Sphere),
        (extent(), extent()).prop_map(|(h, r)| Spec::Capsule(h, r)),
    ]
}

fn sharp_spec() -> impl Strategy<Value = Spec> {
    prop_oneof![
        extents().prop_map(Spec::Cuboid),
        (extent(), extent()).prop_map(|(h, r)| Spec::Cylinder(h, r)),
    ]
}

proptest! {
    #![proptest_config(ProptestConfig::with_cases(300))]

    /// A sphere against a box or a cylinder takes the closed-form nearest surface point;
    /// GJK, and EPA when the centre is inside, must find the same signed distance, and
    /// when apart the same normal (the nearest point is unique outside a convex shape).
    #[test]
    fn closed_form_point_distance_matches_gjk_and_epa(
        radius in extent(), sb in sharp_spec(), pa in pose(), pb in pose(), swap in any::<bool>(),
    ) {
        let (shape_a, shape_b) = (Shape::sphere(radius), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let (closed, iterated) = if swap {
            (signed_distance(&b, &a), signed_distance(&Iterated(b), &Iterated(a)))
        } else {
            (signed_distance(&a, &b), signed_distance(&Iterated(a), &Iterated(b)))
        };
        prop_assert_eq!(closed.iterations, 0);
        // The iteration stops at its relative tolerances; on a cylinder's curved rim
        // GJK's witness settles to about 1e-6 of the size (see `distance_matches_reference`).
        let scale = radius.max(sb.size());
        let curved = matches!(sb, Spec::Cylinder(..));
        let tolerance = if curved { 1e-6 } else { 1e-9 } * scale;
        prop_assert!((closed.distance - iterated.distance).abs() <= tolerance,
            "closed form {} against iterated {}", closed.distance, iterated.distance);
        prop_assert!((closed.point_a.distance(closed.point_b) - closed.distance.abs()).abs() <= 1e-9 * scale);
        if closed.distance + radius > tolerance {
            prop_assert!(closed.normal.dot(iterated.normal) >= 1.0 - 1e-6,
                "normal {} against {}", closed.normal, iterated.normal);
        }
    }

    #[test]
    fn distance_matches_reference(sa in spec(), sb in spec(), pa in pose(), pb in pose()) {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let result = gjk_distance(&a, &b);
        prop_assert!(result.distance.is_finite() && result.point_a.is_finite() && result.point_b.is_finite());
        prop_assert!(result.iterations <= GJK_MAX_ITERATIONS);
        let scale = sa.size().max(sb.size());
        // Exact for polytopes, spheres and capsules. A cylinder's inscribed prism is farther,
        // by at most the prism's sagitta. (A circumscribed prism would give no lower bound
        // once it overlaps the other shape: the reference measures separated cores only.)
        let place = |(f, m): (Features, f64), p| ((transform(&f.0, p), f.1, f.2), m);
        let (x, ma) = place(sa.core(), pa);
        let (y, mb) = place(sb.core(), pb);
        if !result.intersecting {
            let upper = (core_reference(&x, &y) - ma - mb).max(0.0);
            let lower = (upper - sa.prism_sagitta() - sb.prism_sagitta()).max(0.0);
            let tolerance = 1e-9 * scale;
            prop_assert!(lower - tolerance <= result.distance && result.distance <= upper + tolerance,
                "gjk {} not in [{lower}, {upper}]", result.distance);
        } else {
            // Touching or overlapping: no plane separates them.
            let gap = support_reference(&a, &b);
            prop_assert!(gap <= 1e-9 * scale, "intersecting, yet a plane separates by {gap:e}");
        }
        if !result.intersecting {
            // The witnesses are on the surfaces and as far apart as the distance.
            prop_assert!((result.point_a.distance(result.point_b) - result.distance).abs() <= 1e-9 * scale);
            let n = result.normal;
            let error_a = (n.dot(a.support(n)) - n.dot(result.point_a)).abs();
            let error_b = (n.dot(b.support(-n)) - n.dot(result.point_b)).abs();
            // Round-off on |v|² (relative 1e-14) costs the witnesses ε s² / d when nearly
            // touching. A cylinder's rim is curved: GJK stops on round-off and answers with its
            // best iterate, whose witness is within 1e-6 of the size of its support plane.
            let curved = matches!(sa, Spec::Cylinder(..)) || matches!(sb, Spec::Cylinder(..));
            let tolerance = if curved { 1e-6 * scale } else { 1e-9 * scale }
                + 1e-13 * scale * scale / result.distance;
            prop_assert!(error_a.max(error_b) <= tolerance, "witness off its support plane by {error_a:e}, {error_b:e} at distance {} after {} iterations", result.distance, result.iterations);
        }
    }

    /// Spheres and capsules take the closed form; GJK's iteration on the same cores must
    /// find the same distance, witnesses and normal.
    #[test]
    fn closed_form_round_cores_match_iterated_gjk(
        sa in round_spec(), sb in round_spec(), pa in pose(), pb in pose()
    ) {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let closed = gjk_distance(&a, &b);
        let iterated = gjk_distance(&Iterated(a), &Iterated(b));
        prop_assert_eq!(closed.intersecting, iterated.intersecting);
        let tolerance = 1e-9 * sa.size().max(sb.size());
        prop_assert!((closed.distance - iterated.distance).abs() <= tolerance,
            "closed form {} against iterated {}", closed.distance, iterated.distance);
        if !closed.intersecting {
            // Witnesses of parallel capsules are not unique: only their gap is compared.
            prop_assert!((closed.point_a.distance(closed.point_b) - closed.distance).abs() <= tolerance);
            prop_assert!(closed.normal.dot(iterated.normal) >= 1.0 - 1e-9);
        }
    }

    #[test]
    fn distance_is_symmetric(sa in spec(), sb in spec(), pa in pose(), pb in pose()) {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let ab = gjk_distance(&a, &b);
        let ba = gjk_distance(&b, &a);
        let scale = sa.size().max(sb.size());
        prop_assert!((ab.distance - ba.distance).abs() <= 1e-9 * scale);
        if ab.distance > 1e-6 * scale {
            prop_assert!(ab.point_a.distance(ba.point_b) <= 1e-6 * scale);
            prop_assert!(ab.normal.dot(ba.normal) < -0.999_999);
        }
    }

    /// The early exit may only drop pairs that are truly beyond the limit, and must not
    /// change the answer for the others.
    #[test]
    fn distance_within_a_limit_is_the_full_answer_or_none(
        sa in spec(),
        sb in spec(),
        pa in pose(),
        pb in pose(),
        limit_fraction in -0.5..1.5f64,
    ) {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let full = signed_distance(&a, &b);
        let limit = limit_fraction * full.distance.abs();
        match signed_distance_within(&a, &b, limit, EXACT) {
            Some(within) => prop_assert_eq!(within, full),
            None => prop_assert!(full.distance > limit, "{} ≤ {limit}", full.distance),
        }
    }

    /// A search stopped at an accuracy may overstate the gap by that much of the pair's size,
    /// never understate it (GJK closes on the distance from above, EPA on the depth from
    /// below), and agrees with the exact search whether the shapes overlap.
    #[test]
    fn a_coarse_accuracy_overstates_the_gap_by_at_most_that(
        sa in spec(), sb in spec(), pa in pose(), pb in pose(),
    ) {
        const ACCURACY: f64 = 1e-6;
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let exact = signed_distance(&a, &b);
        let coarse = signed_distance_within(&a, &b, f64::INFINITY, ACCURACY).unwrap();
        let size = pa.0.distance(pb.0) + sa.size() + sb.size();
        if exact.distance.abs() > 2.0 * ACCURACY * size {
            prop_assert_eq!(coarse.distance > 0.0, exact.distance > 0.0);
        }
        prop_assert!(coarse.distance >= exact.distance - 1e-9 * size, "{coarse:?} {exact:?}");
        prop_assert!(
            coarse.distance <= exact.distance + ACCURACY * size + 1e-9 * size,
            "{coarse:?} {exact:?}"
        );
    }

    #[test]
    fn intersection_agrees_with_sat_for_polyhedra(
        sa in polyhedron_spec(), sb in polyhedron_spec(), pa in pose(), pb in pose(),
    ) {
        let (a, b) = (sa.polyhedron().unwrap(), sb.polyhedron().unwrap());
        let sat = polyhedron_sat(&a, pa, &b, pb);
        prop_assume!(sat.abs() > 1e-9 * sa.size().max(sb.size()));
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let gjk = gjk_intersects(&posed(&shape_a, pa), &posed(&shape_b, pb));
        prop_assert_eq!(gjk, sat < 0.0, "sat separation {}", sat);
    }

    #[test]
    fn intersection_agrees_with_sat_for_boxes(
        ha in extents(), hb in extents(), pa in pose(), pb in pose(),
    ) {
        let (shape_a, shape_b) = (Shape::cuboid(ha), Shape::cuboid(hb));
        let sat = box_sat(ha, pa, hb, pb);
        prop_assume!(sat.abs() > 1e-9);
        let gjk = gjk_intersects(&posed(&shape_a, pa), &posed(&shape_b, pb));
        prop_assert_eq!(gjk, sat < 0.0, "sat separation {}", sat);
    }

    #[test]
    fn epa_depth_and_normal_separate(sa in spec(), sb in spec(), pa in pose(), pb in pose()) {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let Some(p) = penetration(&a, &b) else { return Ok(()); };
        prop_assert!(p.depth.is_finite() && p.normal.is_finite());
        prop_assert!((p.normal.length() - 1.0).abs() < 1e-9);
        let epsilon = 1e-5 * sa.size().max(sb.size());
        let pushed = b.translated(p.normal * (p.depth + epsilon));
        prop_assert!(!gjk_intersects(&a, &pushed), "depth {} normal {}", p.depth, p.normal);
        if p.depth > epsilon {
            let short = b.translated(p.normal * (p.depth - epsilon));
            prop_assert!(gjk_intersects(&a, &short), "depth {} normal {}", p.depth, p.normal);
        }
    }
}

#[test]
fn touching_boxes_have_zero_distance() {
    let shape = Shape::cuboid(DVec3::splat(0.5));
    let a = PosedShape::new(&shape, DVec3::ZERO, DMat3::IDENTITY);
    let b = PosedShape::new(&shape, DVec3::new(0.3, 1.0, 0.2), DMat3::IDENTITY);
    let result = gjk_distance(&a, &b);
    assert!(result.distance.abs() < 1e-12);
    assert!(result.intersecting);
    let p = penetration(&a, &b).unwrap();
    assert!(p.depth < 1e-9, "depth {}", p.depth);
}

#[test]
fn deep_penetration_of_concentric_spheres() {
    let (big, small) = (Shape::sphere(1.0), Shape::sphere(0.25));
    let a = PosedShape::new(&big, DVec3::ZERO, DMat3::IDENTITY);
    let b = PosedShape::new(&small, DVec3::ZERO, DMat3::IDENTITY);
    let p = penetration(&a, &b).unwrap();
    assert!((p.depth - 1.25).abs() < 1e-6, "depth {}", p.depth);
    // Slightly off centre the normal follows the offset.
    let b = b.translated(DVec3::new(0.0, 0.0, 0.1));
    let p = penetration(&a, &b).unwrap();
    assert!((p.depth - 1.15).abs() < 1e-12);
    assert!(p.normal.distance(DVec3::Z) < 1e-12);
}

#[test]
fn size_ratio_one_to_a_thousand() {
    let (big, small) = (
        Shape::cuboid(DVec3::new(50.0, 10.0, 50.0)),
        Shape::sphere(0.01),
    );
    let ground = PosedShape::new(&big, DVec3::new(0.0, -10.0, 0.0), DMat3::IDENTITY);
    for gap in [1e-6, 1e-3, 0.5] {
        let ball = PosedShape::new(&small, DVec3::new(3.0, 0.01 + gap, -7.0), DMat3::IDENTITY);
        let result = gjk_distance(&ground, &ball);
        assert!(
            (result.distance - gap).abs() < 1e-12,
            "gap {gap}: {}",
            result.distance
        );
        assert!(result.normal.distance(DVec3::Y) < 1e-12);
    }
    // A small box half sunk into the big one, tilted.
    let tiny = Shape::cuboid(DVec3::splat(0.01));
    let rotation = DMat3::from_quat(DQuat::from_rotation_z(0.3));
    let sunk = PosedShape::new(&tiny, DVec3::new(1.0, 0.0, 2.0), rotation);
    let p = penetration(&ground, &sunk).unwrap();
    let expected = 0.01 * (0.3f64.cos() + 0.3f64.sin());
    assert!(
        (p.depth - expected).abs() < 1e-9,
        "depth {} expected {expected}",
        p.depth
    );
    assert!(p.normal.distance(DVec3::Y) < 1e-9);
}

/// The separating-axis theorem for two convex polyhedra, written out independently of the
/// engine: the largest gap between their projections over the face normals of both and the
/// cross products of every pair of edges. Positive: separated by that much along some axis
/// (a lower bound on the distance); negative: overlapping.
fn polyhedron_sat(a: &ConvexHull, pa: (DVec3, DQuat), b: &ConvexHull, pb: (DVec3, DQuat)) -> f64 {
    let world = |hull: &ConvexHull, (t, q): (DVec3, DQuat)| -> Vec<DVec3> {
        hull.vertices.iter().map(|v| t + q * *v).collect()
    };
    let (va, vb) = (world(a, pa), world(b, pb));
    let face_normals = |hull: &ConvexHull, v: &[DVec3]| -> Vec<DVec3> {
        hull.faces
            .iter()
            .map(|f| {
                let [p, q, r] = [0, 1, 2].map(|k| v[f.vertices[k] as usize]);
                (q - p).cross(r - p)
            })
            .collect()
    };
    let edges = |hull: &ConvexHull, v: &[DVec3]| -> Vec<DVec3> {
        hull.edges
            .iter()
            .map(|e| v[e[1] as usize] - v[e[0] as usize])
            .collect()
    };
    let mut axes = face_normals(a, &va);
    axes.extend(face_normals(b, &vb));
    for ea in edges(a, &va) {
        axes.extend(edges(b, &vb).iter().map(|eb| ea.cross(*eb)));
    }
    let range = |v: &[DVec3], axis: DVec3| {
        v.iter()
            .map(|p| p.dot(axis))
            .fold((f64::MAX, f64::MIN), |(lo, hi), d| (lo.min(d), hi.max(d)))
    };
    axes.into_iter()
        .filter(|axis| axis.length() > 1e-9)
        .map(|axis| {
            let axis = axis.normalize();
            let ((a_lo, a_hi), (b_lo, b_hi)) = (range(&va, axis), range(&vb, axis));
            (b_lo - a_hi).max(a_lo - b_hi)
        })
        .fold(f64::MIN, f64::max)
}

/// Two pairs (box edge against a cylinder's rim) where GJK's last step lowered ‖v‖² by
/// round-off but turned v: the witness on the box was 3e-5 to 6e-5 m off its support plane.
/// The search keeps its best iterate, so both witnesses are within 1e-6 × size of their planes.
#[test]
fn gjk_keeps_its_best_iterate_against_a_cylinder_rim() {
    let cases = [
        (
            Spec::Cylinder(0.5334535074956874, 0.8725447152179646),
            Spec::BoxHull(DVec3::new(
                1.6717276541952935,
                1.7345485140730479,
                1.8290096783046148,
            )),
            (
                DVec3::new(0.5624848919829458, -2.7576190015904025, -0.8174257576107572),
                DQuat::from_xyzw(
                    0.31024847769438557,
                    0.7826585430153595,
                    0.5291626420660924,
                    0.10572788362122548,
                ),
            ),
            (
                DVec3::new(0.2376330101027954, 0.0037215844685635317, 1.299487708526767),
                DQuat::from_xyzw(
                    -0.8615382950863664,
                    0.42378306403801197,
                    -0.05619058123116007,
                    0.27386547667629746,
                ),
            ),
        ),
        (
            Spec::BoxHull(DVec3::new(
                1.2534462732979859,
                0.4113951770349152,
                1.124377629949379,
            )),
            Spec::Cylinder(1.8927815463495021, 1.5681349411181076),
            (
                DVec3::new(
                    -0.26740641398214576,
                    -2.054606070811142,
                    -0.8554814223498558,
                ),
                DQuat::from_xyzw(
                    0.9109072991531088,
                    0.19416218221324574,
                    -0.3518108030274667,
                    -0.0936915055965486,
                ),
            ),
            (
                DVec3::new(0.07006495798390602, 0.642655538208205, -0.34614179229529707),
                DQuat::from_xyzw(
                    0.6260575797388468,
                    0.49827141800667457,
                    0.4662981630534832,
                    -0.37728440728726464,
                ),
            ),
        ),
    ];
    for (sa, sb, pa, pb) in cases {
        let (shape_a, shape_b) = (sa.shape(), sb.shape());
        let (a, b) = (posed(&shape_a, pa), posed(&shape_b, pb));
        let result = gjk_distance(&a, &b);
        assert!(!result.intersecting);
        let n = result.normal;
        let error_a = (n.dot(a.support(n)) - n.dot(result.point_a)).abs();
        let error_b = (n.dot(b.support(-n)) - n.dot(result.point_b)).abs();
        let tolerance = 1e-6 * sa.size().max(sb.size());
        assert!(
            error_a.max(error_b) <= tolerance,
            "witnesses off their support planes by {error_a:e}, {error_b:e} (tolerance {tolerance:e})"
        );
    }
}

//! Closest points of two segments, where a segment may shrink to a point: the cores of
//! spheres (a point) and capsules (a segment). GJK takes this closed form for such pairs
//! instead of iterating, and the polyhedron contacts use it for edge against edge.

use glam::DVec3;

/// Closest points of segments [p0, p1] and [q0, q1]; either may have zero length.
pub fn closest_points_of_segments(p0: DVec3, p1: DVec3, q0: DVec3, q1: DVec3) -> (DVec3, DVec3) {
    let (d1, d2, r) = (p1 - p0, q1 - q0, p0 - q0);
    let (a, e, f) = (d1.dot(d1), d2.dot(d2), d2.dot(r));
    if a <= f64::MIN_POSITIVE && e <= f64::MIN_POSITIVE {
        return (p0, q0);
    }
    if a <= f64::MIN_POSITIVE {
        return (p0, q0 + d2 * (f / e).clamp(0.0, 1.0));
    }
    let c = d1.dot(r);
    if e <= f64::MIN_POSITIVE {
        return (p0 + d1 * (-c / a).clamp(0.0, 1.0), q0);
    }
    let b = d1.dot(d2);
    let denom = a * e - b * b;
    // Parallel segments: any s works; take the start of the first one.
    let mut s = if denom > 1e-14 * a * e {
        ((b * f - c * e) / denom).clamp(0.0, 1.0)
    } else {
        0.0
    };
    let mut t = (b * s + f) / e;
    if t < 0.0 {
        t = 0.0;
        s = (-c / a).clamp(0.0, 1.0);
    } else if t > 1.0 {
        t = 1.0;
        s = ((b - c) / a).clamp(0.0, 1.0);
    }
    (p0 + d1 * s, q0 + d2 * t)
}

/// The closest points of two segment cores and their distance, or None when the cores
/// touch or cross (distance below round-off of their size): penetration depth then needs
/// EPA, which works on support points.
pub fn separated_segments(a: [DVec3; 2], b: [DVec3; 2]) -> Option<(DVec3, DVec3, f64)> {
    let (point_a, point_b) = closest_points_of_segments(a[0], a[1], b[0], b[1]);
    let distance_sq = point_a.distance_squared(point_b);
    let size_sq = [a[0], a[1], b[0], b[1]]
        .iter()
        .map(|p| p.length_squared())
        .fold(a[0].distance_squared(b[0]), f64::max);
    (distance_sq > 1e-20 * size_sq && distance_sq.is_finite())
        .then(|| (point_a, point_b, distance_sq.sqrt()))
}

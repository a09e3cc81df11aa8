//! EPA (expanding polytope): when two shapes overlap, the penetration depth is the distance
//! from the origin to the boundary of their Minkowski difference M = A ⊖ B. Starting from a
//! polytope inside M that holds the origin (GJK's last simplex), the face nearest the origin
//! is pushed out to the support point along its normal until the face lies on M's boundary.
//!
//! Normal convention: `normal` points from A towards B. Moving B by `depth * normal` (or A by
//! the opposite) brings the shapes to touching.

use std::cell::Cell;

use glam::DVec3;
use smallvec::{SmallVec, smallvec};

use crate::physics::geometry::gjk::{
    CoreDistance, EXACT, Simplex, SupportMap, SupportPoint, gjk_core_distance_within,
};

/// How deep two overlapping shapes penetrate, along which direction, and where.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Penetration {
    /// How far B must move along `normal` (or A against it) for the shapes to touch, m; ≥ 0.
    pub depth: f64,
    /// Unit, from A towards B.
    pub normal: DVec3,
    /// The point of A deepest inside B, and the point of B deepest inside A (on the cores
    /// when `epa` is called directly; `penetration` adds the margins). World coordinates.
    pub point_a: DVec3,
    /// The point of B deepest inside A; see `point_a`.
    pub point_b: DVec3,
    /// Iterations made: EPA's alone from `epa`, GJK's and EPA's together from `penetration`.
    pub iterations: u32,
}

/// Signed distance between two shapes: positive gap or negative penetration depth, with
/// the normal from A to B and the witness points on each shape.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SignedDistance {
    /// The gap between the surfaces when positive, minus the penetration depth when
    /// negative, m.
    pub distance: f64,
    /// Unit, from A towards B: moving B by `-distance * normal` brings the shapes to
    /// touching.
    pub normal: DVec3,
    /// The witness point on A's surface, world.
    pub point_a: DVec3,
    /// The witness point on B's surface, world.
    pub point_b: DVec3,
    /// GJK iterations plus EPA iterations.
    pub iterations: u32,
}

/// Most expansions EPA makes; past them it settles for the nearest face found so far.
pub const EPA_MAX_ITERATIONS: u32 = 128;
/// The support along the nearest face's normal must lie within this fraction of the size of
/// M from the face (curved shapes only converge to a tolerance).
const RELATIVE_TOLERANCE: f64 = 1e-9;

/// Distance when apart, depth when overlapping: GJK for the gap and shallow overlaps of the
/// margins, EPA on the cores when the cores themselves overlap (then the margins add to the
/// core depth, which keeps round shapes exact).
pub fn signed_distance(a: &impl SupportMap, b: &impl SupportMap) -> SignedDistance {
    signed_distance_within(a, b, f64::INFINITY, EXACT)
        .expect("no distance is beyond an infinite limit")
}

/// The signed distance when it is at most `limit`, else None (found without converging on
/// the distance of shapes that are farther apart: see `gjk_core_distance_within`, which
/// also says what `accuracy` allows of a gap).
pub fn signed_distance_within(
    a: &impl SupportMap,
    b: &impl SupportMap,
    limit: f64,
    accuracy: f64,
) -> Option<SignedDistance> {
    if let Some(found) = point_against_surface(a, b) {
        return (found.distance <= limit).then_some(found);
    }
    if let Some(found) = point_against_surface(b, a) {
        return (found.distance <= limit).then_some(SignedDistance {
            normal: -found.normal,
            point_a: found.point_b,
            point_b: found.point_a,
            ..found
        });
    }
    let margins = a.margin() + b.margin();
    let core = gjk_core_distance_within(a, b, limit + margins, accuracy)?;
    if !core.overlap && core.distance > f64::MIN_POSITIVE {
        let found = from_separate_cores(a, b, &core);
        return (found.distance <= limit).then_some(found);
    }
    let p = epa(a, b, &core.simplex, accuracy);
    let found = SignedDistance {
        distance: -(p.depth + a.margin() + b.margin()),
        normal: p.normal,
        point_a: p.point_a + p.normal * a.margin(),
        point_b: p.point_b - p.normal * b.margin(),
        iterations: core.iterations + p.iterations,
    };
    // Also drops a distance that round-off made NaN.
    (found.distance <= limit).then_some(found)
}

/// None when the shapes are apart; the penetration (possibly 0 when touching) otherwise.
pub fn penetration(a: &impl SupportMap, b: &impl SupportMap) -> Option<Penetration> {
    let signed = signed_distance(a, b);
    (signed.distance <= 0.0).then_some(Penetration {
        depth: -signed.distance,
        normal: signed.normal,
        point_a: signed.point_a,
        point_b: signed.point_b,
        iterations: signed.iterations,
    })
}

/// A shape whose core is a point (a sphere, a surface point) against a sharp shape with a
/// closed-form nearest surface point: exact, and no iteration.
fn point_against_surface(
    point: &impl SupportMap,
    shape: &impl SupportMap,
) -> Option<SignedDistance> {
    let [p, q] = point.core_segment()?;
    if p != q || shape.margin() != 0.0 {
        return None;
    }
    let nearest = shape.nearest_surface(p)?;
    // Positive outside, negative inside: the normal from the point to the shape is the
    // surface's inward normal either way.
    let core_distance = (p - nearest.point).dot(nearest.outward_normal);
    let normal = -nearest.outward_normal;
    Some(SignedDistance {
        distance: core_distance - point.margin(),
        normal,
        point_a: p + normal * point.margin(),
        point_b: nearest.point,
        iterations: 0,
    })
}

fn from_separate_cores(
    a: &impl SupportMap,
    b: &impl SupportMap,
    core: &CoreDistance,
) -> SignedDistance {
    let normal = core.normal;
    SignedDistance {
        distance: core.distance - a.margin() - b.margin(),
        normal,
        point_a: core.point_a + normal * a.margin(),
        point_b: core.point_b - normal * b.margin(),
        iterations: core.iterations,
    }
}

#[derive(Clone, Copy, Debug)]
struct Face {
    vertices: [usize; 3],
    /// The face across edge k, which runs from `vertices[k]` to `vertices[(k + 1) % 3]`.
    adjacent: [usize; 3],
    normal: DVec3,
    /// normal · (any vertex): distance of the face plane from the origin.
    distance: f64,
    alive: bool,
}

/// Removed faces stay in the list (marked dead) so that indices stay valid; live faces keep
/// the order they were added in.
struct Polytope {
    points: Vec<SupportPoint>,
    faces: Vec<Face>,
}

thread_local! {
    /// Each thread's spare polytope lists: an EPA runs for every overlapping round pair in
    /// every step, and would otherwise allocate both lists each time. A polytope takes them
    /// when it is made and gives them back when it is dropped.
    static SPARE_LISTS: Cell<(Vec<SupportPoint>, Vec<Face>)> = const {
        Cell::new((Vec::new(), Vec::new()))
    };
}

/// The spare lists, empty, with room for a typical expansion (growing by doubling
/// reallocated each list four or five times per call).
fn spare_lists() -> (Vec<SupportPoint>, Vec<Face>) {
    let (mut points, mut faces) = SPARE_LISTS.take();
    points.clear();
    faces.clear();
    points.reserve(EXPECTED_POINTS);
    faces.reserve(2 * EXPECTED_POINTS);
    (points, faces)
}

impl Drop for Polytope {
    fn drop(&mut self) {
        let lists = (
            std::mem::take(&mut self.points),
            std::mem::take(&mut self.faces),
        );
        SPARE_LISTS.set(lists);
    }
}

/// A removed face's edge on the rim of the removed region, with the live face beyond it.
struct RimEdge {
    from: usize,
    to: usize,
    outside: usize,
}

impl Polytope {
    /// Faces are wound counter-clockwise seen from outside, so a face's normal points out.
    /// Its adjacency is set by the caller.
    fn add_face(&mut self, vertices: [usize; 3]) {
        let [p, q, r] = vertices.map(|i| self.points[i].w);
        let cross = (q - p).cross(r - p);
        let length = cross.length();
        let scale = (q - p).length() * (r - p).length();
        let (normal, distance) = if length > 1e-13 * scale && length.is_finite() {
            let normal = cross / length;
            (normal, normal.dot(p))
        } else {
            // A sliver: keep it for the topology but never pick it as the nearest face.
            (DVec3::ZERO, f64::INFINITY)
        };
        self.faces.push(Face {
            vertices,
            adjacent: [usize::MAX; 3],
            normal,
            distance,
            alive: true,
        });
    }

    fn nearest_face(&self) -> Option<usize> {
        self.faces
            .iter()
            .enumerate()
            .filter(|(_, f)| f.alive && f.distance.is_finite())
            .min_by(|(_, x), (_, y)| x.distance.total_cmp(&y.distance))
            .map(|(i, _)| i)
    }

    /// Removes the faces that `point` sees and closes the hole with a fan to the point. The
    /// seen region is grown from `seed` (a face the point certainly sees) across shared
    /// edges, so it stays connected and its rim is one simple loop even when round-off
    /// makes far faces look visible.
    fn expand(&mut self, seed: usize, point: SupportPoint) {
        let new_index = self.points.len();
        self.points.push(point);
        let mut rim: SmallVec<[RimEdge; 16]> = SmallVec::new();
        let mut stack: SmallVec<[usize; 16]> = smallvec![seed];
        self.faces[seed].alive = false;
        while let Some(current) = stack.pop() {
            let Face {
                vertices, adjacent, ..
            } = self.faces[current];
            for k in 0..3 {
                let next = adjacent[k];
                if self.faces.get(next).is_none_or(|f| !f.alive) {
                    // Already removed: the edge is inside the region.
                    continue;
                }
                if self.faces[next].sees(point.w) {
                    self.faces[next].alive = false;
                    stack.push(next);
                } else {
                    let (from, to) = (vertices[k], vertices[(k + 1) % 3]);
                    rim.push(RimEdge {
                        from,
                        to,
                        outside: next,
                    });
                }
            }
        }
        let first_new = self.faces.len();
        for edge in &rim {
            self.add_face([edge.from, edge.to, new_index]);
        }
        // Round-off can pinch the removed region at a vertex; its rim then passes that
        // vertex twice and the fan's neighbours are not simply the next and previous edge.
        let simple_loop = rim
            .iter()
            .enumerate()
            .all(|(i, e)| rim[..i].iter().all(|earlier| earlier.from != e.from));
        if !simple_loop {
            self.link_by_search();
            return;
        }
        for (i, edge) in rim.iter().enumerate() {
            let face = first_new + i;
            let outside = &mut self.faces[edge.outside];
            if let Some(k) = (0..3).find(|&k| outside.vertices[k] == edge.to) {
                outside.adjacent[k] = face;
            }
            // Along the edges to the new point, the face on from → to meets the fan's face
            // whose rim edge starts at `to`, and the one whose rim edge ends at `from`.
            let starting_at_to = rim.iter().position(|e| e.from == edge.to);
            let ending_at_from = rim.iter().position(|e| e.to == edge.from);
            self.faces[face].adjacent = [
                edge.outside,
                starting_at_to.map_or(usize::MAX, |j| first_new + j),
                ending_at_from.map_or(usize::MAX, |j| first_new + j),
            ];
        }
    }

    /// Sets the adjacency of every live face to the first live face holding the reversed
    /// edge (none: `usize::MAX`). Used on the starting tetrahedron, and after a pinched
    /// expansion, where matching edges is the only reliable way.
    fn link_by_search(&mut self) {
        for f in 0..self.faces.len() {
            if !self.faces[f].alive {
                continue;
            }
            for k in 0..3 {
                let v = self.faces[f].vertices;
                let (from, to) = (v[k], v[(k + 1) % 3]);
                let across = self.faces.iter().position(|g| {
                    let [p, q, r] = g.vertices;
                    g.alive
                        && ([p, q] == [to, from] || [q, r] == [to, from] || [r, p] == [to, from])
                });
                self.faces[f].adjacent[k] = across.unwrap_or(usize::MAX);
            }
        }
    }
}

impl Face {
    /// Slivers (no normal) count as seen so that they get replaced.
    fn sees(&self, point: DVec3) -> bool {
        !self.distance.is_finite() || self.normal.dot(point) > self.distance
    }
}

/// EPA on the cores (margins excluded) from a GJK core simplex whose hull holds the origin.
/// The depth found is at most `accuracy` × the size of the polytope (and never less than
/// round-off allows) below the true one.
pub fn epa(
    a: &impl SupportMap,
    b: &impl SupportMap,
    simplex: &Simplex,
    accuracy: f64,
) -> Penetration {
    let mut polytope = match initial_polytope(a, b, simplex) {
        Ok(polytope) => polytope,
        Err(flat) => return flat_penetration(a, b, &flat, simplex.witnesses()),
    };
    let scale = polytope
        .points
        .iter()
        .map(|p| p.w.length())
        .fold(0.0, f64::max);
    let tolerance = RELATIVE_TOLERANCE.max(accuracy) * scale.max(f64::MIN_POSITIVE);
    let mut iterations = 0;
    // Every face of a degenerate start (shapes squashed to nothing, non-finite supports) can
    // be a sliver without a normal: then the simplex is treated as flat.
    let Some(mut best) = polytope.nearest_face() else {
        let span = polytope.points[..3].to_vec();
        return flat_penetration(a, b, &span, simplex.witnesses());
    };
    // The best face so far, kept by value: points are never removed, so its vertex indices
    // stay valid even when expanding leaves no usable face.
    let mut face = polytope.faces[best];
    while iterations < EPA_MAX_ITERATIONS {
        iterations += 1;
        let support = SupportPoint::of_cores(a, b, face.normal);
        if support.w.dot(face.normal) - face.distance <= tolerance {
            break;
        }
        polytope.expand(best, support);
        match polytope.nearest_face() {
            Some(next) => best = next,
            None => break,
        }
        face = polytope.faces[best];
    }
    witness(&polytope, &face, iterations)
}

/// Barycentric coordinates of the origin's projection on the face give the points on A and B.
fn witness(polytope: &Polytope, face: &Face, iterations: u32) -> Penetration {
    let [p, q, r] = face.vertices.map(|i| polytope.points[i]);
    let projected = face.normal * face.distance;
    let weights = barycentric(projected, p.w, q.w, r.w);
    Penetration {
        depth: face.distance.max(0.0),
        normal: face.normal,
        point_a: p.a * weights.x + q.a * weights.y + r.a * weights.z,
        point_b: p.b * weights.x + q.b * weights.y + r.b * weights.z,
        iterations,
    }
}

fn barycentric(point: DVec3, p: DVec3, q: DVec3, r: DVec3) -> DVec3 {
    let normal = (q - p).cross(r - p);
    let area = normal.length_squared();
    if area <= f64::MIN_POSITIVE {
        return DVec3::new(1.0, 0.0, 0.0);
    }
    let u = (r - q).cross(point - q).dot(normal) / area;
    let v = (p - r).cross(point - r).dot(normal) / area;
    DVec3::new(u, v, 1.0 - u - v)
}

/// A tetrahedron holding the origin, wound outward. GJK's simplex may have fewer than four
/// points when the shapes just touch; it is completed with supports along directions that
/// leave the simplex's affine hull. When no direction does, the core difference is flat (two
/// round cores: points and segments) and the flat span is returned instead.
fn initial_polytope(
    a: &impl SupportMap,
    b: &impl SupportMap,
    simplex: &Simplex,
) -> Result<Polytope, Vec<SupportPoint>> {
    let (mut points, faces) = spare_lists();
    points.extend_from_slice(simplex.vertices());
    if points.len() == 4 && tetra_volume(&points).abs() <= volume_floor(&points) {
        points.truncate(3);
    }
    while points.len() < 4 {
        let next = most_independent_support(a, b, &points);
        if span_distance(&points, next.w) <= FLAT_TOLERANCE * size_of(&points).max(next.w.length())
        {
            return Err(points);
        }
        points.push(next);
    }
    if tetra_volume(&points) < 0.0 {
        points.swap(0, 1);
    }
    let mut polytope = Polytope { points, faces };
    // With positive volume (b−a)×(c−a)·(d−a) > 0, these windings face outward.
    for face in [[0, 2, 1], [0, 1, 3], [0, 3, 2], [1, 2, 3]] {
        polytope.add_face(face);
    }
    polytope.link_by_search();
    Ok(polytope)
}

/// Polytope vertices to make room for up front: a tetrahedron and about a dozen expansions
/// (each removed face stays in the list, so faces grow by about two per vertex).
const EXPECTED_POINTS: usize = 16;

/// Relative thickness below which a core difference counts as flat.
const FLAT_TOLERANCE: f64 = 1e-9;

fn size_of(points: &[SupportPoint]) -> f64 {
    points.iter().map(|p| p.w.length()).fold(0.0, f64::max)
}

/// Flat core difference through the origin: the cores cross, so the depth of the cores is 0
/// along any normal of their span. Among those normals the one closest to the line between
/// the shapes' inner points is taken, oriented from A to B.
fn flat_penetration(
    a: &impl SupportMap,
    b: &impl SupportMap,
    span: &[SupportPoint],
    (point_a, point_b): (DVec3, DVec3),
) -> Penetration {
    let towards_b = b.inner_point() - a.inner_point();
    let mut normal = towards_b;
    if span.len() == 2 {
        let axis = (span[1].w - span[0].w).normalize_or_zero();
        normal -= axis * axis.dot(normal);
    } else if span.len() == 3 {
        let plane = (span[1].w - span[0].w)
            .cross(span[2].w - span[0].w)
            .normalize_or_zero();
        normal = plane * plane.dot(normal).signum();
    }
    let normal = normal
        .try_normalize()
        .unwrap_or_else(|| fallback_normal(span));
    Penetration {
        depth: 0.0,
        normal,
        point_a,
        point_b,
        iterations: 0,
    }
}

fn fallback_normal(span: &[SupportPoint]) -> DVec3 {
    match span.len() {
        2 => (span[1].w - span[0].w)
            .normalize_or(DVec3::X)
            .any_orthonormal_vector(),
        3 => (span[1].w - span[0].w)
            .cross(span[2].w - span[0].w)
            .normalize_or(DVec3::Y),
        _ => DVec3::Y,
    }
}

fn tetra_volume(points: &[SupportPoint]) -> f64 {
    let [a, b, c, d] = [points[0].w, points[1].w, points[2].w, points[3].w];
    (b - a).cross(c - a).dot(d - a)
}

fn volume_floor(points: &[SupportPoint]) -> f64 {
    let size = size_of(points);
    1e-12 * size * size * size
}

/// Among supports along candidate directions, the one farthest from the current points' span.
fn most_independent_support(
    a: &impl SupportMap,
    b: &impl SupportMap,
    points: &[SupportPoint],
) -> SupportPoint {
    let directions = candidate_directions(points);
    directions
        .iter()
        .map(|&d| SupportPoint::of_cores(a, b, d))
        .max_by(|x, y| span_distance(points, x.w).total_cmp(&span_distance(points, y.w)))
        .expect("candidate directions are never empty")
}

fn candidate_directions(points: &[SupportPoint]) -> Vec<DVec3> {
    let mut directions = vec![
        DVec3::X,
        -DVec3::X,
        DVec3::Y,
        -DVec3::Y,
        DVec3::Z,
        -DVec3::Z,
    ];
    match points.len() {
        2 => {
            let axis = (points[1].w - points[0].w).normalize_or(DVec3::X);
            let (u, v) = axis.any_orthonormal_pair();
            directions.extend([u, -u, v, -v]);
        }
        3 => {
            let normal = (points[1].w - points[0].w)
                .cross(points[2].w - points[0].w)
                .normalize_or(DVec3::X);
            directions.extend([normal, -normal]);
        }
        _ => {}
    }
    directions
}

/// Distance from `w` to the affine hull of `points` (1 to 3 points).
fn span_distance(points: &[SupportPoint], w: DVec3) -> f64 {
    let origin = points[0].w;
    let offset = w - origin;
    match points.len() {
        1 => offset.length(),
        2 => {
            let axis = (points[1].w - origin).normalize_or_zero();
            (offset - axis * axis.dot(offset)).length()
        }
        _ => {
            let normal = (points[1].w - origin)
                .cross(points[2].w - origin)
                .normalize_or_zero();
            normal.dot(offset).abs()
        }
    }
}

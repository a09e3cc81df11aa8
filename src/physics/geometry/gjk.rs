//! GJK (report section 3.1.2): the distance between two convex shapes is the distance from the
//! origin to their Minkowski difference M = A ⊖ B, found by growing and shrinking a simplex
//! of support points of M, with S_M(d) = S_A(d) − S_B(−d).
//!
//! Round shapes are handled as a core plus a margin: a sphere is its centre swept by its
//! radius, a capsule its segment swept by its radius. GJK runs on the cores, where it
//! converges in a few iterations to the exact answer, and the margins are subtracted after.
//! When even the cores overlap, the shapes penetrate deeply and `epa` takes over.

use glam::{DMat3, DVec3};

use crate::physics::geometry::nearest_surface::{NearestSurface, nearest_surface};
use crate::physics::geometry::segment::separated_segments;
use crate::physics::geometry::shape::Shape;

/// Anything GJK can measure: a convex set given by the support function of its core and a
/// margin (the radius of the ball swept over the core). All coordinates are world.
pub trait SupportMap {
    /// The point of the core farthest along `direction` (which need not be unit).
    fn core_support(&self, direction: DVec3) -> DVec3;

    /// 0 for polytopes, cylinders and other sharp shapes.
    fn margin(&self) -> f64;

    /// A point inside the shape, used to choose the first search direction.
    fn inner_point(&self) -> DVec3;

    /// The core as a segment (both ends equal for a point), world coordinates, when it is
    /// one: GJK then measures the distance in closed form (`segment`) instead of iterating.
    fn core_segment(&self) -> Option<[DVec3; 2]> {
        None
    }

    /// The surface point nearest to `point` in closed form, world coordinates, for the
    /// shapes that have one (`nearest_surface`).
    fn nearest_surface(&self, _point: DVec3) -> Option<NearestSurface> {
        None
    }

    /// The support of the full shape (core swept by the margin).
    fn support(&self, direction: DVec3) -> DVec3 {
        self.core_support(direction) + direction.normalize_or_zero() * self.margin()
    }
}

/// A shape placed in the world: its own origin at `origin`, its axes the columns of `rotation`.
#[derive(Clone, Copy, Debug)]
pub struct PosedShape<'a> {
    /// The shape, in its own local frame.
    pub shape: &'a Shape,
    /// Where the shape's own origin is, world coordinates (m).
    pub origin: DVec3,
    /// The shape's orientation: its columns are the shape's axes in world coordinates.
    pub rotation: DMat3,
}

impl<'a> PosedShape<'a> {
    /// `shape` with its own origin at `origin` and its axes the columns of `rotation`.
    pub fn new(shape: &'a Shape, origin: DVec3, rotation: DMat3) -> Self {
        PosedShape {
            shape,
            origin,
            rotation,
        }
    }

    /// The same shape moved by `offset` (world, m), not turned.
    pub fn translated(self, offset: DVec3) -> Self {
        PosedShape {
            origin: self.origin + offset,
            ..self
        }
    }

    /// The convex parts of a compound, each placed in the world; None for convex shapes.
    /// GJK on a compound itself sees the convex hull of its parts: contact generation and
    /// casts go through the parts instead.
    pub fn compound_parts(&self) -> Option<Vec<PosedShape<'a>>> {
        let Shape::Compound(compound) = self.shape else {
            return None;
        };
        let parts = compound
            .parts
            .iter()
            .map(|part| {
                PosedShape::new(
                    &part.shape,
                    self.to_world(part.pose.translation),
                    self.rotation * DMat3::from_quat(part.pose.rotation),
                )
            })
            .collect();
        Some(parts)
    }

    /// A point from shape coordinates to world coordinates.
    pub fn to_world(&self, local: DVec3) -> DVec3 {
        self.origin + self.rotation * local
    }

    /// A direction from world coordinates to shape coordinates (rotated only).
    pub fn to_local_direction(&self, world: DVec3) -> DVec3 {
        self.rotation.transpose() * world
    }
}

impl SupportMap for PosedShape<'_> {
    fn core_support(&self, direction: DVec3) -> DVec3 {
        self.to_world(shape_core_support(
            self.shape,
            self.to_local_direction(direction),
        ))
    }

    fn margin(&self) -> f64 {
        shape_margin(self.shape)
    }

    fn inner_point(&self) -> DVec3 {
        match self.shape {
            // Only these may sit off their origin; the primitives are centred on it, and
            // their bounds' centre is exactly the origin, for no work.
            Shape::ConvexHull(_) | Shape::Compound(_) => {
                let (min, max) = self.shape.local_bounds();
                self.to_world(0.5 * (min + max))
            }
            _ => self.origin,
        }
    }

    fn core_segment(&self) -> Option<[DVec3; 2]> {
        match *self.shape {
            Shape::Sphere { .. } => Some([self.origin; 2]),
            Shape::Capsule { half_height, .. } => {
                let half = self.rotation * DVec3::new(0.0, half_height, 0.0);
                Some([self.origin - half, self.origin + half])
            }
            _ => None,
        }
    }

    fn nearest_surface(&self, point: DVec3) -> Option<NearestSurface> {
        let local = self.rotation.transpose() * (point - self.origin);
        let nearest = nearest_surface(self.shape, local)?;
        Some(NearestSurface {
            point: self.to_world(nearest.point),
            outward_normal: self.rotation * nearest.outward_normal,
            inside: nearest.inside,
        })
    }
}

/// A single point (rays are casts of a point).
impl SupportMap for DVec3 {
    fn core_support(&self, _direction: DVec3) -> DVec3 {
        *self
    }

    fn margin(&self) -> f64 {
        0.0
    }

    fn inner_point(&self) -> DVec3 {
        *self
    }

    fn core_segment(&self) -> Option<[DVec3; 2]> {
        Some([*self; 2])
    }
}

/// The radius swept over the core of a shape (see the module comment).
pub fn shape_margin(shape: &Shape) -> f64 {
    match shape {
        Shape::Sphere { radius } | Shape::Capsule { radius, .. } => *radius,
        _ => 0.0,
    }
}

/// Local support of the core: a sphere's centre, a capsule's segment, else the shape itself.
pub fn shape_core_support(shape: &Shape, direction: DVec3) -> DVec3 {
    match shape {
        Shape::Sphere { .. } => DVec3::ZERO,
        Shape::Capsule { half_height, .. } => {
            DVec3::new(0.0, half_height.copysign(direction.y), 0.0)
        }
        _ => shape.support(direction),
    }
}

/// A vertex of the Minkowski difference with the two shape points it came from.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct SupportPoint {
    /// w = a − b
    pub w: DVec3,
    /// The support point of A's core along the search direction, world.
    pub a: DVec3,
    /// The support point of B's core against the search direction, world.
    pub b: DVec3,
}

impl SupportPoint {
    /// Support of the core difference along `direction`.
    pub fn of_cores(a: &impl SupportMap, b: &impl SupportMap, direction: DVec3) -> Self {
        let pa = a.core_support(direction);
        let pb = b.core_support(-direction);
        SupportPoint {
            w: pa - pb,
            a: pa,
            b: pb,
        }
    }
}

/// Up to four support points with the barycentric weights of the point closest to the origin.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Simplex {
    /// The support points; only the first `len` belong to the simplex.
    pub points: [SupportPoint; 4],
    /// The closest point's barycentric weights, one per point in use, summing to 1.
    pub weights: [f64; 4],
    /// How many of `points` are in use, 1 to 4.
    pub len: usize,
}

impl Simplex {
    fn single(point: SupportPoint) -> Self {
        Simplex {
            points: [point; 4],
            weights: [1.0, 0.0, 0.0, 0.0],
            len: 1,
        }
    }

    /// The support points in use.
    pub fn vertices(&self) -> &[SupportPoint] {
        &self.points[..self.len]
    }

    fn push(&mut self, point: SupportPoint) {
        self.points[self.len] = point;
        self.len += 1;
    }

    /// Σ λᵢ wᵢ, Σ λᵢ aᵢ, Σ λᵢ bᵢ
    fn combine(&self) -> (DVec3, DVec3, DVec3) {
        let mut sums = (DVec3::ZERO, DVec3::ZERO, DVec3::ZERO);
        for (p, &l) in self.vertices().iter().zip(&self.weights) {
            sums.0 += p.w * l;
            sums.1 += p.a * l;
            sums.2 += p.b * l;
        }
        sums
    }

    /// The closest points of A and B that the weights describe.
    pub fn witnesses(&self) -> (DVec3, DVec3) {
        let (_, a, b) = self.combine();
        (a, b)
    }

    fn contains_w(&self, w: DVec3, tolerance_sq: f64) -> bool {
        self.vertices()
            .iter()
            .any(|p| p.w.distance_squared(w) <= tolerance_sq)
    }
}

/// GJK on the cores only (no margins).
#[derive(Clone, Copy, Debug)]
pub struct CoreDistance {
    /// Distance between the cores; 0 when they overlap.
    pub distance: f64,
    /// The closest point of A's core, world (meaningless when `overlap`).
    pub point_a: DVec3,
    /// The closest point of B's core, world (meaningless when `overlap`).
    pub point_b: DVec3,
    /// Unit, from A's core towards B's (zero when they overlap).
    pub normal: DVec3,
    /// The cores overlap: the final simplex encloses (or touches) the origin.
    pub overlap: bool,
    /// The last simplex, from which EPA starts when the cores overlap.
    pub simplex: Simplex,
    /// GJK iterations made; 0 when two separate segment or point cores were measured in
    /// closed form.
    pub iterations: u32,
}

/// Result of `gjk_distance` on the full shapes.
#[derive(Clone, Copy, Debug)]
pub struct GjkResult {
    /// Distance between the shapes; 0 when they touch or intersect.
    pub distance: f64,
    /// Closest points on A and on B. When intersecting with separate cores they are the
    /// witnesses of the penetration (they have crossed); with overlapping cores, the core
    /// witnesses (use `epa::penetration` for a depth).
    pub point_a: DVec3,
    /// The closest point on B, world; see `point_a`.
    pub point_b: DVec3,
    /// Unit vector from A to B along the closest points (zero when the cores overlap).
    pub normal: DVec3,
    /// The shapes touch or overlap: the cores are no farther apart than the two margins.
    pub intersecting: bool,
    /// GJK iterations made on the cores; 0 when two separate segment or point cores were
    /// measured in closed form.
    pub iterations: u32,
}

/// A bound that only pathological inputs reach; typical pairs converge in 3 to 10.
pub const GJK_MAX_ITERATIONS: u32 = 64;

/// Relative progress below which GJK stops: ‖v‖² − v·w ≤ ε ‖v‖².
const RELATIVE_TOLERANCE: f64 = 1e-12;
/// The `accuracy` of a search that runs to round-off.
pub const EXACT: f64 = 0.0;
/// Round-off floor, relative to the square of the size of the simplex.
const ROUND_OFF: f64 = 1e-14;
/// Below this squared distance (relative to the simplex size) the cores touch.
const TOUCHING: f64 = 1e-20;
/// A support point this close (squared, relative) to a simplex vertex is that vertex again.
/// Curved shapes give new points very close to old ones, so this must stay near round-off.
const DUPLICATE: f64 = 1e-26;

/// Distance, closest points and intersection of two convex shapes.
pub fn gjk_distance(a: &impl SupportMap, b: &impl SupportMap) -> GjkResult {
    let core = gjk_core_distance(a, b);
    let margins = a.margin() + b.margin();
    if core.overlap {
        return GjkResult {
            distance: 0.0,
            point_a: core.point_a,
            point_b: core.point_b,
            normal: DVec3::ZERO,
            intersecting: true,
            iterations: core.iterations,
        };
    }
    let normal = core.normal;
    GjkResult {
        distance: (core.distance - margins).max(0.0),
        point_a: core.point_a + normal * a.margin(),
        point_b: core.point_b - normal * b.margin(),
        normal,
        intersecting: core.distance <= margins,
        iterations: core.iterations,
    }
}

/// True when the shapes touch or overlap.
pub fn gjk_intersects(a: &impl SupportMap, b: &impl SupportMap) -> bool {
    gjk_distance(a, b).intersecting
}

/// GJK on the cores of the shapes.
pub fn gjk_core_distance(a: &impl SupportMap, b: &impl SupportMap) -> CoreDistance {
    gjk_core_distance_within(a, b, f64::INFINITY, EXACT)
        .expect("no distance is beyond an infinite limit")
}

/// GJK on the cores, or None as soon as the cores are known to be farther apart than
/// `limit`. Contact generation only wants pairs within its margin, and most pairs the broad
/// phase reports are well beyond it: a support plane proves that after a few iterations,
/// where converging on the distance of two curved shapes takes tens.
/// The distance found is at most `accuracy` × the size of the simplex above the true one
/// (`EXACT`: to round-off).
pub fn gjk_core_distance_within(
    a: &impl SupportMap,
    b: &impl SupportMap,
    limit: f64,
    accuracy: f64,
) -> Option<CoreDistance> {
    if let (Some(core_a), Some(core_b)) = (a.core_segment(), b.core_segment())
        && let Some((point_a, point_b, distance)) = separated_segments(core_a, core_b)
    {
        if distance > limit {
            return None;
        }
        return Some(CoreDistance {
            distance,
            point_a,
            point_b,
            normal: (point_b - point_a) / distance,
            overlap: false,
            simplex: Simplex::single(SupportPoint {
                w: point_a - point_b,
                a: point_a,
                b: point_b,
            }),
            iterations: 0,
        });
    }
    let first_direction = (b.inner_point() - a.inner_point()).normalize_or(DVec3::X);
    let mut simplex = Simplex::single(SupportPoint::of_cores(a, b, -first_direction));
    let mut v = simplex.points[0].w;
    let mut iterations = 0;
    let mut overlap = false;
    let mut endgame = Endgame::new();
    while iterations < GJK_MAX_ITERATIONS {
        iterations += 1;
        let scale_sq = simplex_scale_sq(&simplex);
        let v_sq = v.length_squared();
        if v_sq <= TOUCHING * scale_sq {
            overlap = true;
            break;
        }
        let w = SupportPoint::of_cores(a, b, -v);
        // Every point m of the difference has m·v ≥ w·v, so |m| ≥ w·v / |v|.
        let support_along_v = v.dot(w.w);
        if support_along_v > limit * v_sq.sqrt() {
            return None;
        }
        let gap = v_sq - support_along_v;
        endgame.measured(gap);
        let floor = ROUND_OFF * scale_sq.max(w.w.length_squared());
        // gap / ‖v‖ bounds how far ‖v‖ is above the distance; squared, as gap > 0 here.
        let accurate_enough = gap * gap <= accuracy * accuracy * scale_sq * v_sq;
        if gap <= RELATIVE_TOLERANCE * v_sq + floor
            || accurate_enough
            || simplex.contains_w(w.w, DUPLICATE * scale_sq)
        {
            break;
        }
        endgame.keep_if_best(gap, v_sq * scale_sq, v, &simplex);
        // Pushed in place (a simplex is 4 support points, and copying it every iteration
        // showed in profiles); popping it again restores the previous simplex exactly.
        simplex.push(w);
        let (reduced, enclosed) = closest_on_simplex(&simplex);
        if enclosed {
            overlap = true;
            break;
        }
        // Slivers (near-duplicate points from curved surfaces) can defeat the region tests;
        // then every sub-simplex holding the new point is tried directly.
        let mut new_v = reduced.closest(&simplex.points);
        let mut reduced = reduced;
        if new_v.length_squared() >= v_sq {
            reduced = best_with_newest(&simplex);
            new_v = reduced.closest(&simplex.points);
        }
        if new_v.length_squared() >= v_sq {
            // No progress: round-off has taken over, keep the previous simplex.
            simplex.len -= 1;
            break;
        }
        reduced.reduce(&mut simplex);
        v = new_v;
        endgame.stepped();
    }
    if !overlap && let Some((best_v, best_simplex)) = endgame.better_than_last() {
        (v, simplex) = (best_v, best_simplex);
    }
    let (_, point_a, point_b) = simplex.combine();
    Some(CoreDistance {
        distance: if overlap { 0.0 } else { v.length() },
        point_a,
        point_b,
        // v = a − b is what GJK minimised; its direction is the normal even when round-off
        // makes the witness points a little less accurate than v.
        normal: if overlap { DVec3::ZERO } else { -v.normalize() },
        overlap,
        simplex,
        iterations,
    })
}

/// Witness error (gap / ‖v‖, relative to the simplex size) below which an iterate is kept as
/// the answer in case a later one is worse. Near a curved surface ‖v‖² is flat in v's
/// direction, so a step that lowers ‖v‖² by round-off can turn v away: its gap grows again.
const ENDGAME: f64 = 1e-6;

/// The iterate with the smallest duality gap seen in the endgame, and the gap of the last.
struct Endgame {
    best: Option<(f64, DVec3, Simplex)>,
    last_gap: f64,
}

impl Endgame {
    fn new() -> Self {
        Endgame {
            best: None,
            last_gap: f64::INFINITY,
        }
    }

    /// The gap of the last iterate.
    fn measured(&mut self, gap: f64) {
        self.last_gap = gap;
    }

    /// Keeps the iterate `v`, `simplex` when the search goes on from it in the endgame with
    /// the best gap yet. Polytopes mostly stop at their first iterate this accurate, so they
    /// pay a compare and no copy.
    fn keep_if_best(&mut self, gap: f64, v_sq_scale_sq: f64, v: DVec3, simplex: &Simplex) {
        let improves = self.best.as_ref().is_none_or(|(best, ..)| gap < *best);
        if improves && gap * gap <= ENDGAME * ENDGAME * v_sq_scale_sq {
            self.best = Some((gap, v, *simplex));
        }
    }

    /// A new iterate replaced the last measured one; its gap is unknown until measured.
    fn stepped(&mut self) {
        self.last_gap = f64::INFINITY;
    }

    /// The best iterate, when its gap is smaller than the last one's (an unmeasured last
    /// iterate, left when the iteration cap ends the search, counts as worse).
    fn better_than_last(self) -> Option<(DVec3, Simplex)> {
        let (gap, v, simplex) = self.best?;
        (gap < self.last_gap).then_some((v, simplex))
    }
}

fn simplex_scale_sq(simplex: &Simplex) -> f64 {
    simplex
        .vertices()
        .iter()
        .map(|p| p.w.length_squared())
        .fold(0.0, f64::max)
}

/// A sub-simplex named by the indices of its vertices in a simplex's point list, with the
/// barycentric weights of its point closest to the origin. The reductions below pass these
/// around instead of whole simplices, so no support point is copied until one is chosen.
#[derive(Clone, Copy, Debug)]
struct Sub {
    vertices: [usize; 4],
    weights: [f64; 4],
    len: usize,
}

impl Sub {
    fn single(i: usize) -> Sub {
        Sub {
            vertices: [i; 4],
            weights: [1.0, 0.0, 0.0, 0.0],
            len: 1,
        }
    }

    fn weighted<const N: usize>(vertices: [usize; N], weights: [f64; N]) -> Sub {
        let mut sub = Sub::single(vertices[0]);
        sub.vertices[..N].copy_from_slice(&vertices);
        sub.weights[..N].copy_from_slice(&weights);
        sub.len = N;
        sub
    }

    /// Σ λᵢ wᵢ: the point closest to the origin, summed in vertex order as `Simplex::combine`.
    fn closest(&self, points: &[SupportPoint; 4]) -> DVec3 {
        let mut sum = DVec3::ZERO;
        for k in 0..self.len {
            sum += points[self.vertices[k]].w * self.weights[k];
        }
        sum
    }

    /// Keeps only this sub-simplex's points, in place. Its vertex indices ascend (every
    /// reduction below lists them in order), so moving them forward never overwrites one
    /// still to be moved; the slots past `len` are never read.
    fn reduce(self, simplex: &mut Simplex) {
        for k in 0..self.len {
            debug_assert!(self.vertices[k] >= k);
            simplex.points[k] = simplex.points[self.vertices[k]];
        }
        simplex.weights = self.weights;
        simplex.len = self.len;
    }
}

/// The sub-simplex whose affine hull holds the point closest to the origin, with its
/// barycentric weights; `true` when a full tetrahedron encloses the origin.
fn closest_on_simplex(simplex: &Simplex) -> (Sub, bool) {
    let p = &simplex.points;
    match simplex.len {
        1 => (Sub::single(0), false),
        2 => (closest_on_segment(p, 0, 1), false),
        3 => (closest_on_triangle(p, [0, 1, 2]), false),
        _ => closest_on_tetrahedron(p),
    }
}

fn closest_on_segment(p: &[SupportPoint; 4], i: usize, j: usize) -> Sub {
    let (a, b) = (p[i].w, p[j].w);
    let edge = b - a;
    let length_sq = edge.length_squared();
    if length_sq <= f64::MIN_POSITIVE {
        return Sub::single(i);
    }
    let t = -a.dot(edge) / length_sq;
    if t <= 0.0 {
        Sub::single(i)
    } else if t >= 1.0 {
        Sub::single(j)
    } else {
        Sub::weighted([i, j], [1.0 - t, t])
    }
}

/// Voronoi regions of the triangle seen from the origin: a vertex, an edge or the inside.
fn closest_on_triangle(p: &[SupportPoint; 4], [i, j, k]: [usize; 3]) -> Sub {
    let (a, b, c) = (p[i].w, p[j].w, p[k].w);
    let ab = b - a;
    let ac = c - a;
    let d1 = ab.dot(-a);
    let d2 = ac.dot(-a);
    if d1 <= 0.0 && d2 <= 0.0 {
        return Sub::single(i);
    }
    let d3 = ab.dot(-b);
    let d4 = ac.dot(-b);
    if d3 >= 0.0 && d4 <= d3 {
        return Sub::single(j);
    }
    let d5 = ab.dot(-c);
    let d6 = ac.dot(-c);
    if d6 >= 0.0 && d5 <= d6 {
        return Sub::single(k);
    }
    // Barycentric areas (scaled) opposite each vertex.
    let area_c = d1 * d4 - d3 * d2;
    let area_b = d5 * d2 - d1 * d6;
    let area_a = d3 * d6 - d5 * d4;
    if area_c <= 0.0 && d1 >= 0.0 && d3 <= 0.0 {
        return closest_on_segment(p, i, j);
    }
    if area_b <= 0.0 && d2 >= 0.0 && d6 <= 0.0 {
        return closest_on_segment(p, i, k);
    }
    if area_a <= 0.0 && d4 >= d3 && d5 >= d6 {
        return closest_on_segment(p, j, k);
    }
    let total = area_a + area_b + area_c;
    let scale = ab.length_squared() * ac.length_squared();
    if total <= 1e-14 * scale || !total.is_finite() {
        return best_of(
            p,
            [
                closest_on_segment(p, i, j),
                closest_on_segment(p, i, k),
                closest_on_segment(p, j, k),
            ],
        );
    }
    Sub::weighted([i, j, k], [area_a / total, area_b / total, area_c / total])
}

/// Barycentric coordinates of the origin from signed volumes: the origin is enclosed when
/// all four are non-negative; otherwise it lies beyond each face whose opposite vertex has
/// a negative coordinate, and the closest of those faces wins. A flat (sliver) tetrahedron
/// encloses nothing: its faces are all tried.
fn closest_on_tetrahedron(p: &[SupportPoint; 4]) -> (Sub, bool) {
    let [pa, pb, pc, pd] = [p[0].w, p[1].w, p[2].w, p[3].w];
    let volume = signed_volume(pa, pb, pc, pd);
    // The longest edge; √ of the largest square is the largest √, to the last bit.
    let size = [pb - pa, pc - pa, pd - pa, pc - pb, pd - pb, pd - pc]
        .iter()
        .map(|e| e.length_squared())
        .fold(0.0, f64::max)
        .sqrt();
    const FACES: [[usize; 3]; 4] = [[1, 2, 3], [0, 2, 3], [0, 1, 3], [0, 1, 2]];
    if volume.abs() <= 1e-12 * size * size * size {
        return (best_of(p, FACES.map(|f| closest_on_triangle(p, f))), false);
    }
    let o = DVec3::ZERO;
    let coordinates = [
        signed_volume(o, pb, pc, pd),
        signed_volume(pa, o, pc, pd),
        signed_volume(pa, pb, o, pd),
        signed_volume(pa, pb, pc, o),
    ]
    .map(|v| v / volume);
    if coordinates.iter().all(|&l| l >= 0.0) {
        return (Sub::weighted([0, 1, 2, 3], coordinates), true);
    }
    let candidates = FACES
        .iter()
        .zip(coordinates)
        .filter(|(_, l)| *l < 0.0)
        .map(|(&face, _)| closest_on_triangle(p, face));
    (best_of(p, candidates), false)
}

/// (q − p) × (r − p) · (s − p): six times the signed volume of the tetrahedron pqrs.
fn signed_volume(p: DVec3, q: DVec3, r: DVec3, s: DVec3) -> f64 {
    (q - p).cross(r - p).dot(s - p)
}

/// The best sub-simplex among those that contain the newest (last) point.
fn best_with_newest(simplex: &Simplex) -> Sub {
    let p = &simplex.points;
    let newest = simplex.len - 1;
    let mut best = Sub::single(newest);
    let mut best_sq = best.closest(p).length_squared();
    let mut consider = |candidate: Sub| {
        let distance_sq = candidate.closest(p).length_squared();
        if distance_sq < best_sq {
            (best, best_sq) = (candidate, distance_sq);
        }
    };
    for i in 0..newest {
        consider(closest_on_segment(p, i, newest));
        for j in i + 1..newest {
            consider(closest_on_triangle(p, [i, j, newest]));
        }
    }
    best
}

/// The candidate nearest the origin; the first of equals.
fn best_of(p: &[SupportPoint; 4], candidates: impl IntoIterator<Item = Sub>) -> Sub {
    let mut best: Option<(Sub, f64)> = None;
    for candidate in candidates {
        let distance_sq = candidate.closest(p).length_squared();
        if best.is_none_or(|(_, best_sq)| distance_sq < best_sq) {
            best = Some((candidate, distance_sq));
        }
    }
    best.expect("at least one candidate").0
}

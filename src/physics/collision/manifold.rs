//! Contact generation (narrow phase): the contact points of one pair of convex shapes.
//!
//! - Polyhedra (cuboids, hulls): separating-axis test over the face normals of both shapes
//!   and the cross products of their edges. A face axis gives a reference face and an
//!   incident face, the incident polygon is clipped against the reference face's sides
//!   (Sutherland–Hodgman) and reduced to at most 4 points by area. Kept incident vertices are
//!   the report's vertex-face contacts, clip points its edge-edge contacts; an edge axis gives
//!   one edge-edge contact.
//! - Spheres and capsules, cylinders: closest features from GJK on the cores (EPA when the
//!   cores overlap), plus the capsule's end points or the cylinder's rim points when they lie
//!   flat along the other surface, so that lying shapes get a stable line or patch; a
//!   cylinder's cap facing a polyhedron also gets the corners of the polyhedron's face
//!   clipped to the cap's disc.
//!
//! Contacts are kept while their separation is at most `margin`: the report's tolerance θ
//! between the rewind and the contact search, or a speculative distance.

use glam::DVec3;
use smallvec::SmallVec;

use crate::physics::collision::contact::{
    Contact, ContactKind, ContactManifold, FeatureId, MAX_MANIFOLD_POINTS, ManifoldPoints,
};
use crate::physics::collision::manifold_memory::REUSE_DISTANCE;
use crate::physics::collision::separating_axis::{ContactFeature, SeparatingFeature};
use crate::physics::dynamics::body::{BodyId, RigidBody};
use crate::physics::geometry::epa::signed_distance_within;
use crate::physics::geometry::gjk::{PosedShape, SupportMap};
use crate::physics::geometry::hull::ConvexHull;
use crate::physics::geometry::segment::closest_points_of_segments;
use crate::physics::geometry::shape::Shape;

/// The contacts of two bodies, normal from A to B, or None when they are farther apart
/// than `margin`.
pub fn contact_manifold(
    a: &RigidBody,
    id_a: BodyId,
    b: &RigidBody,
    id_b: BodyId,
    margin: f64,
) -> Option<ContactManifold> {
    let mut manifolds = Vec::with_capacity(1);
    push_contact_manifold((a, id_a), (b, id_b), margin, None, &mut manifolds);
    manifolds.pop()
}

/// What the search found of a pair besides its contacts.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PairOutcome {
    /// A manifold was pushed, clipped from this feature when two polyhedra touch.
    Touching(Option<ContactFeature>),
    /// None was: the pair is farther apart than the margin, along this axis when a
    /// separating axis showed it.
    Apart(Option<SeparatingFeature>),
}

/// The feature of two polyhedra that a search last found, tried first the next time.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) enum PairFeature {
    /// It separated them.
    Apart(SeparatingFeature),
    /// Their contacts were clipped from it.
    Touching(ContactFeature),
}

/// `contact_manifold` pushed onto `manifolds` when there is one (see
/// `ContactManifold::push_built`). `hint`, the feature the last search found, is tried
/// before any search.
pub(crate) fn push_contact_manifold(
    (a, id_a): (&RigidBody, BodyId),
    (b, id_b): (&RigidBody, BodyId),
    margin: f64,
    hint: Option<PairFeature>,
    manifolds: &mut Vec<ContactManifold>,
) -> PairOutcome {
    let (a, b) = (PosedShape::of_body(a), PosedShape::of_body(b));
    let mut found = None;
    let pushed = ContactManifold::push_built(manifolds, id_a, id_b, |points| {
        found = add_manifold_points(&a, &b, margin, hint, points);
    });
    match found {
        Some(PairFeature::Touching(feature)) if pushed => PairOutcome::Touching(Some(feature)),
        _ if pushed => PairOutcome::Touching(None),
        Some(PairFeature::Apart(feature)) => PairOutcome::Apart(Some(feature)),
        _ => PairOutcome::Apart(None),
    }
}

/// The contacts of two placed shapes (deepest first, at most `MAX_MANIFOLD_POINTS`).
/// Compounds are split into their parts; their contacts may then carry different normals.
pub fn generate_contacts(a: &PosedShape, b: &PosedShape, margin: f64) -> Vec<Contact> {
    let mut points = ManifoldPoints::new();
    add_manifold_points(a, b, margin, None, &mut points);
    points.to_vec()
}

/// `generate_contacts`, added to `points`, trying `hint` first (see `push_contact_manifold`).
/// Returns, for two polyhedra, the feature whose axis separates them farther than `margin`
/// or the one their contacts were clipped from.
pub(crate) fn add_manifold_points(
    a: &PosedShape,
    b: &PosedShape,
    margin: f64,
    hint: Option<PairFeature>,
    points: &mut ManifoldPoints,
) -> Option<PairFeature> {
    // Filled in place by the searches below: returned by value, the inline list was copied
    // at every return on the way up.
    let mut contacts = Contacts::new();
    let mut separating = None;
    if let Some(parts) = a.compound_parts() {
        part_contacts(&parts, b, margin, true, &mut contacts);
    } else if let Some(parts) = b.compound_parts() {
        part_contacts(&parts, a, margin, false, &mut contacts);
    } else {
        separating = convex_contacts(a, b, margin, hint, &mut contacts);
    }
    contacts.sort_by(|x, y| x.separation.total_cmp(&y.separation));
    reduce_by_area(&mut contacts);
    // Copied over as a slice: extending would move them one by one.
    points.extend_from_slice(&contacts);
    separating
}

/// The contacts of one pair before they are reduced: held inline up to a box face clipped
/// by a box face, and filled in place by the searches, so that a pair neither allocates
/// nor copies the list on its way back.
type Contacts = SmallVec<[Contact; 8]>;

/// Part k's feature ids are marked with k + 1 in bits 20 to 27, so parts never share ids.
fn part_contacts(
    parts: &[PosedShape],
    other: &PosedShape,
    margin: f64,
    parts_are_a: bool,
    contacts: &mut Contacts,
) {
    for (k, part) in parts.iter().enumerate() {
        let tag = ((k as u32 + 1) & 0xff) << 20;
        let mut found = ManifoldPoints::new();
        if parts_are_a {
            add_manifold_points(part, other, margin, None, &mut found);
        } else {
            add_manifold_points(other, part, margin, None, &mut found);
        }
        contacts.extend(found.into_iter().map(|mut c| {
            if parts_are_a {
                c.feature.on_a |= tag;
            } else {
                c.feature.on_b |= tag;
            }
            c
        }));
    }
}

/// Adds to `contacts` (empty on entry); returns, for two polyhedra, the feature that
/// separates them farther than `margin` or the one their contacts were clipped from.
fn convex_contacts(
    a: &PosedShape,
    b: &PosedShape,
    margin: f64,
    hint: Option<PairFeature>,
    contacts: &mut Contacts,
) -> Option<PairFeature> {
    // Both are checked before either is built: a box against a cylinder builds nothing.
    if a.shape.is_polyhedral() && b.shape.is_polyhedral() {
        if let Some(PairFeature::Apart(feature)) = hint
            && feature.still_separates(a, b, margin)
        {
            return hint;
        }
        let touched = match hint {
            Some(PairFeature::Touching(feature)) => Some(feature),
            _ => None,
        };
        // The polyhedra are matched by reference where they are built: they are large,
        // and moving them out of the pair would copy them.
        if let (Some(pa), Some(pb)) = (&Polyhedron::of(a), &Polyhedron::of(b)) {
            let found = polyhedron_contacts(pa, pb, margin, touched, contacts);
            if contacts.is_empty() && matches!(found, PairFeature::Touching(_)) {
                // Clipping can cut away a whole incident face when a face axis was
                // preferred over a slightly better edge axis; the closest pair still makes
                // one contact.
                contacts.extend(closest_contact(a, b, margin));
            }
            return Some(found);
        }
    }
    // Empty only when the closest pair is beyond the margin: no second search for it.
    round_contacts(a, b, margin, contacts);
    None
}

// ---------------------------------------------------------------------------------------
// Polyhedra: separating axes and clipping.

/// A polyhedron in world coordinates. Only the vertices and planes are computed per pair;
/// the topology (face loops, edges, the faces at each edge) is borrowed from the shape, so
/// building one for a box allocates nothing and sorts nothing.
#[derive(Clone)]
struct Polyhedron<'a> {
    vertices: SmallVec<[DVec3; 8]>,
    faces: SmallVec<[Polygon<'a>; 6]>,
    edges: &'a [[u32; 2]],
    /// The two faces that meet at each edge; None where the faces do not say (a hand-built
    /// hull whose loops do not close), and such an edge is left to the face axes.
    edge_faces: &'a [Option<[usize; 2]>],
    centroid: DVec3,
    /// The farthest vertex's distance from `centroid`.
    size: f64,
    /// The radius of a ball about `centroid` that lies inside the polyhedron: the nearest
    /// face plane's distance. Along any direction the polyhedron reaches at least this far
    /// beyond its centroid, which sharpens the bounds of the separating-axis search.
    inner_radius: f64,
    /// How far a vertex of a face may lie off the face's plane, m (see
    /// `ConvexHull::plane_spread`): 0 for a box, whose faces are exact.
    plane_spread: f64,
    /// A box's frame, for the closed forms of `best_face_axis` and `best_edge_axis`.
    box_frame: Option<BoxFrame>,
}

/// A box placed in the world: its centre, its axes (the columns of its rotation) and its
/// half extents along them.
#[derive(Clone, Copy)]
struct BoxFrame {
    center: DVec3,
    axes: [DVec3; 3],
    half_extents: DVec3,
}

impl BoxFrame {
    /// How far the box reaches from its centre along `direction`, times the length of
    /// `direction`: Σⱼ hⱼ |vⱼ · direction|.
    fn reach(&self, direction: DVec3) -> f64 {
        (0..3)
            .map(|j| self.half_extents[j] * direction.dot(self.axes[j]).abs())
            .sum()
    }
}

#[derive(Clone)]
struct Polygon<'a> {
    vertices: &'a [u32],
    normal: DVec3,
    offset: f64,
}

/// Vertex i of a box is at (±x, ±y, ±z) with bit 0, 1, 2 of i choosing the sign.
pub(crate) const BOX_FACES: [([u32; 4], DVec3); 6] = [
    ([0, 4, 6, 2], DVec3::NEG_X),
    ([1, 3, 7, 5], DVec3::X),
    ([0, 1, 5, 4], DVec3::NEG_Y),
    ([2, 6, 7, 3], DVec3::Y),
    ([0, 2, 3, 1], DVec3::NEG_Z),
    ([4, 5, 7, 6], DVec3::Z),
];
pub(crate) const BOX_EDGES: [[u32; 2]; 12] = [
    [0, 1],
    [2, 3],
    [4, 5],
    [6, 7],
    [0, 2],
    [1, 3],
    [4, 6],
    [5, 7],
    [0, 4],
    [1, 5],
    [2, 6],
    [3, 7],
];

/// The faces at each edge of every box, as `faces_at_edges` finds them (a test checks):
/// written out rather than computed once on first use, which costs a check at every use.
static BOX_EDGE_FACES: [Option<[usize; 2]>; 12] = [
    Some([2, 4]),
    Some([3, 4]),
    Some([2, 5]),
    Some([3, 5]),
    Some([0, 4]),
    Some([1, 4]),
    Some([0, 5]),
    Some([1, 5]),
    Some([0, 2]),
    Some([1, 2]),
    Some([0, 3]),
    Some([1, 3]),
];

impl<'a> Polyhedron<'a> {
    fn of(posed: &PosedShape<'a>) -> Option<Polyhedron<'a>> {
        match posed.shape {
            Shape::Cuboid { half_extents } => Some(Polyhedron::of_box(posed, *half_extents)),
            Shape::ConvexHull(hull) => Some(Polyhedron::of_hull(posed, hull)),
            _ => None,
        }
    }

    /// Built straight into its place, without a tuple of parts in between: the structure
    /// is large, and each move of it is a copy.
    fn of_box(posed: &PosedShape<'a>, half_extents: DVec3) -> Polyhedron<'a> {
        // Corner i is at (±x, ±y, ±z), bit k of i choosing the sign along axis k. Negating
        // a product is exact, so scaling the axes once and adding them with their signs
        // gives the same bits as `posed.to_world` of each corner.
        let scaled = [0, 1, 2].map(|k| posed.rotation.col(k) * half_extents[k]);
        let signed = |i: u32, k: usize| {
            if i & (1 << k) == 0 {
                -scaled[k]
            } else {
                scaled[k]
            }
        };
        let corner = |i: u32| posed.origin + (signed(i, 0) + signed(i, 1) + signed(i, 2));
        // Whole arrays: collecting pushes one at a time, through an extend the compiler may
        // leave out of line.
        let vertices = SmallVec::from_buf([
            corner(0),
            corner(1),
            corner(2),
            corner(3),
            corner(4),
            corner(5),
            corner(6),
            corner(7),
        ]);
        let face = |k: usize| face_of(posed, &BOX_FACES[k].0, BOX_FACES[k].1, &vertices);
        Polyhedron {
            faces: SmallVec::from_buf([face(0), face(1), face(2), face(3), face(4), face(5)]),
            edges: BOX_EDGES.as_slice(),
            edge_faces: BOX_EDGE_FACES.as_slice(),
            centroid: centroid(&vertices),
            size: half_extents.length(),
            inner_radius: half_extents.min_element(),
            plane_spread: 0.0,
            box_frame: Some(BoxFrame {
                center: posed.origin,
                axes: [0, 1, 2].map(|k| posed.rotation.col(k)),
                half_extents,
            }),
            vertices,
        }
    }

    fn of_hull(posed: &PosedShape<'a>, hull: &'a ConvexHull) -> Polyhedron<'a> {
        let vertices: SmallVec<[DVec3; 8]> =
            hull.vertices.iter().map(|&p| posed.to_world(p)).collect();
        let faces: SmallVec<[Polygon<'a>; 6]> = (hull.faces.iter())
            .map(|f| face_of(posed, &f.vertices, f.normal, &vertices))
            .collect();
        let ball = hull.vertex_ball();
        Polyhedron {
            faces,
            edges: hull.edges.as_slice(),
            edge_faces: hull.edge_faces(),
            centroid: posed.to_world(ball.center),
            size: ball.outer_radius,
            inner_radius: ball.inner_radius,
            plane_spread: hull.plane_spread(),
            box_frame: None,
            vertices,
        }
    }

    /// The face turned most against `normal`: the incident face for a reference face or
    /// cap whose outward normal it is.
    fn face_against(&self, normal: DVec3) -> &Polygon<'a> {
        // Each face's dot product is taken once, not at every comparison.
        self.faces
            .iter()
            .map(|f| (f, f.normal.dot(normal)))
            .min_by(|x, y| x.1.total_cmp(&y.1))
            .expect("a polyhedron has faces")
            .0
    }

    fn support_value(&self, direction: DVec3) -> f64 {
        self.vertices
            .iter()
            .map(|v| v.dot(direction))
            .fold(f64::NEG_INFINITY, f64::max)
    }
}

/// Face `indices` of a shape placed by `posed`, its world `vertices` already placed.
fn face_of<'a>(
    posed: &PosedShape,
    indices: &'a [u32],
    local_normal: DVec3,
    vertices: &[DVec3],
) -> Polygon<'a> {
    let normal = posed.rotation * local_normal;
    Polygon {
        offset: normal.dot(vertices[indices[0] as usize]),
        vertices: indices,
        normal,
    }
}

fn centroid(vertices: &[DVec3]) -> DVec3 {
    vertices.iter().sum::<DVec3>() / vertices.len() as f64
}

/// The best axis found by the separating-axis test.
#[derive(Clone, Copy, Debug)]
enum Axis {
    /// A face of A (`true`) or of B, by index.
    Face {
        of_a: bool,
        face: usize,
        separation: f64,
    },
    /// Edge i of A and edge j of B, with the unit axis from A to B.
    Edges {
        edge_a: usize,
        edge_b: usize,
        axis: DVec3,
        separation: f64,
    },
}

impl Axis {
    fn separation(&self) -> f64 {
        match *self {
            Axis::Face { separation, .. } | Axis::Edges { separation, .. } => separation,
        }
    }

    fn feature(&self) -> SeparatingFeature {
        match *self {
            Axis::Face {
                of_a: true, face, ..
            } => SeparatingFeature::FaceOfA(face as u32),
            Axis::Face { face, .. } => SeparatingFeature::FaceOfB(face as u32),
            Axis::Edges { edge_a, edge_b, .. } => {
                SeparatingFeature::Edges(edge_a as u32, edge_b as u32)
            }
        }
    }
}

/// A face or edge axis must beat the previous best by this fraction of the smaller shape's
/// size to be taken: faces are preferred over edges, and A's faces over B's, so that the
/// choice does not flicker between nearly equal axes from one step to the next.
const AXIS_PREFERENCE: f64 = 1e-3;

/// How much the separation along the feature a touching pair's contacts were last clipped
/// from may have changed since its last full search for the feature to be clipped from
/// again without a search, m. As `REUSE_DISTANCE`: the pair has barely moved along it.
pub const FEATURE_TOLERANCE: f64 = REUSE_DISTANCE;

/// Adds to `contacts` (empty on entry); returns the feature whose axis separates the two
/// farther than `margin` (and then adds nothing), or the one the contacts were clipped from.
///
/// `touched`, the feature the last contacts were clipped from, is clipped from again without
/// a search while the separation along it stays within `FEATURE_TOLERANCE` of what the last
/// full search measured: the pair has not turned or slid far enough for another feature to
/// be much better. The full search's separation is kept, so that drift does not add up.
fn polyhedron_contacts(
    a: &Polyhedron,
    b: &Polyhedron,
    margin: f64,
    touched: Option<ContactFeature>,
    contacts: &mut Contacts,
) -> PairFeature {
    if let Some(feature) = touched
        && let Some(axis) = feature_axis(a, b, feature.feature)
        && axis.separation() <= margin
        && (axis.separation() - feature.separation).abs() <= FEATURE_TOLERANCE
    {
        clip_along(a, b, axis, margin, contacts);
        if !contacts.is_empty() {
            return PairFeature::Touching(feature);
        }
    }
    match best_axis(a, b, margin) {
        Ok(separating) => PairFeature::Apart(separating.feature()),
        Err(best) => {
            clip_along(a, b, best, margin, contacts);
            PairFeature::Touching(ContactFeature {
                feature: best.feature(),
                separation: best.separation(),
            })
        }
    }
}

/// The feature's axis with the separation along it in the current poses; None when the
/// polyhedra have no such feature (a stale or hand-edited memory) or an edge pair no longer
/// faces each other on the Gauss map.
fn feature_axis(a: &Polyhedron, b: &Polyhedron, feature: SeparatingFeature) -> Option<Axis> {
    let facing = |owner: &Polyhedron, other: &Polyhedron, k: u32, of_a: bool| {
        let face = owner.faces.get(k as usize)?;
        Some(Axis::Face {
            of_a,
            face: k as usize,
            separation: face_separation(face, other),
        })
    };
    match feature {
        SeparatingFeature::FaceOfA(k) => facing(a, b, k, true),
        SeparatingFeature::FaceOfB(k) => facing(b, a, k, false),
        SeparatingFeature::Edges(i, j) => {
            let (i, j) = (i as usize, j as usize);
            let [f0, f1] = (*a.edge_faces.get(i)?)?;
            let [g0, g1] = (*b.edge_faces.get(j)?)?;
            let arc_a = GaussArc::new(a.faces[f0].normal, a.faces[f1].normal);
            let arc_b = GaussArc::new(-b.faces[g0].normal, -b.faces[g1].normal);
            if !arcs_cross(&arc_a, &arc_b) {
                return None;
            }
            let mut axis = None;
            keep_better_edge_axis(&mut axis, a, i, b, j);
            axis
        }
    }
}

/// Contacts along `axis`: the incident face clipped by the reference face, or the closest
/// points of two edges.
fn clip_along(a: &Polyhedron, b: &Polyhedron, axis: Axis, margin: f64, contacts: &mut Contacts) {
    match axis {
        Axis::Face {
            of_a: true, face, ..
        } => clip_contacts(a, face, b, true, margin, contacts),
        Axis::Face {
            of_a: false, face, ..
        } => clip_contacts(b, face, a, false, margin, contacts),
        Axis::Edges {
            edge_a,
            edge_b,
            axis,
            separation,
        } => contacts.push(edge_contact(a, edge_a, b, edge_b, axis, separation)),
    }
}

/// The full search: Ok with an axis that separates the two farther than `margin`, or Err
/// with the best axis to clip along.
fn best_axis(a: &Polyhedron, b: &Polyhedron, margin: f64) -> Result<Axis, Axis> {
    let (size_a, size_b) = (a.size, b.size);
    let slop = AXIS_PREFERENCE * size_a.min(size_b);
    let reach = a.centroid.length() + size_a + b.centroid.length() + size_b;
    let bound_slack = BOUND_ROUND_OFF * reach;
    let face_a = best_face_axis(a, b, true, bound_slack);
    if face_a.separation() > margin {
        return Ok(face_a);
    }
    let face_b = best_face_axis(b, a, false, bound_slack);
    if face_b.separation() > margin {
        return Ok(face_b);
    }
    let mut best = if face_b.separation() > face_a.separation() + slop {
        face_b
    } else {
        face_a
    };
    // An edge pair no farther apart than this neither separates the shapes nor beats `best`.
    let floor = margin.min(best.separation() + slop);
    if let Some(edges) = best_edge_axis(a, b, floor, bound_slack) {
        if edges.separation() > margin {
            return Ok(edges);
        }
        if edges.separation() > best.separation() + slop {
            best = edges;
        }
    }
    Err(best)
}

/// How far a bound on a separation, computed in f64, may fall below the separation as the
/// search computes it, over the distances from the origin involved: far above round-off,
/// far below any gap that matters.
const BOUND_ROUND_OFF: f64 = 1e-9;

/// The face of `owner` along whose normal `other` is farthest out (largest separation;
/// of equal ones the last).
///
/// Along a face's normal, `other`'s nearest vertex is at least its inner radius nearer than
/// its centroid, so a face whose bound from the centroid lies below the best separation so
/// far (by more than `slack`, round-off) cannot win, and its vertices are not visited. The
/// face with the highest bound is measured first, so that the bar is high from the start.
fn best_face_axis(owner: &Polyhedron, other: &Polyhedron, of_a: bool, slack: f64) -> Axis {
    if let (Some(owner_box), Some(other_box)) = (owner.box_frame, other.box_frame) {
        return best_box_face_axis(&owner_box, &other_box, of_a);
    }
    let bound = |f: &Polygon| f.normal.dot(other.centroid) - other.inner_radius - f.offset;
    let separation = |f: &Polygon| face_separation(f, other);
    let first = (0..owner.faces.len())
        .map(|k| (k, bound(&owner.faces[k])))
        .max_by(|x, y| x.1.total_cmp(&y.1))
        .expect("a polyhedron has faces")
        .0;
    let mut best = (first, separation(&owner.faces[first]));
    for (k, face) in owner.faces.iter().enumerate() {
        if k == first || bound(face) + slack < best.1 {
            continue;
        }
        let value = separation(face);
        if value > best.1 || (value == best.1 && k > best.0) {
            best = (k, value);
        }
    }
    Axis::Face {
        of_a,
        face: best.0,
        separation: best.1,
    }
}

/// How far `other` lies out along the normal of `face`, beyond its plane (negative: into it).
fn face_separation(face: &Polygon, other: &Polyhedron) -> f64 {
    -other.support_value(-face.normal) - face.offset
}

/// `best_face_axis` for two boxes in closed form. Along the owner's axis u_k the other box
/// reaches Σⱼ hⱼ |u_k · vⱼ| from its centre, so the separation of the face on the other's
/// side is |u_k · D| − h_k − Σⱼ hⱼ |u_k · vⱼ| (D between the centres): three axes instead
/// of six faces against eight vertices. Faces are numbered as in `BOX_FACES`, and of equal
/// separations the last wins, as in the general search.
fn best_box_face_axis(owner: &BoxFrame, other: &BoxFrame, of_a: bool) -> Axis {
    let between = other.center - owner.center;
    let mut best = (0, f64::NEG_INFINITY);
    for (k, u) in owner.axes.iter().enumerate() {
        let along = u.dot(between);
        let separation = along.abs() - owner.half_extents[k] - other.reach(*u);
        let face = 2 * k + usize::from(along >= 0.0);
        if separation >= best.1 {
            best = (face, separation);
        }
    }
    Axis::Face {
        of_a,
        face: best.0,
        separation: best.1,
    }
}

/// The edge pair with the largest separation along the cross product of the edges, among
/// pairs where both edges are the supporting features along that axis (a real edge-edge
/// configuration, not a parallel edge elsewhere on the shape).
///
/// Whether they are is read off the Gauss map, without touching any vertex: the normals of
/// the two faces at an edge of A span an arc, those at an edge of B (negated) another, and
/// the edges support the same axis exactly when the arcs cross (they make a face of the
/// Minkowski difference). That keeps the test O(edges²) instead of O(edges² · vertices).
///
/// Pairs that are surely no farther apart than `floor` may be left out (the box shortcut
/// does, and so does the bound of `arc_reaches` on whole edges), so only a result above
/// `floor` is sure to be the best pair.
fn best_edge_axis(a: &Polyhedron, b: &Polyhedron, floor: f64, slack: f64) -> Option<Axis> {
    if let (Some(frame_a), Some(frame_b)) = (a.box_frame, b.box_frame) {
        return best_box_edge_axis(a, &frame_a, b, &frame_b, floor);
    }
    // The other's centroid above each face: an edge's arc reaches towards it no farther than
    // the higher of its two faces (see `arc_reaches`), measured once per face.
    let heights_a = centroid_heights(a, b, slack);
    let heights_b = centroid_heights(b, a, slack);
    let level_b = floor + a.inner_radius - slack;
    let mut edges_b = EdgeArcs::new();
    for j in 0..b.edges.len() {
        let Some([f0, f1]) = b.edge_faces[j] else {
            continue;
        };
        let ends = heights_b[f0].max(heights_b[f1]);
        if ends <= 0.0 && ends < level_b {
            continue; // as `arc_reaches` would find, without reading the edge
        }
        let arc = [-b.faces[f0].normal, -b.faces[f1].normal];
        let point = b.vertices[b.edges[j][0] as usize];
        if arc_reaches(arc, point - a.centroid, level_b, ends) {
            edges_b.push((j, GaussArc::new(arc[0], arc[1])));
        }
    }
    let mut best: Option<Axis> = None;
    for i in 0..a.edges.len() {
        let Some([f0, f1]) = a.edge_faces[i] else {
            continue;
        };
        let ends = heights_a[f0].max(heights_a[f1]);
        let level = floor + b.inner_radius - slack;
        if ends <= 0.0 && ends < level {
            continue; // as `arc_reaches` would find, without reading the edge
        }
        let (na, nb) = (a.faces[f0].normal, a.faces[f1].normal);
        let point = a.vertices[a.edges[i][0] as usize];
        if !arc_reaches([na, nb], b.centroid - point, level, ends) {
            continue;
        }
        let arc_a = GaussArc::new(na, nb);
        for (j, arc_b) in &edges_b {
            if arcs_cross(&arc_a, arc_b) {
                keep_better_edge_axis(&mut best, a, i, b, *j);
            }
        }
    }
    best
}

/// The edges of a polyhedron left in the search, with the arcs of their Gauss map
/// (negated for B): inline up to what a hull of some thirty points keeps.
type EdgeArcs = SmallVec<[(usize, GaussArc); 64]>;

/// Per face of `owner`: how far `other`'s centroid lies above its plane, raised by as much
/// as an edge's end may lie off that plane (twice the spread: the face's offset is taken at
/// one of its vertices) and by round-off `slack`, so that at an edge's end point p on the
/// face, n · (centroid − p) is at most this.
fn centroid_heights(owner: &Polyhedron, other: &Polyhedron, slack: f64) -> FaceHeights {
    let raise = 2.0 * owner.plane_spread + slack;
    (owner.faces.iter())
        .map(|f| f.normal.dot(other.centroid) - f.offset + raise)
        .collect()
}

/// One number per face of a polyhedron: inline up to what a hull of some thirty points has.
type FaceHeights = SmallVec<[f64; 64]>;

/// Whether some unit normal n on the great arc between `arc`'s ends (shorter than a half
/// circle) has n · offset ≥ `level`, where `ends`, at least the larger of the ends'
/// p · offset and q · offset, is all that is read unless it lies between 0 and the level
/// (then the peak inside the arc decides: the ends themselves are below the level).
///
/// For an edge of A with its arc, and any axis n on it, A reaches out along n exactly to
/// the edge, while B's nearest vertex lies at least B's inner radius nearer than its
/// centroid: so with `offset` from the edge to B's centroid and `level` the floor plus that
/// radius, an edge whose arc does not reach the level makes no pair above the floor, and is
/// left out (for an edge of B, its negated arc and the offset from A's centroid to it,
/// likewise).
///
/// The peak is the offset's projection onto the arc's plane, where n · offset is largest
/// on the circle; it lies inside the arc when its dot products with the ends are each at
/// least the other's times p · q, and its squared length times the Gram determinant of p
/// and q is a quadratic form in p · offset and q · offset. So no cross product, square
/// root or division is taken: this runs for most edges of every pair of hulls searched.
#[inline(always)]
fn arc_reaches([p, q]: [DVec3; 2], offset: DVec3, level: f64, ends: f64) -> bool {
    if ends >= level {
        return true;
    }
    if ends <= 0.0 {
        // n = (a p + b q) / |a p + b q| with a, b ≥ 0, and |a p + b q| ≤ a + b: the
        // weighted mean of two values at most `ends` ≤ 0, divided by at most its weight,
        // stays at most `ends`. Most edges face away from the other shape and stop here.
        return false;
    }
    let (pp, qq, pq) = (p.length_squared(), q.length_squared(), p.dot(q));
    let (op, oq) = (offset.dot(p), offset.dot(q));
    let within = pp * oq >= pq * op && qq * op >= pq * oq;
    let gram = pp * qq - pq * pq;
    let peak_squared_times_gram = qq * op * op - 2.0 * pq * op * oq + pp * oq * oq;
    // `level` > `ends` > 0 here. Where p and q are parallel (a Gram determinant of 0) the
    // test keeps the edge: leaving one in is always safe.
    within && peak_squared_times_gram >= level * level * gram
}

/// `best_edge_axis` for two boxes. A box has 12 edges but only 3 directions, and for each
/// pair of directions u × v exactly one edge of each box supports it (on the side of the
/// axis that points from A to B; the opposite pair is the same distance farther apart).
/// That edge is read off the signs of the axis in the box's frame, so 9 direction pairs
/// are tried instead of 144 edge pairs, and the chosen pair is measured as the general
/// loop measures it. Directions with a face of either box square to the axis are skipped:
/// there the supporting feature is a face, and the face axes cover it.
///
/// Most pairs are far from deciding anything: before a pair is measured from its corners,
/// its separation is estimated from the boxes' reaches along the axis, and a pair is left
/// out when even that estimate, raised by far more than its round-off, is below `floor`.
fn best_box_edge_axis(
    a: &Polyhedron,
    frame_a: &BoxFrame,
    b: &Polyhedron,
    frame_b: &BoxFrame,
    floor: f64,
) -> Option<Axis> {
    let between = b.centroid - a.centroid;
    let slack = edge_estimate_slack(frame_a, frame_b);
    let mut best: Option<Axis> = None;
    for (i, u) in frame_a.axes.iter().enumerate() {
        for (j, v) in frame_b.axes.iter().enumerate() {
            let mut axis = u.cross(*v);
            let along = axis.dot(between);
            if along < 0.0 {
                axis = -axis;
            }
            // The separation along the axis times its length (the axis is not normalised).
            let estimate = along.abs() - frame_a.reach(axis) - frame_b.reach(axis);
            if estimate + slack < floor * axis.length() {
                continue;
            }
            let (Some(edge_a), Some(edge_b)) = (
                supporting_box_edge(&frame_a.axes, i, axis),
                supporting_box_edge(&frame_b.axes, j, -axis),
            ) else {
                continue;
            };
            keep_better_edge_axis(&mut best, a, edge_a, b, edge_b);
        }
    }
    best
}

/// How far the estimate of `best_box_edge_axis` (times the axis length) may be below the
/// separation measured from the corners, with a wide safety factor. The measure takes its
/// edge directions from corners rounded at their distance from the origin, so a short edge
/// far out is the least certain: relative round-off of order 1e-16 times (distance / edge
/// length), against 1e-9 here.
fn edge_estimate_slack(a: &BoxFrame, b: &BoxFrame) -> f64 {
    let extent = a.half_extents.element_sum() + b.half_extents.element_sum();
    let far = a.center.length() + b.center.length() + extent;
    let shortest = a
        .half_extents
        .min_element()
        .min(b.half_extents.min_element());
    1e-9 * far * (1.0 + far / shortest)
}

/// The edge along axis `along` of a box farthest out along `direction`, as an index into
/// `BOX_EDGES` (which lists the edges along x, then y, then z, each group ordered by the
/// sign bits of the two other coordinates); None when a face adjoining it is square to
/// `direction` (no single edge supports it).
fn supporting_box_edge(axes: &[DVec3; 3], along: usize, direction: DVec3) -> Option<usize> {
    let mut index = 4 * along;
    let mut weight = 1;
    for (k, axis) in axes.iter().enumerate() {
        if k == along {
            continue;
        }
        let reach = axis.dot(direction);
        if reach == 0.0 {
            return None;
        }
        if reach > 0.0 {
            index += weight;
        }
        weight *= 2;
    }
    Some(index)
}

/// Measures edge i of A against edge j of B along their cross product and keeps the pair
/// in `best` when it is farther apart than what `best` holds.
fn keep_better_edge_axis(
    best: &mut Option<Axis>,
    a: &Polyhedron,
    i: usize,
    b: &Polyhedron,
    j: usize,
) {
    let [a0, a1] = a.edges[i].map(|k| a.vertices[k as usize]);
    let [b0, b1] = b.edges[j].map(|k| b.vertices[k as usize]);
    let cross = (a1 - a0).cross(b1 - b0);
    let length = cross.length();
    if length <= 1e-9 * (a1 - a0).length() * (b1 - b0).length() {
        return; // parallel edges: covered by the face axes
    }
    // The axis points out of A at its edge (A is convex: away from its centroid).
    let mut axis = cross / length;
    if axis.dot(a0 - a.centroid) < 0.0 {
        axis = -axis;
    }
    let separation = axis.dot(b0 - a0);
    if best.is_none_or(|current| separation > current.separation()) {
        *best = Some(Axis::Edges {
            edge_a: i,
            edge_b: j,
            axis,
            separation,
        });
    }
}

/// An arc of the Gauss map, from `start` to `end`, with the normal of its plane
/// (`end × start`), taken once per edge rather than once per pair of edges.
#[derive(Clone, Copy)]
struct GaussArc {
    start: DVec3,
    end: DVec3,
    plane: DVec3,
}

impl GaussArc {
    fn new(start: DVec3, end: DVec3) -> GaussArc {
        GaussArc {
            start,
            end,
            plane: end.cross(start),
        }
    }
}

/// True when the great arc `first` crosses the arc `second` on the unit sphere (each arc
/// shorter than a half circle, as the normals at a convex edge are).
fn arcs_cross(first: &GaussArc, second: &GaussArc) -> bool {
    let (a, b, b_x_a) = (first.start, first.end, first.plane);
    let (c, d, d_x_c) = (second.start, second.end, second.plane);
    let (cba, dba) = (c.dot(b_x_a), d.dot(b_x_a));
    let (adc, bdc) = (a.dot(d_x_c), b.dot(d_x_c));
    // c and d on opposite sides of a–b's plane, a and b on opposite sides of c–d's, and
    // both arcs in the same hemisphere.
    cba * dba < 0.0 && adc * bdc < 0.0 && cba * bdc > 0.0
}

/// Feature ids: a face index, a vertex index or an edge index, tagged so they never collide.
const VERTEX_TAG: u32 = 1 << 28;
const EDGE_TAG: u32 = 2 << 28;

fn edge_contact(
    a: &Polyhedron,
    edge_a: usize,
    b: &Polyhedron,
    edge_b: usize,
    axis: DVec3,
    separation: f64,
) -> Contact {
    let [i, j] = a.edges[edge_a].map(|k| a.vertices[k as usize]);
    let [k, l] = b.edges[edge_b].map(|m| b.vertices[m as usize]);
    let (pa, pb) = closest_points_of_segments(i, j, k, l);
    Contact {
        position: 0.5 * (pa + pb),
        normal: axis,
        separation,
        kind: ContactKind::EdgeEdge,
        feature: FeatureId {
            on_a: EDGE_TAG | edge_a as u32,
            on_b: EDGE_TAG | edge_b as u32,
        },
        time_of_impact: 0.0,
        levers: None,
    }
}

/// A point of the incident polygon with where it came from.
#[derive(Clone, Copy, Debug)]
struct ClipPoint {
    position: DVec3,
    /// On the incident shape: a vertex, or an edge cut by a side of the reference face.
    incident_feature: u32,
    /// On the reference shape: the face, or the side that cut the edge.
    reference_feature: u32,
    kind: ContactKind,
}

/// Room for a box face clipped by a box face (at most 8 points) without allocating.
type ClipPolygon = SmallVec<[ClipPoint; 8]>;

/// Clips the incident face of `incident` against reference face `face` of `reference`.
fn clip_contacts(
    reference: &Polyhedron,
    face: usize,
    incident: &Polyhedron,
    reference_is_a: bool,
    margin: f64,
    contacts: &mut Contacts,
) {
    let ref_face = &reference.faces[face];
    let normal = ref_face.normal;
    let incident_face = incident.face_against(normal);
    // Pushed one by one rather than collected: collecting goes through an out-of-line
    // extend, and moves the built polygon into place.
    let mut polygon = ClipPolygon::new();
    for &i in incident_face.vertices {
        polygon.push(ClipPoint {
            position: incident.vertices[i as usize],
            incident_feature: VERTEX_TAG | i,
            reference_feature: face as u32,
            kind: ContactKind::VertexFace,
        });
    }
    let sides = ref_face.vertices.len();
    let corner = |k: usize| reference.vertices[ref_face.vertices[k] as usize];
    let center = (0..sides).map(corner).sum::<DVec3>() / sides as f64;
    // Each side clips from one buffer into the other; swapping the references, not the
    // buffers, so no polygon is copied.
    let mut clipped = ClipPolygon::new();
    let (mut from, mut to) = (&mut polygon, &mut clipped);
    for side in 0..sides {
        let (start, end) = (corner(side), corner((side + 1) % sides));
        let mut plane = (end - start).cross(normal).normalize_or_zero();
        if plane.dot(start - center) < 0.0 {
            plane = -plane;
        }
        let tag = EDGE_TAG | ((face as u32) << 8) | side as u32;
        clip_polygon(from, plane, plane.dot(start), tag, to);
        std::mem::swap(&mut from, &mut to);
    }
    let slop = AXIS_PREFERENCE * reference.size.min(incident.size);
    // Read after the clipped points rather than pushed onto them, which could spill the
    // inline polygon onto the heap.
    let deepest =
        deepest_clipped_away(incident, normal, ref_face.offset, from, slop).map(|k| ClipPoint {
            position: incident.vertices[k],
            incident_feature: VERTEX_TAG | k as u32,
            reference_feature: face as u32,
            kind: ContactKind::VertexFace,
        });
    let sign = if reference_is_a { 1.0 } else { -1.0 };
    for p in from.iter().chain(&deepest) {
        let separation = normal.dot(p.position) - ref_face.offset;
        if separation <= margin {
            let (on_ref, on_inc) = (p.reference_feature, p.incident_feature);
            let (on_a, on_b) = if reference_is_a {
                (on_ref, on_inc)
            } else {
                (on_inc, on_ref)
            };
            contacts.push(Contact {
                position: p.position - normal * (0.5 * separation),
                normal: normal * sign,
                separation,
                kind: p.kind,
                feature: FeatureId { on_a, on_b },
                time_of_impact: 0.0,
                levers: None,
            });
        }
    }
}

/// Sutherland–Hodgman against one plane: keeps the part with `plane · x ≤ offset`, in `out`.
fn clip_polygon(
    polygon: &[ClipPoint],
    plane: DVec3,
    offset: f64,
    side_tag: u32,
    out: &mut ClipPolygon,
) {
    out.clear();
    let Some(first) = polygon.first() else {
        return;
    };
    // Each point's distance is measured once and carried to the edge that starts at it.
    let distance = |point: &ClipPoint| plane.dot(point.position) - offset;
    let first_distance = distance(first);
    let mut dp = first_distance;
    for (k, &p) in polygon.iter().enumerate() {
        let (q, dq) = match polygon.get(k + 1) {
            Some(next) => (*next, distance(next)),
            None => (*first, first_distance),
        };
        if dp <= 0.0 {
            out.push(p);
        }
        if (dp <= 0.0) != (dq <= 0.0) {
            let t = dp / (dp - dq);
            out.push(ClipPoint {
                position: p.position + (q.position - p.position) * t,
                incident_feature: EDGE_TAG
                    | (p.incident_feature & 0xffff) << 12
                    | (q.incident_feature & 0xfff),
                reference_feature: side_tag,
                kind: ContactKind::EdgeEdge,
            });
        }
        dp = dq;
    }
}

/// Keeps at most 4 points spanning the largest area: the deepest, the farthest from it,
/// then the two that make the largest triangles with those on either side.
fn reduce_by_area(contacts: &mut Contacts) {
    if contacts.len() <= MAX_MANIFOLD_POINTS {
        return;
    }
    let normal = contacts[0].normal;
    let position = |k: usize| contacts[k].position;
    let first = 0; // sorted deepest first
    let second = farthest_from(contacts, position(first));
    let signed_area = |k: usize| {
        (position(second) - position(first))
            .cross(position(k) - position(first))
            .dot(normal)
    };
    let by_area = |pick: fn(f64) -> f64| {
        (0..contacts.len())
            .max_by(|&x, &y| pick(signed_area(x)).total_cmp(&pick(signed_area(y))))
            .expect("more than 4 contacts")
    };
    let keep = [first, second, by_area(|area| area), by_area(|area| -area)];
    // In their order: the kept ones stay sorted deepest first.
    let mut index = 0;
    contacts.retain(|_| {
        let kept = keep.contains(&index);
        index += 1;
        kept
    });
}

fn farthest_from(contacts: &[Contact], point: DVec3) -> usize {
    (0..contacts.len())
        .max_by(|&x, &y| {
            let dx = contacts[x].position.distance_squared(point);
            dx.total_cmp(&contacts[y].position.distance_squared(point))
        })
        .expect("contacts are not empty")
}

// ---------------------------------------------------------------------------------------
// Round shapes: closest features, plus end and rim points for lying capsules and cylinders.

/// When the shape's axis is within this cosine of lying along the contact plane (capsule,
/// cylinder side) or standing on it (cylinder cap), extra points are tested.
const FLAT_COSINE: f64 = 0.1;

/// Adds to `extra` (empty on entry).
fn round_contacts(a: &PosedShape, b: &PosedShape, margin: f64, extra: &mut Contacts) {
    let Some(main) = closest_contact(a, b, margin) else {
        return;
    };
    // Inline up to 8: the extra points of both shapes, or a cap's corners; more (a cap on a
    // box face has up to 12 corners) move it to the heap.
    for (k, point) in extra_points(a, main.normal).into_iter().enumerate() {
        extra.extend(point_contact(
            &point,
            b,
            main.normal,
            margin,
            (k + 1) as u32,
            true,
        ));
    }
    for (k, point) in extra_points(b, -main.normal).into_iter().enumerate() {
        extra.extend(point_contact(
            &point,
            a,
            -main.normal,
            margin,
            (k + 1) as u32,
            false,
        ));
    }
    // The closest pair is the pair's depth: a cap point deeper than that (beyond the
    // search's tolerance) is on a cap they do not touch by.
    let size = a.shape.bounding_radius() + b.shape.bounding_radius();
    let deepest_allowed = main.separation - 1e-6 * size;
    let cap_of_a = (a, b, main.normal);
    add_cap_contacts(cap_of_a, margin, deepest_allowed, true, extra);
    let cap_of_b = (b, a, -main.normal);
    add_cap_contacts(cap_of_b, margin, deepest_allowed, false, extra);
    // A lying shape touches along a line or patch whose ends are the extra points, and the
    // closest pair is just one point of it; otherwise the closest pair is deeper and stays.
    let deepest_extra = extra
        .iter()
        .map(|c| c.separation)
        .fold(f64::INFINITY, f64::min);
    if extra.len() < 2 || main.separation < deepest_extra - 1e-9 * size {
        extra.retain(|c| c.position.distance(main.position) > 1e-6 * size);
        extra.insert(0, main);
    }
}

/// How far above the true gap a contact's separation may be, as a fraction of the pair's
/// size: 0.3 µm on the rain's bodies, against a solver that holds contacts to millimetres.
/// GJK closes on a curved shape's distance by halves, so stopping at this accuracy rather
/// than at round-off spares a curved pair several iterations (BENCHMARKS.md, "Contact
/// accuracy and GJK iterations").
const CONTACT_ACCURACY: f64 = 1e-6;

/// The closest pair of points (GJK, or EPA when the cores overlap) as one contact.
fn closest_contact(a: &PosedShape, b: &PosedShape, margin: f64) -> Option<Contact> {
    let signed = signed_distance_within(a, b, margin, CONTACT_ACCURACY)?;
    Some(Contact {
        position: 0.5 * (signed.point_a + signed.point_b),
        normal: signed.normal,
        separation: signed.distance,
        kind: ContactKind::Closest,
        feature: FeatureId::default(),
        time_of_impact: 0.0,
        levers: None,
    })
}

/// The incident polyhedron's deepest vertex below the reference plane (`normal`, `offset`)
/// when the clipped polygon reaches more than `slop` less deep: a hull can be deepest at a
/// vertex off its face most opposed to the normal, or past the reference face's sides, and
/// clipping then left out the very point that overlaps (two hulls 20 mm into each other
/// had one contact 4.6 mm apart). The overlap along the axis is that vertex's depth.
fn deepest_clipped_away(
    incident: &Polyhedron,
    normal: DVec3,
    offset: f64,
    clipped: &ClipPolygon,
    slop: f64,
) -> Option<usize> {
    let depth = |v: DVec3| normal.dot(v) - offset;
    let (deepest, vertex) = (incident.vertices.iter().enumerate())
        .min_by(|x, y| depth(*x.1).total_cmp(&depth(*y.1)))?;
    let reached = (clipped.iter().map(|p| depth(p.position))).fold(f64::INFINITY, f64::min);
    (depth(*vertex) + slop < reached).then_some(deepest)
}

/// A sphere (radius 0 for a cylinder's rim point) placed on `shape` facing `towards`.
struct SurfacePoint {
    center: DVec3,
    radius: f64,
}

impl SupportMap for SurfacePoint {
    fn core_support(&self, _direction: DVec3) -> DVec3 {
        self.center
    }
    fn margin(&self) -> f64 {
        self.radius
    }
    fn inner_point(&self) -> DVec3 {
        self.center
    }
    fn core_segment(&self) -> Option<[DVec3; 2]> {
        Some([self.center; 2])
    }
}

/// Points of a capsule or cylinder that may touch along with the closest one: the two ends
/// of a lying capsule's segment, the two ends of a lying cylinder's contact line, or four
/// rim points of a standing cylinder's cap. `normal` points away from the shape.
/// At most four: held inline, as this runs for every round pair.
type SurfacePoints = SmallVec<[SurfacePoint; 4]>;

fn extra_points(posed: &PosedShape, normal: DVec3) -> SurfacePoints {
    let axis = posed.rotation * DVec3::Y;
    let along = axis.dot(normal);
    match *posed.shape {
        Shape::Capsule {
            half_height,
            radius,
        } if along.abs() < FLAT_COSINE => [-1.0, 1.0]
            .map(|s| SurfacePoint {
                center: posed.to_world(DVec3::Y * (s * half_height)),
                radius,
            })
            .into_iter()
            .collect(),
        Shape::Cylinder {
            half_height,
            radius,
        } if along.abs() < FLAT_COSINE => {
            let radial = (normal - axis * along).normalize_or_zero() * radius;
            [-1.0, 1.0]
                .map(|s| SurfacePoint {
                    center: posed.to_world(DVec3::ZERO) + axis * (s * half_height) + radial,
                    radius: 0.0,
                })
                .into_iter()
                .collect()
        }
        Shape::Cylinder {
            half_height,
            radius,
        } if along.abs() > 1.0 - FLAT_COSINE => {
            let cap = posed.to_world(DVec3::ZERO) + axis * half_height.copysign(along);
            let (u, v) = (posed.rotation * DVec3::X, posed.rotation * DVec3::Z);
            [u, v, -u, -v]
                .map(|d| SurfacePoint {
                    center: cap + d * radius,
                    radius: 0.0,
                })
                .into_iter()
                .collect()
        }
        _ => SurfacePoints::new(),
    }
}

/// Tags a contact on a cylinder's cap (the other side names the polyhedron's feature).
const CAP_TAG: u32 = 3 << 28;

/// Adds to `found` where a cylinder's cap faces a polyhedron: the polyhedron's face turned
/// most against the cap, clipped to the cap's disc. The rim points of `extra_points` only
/// sample the disc's edge, so a cap resting across a box's edge or corner had the box's
/// corners under it unsupported but for the one deepest point: it tipped over them and sank
/// into the box (BENCHMARKS.md, "Cylinder caps on box edges"). The face's vertices inside
/// the disc and its edges' crossings of the rim (up to 4 + 8 for a box face) are the
/// patch's other corners.
/// `normal` points away from `cylinder`; points deeper than `deepest_allowed` are left out.
fn add_cap_contacts(
    (cylinder, other, normal): (&PosedShape, &PosedShape, DVec3),
    margin: f64,
    deepest_allowed: f64,
    cylinder_is_a: bool,
    found: &mut Contacts,
) {
    let Shape::Cylinder {
        half_height,
        radius,
    } = *cylinder.shape
    else {
        return;
    };
    let axis = cylinder.rotation * DVec3::Y;
    let along = axis.dot(normal);
    if along.abs() <= 1.0 - FLAT_COSINE {
        return;
    }
    let Some(polyhedron) = Polyhedron::of(other) else {
        return;
    };
    let cap_normal = axis * along.signum();
    let cap = Disc {
        center: cylinder.origin + cap_normal * half_height,
        normal: cap_normal,
        radius,
    };
    let face = polyhedron.face_against(cap_normal);
    let mut keep = |point: DVec3, other_feature: u32| {
        let separation = (point - cap.center).dot(cap_normal);
        if separation > margin || separation < deepest_allowed {
            return;
        }
        let (normal, on_a, on_b) = if cylinder_is_a {
            (cap_normal, CAP_TAG, other_feature)
        } else {
            (-cap_normal, other_feature, CAP_TAG)
        };
        found.push(Contact {
            position: point - cap_normal * (0.5 * separation),
            normal,
            separation,
            kind: ContactKind::VertexFace,
            feature: FeatureId { on_a, on_b },
            time_of_impact: 0.0,
            levers: None,
        });
    };
    // Crossings are named by the edge's ends, masked to fit beside the tag: a hull of more
    // than 8192 vertices may give two points one name, which only costs a warm start.
    let corners = face.vertices;
    for (k, &i) in corners.iter().enumerate() {
        let p = polyhedron.vertices[i as usize];
        if cap.holds(p) {
            keep(p, VERTEX_TAG | i);
        }
        let j = corners[(k + 1) % corners.len()];
        let q = polyhedron.vertices[j as usize];
        for (root, t) in cap.rim_crossings(p, q).into_iter().enumerate() {
            keep(
                p + (q - p) * t,
                EDGE_TAG | ((i & 0x3fff) << 14) | ((j & 0x1fff) << 1) | root as u32,
            );
        }
    }
}

/// A cylinder's cap: the disc of `radius` about `center` in the plane of unit `normal`.
struct Disc {
    center: DVec3,
    normal: DVec3,
    radius: f64,
}

impl Disc {
    /// The offset of `p` from the axis, within the cap's plane.
    fn radial(&self, p: DVec3) -> DVec3 {
        let relative = p - self.center;
        relative - self.normal * relative.dot(self.normal)
    }

    /// Whether `p` lies within the cylinder's side, at any height.
    fn holds(&self, p: DVec3) -> bool {
        self.radial(p).length_squared() <= self.radius * self.radius
    }

    /// The fractions t in (0, 1) at which p + t (q − p) crosses the cylinder's side.
    fn rim_crossings(&self, p: DVec3, q: DVec3) -> SmallVec<[f64; 2]> {
        let (start, step) = (self.radial(p), self.radial(q) - self.radial(p));
        // |start + t step|² = r²: a t² + 2 b t + c = 0.
        let a = step.length_squared();
        let b = start.dot(step);
        let c = start.length_squared() - self.radius * self.radius;
        let discriminant = b * b - a * c;
        if a <= f64::MIN_POSITIVE || discriminant <= 0.0 {
            return SmallVec::new();
        }
        let root = discriminant.sqrt();
        [(-b - root) / a, (-b + root) / a]
            .into_iter()
            .filter(|t| *t > 0.0 && *t < 1.0)
            .collect()
    }
}

/// The contact of one extra point with the other shape, kept when within `margin` and
/// facing the same way as the main contact.
fn point_contact(
    point: &SurfacePoint,
    other: &PosedShape,
    normal: DVec3,
    margin: f64,
    index: u32,
    point_is_a: bool,
) -> Option<Contact> {
    let signed = signed_distance_within(point, other, margin, CONTACT_ACCURACY)?;
    if signed.normal.dot(normal) < 1.0 - FLAT_COSINE {
        return None;
    }
    let (normal, on_a, on_b) = if point_is_a {
        (signed.normal, VERTEX_TAG | index, 0)
    } else {
        (-signed.normal, 0, VERTEX_TAG | index)
    };
    Some(Contact {
        position: 0.5 * (signed.point_a + signed.point_b),
        normal,
        separation: signed.distance,
        kind: ContactKind::Closest,
        feature: FeatureId { on_a, on_b },
        time_of_impact: 0.0,
        levers: None,
    })
}

#[cfg(test)]
pub(crate) mod tests {
    use glam::{DMat3, DQuat};
    use proptest::prelude::*;

    use super::*;
    use crate::physics::geometry::epa::signed_distance;
    use crate::physics::geometry::hull::faces_at_edges;

    /// Uniform-ish unit quaternions (rejecting the short ones before normalising).
    pub(crate) fn unit_quat() -> impl Strategy<Value = DQuat> {
        (-1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64, -1.0..1.0f64).prop_filter_map(
            "not near zero",
            |(x, y, z, w)| {
                let q = DQuat::from_xyzw(x, y, z, w);
                (q.length() > 0.1).then(|| q.normalize())
            },
        )
    }

    fn half_extents() -> impl Strategy<Value = DVec3> {
        (0.05..2.0f64, 0.05..2.0f64, 0.05..2.0f64).prop_map(|(x, y, z)| DVec3::new(x, y, z))
    }

    #[test]
    fn box_edge_faces_are_those_of_the_face_loops() {
        let loops = BOX_FACES.iter().map(|(loop_, _)| loop_.as_slice());
        assert_eq!(faces_at_edges(loops, &BOX_EDGES), BOX_EDGE_FACES);
    }

    /// An edge search that left pairs out below `floor` found what the full search found
    /// above it: the same pair at the same separation, or nothing above the floor.
    fn same_above_floor(
        floored: Option<Axis>,
        full: Option<Axis>,
        floor: f64,
    ) -> Result<(), TestCaseError> {
        match (floored, full) {
            (
                Some(Axis::Edges {
                    edge_a,
                    edge_b,
                    separation,
                    ..
                }),
                Some(Axis::Edges {
                    edge_a: ea,
                    edge_b: eb,
                    separation: s,
                    ..
                }),
            ) if s > floor => {
                prop_assert_eq!((edge_a, edge_b), (ea, eb));
                prop_assert_eq!(separation, s);
            }
            (x, y) => prop_assert!(
                x.is_none_or(|x| x.separation() <= floor)
                    && y.is_none_or(|y| y.separation() <= floor),
                "{:?} against {:?} above {}",
                x,
                y,
                floor
            ),
        }
        Ok(())
    }

    /// A hull of 6 to 40 random points: on a unit sphere, or on a prism's two end faces
    /// (whose merged faces are planar only to the construction's tolerance).
    fn hull() -> impl Strategy<Value = Shape> {
        let angles = proptest::collection::vec((0.0..std::f64::consts::TAU, -1.0..1.0f64), 6..40);
        (angles, any::<bool>()).prop_filter_map("a solid", |(angles, prism)| {
            let points: Vec<DVec3> = (angles.iter().enumerate())
                .map(|(k, &(turn, rise))| {
                    if prism {
                        let end = if k % 2 == 0 { -0.4 } else { 0.4 };
                        DVec3::new(turn.cos(), end, turn.sin())
                    } else {
                        let across = (1.0 - rise * rise).sqrt();
                        DVec3::new(across * turn.cos(), rise, across * turn.sin())
                    }
                })
                .collect();
            let hull = ConvexHull::from_points(&points).ok()?;
            (hull.volume() > 1e-2).then(|| Shape::ConvexHull(std::sync::Arc::new(hull)))
        })
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// The edge pairs of two hulls left out below a floor, by the faces' centroid
        /// heights and the arc bound, change nothing above it: the same pair at the same
        /// separation as the search that leaves nothing out.
        #[test]
        fn hull_edge_pairs_left_out_below_a_floor_change_nothing_above_it(
            shape_a in hull(),
            shape_b in hull(),
            turn_a in unit_quat(),
            turn_b in unit_quat(),
            offset in (-2.5..2.5f64, -2.5..2.5f64, -2.5..2.5f64),
            floor in -1.0..0.3f64,
        ) {
            let posed_a = PosedShape::new(&shape_a, DVec3::new(1.0, 2.0, -0.5), DMat3::from_quat(turn_a));
            let offset = DVec3::new(1.0 + offset.0, 2.0 + offset.1, -0.5 + offset.2);
            let posed_b = PosedShape::new(&shape_b, offset, DMat3::from_quat(turn_b));
            let a = Polyhedron::of(&posed_a).expect("a hull is a polyhedron");
            let b = Polyhedron::of(&posed_b).expect("a hull is a polyhedron");
            let slack = BOUND_ROUND_OFF * 20.0;
            let every = best_edge_axis(&a, &b, f64::NEG_INFINITY, slack);
            let floored = best_edge_axis(&a, &b, floor, slack);
            same_above_floor(floored, every, floor)?;
        }
    }

    /// The full search's contacts and the feature they were clipped from.
    fn full_search(
        a: &PosedShape,
        b: &PosedShape,
        margin: f64,
    ) -> (Contacts, Option<ContactFeature>) {
        let mut contacts = Contacts::new();
        let found = convex_contacts(a, b, margin, None, &mut contacts);
        let feature = match found {
            Some(PairFeature::Touching(feature)) => Some(feature),
            _ => None,
        };
        (contacts, feature)
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(300))]

        /// Clipping again from the feature of the last full search. At the same poses it
        /// gives the full search's contacts. After a small move it is taken only while the
        /// separation along the feature stays within `FEATURE_TOLERANCE` of the full
        /// search's, and that separation then lies between the true signed distance (found
        /// by EPA) at the last search less the tolerance and the axis preference, and the
        /// true signed distance now (no axis shows more than the true overlap).
        #[test]
        fn contacts_clipped_from_the_last_feature_stay_within_the_tolerance(
            shape_a in hull(),
            shape_b in hull(),
            turn_a in unit_quat(),
            turn_b in unit_quat(),
            offset in (-1.5..1.5f64, -1.5..1.5f64, -1.5..1.5f64),
            shift in (-3e-3..3e-3f64, -3e-3..3e-3f64, -3e-3..3e-3f64),
            twist in (-5e-3..5e-3f64, -5e-3..5e-3f64, -5e-3..5e-3f64),
        ) {
            let margin = 0.02;
            let posed_a = PosedShape::new(&shape_a, DVec3::ZERO, DMat3::from_quat(turn_a));
            let offset = DVec3::new(offset.0, offset.1, offset.2);
            let before = PosedShape::new(&shape_b, offset, DMat3::from_quat(turn_b));
            let then = signed_distance(&posed_a, &before).distance;
            let (contacts, feature) = full_search(&posed_a, &before, margin);
            prop_assume!(then < 0.0 && feature.is_some());
            let feature = feature.expect("assumed");
            let hint = Some(PairFeature::Touching(feature));

            let mut again = Contacts::new();
            let found = convex_contacts(&posed_a, &before, margin, hint, &mut again);
            prop_assert_eq!(found, hint);
            prop_assert_eq!(again.to_vec(), contacts.to_vec());

            let turn = DQuat::from_scaled_axis(DVec3::new(twist.0, twist.1, twist.2)) * turn_b;
            let moved = offset + DVec3::new(shift.0, shift.1, shift.2);
            let after = PosedShape::new(&shape_b, moved, DMat3::from_quat(turn));
            let mut clipped = Contacts::new();
            let found = convex_contacts(&posed_a, &after, margin, hint, &mut clipped);
            if found == hint {
                let pa = Polyhedron::of(&posed_a).expect("a hull");
                let pb = Polyhedron::of(&after).expect("a hull");
                let axis = feature_axis(&pa, &pb, feature.feature).expect("taken");
                let now = signed_distance(&posed_a, &after).distance;
                let preference = AXIS_PREFERENCE * pa.size.min(pb.size);
                let (low, high) = (then - FEATURE_TOLERANCE - preference, now);
                prop_assert!(
                    axis.separation() >= low - 1e-6 && axis.separation() <= high + 1e-6,
                    "{:?}: separation {} outside {}..{}", feature, axis.separation(), low, high
                );
                prop_assert!(!clipped.is_empty());
                prop_assert!(clipped.iter().all(|c| c.separation <= margin));
            }
        }
    }

    proptest! {
        #![proptest_config(ProptestConfig::with_cases(500))]

        /// The box shortcuts agree with the general searches: the same face at the same
        /// separation (to round-off), and the same edge pair at the same separation to the
        /// last bit (the chosen pair is measured the same way).
        #[test]
        fn box_axes_agree_with_the_general_search(
            size_a in half_extents(),
            size_b in half_extents(),
            turn_a in unit_quat(),
            turn_b in unit_quat(),
            offset in (-3.0..3.0f64, -3.0..3.0f64, -3.0..3.0f64),
            floor in -2.0..0.5f64,
        ) {
            let (shape_a, shape_b) = (Shape::cuboid(size_a), Shape::cuboid(size_b));
            let posed_a = PosedShape::new(&shape_a, DVec3::ZERO, DMat3::from_quat(turn_a));
            let offset = DVec3::new(offset.0, offset.1, offset.2);
            let posed_b = PosedShape::new(&shape_b, offset, DMat3::from_quat(turn_b));
            let a = Polyhedron::of(&posed_a).expect("a box is a polyhedron");
            let b = Polyhedron::of(&posed_b).expect("a box is a polyhedron");
            // The centroids lie within 6 m of the origin and the boxes within 3.5 m of them.
            let slack = BOUND_ROUND_OFF * 20.0;
            for (owner, other, of_a) in [(&a, &b, true), (&b, &a, false)] {
                let closed = best_face_axis(owner, other, of_a, slack);
                let searched = best_face_axis(
                    &Polyhedron { box_frame: None, ..owner.clone() },
                    &Polyhedron { box_frame: None, ..other.clone() },
                    of_a,
                    slack,
                );
                // The search that skips faces by their centroid bound picks what visiting
                // every face picks, to the bit: the farthest out, of equal ones the last.
                let every_face = (owner.faces.iter())
                    .map(|f| -other.support_value(-f.normal) - f.offset)
                    .enumerate()
                    .max_by(|x, y| x.1.total_cmp(&y.1))
                    .expect("a box has faces");
                let Axis::Face { face: pruned_face, separation: pruned, .. } = searched else {
                    panic!("face axes are faces");
                };
                prop_assert_eq!((pruned_face, pruned), every_face);
                let (Axis::Face { face, separation, .. }, Axis::Face { face: f, separation: s, .. }) =
                    (closed, searched)
                else {
                    panic!("face axes are faces");
                };
                prop_assert!((separation - s).abs() <= 1e-12 * (1.0 + s.abs()), "{} against {}", separation, s);
                // Two faces nearly as far out may swap by round-off; the chosen face must be
                // as far out as the one searched.
                let s_of_closed = -other.support_value(-owner.faces[face].normal) - owner.faces[face].offset;
                prop_assert!(face == f || (s_of_closed - s).abs() <= 1e-12 * (1.0 + s.abs()));
            }
            let shortcut = best_edge_axis(&a, &b, f64::NEG_INFINITY, slack);
            let (general_a, general_b) = (
                Polyhedron { box_frame: None, ..a.clone() },
                Polyhedron { box_frame: None, ..b.clone() },
            );
            let searched = best_edge_axis(&general_a, &general_b, f64::NEG_INFINITY, slack);
            match (shortcut, searched) {
                (
                    Some(Axis::Edges { edge_a, edge_b, separation, .. }),
                    Some(Axis::Edges { edge_a: ea, edge_b: eb, separation: s, .. }),
                ) => {
                    prop_assert_eq!((edge_a, edge_b), (ea, eb));
                    prop_assert_eq!(separation, s);
                }
                (x, y) => prop_assert!(x.is_none() && y.is_none(), "{:?} against {:?}", x, y),
            }
            // The pairs left out below a floor, by the box shortcut or by the arc bound of
            // the general search, change nothing above it.
            for floored in [
                best_edge_axis(&a, &b, floor, slack),
                best_edge_axis(&general_a, &general_b, floor, slack),
            ] {
                same_above_floor(floored, searched, floor)?;
            }
        }
    }
}

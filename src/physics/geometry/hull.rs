//! Convex hulls built from point clouds (quickhull), with polygonal faces and exact mass
//! properties from polyhedral volume integrals.
//!
//! Construction runs in three stages:
//! 1. the cloud is centred and scaled into [-1, 1]³, and its `Tolerance`s are derived from the
//!    rounding noise its coordinates carry;
//! 2. quickhull builds a triangulated hull: a point joins it only if it lies farther than
//!    `on_plane` outside, so duplicate, coplanar and mid-edge points never create slivers,
//!    and each new point replaces exactly the triangles it sees (above `visible`);
//! 3. coplanar triangles are merged into convex polygons, vertices left on only two
//!    polygons (points in the middle of an edge) are dropped, and the result is certified:
//!    a closed surface convex at every edge and vertex that holds every input point. Points
//!    that stray from a common plane by about the tolerance can defeat a pass; it is then
//!    repeated at tolerances a decade apart.

use std::collections::{HashMap, HashSet};
use std::sync::OnceLock;

use glam::DVec3;
use serde::{Deserialize, Serialize};
use thiserror::Error;

use crate::physics::geometry::mass::{self, MassProperties};
use crate::physics::geometry::shape::{MAX_EXTENT, MIN_EXTENT};

/// Thresholds, in units of the normalized cloud (its largest half-extent is 1).
#[derive(Clone, Copy, Debug)]
struct Tolerance {
    /// A triangle is seen from a point above its plane by more than this. Just above rounding
    /// noise, so that the region a point sees is the exact one: a thicker threshold can split
    /// it in two and leave a seen triangle behind, which breaks convexity.
    visible: f64,
    /// A point within this of a plane counts as on it: it never joins the hull, and triangles
    /// within it of a common plane merge into one face.
    on_plane: f64,
}

impl Tolerance {
    /// `relative_noise` is the rounding error of the input coordinates over the half-extent:
    /// f64 epsilon, or more for a small cloud far from the origin.
    fn new(relative_noise: f64) -> Self {
        Tolerance {
            visible: 1e3 * relative_noise,
            on_plane: 1e4 * relative_noise,
        }
    }

    fn scaled(self, factor: f64) -> Self {
        Tolerance {
            visible: self.visible * factor,
            on_plane: self.on_plane * factor,
        }
    }
}

/// A face of a hull: a convex polygon with its outward plane `normal · x = offset`.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize)]
pub struct HullFace {
    /// Indices into `ConvexHull::vertices`, counter-clockwise seen from outside.
    pub vertices: Vec<u32>,
    /// Unit outward normal, in shape coordinates.
    pub normal: DVec3,
    /// The plane's offset from the shape origin along `normal` (m): `normal · x = offset`
    /// for every point x of the face.
    pub offset: f64,
}

/// A closed convex polyhedron. Coplanar triangles are merged, so a box has 6 quad faces.
///
/// Built by `from_points`, `cuboid` or, from parts, `new`. The contact search derives which
/// faces meet at each edge on first use and keeps it: change a hull's parts only on a clone
/// that has not yet collided (a clone starts without it).
#[derive(Serialize, Deserialize)]
pub struct ConvexHull {
    /// The corners, in shape coordinates (m); every one is a vertex of some face.
    pub vertices: Vec<DVec3>,
    /// The faces, each a convex polygon with its outward plane.
    pub faces: Vec<HullFace>,
    /// Each undirected edge once, as (lower index, higher index).
    pub edges: Vec<[u32; 2]>,
    /// What contact searches ask of every pair, derived from the parts on first use.
    #[serde(skip)]
    derived: OnceLock<Derived>,
    /// What `validate` found, kept: a body's description, the body and every copy sharing
    /// the hull through its `Arc` ask again, and a large hull's check is not free.
    #[serde(skip)]
    validity: OnceLock<Result<(), HullError>>,
}

/// What is derived from a hull's parts and kept.
struct Derived {
    /// See `ConvexHull::edge_faces`.
    edge_faces: Vec<Option<[usize; 2]>>,
    /// See `ConvexHull::bounds`.
    bounds: (DVec3, DVec3),
    /// See `ConvexHull::radius`.
    radius: f64,
    /// See `ConvexHull::plane_spread`.
    plane_spread: f64,
    /// See `ConvexHull::plane_tolerance`.
    plane_tolerance: f64,
    /// See `ConvexHull::vertex_ball`.
    vertex_ball: VertexBall,
}

/// The mean of a hull's vertices, with the radii of the balls about it that the hull holds
/// and that hold it: rigid motions keep them, so a contact search places the centre and
/// reuses the radii instead of measuring every vertex and face of every pair.
#[derive(Clone, Copy, Debug, PartialEq)]
pub(crate) struct VertexBall {
    /// The mean of the vertices, in shape coordinates.
    pub center: DVec3,
    /// The farthest vertex's distance from `center` (m).
    pub outer_radius: f64,
    /// The nearest face plane's distance from `center` (m), 0 if `center` lay outside one.
    pub inner_radius: f64,
}

impl Clone for ConvexHull {
    /// The parts only: a clone is what gets changed, so what was derived from them is not
    /// carried over.
    fn clone(&self) -> Self {
        ConvexHull::new(
            self.vertices.clone(),
            self.faces.clone(),
            self.edges.clone(),
        )
    }
}

impl PartialEq for ConvexHull {
    fn eq(&self, other: &Self) -> bool {
        (&self.vertices, &self.faces, &self.edges) == (&other.vertices, &other.faces, &other.edges)
    }
}

impl std::fmt::Debug for ConvexHull {
    fn fmt(&self, f: &mut std::fmt::Formatter<'_>) -> std::fmt::Result {
        f.debug_struct("ConvexHull")
            .field("vertices", &self.vertices)
            .field("faces", &self.faces)
            .field("edges", &self.edges)
            .finish()
    }
}

/// Most points a hull may be built from (and most vertices a hand-built hull may have).
/// Hulls of everyday bodies have tens of vertices; support queries are linear in them, so
/// a cloud this large is almost certainly a mesh's vertex buffer passed by mistake.
pub const MAX_HULL_POINTS: usize = 100_000;

/// Why a hull could not be built from a point cloud, or why a hand-built one is invalid.
#[derive(Clone, Debug, Error, PartialEq)]
pub enum HullError {
    /// Fewer than the 4 points of a tetrahedron; holds the count given.
    #[error("needs at least 4 points, got {0}")]
    TooFewPoints(usize),
    /// More than `MAX_HULL_POINTS`; holds the count given.
    #[error("{0} points, more than the {MAX_HULL_POINTS} a hull may have")]
    TooManyPoints(usize),
    /// The point (or vertex) at this index is NaN or infinite.
    #[error("point {0} is not finite")]
    NotFinite(usize),
    /// The points enclose no volume that f64 can resolve (they coincide, are collinear,
    /// coplanar or too thin), or a hand-built hull's volume is not positive; says which.
    #[error("points are degenerate: {0}")]
    Degenerate(&'static str),
    /// The face at this index has fewer than 3 vertices or indexes a missing one.
    #[error("face {0} has fewer than 3 vertices or refers to a missing vertex")]
    InvalidFace(usize),
    /// The edge at this index indexes a missing vertex or joins a vertex to itself.
    #[error("edge {0} refers to a missing vertex or joins a vertex to itself")]
    InvalidEdge(usize),
    /// A half-extent of the vertices' bounding box (m) lies outside
    /// [`MIN_EXTENT`, `MAX_EXTENT`]; holds that half-extent.
    #[error("extent {0} m lies outside [{MIN_EXTENT}, {MAX_EXTENT}] m")]
    ExtentOutOfRange(f64),
    /// The face at this index has a normal that is not unit length, or a vertex off its
    /// plane.
    #[error("face {0}: normal not unit length, or its plane misses a vertex of the face")]
    BadPlane(usize),
    /// Some vertex lies above the plane of the face at this index.
    #[error("a vertex lies outside the plane of face {0}: the hull is not convex")]
    NotConvex(usize),
    /// A hull with more vertex-face pairs than `CONTAINMENT_CHECK_BUDGET` is checked edge
    /// by edge, and its faces do not close into a surface convex across every edge and
    /// vertex.
    #[error(
        "the faces do not close into a convex surface (a hull of more than \
         {CONTAINMENT_CHECK_BUDGET} vertex-face pairs is checked edge by edge)"
    )]
    NotConvexSurface,
    /// The vertex at this index is on no face, which the edge-by-edge check of a hull of
    /// more than `CONTAINMENT_CHECK_BUDGET` vertex-face pairs cannot place.
    #[error(
        "vertex {0} is on no face (a hull of more than {CONTAINMENT_CHECK_BUDGET} \
         vertex-face pairs is checked edge by edge, which needs every vertex on a face)"
    )]
    LooseVertex(usize),
}

/// How far (relative to the hull's size) a hand-built hull's vertices may stray from the face
/// planes, on top of what `from_points` itself allows: loose enough for planes computed in
/// f64 from rounded vertices, tight enough to catch a wrong normal or offset.
const VALIDATE_TOLERANCE: f64 = 1e-9;

impl ConvexHull {
    /// The hull with these parts, taken as given: `validate` checks them.
    pub fn new(vertices: Vec<DVec3>, faces: Vec<HullFace>, edges: Vec<[u32; 2]>) -> Self {
        ConvexHull {
            vertices,
            faces,
            edges,
            derived: OnceLock::new(),
            validity: OnceLock::new(),
        }
    }

    fn derived(&self) -> &Derived {
        self.derived.get_or_init(|| {
            let (min, max) = bounds(&self.vertices);
            Derived {
                edge_faces: faces_at_edges(self.face_loops(), &self.edges),
                bounds: (min, max),
                radius: (self.vertices.iter())
                    .map(|v| v.length())
                    .fold(0.0, f64::max),
                plane_spread: self.farthest_off_plane(),
                plane_tolerance: plane_tolerance(min, max),
                vertex_ball: self.measure_vertex_ball(),
            }
        })
    }

    fn measure_vertex_ball(&self) -> VertexBall {
        let center = self.vertices.iter().sum::<DVec3>() / self.vertices.len().max(1) as f64;
        VertexBall {
            center,
            outer_radius: (self.vertices.iter())
                .map(|v| v.distance(center))
                .fold(0.0, f64::max),
            inner_radius: (self.faces.iter())
                .map(|f| f.offset - f.normal.dot(center))
                .fold(f64::INFINITY, f64::min)
                .max(0.0),
        }
    }

    fn farthest_off_plane(&self) -> f64 {
        let off_plane = |face: &HullFace| {
            (face.vertices.iter())
                .filter_map(|&v| self.vertices.get(v as usize))
                .map(|&v| (face.normal.dot(v) - face.offset).abs())
                .fold(0.0, f64::max)
        };
        self.faces.iter().map(off_plane).fold(0.0, f64::max)
    }

    /// For each edge, the two faces whose loops run along it (one each way); None where
    /// the loops do not say (a hand-built hull whose loops do not close).
    pub(crate) fn edge_faces(&self) -> &[Option<[usize; 2]>] {
        &self.derived().edge_faces
    }

    /// The smallest and largest coordinates of the vertices, (min, max), in shape
    /// coordinates; kept, as every pair's search asks for them.
    pub fn bounds(&self) -> (DVec3, DVec3) {
        self.derived().bounds
    }

    /// How far the farthest vertex lies from the shape origin (m): the radius of the
    /// smallest sphere about the origin that holds the hull; kept, as every pair's search
    /// asks for it.
    pub fn radius(&self) -> f64 {
        self.derived().radius
    }

    /// How far any face's vertex lies off the face's plane (m): merged faces are planar to
    /// the construction's tolerance, not exactly; kept, as every pair's search asks for it.
    pub(crate) fn plane_spread(&self) -> f64 {
        self.derived().plane_spread
    }

    /// The mean of the vertices and the balls about it inside and around the hull; kept, as
    /// every pair's search asks for them.
    pub(crate) fn vertex_ball(&self) -> VertexBall {
        self.derived().vertex_ball
    }

    /// How far any vertex of a hull that passes `validate` lies above any face's plane, at
    /// most (m): a face's offset plus this bounds the hull's reach along its normal.
    pub(crate) fn plane_tolerance(&self) -> f64 {
        self.derived().plane_tolerance
    }

    /// The convex hull of `points`. Interior, duplicate and mid-edge/mid-face points are
    /// dropped; the remaining vertices are re-indexed in their input order.
    pub fn from_points(points: &[DVec3]) -> Result<Self, HullError> {
        check_point_count(points.len())?;
        if let Some(index) = points.iter().position(|p| !p.is_finite()) {
            return Err(HullError::NotFinite(index));
        }
        let (unit_cloud, tolerance) = normalized(points)?;
        let simplex = initial_simplex(&unit_cloud, tolerance.on_plane)?;
        // A pass that fails its certificate is repeated at tolerances a decade apart.
        [1.0, 10.0, 100.0, 0.1]
            .into_iter()
            .find_map(|factor| hull_polygons(&unit_cloud, simplex, tolerance.scaled(factor)))
            .map(|polygons| Self::from_polygons(points, &polygons))
            .ok_or(HullError::Degenerate(
                "too thin or too nearly coplanar to resolve in f64",
            ))
    }

    /// A box centred on the origin, as a hull with 6 quads (for face-based collision).
    pub fn cuboid(half_extents: DVec3) -> Self {
        // Corner i has the sign pattern of its bits: bit 0 → x, bit 1 → y, bit 2 → z.
        let corners: Vec<DVec3> = (0..8u32)
            .map(|i| {
                let sign = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                DVec3::new(sign(0), sign(1), sign(2)) * half_extents
            })
            .collect();
        // For the face on +axis k, walking (−,−), (+,−), (+,+), (−,+) over the next two axes
        // (i, j) in cyclic order is counter-clockwise about +k because e_i × e_j = e_k.
        let polygons: Vec<Vec<u32>> = (0..3)
            .flat_map(|k| {
                let (i, j) = ((k + 1) % 3, (k + 2) % 3);
                let corner = move |high_k: bool, high_i: bool, high_j: bool| {
                    (u32::from(high_k) << k) | (u32::from(high_i) << i) | (u32::from(high_j) << j)
                };
                let ring = [(false, false), (true, false), (true, true), (false, true)];
                let positive: Vec<u32> = ring.iter().map(|&(a, b)| corner(true, a, b)).collect();
                let negative: Vec<u32> = ring
                    .iter()
                    .rev()
                    .map(|&(a, b)| corner(false, a, b))
                    .collect();
                [positive, negative]
            })
            .collect();
        Self::from_polygons(&corners, &polygons)
    }

    /// Checks what a hand-built hull can get wrong: finite vertices, 4 to `MAX_HULL_POINTS` of them, faces
    /// and edges that index real vertices, extents within [MIN_EXTENT, MAX_EXTENT], face planes that
    /// match their vertices, convexity and a positive volume.
    ///
    /// Convexity is checked vertex against face up to `CONTAINMENT_CHECK_BUDGET` pairs, and
    /// beyond it edge by edge (a closed surface convex at every edge and vertex bounds a
    /// convex solid), so the check stays near linear: vertex against face took 16 s for a
    /// 100 000-point hull. The result is kept (as what `bounds` derives is: change a hull's
    /// parts only on a fresh clone).
    pub fn validate(&self) -> Result<(), HullError> {
        self.validity.get_or_init(|| self.check()).clone()
    }

    fn check(&self) -> Result<(), HullError> {
        if let Some(index) = self.vertices.iter().position(|v| !v.is_finite()) {
            return Err(HullError::NotFinite(index));
        }
        check_point_count(self.vertices.len())?;
        let vertex_count = self.vertices.len();
        for (index, face) in self.faces.iter().enumerate() {
            let dangling = face.vertices.iter().any(|&v| v as usize >= vertex_count);
            if face.vertices.len() < 3 || dangling {
                return Err(HullError::InvalidFace(index));
            }
        }
        for (index, &[i, j]) in self.edges.iter().enumerate() {
            if i == j || i as usize >= vertex_count || j as usize >= vertex_count {
                return Err(HullError::InvalidEdge(index));
            }
        }
        let (min, max) = bounds(&self.vertices);
        for half_extent in ((max - min) * 0.5).to_array() {
            if !(MIN_EXTENT..=MAX_EXTENT).contains(&half_extent) {
                return Err(HullError::ExtentOutOfRange(half_extent));
            }
        }
        let slack = plane_tolerance(min, max);
        let pairs = vertex_count.saturating_mul(self.faces.len());
        let each_vertex = pairs <= CONTAINMENT_CHECK_BUDGET;
        for (index, face) in self.faces.iter().enumerate() {
            let off_plane =
                |&v: &u32| (face.normal.dot(self.vertices[v as usize]) - face.offset).abs() > slack;
            if (face.normal.length() - 1.0).abs() > 1e-9 || face.vertices.iter().any(off_plane) {
                return Err(HullError::BadPlane(index));
            }
            if each_vertex
                && (self.vertices.iter()).any(|&v| face.normal.dot(v) - face.offset > slack)
            {
                return Err(HullError::NotConvex(index));
            }
        }
        if !each_vertex {
            let mut on_face = vec![false; vertex_count];
            self.face_loops()
                .flatten()
                .for_each(|&v| on_face[v as usize] = true);
            if let Some(loose) = on_face.iter().position(|&on| !on) {
                return Err(HullError::LooseVertex(loose));
            }
            let loops: Vec<Vec<u32>> = self.face_loops().map(<[u32]>::to_vec).collect();
            if !is_closed_and_convex(&self.vertices, &loops, slack) {
                return Err(HullError::NotConvexSurface);
            }
        }
        // Inward-wound faces give a negative volume, open surfaces an arbitrary one.
        if self.volume() <= 0.0 {
            return Err(HullError::Degenerate("volume is not positive"));
        }
        Ok(())
    }

    /// The vertex farthest along `direction` (shape coordinates); the origin for a hull
    /// without vertices. Linear in the number of vertices.
    pub fn support(&self, direction: DVec3) -> DVec3 {
        // Each vertex's reach is taken once (a comparison of `max_by` takes two), and of
        // equal ones the last wins, as with `max_by`.
        let Some((&first, rest)) = self.vertices.split_first() else {
            return DVec3::ZERO;
        };
        let mut best = (first, first.dot(direction));
        for &vertex in rest {
            let reach = vertex.dot(direction);
            if reach.total_cmp(&best.1).is_ge() {
                best = (vertex, reach);
            }
        }
        best.0
    }

    /// Enclosed volume (m³), exact for the polyhedron.
    pub fn volume(&self) -> f64 {
        mass::polyhedron(&self.vertices, self.face_loops(), 1.0).mass
    }

    /// Mass, centre of mass and inertia of the hull filled with uniform `density` (kg/m³),
    /// exact for the polyhedron.
    pub fn mass_properties(&self, density: f64) -> MassProperties {
        mass::polyhedron(&self.vertices, self.face_loops(), density)
    }

    fn face_loops(&self) -> impl Iterator<Item = &[u32]> {
        self.faces.iter().map(|face| face.vertices.as_slice())
    }

    /// Builds the hull from counter-clockwise polygons over `points`, keeping only the points
    /// the polygons use and renumbering them in input order.
    fn from_polygons(points: &[DVec3], polygons: &[Vec<u32>]) -> Self {
        let mut used = vec![false; points.len()];
        for &v in polygons.iter().flatten() {
            used[v as usize] = true;
        }
        let mut new_index = vec![u32::MAX; points.len()];
        let mut vertices = Vec::new();
        for old in (0..points.len()).filter(|&i| used[i]) {
            new_index[old] = vertices.len() as u32;
            vertices.push(points[old]);
        }
        let faces: Vec<HullFace> = polygons
            .iter()
            .map(|polygon| {
                let ring: Vec<u32> = polygon.iter().map(|&v| new_index[v as usize]).collect();
                face_with_plane(&vertices, ring)
            })
            .collect();
        let mut edges: Vec<[u32; 2]> = faces
            .iter()
            .flat_map(|face| ring_edges(&face.vertices))
            .map(|(a, b)| [a.min(b), a.max(b)])
            .collect();
        edges.sort_unstable();
        edges.dedup();
        ConvexHull::new(vertices, faces, edges)
    }
}

/// For each edge, the two faces whose loops (vertex indices) run along it (one each way).
pub(crate) fn faces_at_edges<'f>(
    loops: impl Iterator<Item = &'f [u32]>,
    edges: &[[u32; 2]],
) -> Vec<Option<[usize; 2]>> {
    let mut sides: Vec<(u32, u32, usize)> = loops
        .enumerate()
        .flat_map(|(f, face)| {
            let n = face.len();
            (0..n).map(move |k| {
                let (i, j) = (face[k], face[(k + 1) % n]);
                (i.min(j), i.max(j), f)
            })
        })
        .collect();
    sides.sort_unstable();
    edges
        .iter()
        .map(|&[i, j]| {
            let key = (i.min(j), i.max(j));
            let start = sides.partition_point(|s| (s.0, s.1) < key);
            match sides.get(start..start + 2) {
                Some([x, y]) if (x.0, x.1) == key && (y.0, y.1) == key => Some([x.2, y.2]),
                _ => None,
            }
        })
        .collect()
}

/// The hull's faces over the normalized cloud, certified convex, or `None` if rounding
/// defeated this attempt.
fn hull_polygons(
    unit_cloud: &[DVec3],
    simplex: [u32; 4],
    tolerance: Tolerance,
) -> Option<Vec<Vec<u32>>> {
    let triangles = Quickhull::new(unit_cloud, simplex, tolerance).run();
    let polygons = merge_coplanar(unit_cloud, &triangles, tolerance.on_plane)?;
    let affordable = unit_cloud.len() * polygons.len() <= CONTAINMENT_CHECK_BUDGET;
    let certified = is_closed_and_convex(unit_cloud, &polygons, tolerance.on_plane)
        && (!affordable || contains_all(unit_cloud, &polygons, tolerance.on_plane));
    certified.then_some(polygons)
}

/// Point-face pairs up to which every input point is checked against every face of the
/// result (and `validate` checks every vertex against every face), which bounds the time
/// the check may take; beyond it the local convexity certificate alone vouches for the
/// hull (BENCHMARKS.md, "Hull containment check").
pub const CONTAINMENT_CHECK_BUDGET: usize = 10_000_000;

/// Whether no point lies above any polygon's plane by more than a few `on_plane`: the
/// refitted plane of a merged face may sit up to about `on_plane` from points that were
/// counted as on it.
fn contains_all(points: &[DVec3], polygons: &[Vec<u32>], on_plane: f64) -> bool {
    polygons.iter().all(|ring| {
        let face = face_with_plane(points, ring.clone());
        points
            .iter()
            .all(|&p| height_above(face.normal, face.offset, p) <= 4.0 * on_plane)
    })
}

/// The plane of a polygon by Newell's method, which averages over all its vertices and so
/// stays accurate for long thin polygons where one cross product would not.
fn face_with_plane(vertices: &[DVec3], ring: Vec<u32>) -> HullFace {
    let points: Vec<DVec3> = ring.iter().map(|&v| vertices[v as usize]).collect();
    let centroid = points.iter().sum::<DVec3>() / points.len() as f64;
    let area_vector: DVec3 = ring_edges(&ring)
        .map(|(a, b)| {
            let (a, b) = (
                vertices[a as usize] - centroid,
                vertices[b as usize] - centroid,
            );
            a.cross(b)
        })
        .sum();
    let normal = area_vector.normalize_or_zero();
    HullFace {
        offset: normal.dot(centroid),
        vertices: ring,
        normal,
    }
}

/// Consecutive vertex pairs around a closed polygon.
fn ring_edges(ring: &[u32]) -> impl Iterator<Item = (u32, u32)> + '_ {
    ring.iter()
        .zip(ring.iter().cycle().skip(1))
        .map(|(&a, &b)| (a, b))
}

fn bounds(points: &[DVec3]) -> (DVec3, DVec3) {
    points.iter().fold(
        (DVec3::splat(f64::INFINITY), DVec3::splat(f64::NEG_INFINITY)),
        |(min, max), &p| (min.min(p), max.max(p)),
    )
}

/// How far a valid hull's vertices may lie above a face's plane, for a hull within these
/// bounds: what `validate` allows.
fn plane_tolerance(min: DVec3, max: DVec3) -> f64 {
    let half_size = ((max - min) * 0.5).max_element();
    let construction = Tolerance::new(relative_noise(min, max)).on_plane;
    (VALIDATE_TOLERANCE + 10.0 * construction) * half_size
}

/// At least a tetrahedron's 4, at most `MAX_HULL_POINTS`.
fn check_point_count(count: usize) -> Result<(), HullError> {
    if count < 4 {
        return Err(HullError::TooFewPoints(count));
    }
    if count > MAX_HULL_POINTS {
        return Err(HullError::TooManyPoints(count));
    }
    Ok(())
}

/// The cloud moved to its bounding-box centre and divided by its largest half-extent, so that
/// it spans [-1, 1] along at least one axis, with the tolerances that fit it.
fn normalized(points: &[DVec3]) -> Result<(Vec<DVec3>, Tolerance), HullError> {
    let (min, max) = bounds(points);
    // Halving before subtracting keeps clouds near ±f64::MAX from overflowing.
    let centre = min * 0.5 + max * 0.5;
    let scale = (max * 0.5 - min * 0.5).max_element();
    if scale == 0.0 {
        return Err(HullError::Degenerate("all points coincide"));
    }
    let tolerance = Tolerance::new(relative_noise(min, max));
    let unit_cloud = points.iter().map(|&p| (p - centre) / scale).collect();
    Ok((unit_cloud, tolerance))
}

/// Rounding error of coordinates within these bounds, over the largest half-extent.
/// Coordinates are only known to f64 epsilon of their magnitude: a cloud far from the origin
/// compared with its size has a proportionally noisier shape.
fn relative_noise(min: DVec3, max: DVec3) -> f64 {
    let magnitude = min.abs().max(max.abs()).max_element();
    let half_size = (max * 0.5 - min * 0.5).max_element();
    f64::EPSILON * magnitude / half_size
}

/// Signed distance of `point` above the plane of a triangle or polygon.
fn height_above(normal: DVec3, offset: f64, point: DVec3) -> f64 {
    normal.dot(point) - offset
}

/// A triangle of the hull under construction, counter-clockwise seen from outside.
struct Triangle {
    corners: [u32; 3],
    normal: DVec3,
    offset: f64,
    /// Points above this triangle by more than the tolerance, not yet on the hull.
    outside: Vec<u32>,
    alive: bool,
}

impl Triangle {
    fn edges(&self) -> [(u32, u32); 3] {
        let [a, b, c] = self.corners;
        [(a, b), (b, c), (c, a)]
    }
}

struct Quickhull<'a> {
    points: &'a [DVec3],
    tolerance: Tolerance,
    triangles: Vec<Triangle>,
    /// Directed edge (from, to) → the live triangle that has it in counter-clockwise order;
    /// the neighbour across an edge is the owner of the reversed edge.
    edge_owner: HashMap<(u32, u32), usize>,
    /// Triangles that may still have outside points.
    pending: Vec<usize>,
}

impl<'a> Quickhull<'a> {
    fn new(points: &'a [DVec3], simplex: [u32; 4], tolerance: Tolerance) -> Self {
        let mut hull = Quickhull {
            points,
            tolerance,
            triangles: Vec::new(),
            edge_owner: HashMap::new(),
            pending: Vec::new(),
        };
        for left_out in 0..4 {
            let mut corners: Vec<u32> = (0..4)
                .filter(|&i| i != left_out)
                .map(|i| simplex[i])
                .collect();
            let opposite = points[simplex[left_out] as usize];
            let [a, b, c] = [0, 1, 2].map(|i| points[corners[i] as usize]);
            if (b - a).cross(c - a).dot(opposite - a) > 0.0 {
                corners.swap(1, 2);
            }
            hull.add_triangle([corners[0], corners[1], corners[2]]);
        }
        let first_faces: Vec<usize> = (0..4).collect();
        let others = (0..points.len() as u32).filter(|i| !simplex.contains(i));
        hull.assign_outside(others, &first_faces);
        hull
    }

    /// Adds the farthest outside point of some triangle until no triangle has any; returns
    /// the live triangles.
    fn run(mut self) -> Vec<[u32; 3]> {
        while let Some(start) = self.pending.pop() {
            let triangle = &self.triangles[start];
            let points = self.points;
            let farthest = triangle.outside.iter().copied().max_by(|&p, &q| {
                let height =
                    |i: u32| height_above(triangle.normal, triangle.offset, points[i as usize]);
                height(p).total_cmp(&height(q))
            });
            if let (true, Some(apex)) = (triangle.alive, farthest) {
                self.add_point(start, apex);
            }
        }
        self.triangles
            .iter()
            .filter(|t| t.alive)
            .map(|t| t.corners)
            .collect()
    }

    /// Replaces the triangles `apex` sees by a cone of new triangles from the horizon to it.
    fn add_point(&mut self, start: usize, apex: u32) {
        // If rounding left the visible region with a hole or a pinch, try again also taking
        // the triangles the apex lies on within rounding.
        let visible = self.tolerance.visible;
        let region = [visible, -visible].into_iter().find_map(|threshold| {
            let visible = self.visible_region(start, apex, threshold);
            self.horizon(&visible).map(|horizon| (visible, horizon))
        });
        let Some((visible, horizon)) = region else {
            // Only reachable for a point within rounding of several planes at once: leave it
            // out rather than corrupt the surface.
            self.triangles[start].outside.retain(|&p| p != apex);
            self.pending.push(start);
            return;
        };
        let mut orphans = Vec::new();
        for &t in &visible {
            orphans.append(&mut self.triangles[t].outside);
            self.remove_triangle(t);
        }
        let cone: Vec<usize> = horizon
            .iter()
            .map(|&(a, b)| self.add_triangle([a, b, apex]))
            .collect();
        // In exact arithmetic an orphan outside the new hull is above a cone triangle. Where
        // rounding bends that rule, it is above a triangle just beyond the horizon instead:
        // offering those too keeps such points from being lost.
        let beyond_horizon = horizon.iter().map(|&(a, b)| self.edge_owner[&(b, a)]);
        let candidates: Vec<usize> = cone.iter().copied().chain(beyond_horizon).collect();
        self.assign_outside(orphans.into_iter().filter(|&p| p != apex), &candidates);
    }

    /// Triangles reachable from `start` across edges whose plane `apex` is above by more than
    /// `threshold`, in the order they were reached (the hash set only answers membership, so
    /// that nothing depends on hash order and the hull is the same on every run).
    fn visible_region(&self, start: usize, apex: u32, threshold: f64) -> Vec<usize> {
        let point = self.points[apex as usize];
        let mut reached = HashSet::from([start]);
        let mut region = vec![start];
        let mut next = 0;
        while let Some(&t) = region.get(next) {
            next += 1;
            for (a, b) in self.triangles[t].edges() {
                let neighbour = self.edge_owner[&(b, a)];
                let seen = &self.triangles[neighbour];
                if height_above(seen.normal, seen.offset, point) > threshold
                    && reached.insert(neighbour)
                {
                    region.push(neighbour);
                }
            }
        }
        region
    }

    /// The boundary of the visible region as one closed loop of directed edges, or `None` if
    /// the region is not a disc (its boundary has several loops or touches itself).
    fn horizon(&self, visible: &[usize]) -> Option<Vec<(u32, u32)>> {
        let members: HashSet<usize> = visible.iter().copied().collect();
        let mut next = HashMap::new();
        let mut start = None;
        for &t in visible {
            for (a, b) in self.triangles[t].edges() {
                let across = self.edge_owner[&(b, a)];
                if !members.contains(&across) {
                    if next.insert(a, b).is_some() {
                        return None;
                    }
                    start.get_or_insert(a);
                }
            }
        }
        let start = start?;
        let mut loop_edges = Vec::with_capacity(next.len());
        let mut from = start;
        loop {
            let to = next[&from];
            loop_edges.push((from, to));
            from = to;
            if from == start {
                break;
            }
            if loop_edges.len() > next.len() || !next.contains_key(&from) {
                return None;
            }
        }
        (loop_edges.len() == next.len()).then_some(loop_edges)
    }

    fn add_triangle(&mut self, corners: [u32; 3]) -> usize {
        let [a, b, c] = corners.map(|i| self.points[i as usize]);
        let normal = (b - a).cross(c - a).normalize_or_zero();
        let index = self.triangles.len();
        self.triangles.push(Triangle {
            corners,
            normal,
            // Through the centroid: the rounding error is then the same for all three corners.
            offset: normal.dot((a + b + c) / 3.0),
            outside: Vec::new(),
            alive: true,
        });
        for edge in self.triangles[index].edges() {
            self.edge_owner.insert(edge, index);
        }
        index
    }

    fn remove_triangle(&mut self, index: usize) {
        self.triangles[index].alive = false;
        for edge in self.triangles[index].edges() {
            self.edge_owner.remove(&edge);
        }
    }

    /// Gives each point to the candidate triangle it is farthest above, if it is above any by
    /// more than `on_plane`; the others are inside the hull (or on it) and are dropped.
    fn assign_outside(&mut self, points: impl Iterator<Item = u32>, candidates: &[usize]) {
        for p in points {
            let point = self.points[p as usize];
            let best = candidates
                .iter()
                .map(|&t| {
                    let triangle = &self.triangles[t];
                    (t, height_above(triangle.normal, triangle.offset, point))
                })
                .max_by(|x, y| x.1.total_cmp(&y.1));
            if let Some((t, _)) = best.filter(|&(_, height)| height > self.tolerance.on_plane) {
                if self.triangles[t].outside.is_empty() {
                    self.pending.push(t);
                }
                self.triangles[t].outside.push(p);
            }
        }
    }
}

/// Four points spanning a tetrahedron as large as a cheap search finds, or the reason none
/// exists: the extremes of the widest axis, then the point farthest from their line, then the
/// point farthest from their plane.
fn initial_simplex(points: &[DVec3], on_plane: f64) -> Result<[u32; 4], HullError> {
    let farthest = |measure: &dyn Fn(DVec3) -> f64| {
        (0..points.len())
            .map(|i| (i as u32, measure(points[i])))
            .max_by(|x, y| x.1.total_cmp(&y.1))
            .expect("at least 4 points")
    };
    // The cloud is normalized, so its widest axis spans [-1, 1]: a and b are distinct.
    let (min, max) = bounds(points);
    let spread = max - min;
    let axis = if spread.x >= spread.y.max(spread.z) {
        0
    } else if spread.y >= spread.z {
        1
    } else {
        2
    };
    let (a, _) = farthest(&|p| -p[axis]);
    let (b, _) = farthest(&|p| p[axis]);
    let (pa, pb) = (points[a as usize], points[b as usize]);
    let direction = (pb - pa).normalize();
    let (c, off_line) = farthest(&|p| (p - pa).cross(direction).length());
    if off_line <= on_plane {
        return Err(HullError::Degenerate("points are collinear"));
    }
    let normal = direction.cross(points[c as usize] - pa).normalize();
    let (d, off_plane) = farthest(&|p| normal.dot(p - pa).abs());
    if off_plane <= on_plane {
        return Err(HullError::Degenerate("points are coplanar"));
    }
    Ok([a, b, c, d])
}

/// Groups the triangles of a closed hull into planar regions and returns each region's
/// boundary as a counter-clockwise polygon, keeping only vertices where three or more
/// polygons meet; `None` if that leaves a polygon with fewer than 3 corners.
fn merge_coplanar(
    points: &[DVec3],
    triangles: &[[u32; 3]],
    on_plane: f64,
) -> Option<Vec<Vec<u32>>> {
    let mesh = TriangleMesh::new(points, triangles);
    let regions = mesh.coplanar_regions(on_plane);
    let mut polygons: Vec<Vec<u32>> = Vec::new();
    for region in &regions {
        match mesh.boundary_loop(region) {
            Some(ring) => polygons.push(ring),
            // A region that is not a disc means rounding grouped the wrong triangles: keep
            // them as separate faces rather than guess.
            None => polygons.extend(region.iter().map(|&t| triangles[t].to_vec())),
        }
    }
    let mut faces_at_vertex: HashMap<u32, usize> = HashMap::new();
    for &v in polygons.iter().flatten() {
        *faces_at_vertex.entry(v).or_default() += 1;
    }
    // A vertex on only two faces lies on the straight edge between them. If that leaves a
    // face with fewer than 3 corners, the merge was inconsistent.
    for polygon in &mut polygons {
        polygon.retain(|v| faces_at_vertex[v] >= 3);
    }
    polygons
        .iter()
        .all(|polygon| polygon.len() >= 3)
        .then_some(polygons)
}

/// A closed, consistently wound triangle mesh with edge adjacency.
struct TriangleMesh<'a> {
    points: &'a [DVec3],
    triangles: &'a [[u32; 3]],
    edge_owner: HashMap<(u32, u32), usize>,
}

impl<'a> TriangleMesh<'a> {
    fn new(points: &'a [DVec3], triangles: &'a [[u32; 3]]) -> Self {
        let edge_owner = triangles
            .iter()
            .enumerate()
            .flat_map(|(t, &[a, b, c])| [((a, b), t), ((b, c), t), ((c, a), t)])
            .collect();
        TriangleMesh {
            points,
            triangles,
            edge_owner,
        }
    }

    fn edges(&self, t: usize) -> [(u32, u32); 3] {
        let [a, b, c] = self.triangles[t];
        [(a, b), (b, c), (c, a)]
    }

    /// Twice the area, along the outward normal.
    fn area_vector(&self, t: usize) -> DVec3 {
        let [a, b, c] = self.triangles[t].map(|i| self.points[i as usize]);
        (b - a).cross(c - a)
    }

    /// Regions grown from the largest remaining triangle (whose plane is the best determined)
    /// over neighbours whose corners all lie within `on_plane` of the seed's plane.
    fn coplanar_regions(&self, on_plane: f64) -> Vec<Vec<usize>> {
        let mut by_area: Vec<usize> = (0..self.triangles.len()).collect();
        by_area.sort_by(|&s, &t| {
            let area = |i: usize| self.area_vector(i).length_squared();
            area(t).total_cmp(&area(s))
        });
        let mut assigned = vec![false; self.triangles.len()];
        let mut regions = Vec::new();
        for seed in by_area {
            if assigned[seed] {
                continue;
            }
            assigned[seed] = true;
            let normal = self.area_vector(seed).normalize_or_zero();
            let offset = normal.dot(self.points[self.triangles[seed][0] as usize]);
            let on_plane = |t: usize| {
                self.area_vector(t).dot(normal) > 0.0
                    && self.triangles[t].iter().all(|&v| {
                        height_above(normal, offset, self.points[v as usize]).abs() <= on_plane
                    })
            };
            let mut region = vec![seed];
            let mut frontier = vec![seed];
            while let Some(t) = frontier.pop() {
                for (a, b) in self.edges(t) {
                    let neighbour = self.edge_owner[&(b, a)];
                    if !assigned[neighbour] && on_plane(neighbour) {
                        assigned[neighbour] = true;
                        region.push(neighbour);
                        frontier.push(neighbour);
                    }
                }
            }
            regions.push(region);
        }
        regions
    }

    /// The region's outer boundary in winding order, or `None` if it is not one simple loop.
    fn boundary_loop(&self, region: &[usize]) -> Option<Vec<u32>> {
        let members: HashSet<usize> = region.iter().copied().collect();
        let mut next = HashMap::new();
        for &t in region {
            for (a, b) in self.edges(t) {
                let outside = !members.contains(&self.edge_owner[&(b, a)]);
                if outside && next.insert(a, b).is_some() {
                    return None;
                }
            }
        }
        let &start = next.keys().min()?;
        let mut ring = vec![start];
        let mut vertex = *next.get(&start)?;
        while vertex != start {
            if ring.len() >= next.len() {
                return None;
            }
            ring.push(vertex);
            vertex = *next.get(&vertex)?;
        }
        (ring.len() == next.len()).then_some(ring)
    }
}

/// Whether the polygons bound a convex solid: a closed, consistently wound surface of sphere
/// topology (V − E + F = 2) whose faces are convex and counter-clockwise, which is convex
/// across every edge (no vertex of a neighbouring face above a face's plane by more than
/// `on_plane`, and no two nearly coplanar faces folded onto each other) and at every vertex
/// (face angles summing to less than a full turn, so the surface does not wind around it
/// twice). A closed surface locally convex at every edge and vertex bounds a convex solid, so
/// this certifies the hull without testing every input point against every face.
fn is_closed_and_convex(points: &[DVec3], polygons: &[Vec<u32>], on_plane: f64) -> bool {
    let mut edge_owner = HashMap::new();
    for (face, ring) in polygons.iter().enumerate() {
        for edge in ring_edges(ring) {
            if edge_owner.insert(edge, face).is_some() {
                return false;
            }
        }
    }
    let vertex_count = polygons.iter().flatten().collect::<HashSet<_>>().len();
    let edge_count = edge_owner.len() / 2;
    if vertex_count + polygons.len() != edge_count + 2 {
        return false;
    }
    let mut angle_at_vertex: HashMap<u32, f64> = HashMap::new();
    let faces_convex = polygons.iter().all(|ring| {
        let face = face_with_plane(points, ring.clone());
        let corner = |i: usize| points[ring[i % ring.len()] as usize];
        let turns_left = (0..ring.len()).all(|i| {
            let (a, b, c) = (corner(i), corner(i + 1), corner(i + 2));
            *angle_at_vertex
                .entry(ring[(i + 1) % ring.len()])
                .or_default() += (a - b).angle_between(c - b);
            (b - a).cross(c - b).dot(face.normal) > 0.0
        });
        let edges_convex = ring_edges(ring).all(|(a, b)| {
            edge_owner.get(&(b, a)).is_some_and(|&across| {
                let (start, end) = (points[a as usize], points[b as usize]);
                // Points into the face, perpendicular to the edge, |b − a| long.
                let inward = face.normal.cross(end - start);
                polygons[across].iter().all(|&v| {
                    let p = points[v as usize];
                    let height = height_above(face.normal, face.offset, p);
                    let folded = height > -on_plane
                        && inward.dot(p - start) > on_plane * (end - start).length();
                    height <= on_plane && !folded
                })
            })
        });
        turns_left && edges_convex
    });
    // Rounding in a nearly flat vertex's angles is far below this margin; a doubly wound
    // vertex exceeds a full turn by a large fraction of it.
    let full_turn = 2.0 * std::f64::consts::PI + 1e-9;
    faces_convex && angle_at_vertex.values().all(|&angle| angle < full_turn)
}

#[cfg(test)]
mod tests {
    use super::*;

    /// A 2 × 4 × 6 box off the origin: the corners' mean is its centre, the farthest corner
    /// lies half a diagonal, √14, from it, and the nearest face half the shortest side, 1.
    #[test]
    fn a_box_s_vertex_ball_is_its_centre_half_diagonal_and_half_side() {
        let centre = DVec3::new(0.5, -1.0, 2.0);
        let half = DVec3::new(1.0, 2.0, 3.0);
        let corners: Vec<DVec3> = (0..8)
            .map(|i| {
                let sign = |bit: u32| if i & (1 << bit) != 0 { 1.0 } else { -1.0 };
                centre + half * DVec3::new(sign(0), sign(1), sign(2))
            })
            .collect();
        let ball = ConvexHull::from_points(&corners).unwrap().vertex_ball();
        assert!(ball.center.distance(centre) < 1e-12, "{:?}", ball.center);
        assert!((ball.outer_radius - 14f64.sqrt()).abs() < 1e-12);
        assert!((ball.inner_radius - 1.0).abs() < 1e-12);
    }

    /// The corner tetrahedron: the mean (¼, ¼, ¼) lies √11/4 from the corner on an axis and
    /// (1 − ¾)/√3 from the slanted face, nearer than the ¼ to the faces on the axis planes.
    #[test]
    fn the_corner_tetrahedron_s_vertex_ball_has_its_closed_form() {
        let corners = [DVec3::ZERO, DVec3::X, DVec3::Y, DVec3::Z];
        let ball = ConvexHull::from_points(&corners).unwrap().vertex_ball();
        assert!(ball.center.distance(DVec3::splat(0.25)) < 1e-12);
        assert!((ball.outer_radius - 11f64.sqrt() / 4.0).abs() < 1e-12);
        assert!((ball.inner_radius - 0.25 / 3f64.sqrt()).abs() < 1e-12);
    }
}

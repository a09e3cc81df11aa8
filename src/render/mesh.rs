//! Triangle meshes for every shape, built once per distinct shape on the CPU. Polyhedra get
//! flat per-face normals; round surfaces get smooth normals, so they shade as round.

use std::f32::consts::{PI, TAU};

use bytemuck::{Pod, Zeroable};
use glam::{Mat4, Vec2, Vec3};

use crate::physics::{ConvexHull, Shape};

#[repr(C)]
/// One mesh vertex, as the mesh pipeline reads it.
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Vertex {
    /// In the shape's own frame, m.
    pub position: [f32; 3],
    /// Unit length, pointing out of the shape.
    pub normal: [f32; 3],
}

/// An indexed triangle mesh on the CPU.
#[derive(Clone, Debug, Default)]
pub struct MeshData {
    /// The vertices the indices refer to.
    pub vertices: Vec<Vertex>,
    /// Three indices into `vertices` per triangle, counter-clockwise seen from outside.
    pub indices: Vec<u32>,
}

/// Segments around the axis of round shapes, and rings from pole to pole of a sphere.
const SEGMENTS: usize = 32;
const RINGS: usize = 16;

impl MeshData {
    fn push_vertex(&mut self, position: Vec3, normal: Vec3) -> u32 {
        self.vertices.push(Vertex {
            position: position.into(),
            normal: normal.into(),
        });
        self.vertices.len() as u32 - 1
    }

    /// A flat convex polygon, fan-triangulated around its first corner.
    fn push_polygon(&mut self, corners: &[Vec3], normal: Vec3) {
        let first = self.vertices.len() as u32;
        for &c in corners {
            self.push_vertex(c, normal);
        }
        for i in 1..corners.len().saturating_sub(1) as u32 {
            self.indices.extend([first, first + i, first + i + 1]);
        }
    }

    /// Appends `other` moved by `transform` (a rigid motion, so normals rotate only).
    fn append_transformed(&mut self, other: &MeshData, transform: Mat4) {
        let base = self.vertices.len() as u32;
        for v in &other.vertices {
            let p = transform.transform_point3(Vec3::from(v.position));
            let n = transform.transform_vector3(Vec3::from(v.normal));
            self.push_vertex(p, n);
        }
        self.indices.extend(other.indices.iter().map(|i| base + i));
    }
}

/// The mesh of a shape in its own frame (the frame the snapshot's pose places).
pub fn shape_mesh(shape: &Shape) -> MeshData {
    match shape {
        Shape::Sphere { radius } => sphere(*radius as f32),
        Shape::Cuboid { half_extents } => cuboid(half_extents.as_vec3()),
        Shape::Capsule {
            half_height,
            radius,
        } => capsule(*half_height as f32, *radius as f32),
        Shape::Cylinder {
            half_height,
            radius,
        } => cylinder(*half_height as f32, *radius as f32),
        Shape::ConvexHull(hull) => hull_mesh(hull),
        Shape::Compound(compound) => {
            let mut mesh = MeshData::default();
            for part in &compound.parts {
                let pose = Mat4::from_rotation_translation(
                    part.pose.rotation.as_quat(),
                    part.pose.translation.as_vec3(),
                );
                mesh.append_transformed(&shape_mesh(&part.shape), pose);
            }
            mesh
        }
    }
}

/// A box centred on the origin with half extents `h` (m): six faces with flat normals.
pub fn cuboid(h: Vec3) -> MeshData {
    let mut mesh = MeshData::default();
    for axis in 0..3 {
        for sign in [-1.0f32, 1.0] {
            let mut normal = Vec3::ZERO;
            normal[axis] = sign;
            // Two tangents (u, v) with u × v = normal, so corners run counter-clockwise.
            let u = Vec3::from_array(std::array::from_fn(|i| f32::from(i == (axis + 1) % 3)));
            let v = normal.cross(u);
            let centre = normal * h;
            let (du, dv) = (u * h, v * h);
            let corners = [
                centre - du - dv,
                centre + du - dv,
                centre + du + dv,
                centre - du + dv,
            ];
            mesh.push_polygon(&corners, normal);
        }
    }
    mesh
}

/// A point of a surface of revolution's profile: distance from the y axis, height, and the
/// profile normal (radial, y).
struct ProfilePoint {
    radius: f32,
    y: f32,
    normal: Vec2,
}

/// Revolves a profile (bottom to top) around the y axis.
fn lathe(profile: &[ProfilePoint], mesh: &mut MeshData) {
    let first = mesh.vertices.len() as u32;
    for p in profile {
        for s in 0..=SEGMENTS {
            let angle = s as f32 / SEGMENTS as f32 * TAU;
            let (sin, cos) = angle.sin_cos();
            let position = Vec3::new(p.radius * cos, p.y, p.radius * sin);
            let normal = Vec3::new(p.normal.x * cos, p.normal.y, p.normal.x * sin);
            mesh.push_vertex(position, normal.normalize_or(Vec3::Y));
        }
    }
    let row = SEGMENTS as u32 + 1;
    for r in 0..profile.len() as u32 - 1 {
        for s in 0..SEGMENTS as u32 {
            let a = first + r * row + s;
            let b = a + row;
            mesh.indices.extend([a, b, a + 1, a + 1, b, b + 1]);
        }
    }
}

/// Quarter-circle arcs of radius `r` centred at height `centre`, from polar angle `from` to
/// `to` (0 = straight down, π = straight up).
fn arc(
    r: f32,
    centre: f32,
    from: f32,
    to: f32,
    steps: usize,
) -> impl Iterator<Item = ProfilePoint> {
    (0..=steps).map(move |i| {
        let theta = from + (to - from) * i as f32 / steps as f32;
        let normal = Vec2::new(theta.sin(), -theta.cos());
        ProfilePoint {
            radius: r * normal.x,
            y: centre + r * normal.y,
            normal,
        }
    })
}

/// A sphere of radius `r` (m) centred on the origin, with smooth normals.
pub fn sphere(r: f32) -> MeshData {
    let mut mesh = MeshData::default();
    let profile: Vec<_> = arc(r, 0.0, 0.0, PI, RINGS).collect();
    lathe(&profile, &mut mesh);
    mesh
}

/// A capsule along the y axis: the centres of its two end hemispheres of radius `r` are at
/// y = ±`half_height` (m). Smooth normals.
pub fn capsule(half_height: f32, r: f32) -> MeshData {
    let mut mesh = MeshData::default();
    let half = RINGS / 2;
    let profile: Vec<_> = arc(r, -half_height, 0.0, PI / 2.0, half)
        .chain(arc(r, half_height, PI / 2.0, PI, half))
        .collect();
    lathe(&profile, &mut mesh);
    mesh
}

/// A cylinder of radius `r` along the y axis, from y = -`half_height` to `half_height` (m):
/// a smooth side and two flat caps.
pub fn cylinder(half_height: f32, r: f32) -> MeshData {
    let mut mesh = MeshData::default();
    let side = [-half_height, half_height].map(|y| ProfilePoint {
        radius: r,
        y,
        normal: Vec2::X,
    });
    lathe(&side, &mut mesh);
    for sign in [-1.0f32, 1.0] {
        let mut rim: Vec<Vec3> = (0..SEGMENTS)
            .map(|s| {
                let (sin, cos) = (s as f32 / SEGMENTS as f32 * TAU).sin_cos();
                Vec3::new(r * cos, sign * half_height, r * sin)
            })
            .collect();
        if sign > 0.0 {
            rim.reverse();
        }
        mesh.push_polygon(&rim, Vec3::Y * sign);
    }
    mesh
}

/// Each polygon face fan-triangulated, with the face's own normal.
pub fn hull_mesh(hull: &ConvexHull) -> MeshData {
    let mut mesh = MeshData::default();
    for face in &hull.faces {
        let corners: Vec<Vec3> = face
            .vertices
            .iter()
            .map(|&i| hull.vertices[i as usize].as_vec3())
            .collect();
        mesh.push_polygon(&corners, face.normal.as_vec3());
    }
    mesh
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::physics::HullFace;
    use glam::DVec3;

    /// Every triangle's winding agrees with its vertices' normals (counter-clockwise seen
    /// from outside), and every normal is unit length.
    fn assert_outward(mesh: &MeshData) {
        for tri in mesh.indices.chunks(3) {
            let [a, b, c] = [0, 1, 2].map(|k| Vec3::from(mesh.vertices[tri[k] as usize].position));
            let n = Vec3::from(mesh.vertices[tri[0] as usize].normal);
            assert!((n.length() - 1.0).abs() < 1e-4);
            let face = (b - a).cross(c - a);
            if face.length() > 1e-6 {
                assert!(face.dot(n) > 0.0, "inward triangle {a} {b} {c}, normal {n}");
            }
        }
    }

    #[test]
    fn primitives_are_closed_outward_and_sized() {
        for shape in [
            Shape::sphere(0.5),
            Shape::cuboid(DVec3::new(1.0, 2.0, 3.0)),
            Shape::capsule(1.0, 0.5),
            Shape::cylinder(1.0, 0.5),
        ] {
            let mesh = shape_mesh(&shape);
            assert!(!mesh.indices.is_empty());
            assert_outward(&mesh);
            let (min, max) = shape.local_bounds();
            for v in &mesh.vertices {
                let p = Vec3::from(v.position).as_dvec3();
                assert!(
                    p.cmpge(min - 1e-5).all() && p.cmple(max + 1e-5).all(),
                    "{shape:?}"
                );
            }
        }
    }

    #[test]
    fn hull_faces_are_fan_triangulated() {
        // A unit square pyramid: one quad and four triangles.
        let vertices = vec![
            DVec3::new(-1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, -1.0),
            DVec3::new(1.0, 0.0, 1.0),
            DVec3::new(-1.0, 0.0, 1.0),
            DVec3::new(0.0, 1.0, 0.0),
        ];
        let face = |v: Vec<u32>| {
            let [a, b, c] = [0, 1, 2].map(|k| vertices[v[k] as usize]);
            let normal = (b - a).cross(c - a).normalize();
            HullFace {
                offset: normal.dot(a),
                vertices: v,
                normal,
            }
        };
        let faces = vec![
            face(vec![0, 1, 2, 3]),
            face(vec![0, 4, 1]),
            face(vec![1, 4, 2]),
            face(vec![2, 4, 3]),
            face(vec![3, 4, 0]),
        ];
        let hull = ConvexHull::new(vertices.clone(), faces, vec![]);
        let mesh = hull_mesh(&hull);
        assert_eq!(mesh.indices.len(), 3 * (2 + 4));
        assert_outward(&mesh);
    }
}

//! Shapes and bodies built by hand for the detection tests (hulls come from explicit faces, so
//! these tests do not depend on quickhull).
#![allow(dead_code)]

pub mod garble;
pub mod tools;
pub mod xorshift;

use std::sync::Arc;

use glam::{DMat3, DQuat, DVec3};
use rigid::physics::{BodyDesc, ConvexHull, HullFace, Motion, RigidBody, Shape};

/// Builds a hull from vertices and counter-clockwise faces; normals, offsets and edges follow.
pub fn hull_from_faces(vertices: Vec<DVec3>, faces: &[&[u32]]) -> ConvexHull {
    let faces: Vec<HullFace> = faces
        .iter()
        .map(|indices| {
            let [p, q, r] = [0, 1, 2].map(|k| vertices[indices[k] as usize]);
            let normal = (q - p).cross(r - p).normalize();
            HullFace {
                vertices: indices.to_vec(),
                normal,
                offset: normal.dot(p),
            }
        })
        .collect();
    let mut edges: Vec<[u32; 2]> = faces
        .iter()
        .flat_map(|f| {
            let n = f.vertices.len();
            (0..n).map(move |k| {
                let (i, j) = (f.vertices[k], f.vertices[(k + 1) % n]);
                [i.min(j), i.max(j)]
            })
        })
        .collect();
    edges.sort();
    edges.dedup();
    ConvexHull::new(vertices, faces, edges)
}

/// The box hull with 6 quad faces.
pub fn box_hull(h: DVec3) -> ConvexHull {
    let vertices = (0..8)
        .map(|i| {
            DVec3::new(
                if i & 1 == 0 { -h.x } else { h.x },
                if i & 2 == 0 { -h.y } else { h.y },
                if i & 4 == 0 { -h.z } else { h.z },
            )
        })
        .collect();
    let faces: [&[u32]; 6] = [
        &[0, 4, 6, 2], // -x
        &[1, 3, 7, 5], // +x
        &[0, 1, 5, 4], // -y
        &[2, 6, 7, 3], // +y
        &[0, 2, 3, 1], // -z
        &[4, 5, 7, 6], // +z
    ];
    hull_from_faces(vertices, &faces)
}

/// The octahedron with vertices at ±h along each axis.
pub fn octahedron_hull(h: DVec3) -> ConvexHull {
    let vertices = vec![
        DVec3::new(h.x, 0.0, 0.0),
        DVec3::new(-h.x, 0.0, 0.0),
        DVec3::new(0.0, h.y, 0.0),
        DVec3::new(0.0, -h.y, 0.0),
        DVec3::new(0.0, 0.0, h.z),
        DVec3::new(0.0, 0.0, -h.z),
    ];
    let faces: [&[u32]; 8] = [
        &[0, 2, 4],
        &[2, 1, 4],
        &[1, 3, 4],
        &[3, 0, 4],
        &[2, 0, 5],
        &[1, 2, 5],
        &[3, 1, 5],
        &[0, 3, 5],
    ];
    hull_from_faces(vertices, &faces)
}

pub fn hull_shape(hull: ConvexHull) -> Shape {
    Shape::ConvexHull(Arc::new(hull))
}

/// A body built field by field, so that hull shapes need no mass properties; the mass and
/// inertia are those of a unit sphere-like body, which detection never reads.
pub fn body(shape: Shape, position: DVec3, rotation: DQuat, motion: Motion) -> RigidBody {
    let proxy = BodyDesc::dynamic(Shape::sphere(1.0));
    let mut body = RigidBody::from_desc(&proxy).unwrap();
    body.shape = shape;
    body.motion = motion;
    body.local_center = DVec3::ZERO;
    body.position = position;
    body.orientation = DMat3::from_quat(rotation.normalize());
    if motion == Motion::Static {
        body.inv_mass = 0.0;
        body.inv_inertia_local = DMat3::ZERO;
    }
    body.refresh_world_inertia();
    body
}

/// A rotation from three numbers in [-1, 1] (a scaled axis up to π).
pub fn rotation_from(v: DVec3) -> DQuat {
    DQuat::from_scaled_axis(v * std::f64::consts::PI)
}

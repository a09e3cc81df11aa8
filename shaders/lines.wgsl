// Unlit coloured lines (grid and overlays). Colours are already gamma-encoded.

struct Globals {
    view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    light_dir: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) color: vec4<f32>,
};

fn project(position: vec3<f32>, color: vec4<f32>) -> VertexOut {
    var out: VertexOut;
    out.clip = globals.view_proj * vec4<f32>(position, 1.0);
    out.color = color;
    return out;
}

@vertex
fn vs_main(@location(0) position: vec3<f32>, @location(1) color: vec4<f32>) -> VertexOut {
    return project(position, color);
}

// Overlays hidden by the bodies in front of them: each vertex is drawn as if 1 % nearer the
// eye, so that what lies on a surface (a contact point, a normal's foot, a box's edge)
// is not hidden by that surface, while what lies behind another body is.
const NEARER: f32 = 0.01;

@vertex
fn vs_tested(@location(0) position: vec3<f32>, @location(1) color: vec4<f32>) -> VertexOut {
    let eye = globals.camera_pos.xyz;
    let nearer = position + (eye - position) * NEARER;
    return project(nearer, color);
}

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    return in.color;
}

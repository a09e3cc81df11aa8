// Lit bodies (instanced: one model matrix and colour per body) and the sky gradient.
// Colours are computed in linear space and written gamma-encoded to a non-sRGB target.

struct Globals {
    view_proj: mat4x4<f32>,
    camera_pos: vec4<f32>,
    // xyz: direction the sunlight travels, w unused.
    light_dir: vec4<f32>,
};

@group(0) @binding(0) var<uniform> globals: Globals;

struct VertexIn {
    @location(0) position: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) model_0: vec4<f32>,
    @location(3) model_1: vec4<f32>,
    @location(4) model_2: vec4<f32>,
    @location(5) model_3: vec4<f32>,
    @location(6) color: vec4<f32>,
};

struct VertexOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) world_pos: vec3<f32>,
    @location(1) normal: vec3<f32>,
    @location(2) color: vec4<f32>,
};

@vertex
fn vs_main(v: VertexIn) -> VertexOut {
    let model = mat4x4<f32>(v.model_0, v.model_1, v.model_2, v.model_3);
    let world = model * vec4<f32>(v.position, 1.0);
    var out: VertexOut;
    out.clip = globals.view_proj * world;
    out.world_pos = world.xyz;
    // Models are rigid motions, so the upper 3×3 rotates normals correctly.
    out.normal = (model * vec4<f32>(v.normal, 0.0)).xyz;
    out.color = v.color;
    return out;
}

const SKY_LINEAR: vec3<f32> = vec3<f32>(0.52, 0.62, 0.78);
const GROUND_LINEAR: vec3<f32> = vec3<f32>(0.18, 0.16, 0.14);

@fragment
fn fs_main(in: VertexOut) -> @location(0) vec4<f32> {
    let n = normalize(in.normal);
    let to_light = -normalize(globals.light_dir.xyz);
    let to_eye = normalize(globals.camera_pos.xyz - in.world_pos);
    let diffuse = max(dot(n, to_light), 0.0);
    // A weaker fill light from the opposite side keeps shadowed faces readable.
    let fill = max(dot(n, -to_light * vec3<f32>(1.0, -0.3, 1.0)), 0.0) * 0.2;
    let ambient = mix(GROUND_LINEAR, SKY_LINEAR, 0.5 + 0.5 * n.y) * 0.55;
    let half_way = normalize(to_light + to_eye);
    let specular = pow(max(dot(n, half_way), 0.0), 48.0) * 0.25;
    let base = in.color.rgb;
    let lit = base * (ambient + diffuse * 0.85 + fill) + vec3<f32>(specular);
    return vec4<f32>(pow(lit, vec3<f32>(1.0 / 2.2)), 1.0);
}

struct SkyOut {
    @builtin(position) clip: vec4<f32>,
    @location(0) height: f32,
};

// One triangle that covers the screen; `height` runs from -1 (bottom) to 1 (top).
@vertex
fn vs_sky(@builtin(vertex_index) index: u32) -> SkyOut {
    let x = f32(i32(index & 1u) * 4 - 1);
    let y = f32(i32(index >> 1u) * 4 - 1);
    var out: SkyOut;
    out.clip = vec4<f32>(x, y, 1.0, 1.0);
    out.height = y;
    return out;
}

@fragment
fn fs_sky(in: SkyOut) -> @location(0) vec4<f32> {
    let top = vec3<f32>(0.55, 0.66, 0.80);
    let bottom = vec3<f32>(0.86, 0.88, 0.90);
    let t = clamp(in.height * 0.5 + 0.5, 0.0, 1.0);
    return vec4<f32>(mix(bottom, top, t), 1.0);
}

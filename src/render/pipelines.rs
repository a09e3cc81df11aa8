//! The render pipelines: lit instanced meshes, the sky, and lines with and without depth
//! testing. All share one bind group (the `Globals` uniform).

use bytemuck::{Pod, Zeroable};

use crate::render::lines::LineVertex;
use crate::render::mesh::Vertex;

/// The depth buffer format of every pass.
pub const DEPTH_FORMAT: wgpu::TextureFormat = wgpu::TextureFormat::Depth32Float;

/// Per-frame uniforms; the layout matches `Globals` in shaders/*.wgsl.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Globals {
    /// The world-to-clip matrix, by columns.
    pub view_proj: [[f32; 4]; 4],
    /// The eye position in world space in xyz; w is 1.
    pub camera_pos: [f32; 4],
    /// The direction the sunlight travels in xyz (unit length, world space); w is 0.
    pub light_dir: [f32; 4],
}

/// Per-body instance data: model matrix columns and linear colour.
#[repr(C)]
#[derive(Clone, Copy, Debug, Pod, Zeroable)]
pub struct Instance {
    /// The shape-frame-to-world matrix, by columns.
    pub model: [[f32; 4]; 4],
    /// Linear RGB (the lighting works in linear values); alpha is 1.
    pub color: [f32; 4],
}

/// Every render pipeline the scene renderer draws with, for one colour format and sample
/// count.
pub struct Pipelines {
    /// The layout of bind group 0: the `Globals` uniform, seen by vertex and fragment
    /// stages.
    pub globals_layout: wgpu::BindGroupLayout,
    /// Lit, instanced body meshes (`Vertex` and `Instance` buffers), depth tested and
    /// written.
    pub mesh: wgpu::RenderPipeline,
    /// The sky gradient: one full-screen triangle, no vertex buffers, drawn first.
    pub sky: wgpu::RenderPipeline,
    /// Lines hidden by bodies (the grid).
    pub world_lines: wgpu::RenderPipeline,
    /// Overlays hidden by the bodies in front of them, drawn slightly nearer the eye so
    /// that the surface they lie on does not hide them.
    pub tested_lines: wgpu::RenderPipeline,
    /// Lines drawn over everything (overlays in x-ray, the drag line).
    pub overlay_lines: wgpu::RenderPipeline,
}

/// What differs between the pipelines built from one shader module.
struct PipelineSpec<'a> {
    label: &'a str,
    module: &'a wgpu::ShaderModule,
    vertex_entry: &'a str,
    fragment_entry: &'a str,
    buffers: &'a [Option<wgpu::VertexBufferLayout<'a>>],
    topology: wgpu::PrimitiveTopology,
    depth: Option<(bool, wgpu::CompareFunction)>,
    blend: Option<wgpu::BlendState>,
}

impl Pipelines {
    /// Builds the pipelines for colour targets of `format` multisampled `samples` times,
    /// with a `DEPTH_FORMAT` depth attachment.
    pub fn new(device: &wgpu::Device, format: wgpu::TextureFormat, samples: u32) -> Self {
        let globals_layout = device.create_bind_group_layout(&wgpu::BindGroupLayoutDescriptor {
            label: Some("globals"),
            entries: &[wgpu::BindGroupLayoutEntry {
                binding: 0,
                visibility: wgpu::ShaderStages::VERTEX | wgpu::ShaderStages::FRAGMENT,
                ty: wgpu::BindingType::Buffer {
                    ty: wgpu::BufferBindingType::Uniform,
                    has_dynamic_offset: false,
                    min_binding_size: None,
                },
                count: None,
            }],
        });
        let layout = device.create_pipeline_layout(&wgpu::PipelineLayoutDescriptor {
            label: Some("scene"),
            bind_group_layouts: &[Some(&globals_layout)],
            immediate_size: 0,
        });
        let mesh_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("mesh.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/mesh.wgsl").into()),
        });
        let line_module = device.create_shader_module(wgpu::ShaderModuleDescriptor {
            label: Some("lines.wgsl"),
            source: wgpu::ShaderSource::Wgsl(include_str!("../../shaders/lines.wgsl").into()),
        });
        let build = |spec: PipelineSpec| build_pipeline(device, &layout, format, samples, spec);

        let mesh_buffers = [
            Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<Vertex>() as u64,
                step_mode: wgpu::VertexStepMode::Vertex,
                attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x3],
            }),
            Some(wgpu::VertexBufferLayout {
                array_stride: size_of::<Instance>() as u64,
                step_mode: wgpu::VertexStepMode::Instance,
                attributes: &wgpu::vertex_attr_array![
                    2 => Float32x4, 3 => Float32x4, 4 => Float32x4, 5 => Float32x4, 6 => Float32x4
                ],
            }),
        ];
        let line_buffers = [Some(wgpu::VertexBufferLayout {
            array_stride: size_of::<LineVertex>() as u64,
            step_mode: wgpu::VertexStepMode::Vertex,
            attributes: &wgpu::vertex_attr_array![0 => Float32x3, 1 => Float32x4],
        })];
        let line_spec = |label, vertex_entry, depth| PipelineSpec {
            label,
            module: &line_module,
            vertex_entry,
            fragment_entry: "fs_main",
            buffers: &line_buffers,
            topology: wgpu::PrimitiveTopology::LineList,
            depth,
            blend: Some(wgpu::BlendState::ALPHA_BLENDING),
        };
        Pipelines {
            mesh: build(PipelineSpec {
                label: "mesh",
                module: &mesh_module,
                vertex_entry: "vs_main",
                fragment_entry: "fs_main",
                buffers: &mesh_buffers,
                topology: wgpu::PrimitiveTopology::TriangleList,
                depth: Some((true, wgpu::CompareFunction::Less)),
                blend: None,
            }),
            sky: build(PipelineSpec {
                label: "sky",
                module: &mesh_module,
                vertex_entry: "vs_sky",
                fragment_entry: "fs_sky",
                buffers: &[],
                topology: wgpu::PrimitiveTopology::TriangleList,
                depth: None,
                blend: None,
            }),
            world_lines: build(line_spec(
                "world lines",
                "vs_main",
                Some((false, wgpu::CompareFunction::LessEqual)),
            )),
            tested_lines: build(line_spec(
                "depth-tested overlay lines",
                "vs_tested",
                Some((false, wgpu::CompareFunction::LessEqual)),
            )),
            overlay_lines: build(line_spec("overlay lines", "vs_main", None)),
            globals_layout,
        }
    }
}

/// `depth`: (write, compare) or None for "always pass, never write". Every pipeline keeps a
/// depth state because every pass has a depth attachment.
fn build_pipeline(
    device: &wgpu::Device,
    layout: &wgpu::PipelineLayout,
    format: wgpu::TextureFormat,
    samples: u32,
    spec: PipelineSpec,
) -> wgpu::RenderPipeline {
    let (write, compare) = spec.depth.unwrap_or((false, wgpu::CompareFunction::Always));
    device.create_render_pipeline(&wgpu::RenderPipelineDescriptor {
        label: Some(spec.label),
        layout: Some(layout),
        vertex: wgpu::VertexState {
            module: spec.module,
            entry_point: Some(spec.vertex_entry),
            buffers: spec.buffers,
            compilation_options: Default::default(),
        },
        primitive: wgpu::PrimitiveState {
            topology: spec.topology,
            // Meshes are closed and outward, but culling buys little here and hides any
            // winding mistake; depth testing does the work.
            cull_mode: None,
            ..Default::default()
        },
        depth_stencil: Some(wgpu::DepthStencilState {
            format: DEPTH_FORMAT,
            depth_write_enabled: Some(write),
            depth_compare: Some(compare),
            stencil: wgpu::StencilState::default(),
            bias: wgpu::DepthBiasState::default(),
        }),
        multisample: wgpu::MultisampleState {
            count: samples,
            ..Default::default()
        },
        fragment: Some(wgpu::FragmentState {
            module: spec.module,
            entry_point: Some(spec.fragment_entry),
            targets: &[Some(wgpu::ColorTargetState {
                format,
                blend: spec.blend,
                write_mask: wgpu::ColorWrites::ALL,
            })],
            compilation_options: Default::default(),
        }),
        multiview_mask: None,
        cache: None,
    })
}

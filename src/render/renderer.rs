//! Draws one frame of a snapshot: sky, grid, bodies (one instanced draw per distinct shape),
//! then overlays. The same code draws into a window's surface or an offscreen texture.

use std::ops::Range;

use glam::{Mat4, Vec3};
use wgpu::util::DeviceExt;

use crate::render::camera::OrbitCamera;
use crate::render::gpu::Gpu;
use crate::render::lines::{AABB_COLOR, BROAD_PHASE_COLOR, GRID_CELL_COLOR, LineList};
use crate::render::mesh;
use crate::render::pipelines::{DEPTH_FORMAT, Globals, Instance, Pipelines};
use crate::sim::snapshot::{BodyPose, JointSketch};
use crate::sim::{LineSegment, Snapshot};

/// Multisampling: smooth edges for lines and silhouettes, cheap even on software adapters.
pub const SAMPLES: u32 = 4;

/// Body colours (gamma-encoded). Dynamic bodies cycle through the palette by index.
pub const PALETTE: [[f32; 3]; 6] = [
    [0.93, 0.55, 0.24],
    [0.27, 0.68, 0.62],
    [0.88, 0.36, 0.36],
    [0.95, 0.78, 0.30],
    [0.50, 0.74, 0.36],
    [0.80, 0.50, 0.72],
];
/// Fixed bodies (gamma-encoded); its brightness steps with the shape so that touching
/// fixed parts stay apart.
pub const STATIC_COLOR: [f32; 3] = [0.60, 0.63, 0.68];
/// Bodies moved by a script or a set velocity (gamma-encoded): a dark steel blue, apart from
/// the fixed grey and from every palette entry, so that the machinery shows against the
/// board it turns on.
pub const KINEMATIC_COLOR: [f32; 3] = [0.20, 0.33, 0.52];
/// Distinct from every palette entry: a saturated blue-violet.
pub const SLEEP_COLOR: [f32; 3] = [0.35, 0.35, 0.95];
/// A body spawned a moment ago (gamma-encoded): a saturated magenta, far from every palette
/// entry, so the user sees at once where it appeared.
pub const SPAWN_COLOR: [f32; 3] = [1.0, 0.1, 0.85];
/// How far the selected body's colour moves toward white.
const SELECTED_LIGHTEN: f32 = 0.45;

/// Which overlays to draw.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub struct Overlays {
    /// The ground grid (on by default).
    pub grid: bool,
    /// Each body's bounding box, in `AABB_COLOR`.
    pub aabbs: bool,
    /// Velocity arrows on dynamic bodies.
    pub velocities: bool,
    /// The snapshot's contact points and normals (on by default).
    pub contacts: bool,
    /// The joints: a line between the anchors, from each moving body's origin to its
    /// anchor, and the axis a hinge, slider or cone-twist turns or slides about (on by
    /// default).
    pub joints: bool,
    /// The broad phase's boxes of awake bodies (bounds grown by the step's reach).
    pub broad_phase: bool,
    /// Draw sleeping bodies in `SLEEP_COLOR` (on by default).
    pub sleep_tint: bool,
    /// Draw the bounding boxes, velocities, contacts, broad phase and joints through the
    /// bodies in front of them; off (the default), those bodies hide them (a ragdoll's
    /// joints inside its limbs cluttered the view). The drag line is always drawn on top.
    pub x_ray: bool,
}

impl Default for Overlays {
    fn default() -> Self {
        Overlays {
            grid: true,
            aabbs: false,
            velocities: false,
            contacts: true,
            joints: true,
            broad_phase: false,
            sleep_tint: true,
            x_ray: false,
        }
    }
}

/// Everything one frame shows.
pub struct FrameInput<'a> {
    /// The bodies, shapes and overlay data to draw.
    pub snapshot: &'a Snapshot,
    /// One pose per body of `snapshot` (interpolated between steps).
    pub poses: &'a [BodyPose],
    /// Where the scene is seen from.
    pub camera: &'a OrbitCamera,
    /// Which overlays to draw.
    pub overlays: Overlays,
    /// The body under the mouse or being dragged (an index into the snapshot's bodies),
    /// drawn highlighted.
    pub selected: Option<usize>,
    /// Lines from the viewer itself (the drag spring), drawn over everything.
    pub extra_lines: &'a [LineSegment],
    /// The part of the target the scene occupies (the panel covers the rest).
    pub viewport: Viewport,
}

/// A rectangle of the target, in pixels from the top-left corner.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Viewport {
    /// Left edge, pixels.
    pub x: f32,
    /// Top edge, pixels.
    pub y: f32,
    /// Width, pixels.
    pub width: f32,
    /// Height, pixels.
    pub height: f32,
}

impl Viewport {
    /// The whole of a target of `size` pixels (width, height).
    pub fn full(size: (u32, u32)) -> Self {
        Viewport {
            x: 0.0,
            y: 0.0,
            width: size.0 as f32,
            height: size.1 as f32,
        }
    }

    /// Width over height, for the projection (a height under one pixel counts as one).
    pub fn aspect(&self) -> f32 {
        self.width / self.height.max(1.0)
    }
}

struct GpuMesh {
    vertices: wgpu::Buffer,
    indices: wgpu::Buffer,
    index_count: u32,
}

/// The multisampled colour and the depth buffer for one target size.
struct Targets {
    size: (u32, u32),
    color: wgpu::TextureView,
    depth: wgpu::TextureView,
}

/// Draws snapshots with the GPU resources it keeps between frames: the pipelines, one mesh
/// per distinct shape (rebuilt only when the shape table changes) and the multisampled
/// colour and depth buffers (rebuilt when the target size does).
pub struct SceneRenderer {
    format: wgpu::TextureFormat,
    pipelines: Pipelines,
    globals: wgpu::Buffer,
    globals_bind: wgpu::BindGroup,
    meshes: Vec<GpuMesh>,
    mesh_generation: Option<u64>,
    instances: Option<wgpu::Buffer>,
    /// (mesh index, instance range), one per distinct shape present.
    draws: Vec<(usize, Range<u32>)>,
    lines: Option<wgpu::Buffer>,
    world_lines: Range<u32>,
    /// Overlays that bodies hide unless in x-ray.
    tested_lines: Range<u32>,
    x_ray: bool,
    /// Overlays always on top.
    overlay_lines: Range<u32>,
    targets: Option<Targets>,
    viewport: Viewport,
}

impl SceneRenderer {
    /// A renderer for targets of `format`, the format of the view later passed to
    /// [`encode`](Self::encode).
    pub fn new(gpu: &Gpu, format: wgpu::TextureFormat) -> Self {
        let pipelines = Pipelines::new(&gpu.device, format, SAMPLES);
        let globals = gpu.device.create_buffer(&wgpu::BufferDescriptor {
            label: Some("globals"),
            size: size_of::<Globals>() as u64,
            usage: wgpu::BufferUsages::UNIFORM | wgpu::BufferUsages::COPY_DST,
            mapped_at_creation: false,
        });
        let globals_bind = gpu.device.create_bind_group(&wgpu::BindGroupDescriptor {
            label: Some("globals"),
            layout: &pipelines.globals_layout,
            entries: &[wgpu::BindGroupEntry {
                binding: 0,
                resource: globals.as_entire_binding(),
            }],
        });
        SceneRenderer {
            format,
            pipelines,
            globals,
            globals_bind,
            meshes: Vec::new(),
            mesh_generation: None,
            instances: None,
            draws: Vec::new(),
            lines: None,
            world_lines: 0..0,
            tested_lines: 0..0,
            x_ray: false,
            overlay_lines: 0..0,
            targets: None,
            viewport: Viewport::full((1, 1)),
        }
    }

    /// Uploads what `frame` needs for a target of `size` pixels (width, height); the frame's
    /// viewport is the part of it drawn to. Call before each [`encode`](Self::encode).
    pub fn prepare(&mut self, gpu: &Gpu, frame: &FrameInput, size: (u32, u32)) {
        self.ensure_targets(gpu, size);
        self.ensure_meshes(gpu, frame.snapshot);
        self.viewport = frame.viewport;
        let aspect = frame.viewport.aspect();
        let globals = Globals {
            view_proj: frame.camera.view_projection(aspect).to_cols_array_2d(),
            camera_pos: frame.camera.eye().extend(1.0).into(),
            light_dir: Vec3::new(-0.5, -1.0, -0.7).normalize().extend(0.0).into(),
        };
        gpu.queue
            .write_buffer(&self.globals, 0, bytemuck::bytes_of(&globals));
        self.upload_instances(gpu, frame);
        self.upload_lines(gpu, frame);
    }

    /// Records the frame into `encoder`, clearing and resolving into `target`, which must
    /// have the size given to [`prepare`](Self::prepare) and the renderer's format.
    ///
    /// # Panics
    ///
    /// If `prepare` was never called.
    pub fn encode(&self, encoder: &mut wgpu::CommandEncoder, target: &wgpu::TextureView) {
        let targets = self.targets.as_ref().expect("prepare() before encode()");
        let mut pass = encoder.begin_render_pass(&wgpu::RenderPassDescriptor {
            label: Some("scene"),
            color_attachments: &[Some(wgpu::RenderPassColorAttachment {
                view: &targets.color,
                depth_slice: None,
                resolve_target: Some(target),
                ops: wgpu::Operations {
                    load: wgpu::LoadOp::Clear(wgpu::Color::BLACK),
                    store: wgpu::StoreOp::Discard,
                },
            })],
            depth_stencil_attachment: Some(wgpu::RenderPassDepthStencilAttachment {
                view: &targets.depth,
                depth_ops: Some(wgpu::Operations {
                    load: wgpu::LoadOp::Clear(1.0),
                    store: wgpu::StoreOp::Discard,
                }),
                stencil_ops: None,
            }),
            timestamp_writes: None,
            occlusion_query_set: None,
            multiview_mask: None,
        });
        let v = self.viewport;
        pass.set_viewport(v.x, v.y, v.width, v.height, 0.0, 1.0);
        pass.set_bind_group(0, &self.globals_bind, &[]);
        pass.set_pipeline(&self.pipelines.sky);
        pass.draw(0..3, 0..1);
        if let Some(instances) = &self.instances {
            pass.set_pipeline(&self.pipelines.mesh);
            pass.set_vertex_buffer(1, instances.slice(..));
            for (mesh, range) in &self.draws {
                let mesh = &self.meshes[*mesh];
                pass.set_vertex_buffer(0, mesh.vertices.slice(..));
                pass.set_index_buffer(mesh.indices.slice(..), wgpu::IndexFormat::Uint32);
                pass.draw_indexed(0..mesh.index_count, 0, range.clone());
            }
        }
        if let Some(lines) = &self.lines {
            pass.set_vertex_buffer(0, lines.slice(..));
            pass.set_pipeline(&self.pipelines.world_lines);
            pass.draw(self.world_lines.clone(), 0..1);
            if self.x_ray {
                pass.set_pipeline(&self.pipelines.overlay_lines);
            } else {
                pass.set_pipeline(&self.pipelines.tested_lines);
            }
            pass.draw(self.tested_lines.clone(), 0..1);
            pass.set_pipeline(&self.pipelines.overlay_lines);
            pass.draw(self.overlay_lines.clone(), 0..1);
        }
    }

    fn ensure_targets(&mut self, gpu: &Gpu, size: (u32, u32)) {
        if self.targets.as_ref().is_some_and(|t| t.size == size) {
            return;
        }
        let texture = |label, format| {
            gpu.device
                .create_texture(&wgpu::TextureDescriptor {
                    label: Some(label),
                    size: wgpu::Extent3d {
                        width: size.0,
                        height: size.1,
                        depth_or_array_layers: 1,
                    },
                    mip_level_count: 1,
                    sample_count: SAMPLES,
                    dimension: wgpu::TextureDimension::D2,
                    format,
                    usage: wgpu::TextureUsages::RENDER_ATTACHMENT,
                    view_formats: &[],
                })
                .create_view(&Default::default())
        };
        self.targets = Some(Targets {
            size,
            color: texture("scene colour", self.format),
            depth: texture("scene depth", DEPTH_FORMAT),
        });
    }

    /// Rebuilds the meshes when the snapshot's shape table changed.
    fn ensure_meshes(&mut self, gpu: &Gpu, snapshot: &Snapshot) {
        if self.mesh_generation == Some(snapshot.shapes.generation) {
            return;
        }
        self.meshes = snapshot
            .shapes
            .shapes
            .iter()
            .map(|shape| upload_mesh(gpu, &mesh::shape_mesh(shape)))
            .collect();
        self.mesh_generation = Some(snapshot.shapes.generation);
    }

    /// One instance per body, grouped by shape so each shape is a single draw.
    fn upload_instances(&mut self, gpu: &Gpu, frame: &FrameInput) {
        let bodies = &frame.snapshot.bodies;
        let mut order: Vec<usize> = (0..bodies.len()).filter(|&i| bodies[i].visible).collect();
        order.sort_by_key(|&i| bodies[i].shape_id);
        let mut instances = Vec::with_capacity(order.len());
        self.draws.clear();
        for &i in &order {
            let shape = bodies[i].shape_id as usize;
            let at = instances.len() as u32;
            match self.draws.last_mut() {
                Some((mesh, range)) if *mesh == shape => range.end = at + 1,
                _ => self.draws.push((shape, at..at + 1)),
            }
            let pose = frame.poses[i];
            instances.push(Instance {
                model: Mat4::from_rotation_translation(pose.rotation, pose.position)
                    .to_cols_array_2d(),
                color: linear(body_color(frame, i)),
            });
        }
        self.instances = (!instances.is_empty()).then(|| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("instances"),
                    contents: bytemuck::cast_slice(&instances),
                    usage: wgpu::BufferUsages::VERTEX,
                })
        });
    }

    fn upload_lines(&mut self, gpu: &Gpu, frame: &FrameInput) {
        let mut lines = LineList::default();
        if frame.overlays.grid {
            lines.grid();
        }
        let world_end = lines.vertices.len() as u32;
        let snapshot = frame.snapshot;
        let drawn = snapshot
            .bodies
            .iter()
            .zip(frame.poses)
            .filter(|(b, _)| b.visible);
        for (body, pose) in drawn {
            if frame.overlays.aabbs {
                // The box was computed at the newest pose: carry it along to the drawn one.
                let shift = pose.position - body.pose.position;
                lines.aabb(body.aabb.0 + shift, body.aabb.1 + shift, AABB_COLOR);
            }
            if frame.overlays.velocities && body.is_dynamic {
                lines.velocity(body);
            }
        }
        if frame.overlays.contacts {
            lines.segments(&snapshot.lines);
        }
        if frame.overlays.broad_phase {
            for &(min, max) in &snapshot.broad_phase_boxes {
                lines.aabb(min, max, BROAD_PHASE_COLOR);
            }
            for &(min, max) in &snapshot.broad_phase_cells {
                lines.aabb(min, max, GRID_CELL_COLOR);
            }
        }
        if frame.overlays.joints {
            let shown = |s: &&JointSketch| s.bodies.iter().all(|&i| snapshot.bodies[i].visible);
            for sketch in snapshot.joints.iter().filter(shown) {
                lines.joint(
                    sketch,
                    [frame.poses[sketch.bodies[0]], frame.poses[sketch.bodies[1]]],
                );
            }
        }
        let tested_end = lines.vertices.len() as u32;
        lines.segments(frame.extra_lines);
        self.world_lines = 0..world_end;
        self.tested_lines = world_end..tested_end;
        self.x_ray = frame.overlays.x_ray;
        self.overlay_lines = tested_end..lines.vertices.len() as u32;
        self.lines = (!lines.vertices.is_empty()).then(|| {
            gpu.device
                .create_buffer_init(&wgpu::util::BufferInitDescriptor {
                    label: Some("lines"),
                    contents: bytemuck::cast_slice(&lines.vertices),
                    usage: wgpu::BufferUsages::VERTEX,
                })
        });
    }
}

fn body_color(frame: &FrameInput, index: usize) -> [f32; 3] {
    let body = &frame.snapshot.bodies[index];
    let base = if body.just_spawned {
        SPAWN_COLOR
    } else if body.sleeping && frame.overlays.sleep_tint {
        SLEEP_COLOR
    } else if body.is_kinematic {
        KINEMATIC_COLOR
    } else if !body.is_dynamic {
        static_color(body.shape_id)
    } else {
        PALETTE[index % PALETTE.len()]
    };
    if frame.selected == Some(index) {
        // Lightened rather than replaced, so the body keeps its identity while held.
        base.map(|c| c + (1.0 - c) * SELECTED_LIGHTEN)
    } else {
        base
    }
}

/// Fixed bodies share one tint; its brightness steps with the shape so that touching fixed
/// parts (pins on a board, a cube on a platform) stay distinguishable.
fn static_color(shape_id: u32) -> [f32; 3] {
    let shade = [1.0, 0.78, 0.9][shape_id as usize % 3];
    STATIC_COLOR.map(|c| c * shade)
}

/// Gamma-encoded colour to the linear values the lighting works in.
fn linear(c: [f32; 3]) -> [f32; 4] {
    [c[0].powf(2.2), c[1].powf(2.2), c[2].powf(2.2), 1.0]
}

fn upload_mesh(gpu: &Gpu, data: &mesh::MeshData) -> GpuMesh {
    let vertices = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh vertices"),
            contents: bytemuck::cast_slice(&data.vertices),
            usage: wgpu::BufferUsages::VERTEX,
        });
    let indices = gpu
        .device
        .create_buffer_init(&wgpu::util::BufferInitDescriptor {
            label: Some("mesh indices"),
            contents: bytemuck::cast_slice(&data.indices),
            usage: wgpu::BufferUsages::INDEX,
        });
    GpuMesh {
        vertices,
        indices,
        index_count: data.indices.len() as u32,
    }
}

//! Environment mapping with a real map (Tortelli & Walter 4.2, after Blinn & Newell
//! 1976): the chamber — rock, floor, the lamp — rendered by sediment itself into the
//! six faces of a floating-point cube map seen from the speleothems' centre, then
//! box-filtered down a mip chain, so the surface pass reads a sharp reflection on wet
//! smooth calcite and a blurred one where the normal map says it is rough. Rendered
//! again whenever the chamber changes (a new seed, another lamp).

use std::sync::Arc;

use glam::{Mat4, Vec3, Vec4};

use super::lit_mesh::{FrameUniforms, GpuMesh, LitMeshPass, ObjectPush};
use super::tone_map::ToneMap;
use crate::error::Result;
use crate::gpu::{
    Context, DEPTH_FORMAT, Image, ImageDesc, OffscreenTarget, Sampler, TargetFormat, vk,
};

/// The faces' format: half floats keep the lamp's radiance above 1.
pub const FACE_FORMAT: TargetFormat = TargetFormat {
    color: vk::Format::R16G16B16A16_SFLOAT,
    depth: DEPTH_FORMAT,
    samples: vk::SampleCountFlags::TYPE_1,
};

/// Per face (layer order +X, -X, +Y, -Y, +Z, -Z): the direction it looks along and
/// the directions of increasing s (columns) and t (rows), from the Vulkan spec's cube
/// map face selection table (sc, tc of each major axis).
const FACES: [(Vec3, Vec3, Vec3); 6] = [
    (Vec3::X, Vec3::NEG_Z, Vec3::NEG_Y),
    (Vec3::NEG_X, Vec3::Z, Vec3::NEG_Y),
    (Vec3::Y, Vec3::X, Vec3::Z),
    (Vec3::NEG_Y, Vec3::X, Vec3::NEG_Z),
    (Vec3::Z, Vec3::X, Vec3::NEG_Y),
    (Vec3::NEG_Z, Vec3::NEG_X, Vec3::NEG_Y),
];

/// The view-projection of cube face `face` seen from `eye`: clip x, y are the face's s
/// and t axes (so the rendered image is the face exactly as the cube sampler reads
/// it), w the distance along the face's axis, depth 0..1 between `near` and `far`.
pub fn face_view_proj(face: usize, eye: Vec3, near: f32, far: f32) -> Mat4 {
    let (f, s, t) = FACES[face % 6];
    let k = far / (far - near);
    // Rows of the matrix acting on (p - eye, 1): x = s.q, y = t.q, w = f.q and
    // z = k (f.q - near), so depth z / w runs from 0 at `near` to 1 at `far`.
    let rows = Mat4::from_cols(
        s.extend(0.0),
        t.extend(0.0),
        (f * k).extend(-k * near),
        f.extend(0.0),
    )
    .transpose();
    rows * Mat4::from_translation(-eye)
}

/// A chamber's environment cube and the pass that renders it.
pub struct EnvironmentMap {
    sampler: Sampler,
    cube: Image,
    target: OffscreenTarget,
    pass: LitMeshPass,
    size: u32,
}

impl EnvironmentMap {
    /// A cube of `size`² faces (a power of two) with its whole mip chain, cleared to
    /// black until first rendered.
    pub fn new(ctx: &Arc<Context>, size: u32) -> Result<Self> {
        let levels = 32 - size.max(1).leading_zeros();
        let cube = Image::new(
            ctx,
            "environment cube",
            ImageDesc::new_cube(
                size,
                FACE_FORMAT.color,
                vk::ImageUsageFlags::SAMPLED
                    | vk::ImageUsageFlags::TRANSFER_DST
                    | vk::ImageUsageFlags::TRANSFER_SRC,
            )
            .mip_levels(levels),
        )?;
        let mut env = Self {
            sampler: Sampler::linear_clamp_mips(ctx, "environment sampler")?,
            target: OffscreenTarget::with_format(ctx, size, size, FACE_FORMAT)?,
            pass: LitMeshPass::two_sided(ctx, FACE_FORMAT, ToneMap::Linear)?,
            cube,
            size,
        };
        let dark = FrameUniforms {
            view_proj: Mat4::IDENTITY,
            camera_pos: Vec4::W,
            sun_dir: Vec4::Y,
            sun_color: Vec4::ZERO,
            sky_color: Vec4::ZERO,
            ground_color: Vec4::ZERO,
            // Exposure 1 (the pass does not tone-map: `ToneMap::Linear`).
            params: Vec4::new(1.0, 0.0, 0.0, 0.0),
        };
        env.render(ctx, Vec3::ZERO, &dark, &[])?;
        Ok(env)
    }

    /// Mip levels of the cube (the finest is 0).
    pub fn levels(&self) -> u32 {
        self.cube.desc().mip_levels
    }

    /// The cube view of every face and level, in SHADER_READ_ONLY_OPTIMAL after `render`;
    /// owned by the map.
    pub fn view(&self) -> vk::ImageView {
        self.cube.view()
    }

    /// The trilinear, edge-clamped sampler to read the cube with (level by roughness).
    pub fn sampler(&self) -> &Sampler {
        &self.sampler
    }

    /// Renders `draws` seen from `eye` into the six faces with `light` (its view and
    /// projection are replaced per face; the faces are not tone-mapped), then the
    /// mip chain. One submission per face and one for the chain.
    pub fn render(
        &mut self,
        ctx: &Arc<Context>,
        eye: Vec3,
        light: &FrameUniforms,
        draws: &[(&GpuMesh, ObjectPush)],
    ) -> Result<()> {
        let far = 1e3 * self.size as f32;
        for face in 0..6 {
            self.pass.set_frame(&FrameUniforms {
                view_proj: face_view_proj(face, eye, 0.01, far),
                camera_pos: eye.extend(1.0),
                ..*light
            })?;
            let (target, pass, cube) = (&self.target, &self.pass, &self.cube);
            ctx.submit_and_wait("environment face", |cmd| {
                target.begin(cmd, [0.0, 0.0, 0.0, 1.0]);
                for (mesh, object) in draws {
                    pass.draw(cmd, mesh, object)?;
                }
                target.end(cmd);
                target.copy_into_layer(cmd, cube, face as u32);
                Ok(())
            })?;
        }
        let cube = &self.cube;
        ctx.submit_and_wait("environment mips", |cmd| {
            cube.record_mips(cmd, 1);
            Ok(())
        })
    }
}

#[cfg(test)]
mod tests {
    use super::*;

    /// Each face's matrix puts its own axis at the centre of the image, its s and t
    /// directions at the right and bottom edges, as the cube sampler reads them.
    #[test]
    fn faces_project_their_directions_where_the_sampler_reads_them() {
        let eye = Vec3::new(1.0, 2.0, 3.0);
        for (i, (f, s, t)) in FACES.iter().enumerate() {
            let m = face_view_proj(i, eye, 0.1, 100.0);
            let ndc = |d: Vec3| {
                let c = m * (eye + d * 10.0).extend(1.0);
                Vec3::new(c.x / c.w, c.y / c.w, c.z / c.w)
            };
            let centre = ndc(*f);
            assert!(centre.x.abs() < 1e-5 && centre.y.abs() < 1e-5, "face {i}");
            assert!(
                (0.0..=1.0).contains(&centre.z),
                "face {i} depth {}",
                centre.z
            );
            let right = ndc(*f + *s);
            assert!(
                (right.x - 1.0).abs() < 1e-5 && right.y.abs() < 1e-5,
                "face {i}"
            );
            let down = ndc(*f + *t);
            assert!(
                down.x.abs() < 1e-5 && (down.y - 1.0).abs() < 1e-5,
                "face {i}"
            );
            // Near and far map to 0 and 1.
            let near = m * (eye + *f * 0.1).extend(1.0);
            let far = m * (eye + *f * 100.0).extend(1.0);
            assert!((near.z / near.w).abs() < 1e-5 && (far.z / far.w - 1.0).abs() < 1e-4);
        }
    }
}

//! What a growth leaves besides its picture: the grown speleothems as a file's asset
//! (named parts, the mineral colours, metres), every ring as CSV, and the first
//! stalagmite cut open.

use std::sync::Arc;

use glam::Vec3;

use crate::error::Result;
use crate::export::asset::{Asset, Material, PartMesh};
use crate::export::union::Solid;
use crate::gpu::Context;
use crate::model::speleothem::plan::{Kind as SpeleothemKind, StopReason};
use crate::model::speleothem::{GrowthPlan, RingVertex};
use crate::render::speleothem_surface::speleothem_info;

/// The parts a grown scene exports: stalactites, stalagmites and columns (both halves
/// of a site that joined, and speleothems that met another), each welded from the
/// transform-feedback triangles and the caps of open fronts and of the base rings sunk
/// in the rock into one vertex per position (closed solids as mesh tools count them; a
/// cap's rim shaded round), with the mineral colours the surface shader uses as
/// COLOR_0. A contact — a front stopped against a speleothem of the other kind — is
/// written as one solid: the two and the joint's fillet between them
/// (`model::speleothem::joints::joints`) united (`export::union`).
/// Positions stay in the plan's scene units; the caller places them
/// ([`Asset::to_metres`]).
pub fn export_parts(plan: &GrowthPlan, vertices: &[RingVertex], asset: &mut Asset) {
    let info = speleothem_info(plan, plan.passes);
    // surface.vert's colour: the mineral's share over white calcite rising from 35 % at
    // the base to all of it at the tip, times the intensity.
    let color_of = |v: &RingVertex| {
        const CALCITE: Vec3 = Vec3::splat(0.8);
        let sp = v.speleothem().min(plan.speleothems.len().saturating_sub(1));
        let (mineral, misc) = (info[3 * sp], info[3 * sp + 1]);
        let t = if mineral.w > 0.0 {
            (v.extra[3] / mineral.w).clamp(0.0, 1.0)
        } else {
            1.0
        };
        (
            CALCITE.lerp(mineral.truncate(), misc.y * (0.35 + 0.65 * t)),
            Vec3::new(0.0, misc.x, 0.0),
        )
    };
    let n = plan.speleothems.len();
    let mut bodies: Vec<Solid> = vec![Solid::default(); n];
    let push = |solid: &mut Solid, p: Vec3, normal: Vec3, color: Vec3| {
        solid.positions.push(p);
        solid.normals.push(normal);
        solid.colors.push(color);
    };
    for tri in vertices.chunks_exact(3) {
        let Some(body) = bodies.get_mut(tri[0].speleothem()) else {
            continue;
        };
        for v in tri {
            let (color, g) = color_of(v);
            push(
                body,
                v.position(),
                (v.normal() - g * v.extra[2]).normalize_or(g),
                color,
            );
        }
    }
    for cap in crate::model::speleothem::caps(vertices, plan, plan.passes) {
        let (color, _) = color_of(&cap.from);
        let Some(body) = bodies.get_mut(cap.from.speleothem()) else {
            continue;
        };
        for (p, n) in cap.corners.into_iter().zip(cap.normals) {
            push(body, p, n, color);
        }
    }
    // The base rings, sunk in the rock, closed too: a file's bodies are then solids
    // (for booleans, printing, volume), each a fan facing into the rock.
    for (i, s) in plan.speleothems.iter().enumerate() {
        let base: Vec<&RingVertex> = vertices
            .iter()
            .filter(|v| v.speleothem() == i && v.ring() == 0)
            .collect();
        let down = Vec3::Y * -s.kind.sign();
        let bottom: Vec<&RingVertex> = base
            .iter()
            .copied()
            .filter(|v| ((v.position() - s.base).dot(down)).abs() < 1e-5)
            .collect();
        for tri in vertices
            .chunks_exact(3)
            .filter(|t| t[0].speleothem() == i && t.iter().all(|v| v.ring() == 0))
        {
            // The triangle's edge on the bottom ring, taken the other way round.
            for (a, b) in [(0, 1), (1, 2), (2, 0)] {
                let on = |v: &RingVertex| bottom.iter().any(|w| w.position() == v.position());
                if on(&tri[a]) && on(&tri[b]) && tri[a].position() != tri[b].position() {
                    let (color, _) = color_of(&tri[a]);
                    for p in [tri[b].position(), tri[a].position(), s.base] {
                        push(&mut bodies[i], p, down, color);
                    }
                }
            }
        }
    }
    // The joints, thickened as the surface pass draws them (their vertices are stored
    // less their speleothem's thickening, which the shader adds along their normals):
    // per speleothem, each joint's solid (a fillet, a web) closed on its own.
    let thickening = crate::model::speleothem::accumulated_thickening(plan, plan.passes);
    let mut joints: Vec<Vec<Solid>> = vec![Vec::new(); n];
    for piece in crate::model::speleothem::joints::joint_solids(plan) {
        let Some(i) = piece.first().map(RingVertex::speleothem) else {
            continue;
        };
        let Some(solids) = joints.get_mut(i) else {
            continue;
        };
        let mut joint = Solid::default();
        for v in &piece {
            let (color, g) = color_of(v);
            let radial = v.normal();
            push(
                &mut joint,
                v.position() + radial * thickening[i],
                (radial - g * v.extra[2]).normalize_or(g),
                color,
            );
        }
        solids.push(joint);
    }

    // Solids: a column is one (its halves join one meeting ring, welded by position;
    // the meeting decides the halves, which need not share a site); a contact unites
    // the two that met and their joint.
    let mut parent: Vec<usize> = (0..n).collect();
    fn root(parent: &mut [usize], mut i: usize) -> usize {
        while parent[i] != i {
            parent[i] = parent[parent[i]];
            i = parent[i];
        }
        i
    }
    let meeting = |i: usize| match plan.speleothems[i].stop {
        Some((pass, StopReason::Column)) => {
            let step = plan.step(pass, i);
            Some((pass, step.target.to_array().map(f32::to_bits)))
        }
        _ => None,
    };
    let mut columns: Vec<usize> = (0..n).collect();
    for a in 0..n {
        for b in a + 1..n {
            if meeting(a).is_some() && meeting(a) == meeting(b) {
                let (ra, rb) = (root(&mut columns, a), root(&mut columns, b));
                columns[rb] = ra;
                let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
                parent[rb] = ra;
            }
        }
    }
    for (a, s) in plan.speleothems.iter().enumerate() {
        if let Some(b) = s.touched.filter(|&b| b < n) {
            let (ra, rb) = (root(&mut parent, a), root(&mut parent, b));
            parent[rb] = ra;
        }
    }
    // 0 stalactites, 1 stalagmites, 2 columns.
    let part_of = |group: &[usize]| {
        if group.len() > 1 {
            2
        } else {
            match plan.speleothems[group[0]].kind {
                SpeleothemKind::Stalactite => 0,
                SpeleothemKind::Stalagmite => 1,
            }
        }
    };
    let mut parts: [Solid; 3] = Default::default();
    let mut seen = vec![false; n];
    for first in 0..n {
        let r = root(&mut parent, first);
        if seen[r] {
            continue;
        }
        seen[r] = true;
        let group: Vec<usize> = (0..n).filter(|&i| root(&mut parent, i) == r).collect();
        // One solid per column in the group, then its joints.
        let mut solids: Vec<Solid> = Vec::new();
        let mut units: Vec<usize> = group.iter().map(|&i| root(&mut columns, i)).collect();
        units.sort_unstable();
        units.dedup();
        for unit in units {
            let mut solid = Solid::default();
            for &i in &group {
                if root(&mut columns, i) == unit {
                    solid.extend(&bodies[i]);
                }
            }
            solids.push(solid);
        }
        for &i in &group {
            solids.extend(
                joints[i]
                    .iter()
                    .filter(|j| !j.positions.is_empty())
                    .cloned(),
            );
        }
        let part = &mut parts[part_of(&group)];
        if solids.len() == 1 {
            part.extend(&solids[0]);
            continue;
        }
        match crate::export::union::union(&solids) {
            Ok(united) => part.extend(&united),
            Err(why) => {
                log::warn!(
                    "speleothems {group:?} met but are exported as separate solids (the \
                     union failed: {why})"
                );
                for solid in &solids {
                    part.extend(solid);
                }
            }
        }
    }
    for (solid, name) in parts.iter().zip(["stalactites", "stalagmites", "columns"]) {
        asset.push(
            name,
            PartMesh::weld_by_position(&solid.positions, &solid.normals, Some(&solid.colors)),
            // Wet calcite: a smooth dielectric; the colour is the vertices'.
            Material::plain("grow_calcite", Vec3::ONE, 0.35),
        );
    }
}

/// What a growth made, for `--json` (`made`): the speleothems by kind and by why they
/// stopped, passes and rings, the longest and widest in metres (`metres_per_unit`
/// metres per scene unit), and with a climate record the years the rings span.
pub fn growth_made(plan: &GrowthPlan, metres_per_unit: f32) -> serde_json::Value {
    let of_kind = |k: SpeleothemKind| plan.speleothems.iter().filter(|s| s.kind == k).count();
    let stopped = |r: StopReason| {
        plan.speleothems
            .iter()
            .filter(|s| s.stop.is_some_and(|(_, why)| why == r))
            .count()
    };
    let (mut longest, mut widest) = (0.0f32, 0.0f32);
    for i in 0..plan.speleothems.len() {
        for ring in plan.rings(i) {
            longest = longest.max(ring.height);
            widest = widest.max(ring.radius);
        }
    }
    let m = |units: f32| crate::text::json_f32(units * metres_per_unit);
    serde_json::json!({
        "speleothems": plan.speleothems.len(),
        "stalactites": of_kind(SpeleothemKind::Stalactite),
        "stalagmites": of_kind(SpeleothemKind::Stalagmite),
        "stopped": {
            "tip_closed": stopped(StopReason::TipClosed),
            "cave_boundary": stopped(StopReason::CaveBoundary),
            "column": stopped(StopReason::Column),
            "contact": stopped(StopReason::Contact),
            "narrowed": stopped(StopReason::Narrowed),
        },
        "passes": plan.passes,
        "segments_per_ring": plan.segments,
        "rings": plan.speleothems.iter().map(|s| u64::from(s.rings)).sum::<u64>(),
        "longest_m": m(longest),
        "widest_radius_m": m(widest),
        "metres_per_unit": crate::text::json_f32(metres_per_unit),
        "years": plan.dates.map(|(first, per_pass)| serde_json::json!({
            "first": first,
            "per_pass": per_pass,
            "last": first + f64::from(plan.passes) * per_pass,
        })),
    })
}

/// The grown speleothems as a file's asset: in metres (`metres_per_unit` per scene
/// unit) with the chamber's floor centre at the origin.
pub fn export_asset(
    plan: &GrowthPlan,
    vertices: &[RingVertex],
    title: &str,
    metres_per_unit: f32,
    floor_y: f32,
) -> Asset {
    let mut asset = Asset::new(title);
    export_parts(plan, vertices, &mut asset);
    asset.to_metres(metres_per_unit, Vec3::new(0.0, floor_y, 0.0));
    asset
}

/// Every ring of every speleothem as CSV (`sediment grow --csv`): with a climate record
/// the year each ring was complete, else the pass that made it; heights and radii in
/// scene units (metres: the chamber is 2.4 m high, a climate growth is in metres).
pub fn write_rings_csv(path: &std::path::Path, plan: &GrowthPlan) -> Result<()> {
    use crate::tables::Cell;
    let when_column = if plan.dates.is_some() { "year" } else { "pass" };
    let header = [
        "speleothem",
        "kind",
        "ring",
        when_column,
        "height_m",
        "radius_m",
    ];
    crate::tables::write_file(path, "--csv", &header, |table| {
        for (i, s) in plan.speleothems.iter().enumerate() {
            let kind = match s.kind {
                SpeleothemKind::Stalactite => "stalactite",
                SpeleothemKind::Stalagmite => "stalagmite",
            };
            for r in plan.rings(i) {
                let when = r.pass.map_or(0, |p| p + 1);
                let when = match plan.dates {
                    Some((first, years)) => Cell::Num(first + f64::from(when) * years),
                    None => Cell::Int(u64::from(when)),
                };
                table.row(&[
                    Cell::Int(i as u64),
                    Cell::Text(kind),
                    Cell::Int(u64::from(r.ring)),
                    when,
                    Cell::Fixed(f64::from(r.height), 6),
                    Cell::Fixed(f64::from(r.radius), 6),
                ])?;
            }
        }
        Ok(())
    })
}

/// The plan's first stalagmite cut open, its rings as growth layers in bands of 10
/// rings, rendered as `sediment layers --render` draws Franke's layers.
pub fn cut_away_render(
    ctx: &Arc<Context>,
    plan: &GrowthPlan,
    size: crate::Size,
) -> Result<image::RgbaImage> {
    let index = plan
        .speleothems
        .iter()
        .position(|s| s.kind == SpeleothemKind::Stalagmite)
        .ok_or_else(|| {
            crate::error::Error::invalid("--cut-away", "the growth has no stalagmite")
        })?;
    let layers = crate::model::speleothem::climate::dated_layers(plan, index)
        .ok_or_else(|| crate::error::Error::internal("cut-away", "no rings"))?;
    let cut = crate::scene::layers::cut_away(&layers, 10);
    crate::scene::layers::picture(ctx, &cut, size)
}

#[cfg(test)]
mod tests {
    use std::collections::HashMap;

    use super::*;
    use crate::model::speleothem::grow_reference;

    /// Every preset's exported parts are closed as mesh tools count them, without
    /// merging first: each edge between two of the file's vertices is shared by
    /// exactly two triangles (before, the caps' rims and the columns' meeting rings were
    /// vertices twice, once per normal, and the base rings were open), and the solids
    /// enclose a positive volume (outward faces).
    #[test]
    fn exported_speleothems_are_closed_solids() {
        for (name, scene) in crate::scene::grow::preset_scenes() {
            let plan = scene.plan().expect("plan");
            let mut asset = Asset::new(name);
            export_parts(&plan, &grow_reference(&plan, plan.passes), &mut asset);
            for part in &asset.parts {
                let m = &part.mesh;
                let mut edges: HashMap<(u32, u32), u32> = HashMap::new();
                for t in m.indices.chunks_exact(3) {
                    for (a, b) in [(t[0], t[1]), (t[1], t[2]), (t[2], t[0])] {
                        *edges.entry((a.min(b), a.max(b))).or_insert(0) += 1;
                    }
                }
                for (&(a, b), &n) in &edges {
                    assert_eq!(
                        n, 2,
                        "{name} {}: an edge in {n} triangles at {:?} to {:?}",
                        part.name, m.positions[a as usize], m.positions[b as usize]
                    );
                }
                let p = |i: u32| Vec3::from(m.positions[i as usize]);
                let volume: f32 = m
                    .indices
                    .chunks_exact(3)
                    .map(|t| p(t[0]).dot(p(t[1]).cross(p(t[2]))) / 6.0)
                    .sum();
                assert!(volume > 0.0, "{name} {}: volume {volume}", part.name);
            }
        }
    }
}

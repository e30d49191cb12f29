//! Speleothems in the cave (Cui et al. section 4.2): stalactites on downward-facing
//! ceiling, each stalagmite on the floor straight below its stalactite, grown at the
//! paper's 1.5x rate, columns where the two meet; bases sunk into the rock so they
//! join the wall without a gap. Stalactites take Short et al.'s profile as the paper
//! does; stalagmites Franke's stationary shape (a rounded top), not an upturned
//! stalactite.

use glam::Vec3;

use super::profile::Profile;
use super::short_profile::{self, ShortShape};
use super::stalagmite_profile;
use crate::model::mesh::Mesh;
use crate::model::random::{Rng, mix64};

/// Vertical lines against a closed mesh: where they cross it, and which side of the
/// wall a point is on. Triangles are bucketed by their footprint in x-z.
pub struct VerticalRays<'a> {
    mesh: &'a Mesh,
    min: (f32, f32),
    cell: f32,
    nx: usize,
    nz: usize,
    buckets: Vec<Vec<u32>>,
}

impl<'a> VerticalRays<'a> {
    /// Buckets `mesh`'s triangles on an x-z grid of `cell`-sized squares (the mesh's
    /// units, metres for a cave) over its bounding box.
    pub fn new(mesh: &'a Mesh, cell: f32) -> Self {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for p in &mesh.positions {
            lo = lo.min(*p);
            hi = hi.max(*p);
        }
        let nx = (((hi.x - lo.x) / cell).ceil() as usize).max(1);
        let nz = (((hi.z - lo.z) / cell).ceil() as usize).max(1);
        let mut buckets = vec![Vec::new(); nx * nz];
        for (t, tri) in mesh.indices.chunks_exact(3).enumerate() {
            let p = [0, 1, 2].map(|i| mesh.positions[tri[i] as usize]);
            let (x0, x1) = (
                p[0].x.min(p[1].x).min(p[2].x),
                p[0].x.max(p[1].x).max(p[2].x),
            );
            let (z0, z1) = (
                p[0].z.min(p[1].z).min(p[2].z),
                p[0].z.max(p[1].z).max(p[2].z),
            );
            let ix = |x: f32| (((x - lo.x) / cell) as usize).min(nx - 1);
            let iz = |z: f32| (((z - lo.z) / cell) as usize).min(nz - 1);
            for gz in iz(z0)..=iz(z1) {
                for gx in ix(x0)..=ix(x1) {
                    buckets[gz * nx + gx].push(t as u32);
                }
            }
        }
        Self {
            mesh,
            min: (lo.x, lo.z),
            cell,
            nx,
            nz,
            buckets,
        }
    }

    /// Heights where the vertical line through (x, z) crosses the mesh, ascending.
    pub fn crossings(&self, x: f32, z: f32) -> Vec<f32> {
        let gx = ((x - self.min.0) / self.cell).floor();
        let gz = ((z - self.min.1) / self.cell).floor();
        if gx < 0.0 || gz < 0.0 || gx as usize >= self.nx || gz as usize >= self.nz {
            return Vec::new();
        }
        let mut ys: Vec<f32> = self.buckets[gz as usize * self.nx + gx as usize]
            .iter()
            .filter_map(|&t| {
                let i = 3 * t as usize;
                let p = [0, 1, 2].map(|k| self.mesh.positions[self.mesh.indices[i + k] as usize]);
                // Barycentric coordinates of (x, z) in the triangle's x-z shadow; the
                // half-open edge rule counts a line through a shared edge once.
                let d =
                    (p[1].x - p[0].x) * (p[2].z - p[0].z) - (p[2].x - p[0].x) * (p[1].z - p[0].z);
                if d.abs() < 1e-12 {
                    return None;
                }
                let w1 = ((x - p[0].x) * (p[2].z - p[0].z) - (p[2].x - p[0].x) * (z - p[0].z)) / d;
                let w2 = ((p[1].x - p[0].x) * (z - p[0].z) - (x - p[0].x) * (p[1].z - p[0].z)) / d;
                let w0 = 1.0 - w1 - w2;
                (w0 >= 0.0 && w1 >= 0.0 && w2 >= 0.0 && (w0 > 0.0 || w1 > 0.0 || w2 > 0.0))
                    .then(|| w0 * p[0].y + w1 * p[1].y + w2 * p[2].y)
            })
            .collect();
        ys.sort_by(f32::total_cmp);
        ys.dedup_by(|a, b| (*a - *b).abs() < 1e-6);
        ys
    }

    /// Whether `p` is in the rock (outside the closed cave surface): an even number of
    /// crossings above it.
    pub fn in_rock(&self, p: Vec3) -> bool {
        self.crossings(p.x, p.z)
            .iter()
            .filter(|&&y| y > p.y)
            .count()
            % 2
            == 0
    }
}

/// How many speleothems and how they look.
#[derive(Clone, Debug, PartialEq)]
pub struct PlacementParams {
    /// Seed of the sites, their shapes and their order of trial.
    pub seed: u64,
    /// Stalactite sites, 0..=200.
    pub count: u32,
    /// Metres per unit of the paper's r (their "units").
    pub unit_m: f32,
    /// Stalagmite growth relative to its stalactite (paper 1.5).
    pub growth_ratio: f32,
    /// A walkway kept free: no site within `clear_radius_m` (horizontally) of this
    /// polyline, so a camera can travel the passage.
    pub clear_path: Vec<Vec3>,
    /// Horizontal clearance around `clear_path`, metres (plus each site's base radius).
    pub clear_radius_m: f32,
}

/// Horizontal distance from `p` to the polyline `path`.
fn distance_to_path(p: Vec3, path: &[Vec3]) -> f32 {
    let p = p.with_y(0.0);
    path.windows(2)
        .map(|w| {
            let (a, b) = (w[0].with_y(0.0), w[1].with_y(0.0));
            let ab = b - a;
            let t = ((p - a).dot(ab) / ab.length_squared().max(1e-12)).clamp(0.0, 1.0);
            (a + ab * t - p).length()
        })
        .fold(f32::INFINITY, f32::min)
}

/// The three shape classes of the paper's Fig. 6 (r range, s), combined at random
/// as in Fig. 6d.
pub const SHAPE_CLASSES: [((f32, f32), f32); 3] = [
    ((5.0, 10.0), 10.0),
    ((10.0, 20.0), 1.0),
    ((20.0, 50.0), 0.5),
];

/// One site: a stalactite on the ceiling and its stalagmite on the floor below.
#[derive(Clone, Debug, PartialEq)]
pub struct Site {
    /// Where the axis meets the ceiling (the wall surface), metres.
    pub ceiling: Vec3,
    /// Where the axis meets the floor straight below, metres.
    pub floor: Vec3,
    /// The stalactite's shape (r, s); r also sets the stalagmite's base radius.
    pub shape: ShortShape,
    /// Visible length of the stalactite below the ceiling, metres.
    pub stalactite_m: f32,
    /// Visible length of the stalagmite above the floor, metres (in a column, past
    /// the meeting point into the stalactite's end).
    pub stalagmite_m: f32,
    /// How far each base continues into the rock, metres.
    pub sink_m: f32,
    /// The two meet in a column.
    pub column: bool,
}

impl Site {
    /// Base radius in metres.
    pub fn base_radius_m(&self, unit_m: f32) -> f32 {
        self.shape.r * unit_m
    }
}

/// Segments around each speleothem mesh.
pub const SEGMENTS: u32 = 24;

/// Picks up to `count` sites on downward-facing ceiling triangles of the closed cave
/// `mesh` (weighted by area, spaced apart), casts each down to the floor, fits the
/// pair into the gap (a column if they would overlap) and sinks both bases until
/// every base-ring vertex is in the rock. Sites where that fails are skipped.
pub fn place(mesh: &Mesh, rays: &VerticalRays<'_>, params: &PlacementParams) -> Vec<Site> {
    let mut rng = Rng::new(mix64(params.seed ^ 0x57A1_AC71));
    // Downward-facing ceiling triangles and their cumulative areas.
    let mut ceiling = Vec::new();
    let mut total = 0.0f32;
    for tri in mesh.indices.chunks_exact(3) {
        let p = [0, 1, 2].map(|k| mesh.positions[tri[k] as usize]);
        let n = (p[1] - p[0]).cross(p[2] - p[0]);
        let area = 0.5 * n.length();
        if area > 0.0 && n.y / (2.0 * area) < -0.85 {
            total += area;
            ceiling.push((total, p));
        }
    }
    let mut sites: Vec<Site> = Vec::new();
    if ceiling.is_empty() || params.count == 0 {
        return sites;
    }
    let attempts = params.count * 20;
    for _ in 0..attempts {
        if sites.len() as u32 >= params.count {
            break;
        }
        let pick = rng.next_f32() * total;
        let at = ceiling
            .partition_point(|(c, _)| *c < pick)
            .min(ceiling.len() - 1);
        let p = ceiling[at].1;
        let (mut u, mut v) = (rng.next_f32(), rng.next_f32());
        if u + v > 1.0 {
            (u, v) = (1.0 - u, 1.0 - v);
        }
        let point = p[0] + (p[1] - p[0]) * u + (p[2] - p[0]) * v;
        let ((lo, hi), s) = SHAPE_CLASSES[(rng.next_u64() % 3) as usize];
        let shape = ShortShape {
            r: lo + (hi - lo) * rng.next_f32(),
            s,
        };
        let radius = shape.r * params.unit_m;
        if distance_to_path(point, &params.clear_path) < params.clear_radius_m + radius {
            continue;
        }
        if sites.iter().any(|o| {
            (o.ceiling - point).with_y(0.0).length()
                < 2.0 * (radius + o.base_radius_m(params.unit_m))
        }) {
            continue;
        }
        if let Some(site) = fit(rays, point, shape, params) {
            sites.push(site);
        }
    }
    sites
}

/// The pair at ceiling point `point`, or `None` where no floor lies below or the base
/// cannot be sunk into rock.
fn fit(
    rays: &VerticalRays<'_>,
    point: Vec3,
    shape: ShortShape,
    params: &PlacementParams,
) -> Option<Site> {
    let radius = shape.r * params.unit_m;
    let crossings = rays.crossings(point.x, point.z);
    // The ceiling is the crossing at the point; the floor the next one down.
    let ceiling_y = *crossings
        .iter()
        .min_by(|a, b| (*a - point.y).abs().total_cmp(&(*b - point.y).abs()))?;
    let floor_y = crossings
        .iter()
        .copied()
        .filter(|&y| y < ceiling_y - 1e-4)
        .fold(f32::MIN, f32::max);
    if floor_y == f32::MIN {
        return None;
    }
    let gap = ceiling_y - floor_y;
    let mut down = shape.length() * params.unit_m;
    let mut up = down * params.growth_ratio;
    let column = down + up >= gap;
    if column {
        // Meet where their growth rates put the meeting point. The stalactite is cut
        // where it is half the base radius wide and that end sits inside the
        // stalagmite's top, where the stalagmite is wider still, so the column is one
        // body and nowhere narrower than half its base radius (no hourglass).
        down = gap / (1.0 + params.growth_ratio);
        let hanging = short_profile::profile(shape, params.unit_m, down);
        let cut = hanging.distance_at_radius(COLUMN_WAIST * radius);
        let top =
            stalagmite_profile::profile(radius, gap).distance_at_radius(COLUMN_OVERLAP * radius);
        up = gap - down + cut + top;
    }
    if down < 2.0 * radius.min(0.05 * gap) && !column {
        return None;
    }
    let ceiling = Vec3::new(point.x, ceiling_y, point.z);
    let floor = Vec3::new(point.x, floor_y, point.z);
    // Sink both bases until their base rings (widened where a sloping flank carries on
    // into the rock) are in rock.
    let mut sink = radius + 0.05 * gap;
    for _ in 0..4 {
        let site = Site {
            ceiling,
            floor,
            shape,
            stalactite_m: down,
            stalagmite_m: up,
            sink_m: sink,
            column,
        };
        let ring_in_rock = |centre: Vec3, radius: f32| {
            (0..SEGMENTS).all(|k| {
                let a = std::f32::consts::TAU * k as f32 / SEGMENTS as f32;
                rays.in_rock(centre + Vec3::new(a.cos(), 0.0, a.sin()) * radius)
            })
        };
        if base_rings(&site, params.unit_m)
            .iter()
            .all(|&(centre, radius)| ring_in_rock(centre, radius))
        {
            return Some(site);
        }
        sink *= 2.0;
    }
    None
}

/// A column's stalactite ends where it is this fraction of the base radius wide...
pub const COLUMN_WAIST: f32 = 0.5;
/// ...inside its stalagmite's top, where that is this fraction wide.
const COLUMN_OVERLAP: f32 = 0.7;

/// The outlines of a site's stalactite and stalagmite (tip to base ring, in metres;
/// not yet into the rock): Short et al.'s stalactite — in a column cut where it is
/// [`COLUMN_WAIST`] of the base radius wide — and Franke's stationary stalagmite of
/// the base radius.
pub fn site_profiles(site: &Site, unit_m: f32) -> [Profile; 2] {
    let radius = site.base_radius_m(unit_m);
    let mut hanging = short_profile::profile(site.shape, unit_m, site.stalactite_m);
    if site.column {
        hanging = hanging.cut_below_radius(COLUMN_WAIST * radius);
    }
    [
        hanging,
        stalagmite_profile::profile(radius, site.stalagmite_m),
    ]
}

/// The axis points of a site's two outlines' tips, and the directions from the tip to
/// the base.
fn tips_and_ups(site: &Site) -> [(Vec3, Vec3); 2] {
    [
        (site.ceiling - Vec3::Y * site.stalactite_m, Vec3::Y),
        (site.floor + Vec3::Y * site.stalagmite_m, Vec3::NEG_Y),
    ]
}

/// A site's stalactite and stalagmite as solids, the parts in the rock included
/// (`--voxel-speleothems` fills their voxels).
pub struct SiteSolid {
    /// Per body: outline into the rock, tip, direction from the tip to the base.
    bodies: [(Profile, Vec3, Vec3); 2],
}

impl SiteSolid {
    /// The solids of `site`, with `unit_m` metres per unit of the paper's r.
    pub fn new(site: &Site, unit_m: f32) -> Self {
        let [a, b] = site_profiles(site, unit_m);
        let [(ta, ua), (tb, ub)] = tips_and_ups(site);
        Self {
            bodies: [
                (a.into_rock(site.sink_m), ta, ua),
                (b.into_rock(site.sink_m), tb, ub),
            ],
        }
    }
}

impl super::Solid for SiteSolid {
    fn bounds(&self) -> (Vec3, Vec3) {
        let (mut lo, mut hi) = (Vec3::splat(f32::MAX), Vec3::splat(f32::MIN));
        for (profile, tip, up) in &self.bodies {
            let widest = profile.points.iter().map(|p| p[0]).fold(0.0, f32::max);
            for end in [*tip, *tip + *up * profile.length()] {
                lo = lo.min(end - Vec3::splat(widest));
                hi = hi.max(end + Vec3::splat(widest));
            }
        }
        (lo, hi)
    }

    fn contains(&self, p: Vec3) -> bool {
        self.bodies.iter().any(|(profile, tip, up)| {
            let h = (p - *tip).dot(*up);
            let r = (p - *tip - *up * h).length();
            r <= profile.radius_at(h)
        })
    }
}

/// The stalactite and stalagmite meshes of `site` in world space, closed, their bases
/// continued into the rock.
pub fn site_meshes(site: &Site, unit_m: f32) -> [Mesh; 2] {
    let profiles = site_profiles(site, unit_m);
    let mut out = [Mesh::default(), Mesh::default()];
    for ((mesh, profile), (tip, up)) in out.iter_mut().zip(&profiles).zip(tips_and_ups(site)) {
        *mesh = profile.into_rock(site.sink_m).mesh(up, SEGMENTS);
        mesh.positions.iter_mut().for_each(|p| *p += tip);
    }
    out
}

/// The base-ring centres and radii of a site's two meshes, in the rock (top of the
/// stalactite, bottom of the stalagmite).
pub fn base_rings(site: &Site, unit_m: f32) -> [(Vec3, f32); 2] {
    let [hanging, standing] = site_profiles(site, unit_m);
    [
        (
            site.ceiling + Vec3::Y * site.sink_m,
            hanging.into_rock(site.sink_m).base_radius(),
        ),
        (
            site.floor - Vec3::Y * site.sink_m,
            standing.into_rock(site.sink_m).base_radius(),
        ),
    ]
}

//! The robot as drawn: per link, triangle meshes in the link frame, from the URDF's visual
//! shapes, else its collision shapes, else capsules from the link's origin to each child
//! joint (and collision point). Mesh files are read only from inside the URDF's package.

use std::path::{Path, PathBuf};

use crate::model::{LinkGeometry, Model, Shape, ShapeKind};
pub use crate::model::{base_link, frames_only};

use super::stl;

/// One drawn piece of a link: triangles in the link frame.
#[derive(Debug, Clone, PartialEq)]
pub struct Part {
    /// Index of the link in [`Model::link_names`].
    pub link: usize,
    /// Fill colour, red, green, blue in [0, 1].
    pub color: [f32; 3],
    /// Vertices in the link frame (length units).
    pub vertices: Vec<[f64; 3]>,
    /// Triangles as vertex indices.
    pub triangles: Vec<[u32; 3]>,
    /// For the capsule along a prismatic joint: (child link, first vertex): the vertices
    /// from `first` on are in the child's frame and move with it, so the capsule stretches
    /// from the joint's origin to wherever the joint has slid the child.
    pub slide: Option<(usize, u32)>,
}

/// The drawn robot and what could not be drawn as the URDF asks.
#[derive(Debug, Clone, Default)]
pub struct Body {
    /// Every part of every link.
    pub parts: Vec<Part>,
    /// One line per kind of fallback (missing or refused meshes), for the user.
    pub warnings: Vec<String>,
}

const LINK_COLOR: [f32; 3] = [0.62, 0.66, 0.74];
const SKELETON_COLOR: [f32; 3] = [0.85, 0.55, 0.25];

/// The directory a URDF's mesh paths may reach: the nearest ancestor of the URDF holding a
/// `package.xml` (a ROS package), else the URDF's own directory.
pub fn package_root(urdf: &Path) -> PathBuf {
    let dir = urdf
        .canonicalize()
        .ok()
        .and_then(|p| p.parent().map(Path::to_owned))
        .unwrap_or_else(|| urdf.parent().unwrap_or(Path::new(".")).to_owned());
    dir.ancestors()
        .find(|d| d.join("package.xml").is_file())
        .map_or_else(|| dir.clone(), Path::to_owned)
}

/// Where a mesh `filename` points, when it is a file inside `root`: relative paths are taken
/// from the URDF's directory, `package://name/rest` from the package root. Absolute paths,
/// `file://` and other URLs, and anything resolving outside the root are refused (as text).
pub fn resolve_mesh(filename: &str, urdf_dir: &Path, root: &Path) -> Result<PathBuf, String> {
    let candidate = if let Some(rest) = filename.strip_prefix("package://") {
        let rest = rest.split_once('/').map_or("", |(_, r)| r);
        root.join(rest)
    } else if filename.contains("://") {
        return Err("a URL, not a path inside the URDF's package".into());
    } else if Path::new(filename).is_absolute() {
        return Err("an absolute path, not a path inside the URDF's package".into());
    } else {
        urdf_dir.join(filename)
    };
    let resolved = candidate
        .canonicalize()
        .map_err(|_| "not found".to_string())?;
    let root = root.canonicalize().unwrap_or_else(|_| root.to_owned());
    if !resolved.starts_with(&root) {
        return Err(format!(
            "outside the URDF's package {} (not read)",
            root.display()
        ));
    }
    if !resolved.is_file() {
        return Err("not a regular file".into());
    }
    Ok(resolved)
}

/// R(rpy) = Rz(y)·Ry(p)·Rx(r), row-major.
fn rpy_matrix(rpy: &[f64; 3]) -> [[f64; 3]; 3] {
    let (sr, cr) = rpy[0].sin_cos();
    let (sp, cp) = rpy[1].sin_cos();
    let (sy, cy) = rpy[2].sin_cos();
    [
        [cy * cp, cy * sp * sr - sy * cr, cy * sp * cr + sy * sr],
        [sy * cp, sy * sp * sr + cy * cr, sy * sp * cr - cy * sr],
        [-sp, cp * sr, cp * cr],
    ]
}

/// A triangle mesh under construction.
#[derive(Default)]
struct Mesh {
    vertices: Vec<[f64; 3]>,
    triangles: Vec<[u32; 3]>,
}

impl Mesh {
    fn vertex(&mut self, v: [f64; 3]) -> u32 {
        self.vertices.push(v);
        (self.vertices.len() - 1) as u32
    }
    /// Rows of vertices joined into quads (each row the same length, closed around).
    fn rows(&mut self, rows: &[Vec<[f64; 3]>]) {
        let first = self.vertices.len() as u32;
        let n = rows.first().map_or(0, Vec::len) as u32;
        for row in rows {
            self.vertices.extend_from_slice(row);
        }
        for r in 0..rows.len().saturating_sub(1) as u32 {
            for i in 0..n {
                let (a, b) = (first + r * n + i, first + r * n + (i + 1) % n);
                let (c, d) = (a + n, b + n);
                self.triangles.push([a, b, d]);
                self.triangles.push([a, d, c]);
            }
        }
    }
    /// A fan closing a row around a centre.
    fn cap(&mut self, centre: [f64; 3], row: &[[f64; 3]]) {
        let c = self.vertex(centre);
        let first = self.vertices.len() as u32;
        self.vertices.extend_from_slice(row);
        let n = row.len() as u32;
        for i in 0..n {
            self.triangles.push([c, first + i, first + (i + 1) % n]);
        }
    }
}

const SEGMENTS: usize = 12;

fn ring(radius: f64, z: f64) -> Vec<[f64; 3]> {
    (0..SEGMENTS)
        .map(|i| {
            let a = std::f64::consts::TAU * i as f64 / SEGMENTS as f64;
            [radius * a.cos(), radius * a.sin(), z]
        })
        .collect()
}

/// A capsule along z (a sphere when `length` is 0), centred on the origin.
fn capsule(radius: f64, length: f64) -> Mesh {
    let mut mesh = Mesh::default();
    const HALF: usize = 4;
    let mut rows = Vec::new();
    for i in 1..=HALF {
        let a = std::f64::consts::FRAC_PI_2 * i as f64 / HALF as f64;
        rows.push(ring(radius * a.sin(), length / 2.0 + radius * a.cos()));
    }
    for i in (1..=HALF).rev() {
        let a = std::f64::consts::FRAC_PI_2 * i as f64 / HALF as f64;
        rows.push(ring(radius * a.sin(), -length / 2.0 - radius * a.cos()));
    }
    let top = rows[0].clone();
    let bottom = rows[rows.len() - 1].clone();
    mesh.rows(&rows);
    mesh.cap([0.0, 0.0, length / 2.0 + radius], &top);
    mesh.cap([0.0, 0.0, -length / 2.0 - radius], &bottom);
    mesh
}

fn cylinder(radius: f64, length: f64) -> Mesh {
    let mut mesh = Mesh::default();
    let (top, bottom) = (ring(radius, length / 2.0), ring(radius, -length / 2.0));
    mesh.rows(&[top.clone(), bottom.clone()]);
    mesh.cap([0.0, 0.0, length / 2.0], &top);
    mesh.cap([0.0, 0.0, -length / 2.0], &bottom);
    mesh
}

fn cuboid(size: [f64; 3]) -> Mesh {
    let h = size.map(|s| s / 2.0);
    let mut mesh = Mesh::default();
    for i in 0..8 {
        let sign = |bit: usize| if i & bit != 0 { 1.0 } else { -1.0 };
        mesh.vertex([sign(1) * h[0], sign(2) * h[1], sign(4) * h[2]]);
    }
    for [a, b, c, d] in [
        [0, 2, 3, 1],
        [4, 5, 7, 6],
        [0, 1, 5, 4],
        [2, 6, 7, 3],
        [0, 4, 6, 2],
        [1, 3, 7, 5],
    ] {
        mesh.triangles.push([a, b, c]);
        mesh.triangles.push([a, c, d]);
    }
    mesh
}

/// Moves a mesh by (R, t).
fn placed(mut mesh: Mesh, rotation: &[[f64; 3]; 3], t: [f64; 3]) -> Mesh {
    for v in &mut mesh.vertices {
        let r = rotation;
        *v = [
            t[0] + r[0][0] * v[0] + r[0][1] * v[1] + r[0][2] * v[2],
            t[1] + r[1][0] * v[0] + r[1][1] * v[1] + r[1][2] * v[2],
            t[2] + r[2][0] * v[0] + r[2][1] * v[1] + r[2][2] * v[2],
        ];
    }
    mesh
}

/// A capsule of radius `radius` from `a` to `b`.
fn capsule_between(a: [f64; 3], b: [f64; 3], radius: f64) -> Mesh {
    let d = [b[0] - a[0], b[1] - a[1], b[2] - a[2]];
    let length = (d[0] * d[0] + d[1] * d[1] + d[2] * d[2]).sqrt();
    let z = d.map(|x| x / length);
    // Any unit vector perpendicular to z, then y = z × x.
    let helper = if z[0].abs() < 0.9 {
        [1.0, 0.0, 0.0]
    } else {
        [0.0, 1.0, 0.0]
    };
    let dot = helper[0] * z[0] + helper[1] * z[1] + helper[2] * z[2];
    let x = [
        helper[0] - dot * z[0],
        helper[1] - dot * z[1],
        helper[2] - dot * z[2],
    ];
    let nx = (x[0] * x[0] + x[1] * x[1] + x[2] * x[2]).sqrt();
    let x = x.map(|v| v / nx);
    let y = [
        z[1] * x[2] - z[2] * x[1],
        z[2] * x[0] - z[0] * x[2],
        z[0] * x[1] - z[1] * x[0],
    ];
    let rotation = [[x[0], y[0], z[0]], [x[1], y[1], z[1]], [x[2], y[2], z[2]]];
    let mid = [
        (a[0] + b[0]) / 2.0,
        (a[1] + b[1]) / 2.0,
        (a[2] + b[2]) / 2.0,
    ];
    placed(capsule(radius, length), &rotation, mid)
}

/// A mesh file's triangles.
type Triangles = Vec<[[f32; 3]; 3]>;

/// Reads meshes once per file and remembers why others could not be read.
struct MeshFiles {
    urdf_dir: PathBuf,
    root: PathBuf,
    loaded: Vec<(String, Result<Triangles, String>)>,
}

impl MeshFiles {
    fn get(&mut self, filename: &str) -> Result<&Vec<[[f32; 3]; 3]>, String> {
        if let Some(i) = self.loaded.iter().position(|(f, _)| f == filename) {
            return self.loaded[i].1.as_ref().map_err(Clone::clone);
        }
        let result = resolve_mesh(filename, &self.urdf_dir, &self.root).and_then(|path| {
            if !path
                .extension()
                .is_some_and(|e| e.eq_ignore_ascii_case("stl"))
            {
                return Err("not an STL file (only STL meshes are drawn)".into());
            }
            let bytes = std::fs::read(&path).map_err(|e| format!("cannot be read ({e})"))?;
            stl::parse(&bytes)
        });
        self.loaded.push((filename.to_owned(), result));
        self.loaded[self.loaded.len() - 1]
            .1
            .as_ref()
            .map_err(Clone::clone)
    }
}

/// The mesh of one shape, or why it cannot be drawn.
fn shape_mesh(shape: &Shape, files: &mut MeshFiles) -> Result<Mesh, String> {
    let mesh = match &shape.kind {
        ShapeKind::Box { size } => cuboid(*size),
        ShapeKind::Cylinder { radius, length } => cylinder(*radius, *length),
        ShapeKind::Capsule { radius, length } => capsule(*radius, *length),
        ShapeKind::Sphere { radius } => capsule(*radius, 0.0),
        ShapeKind::Mesh { filename, scale } => {
            let triangles = files.get(filename)?;
            let mut mesh = Mesh::default();
            for t in triangles {
                let i = mesh.vertices.len() as u32;
                for v in t {
                    mesh.vertices.push([
                        f64::from(v[0]) * scale[0],
                        f64::from(v[1]) * scale[1],
                        f64::from(v[2]) * scale[2],
                    ]);
                }
                mesh.triangles.push([i, i + 1, i + 2]);
            }
            mesh
        }
    };
    Ok(placed(mesh, &rpy_matrix(&shape.rpy), shape.xyz))
}

/// Whether a shape has a volume to draw (a zero-radius sphere is a contact point).
fn has_volume(shape: &Shape) -> bool {
    !matches!(shape.kind, ShapeKind::Sphere { radius } if radius <= 0.0)
}

/// A capsule of radius `radius` along a prismatic joint at `xyz` (axis `axis`, unit, in the
/// parent's frame; child axes R = `rotation` in the parent's): its near end fixed in the
/// parent at `xyz`, its far end in the child's frame at the child's origin; returns the mesh
/// (near vertices first) and the index of the first far vertex.
fn sliding_capsule(
    xyz: [f64; 3],
    axis: [f64; 3],
    rotation: &[[f64; 3]; 3],
    radius: f64,
) -> (Mesh, u32) {
    let end = [xyz[0] + axis[0], xyz[1] + axis[1], xyz[2] + axis[2]];
    let mesh = capsule_between(xyz, end, radius);
    let along = |v: &[f64; 3]| {
        (v[0] - xyz[0]) * axis[0] + (v[1] - xyz[1]) * axis[1] + (v[2] - xyz[2]) * axis[2]
    };
    let (near, far): (Vec<usize>, Vec<usize>) =
        (0..mesh.vertices.len()).partition(|&i| along(&mesh.vertices[i]) <= 0.5);
    let mut index = vec![0u32; mesh.vertices.len()];
    let mut out = Mesh::default();
    for &i in &near {
        index[i] = out.vertex(mesh.vertices[i]);
    }
    let r = rotation;
    for &i in &far {
        // Rᵀ (v − end): the vertex relative to the child's origin, in the child's axes.
        let v = mesh.vertices[i];
        let d = [v[0] - end[0], v[1] - end[1], v[2] - end[2]];
        index[i] = out.vertex([
            r[0][0] * d[0] + r[1][0] * d[1] + r[2][0] * d[2],
            r[0][1] * d[0] + r[1][1] * d[1] + r[2][1] * d[2],
            r[0][2] * d[0] + r[1][2] * d[1] + r[2][2] * d[2],
        ]);
    }
    out.triangles = mesh
        .triangles
        .iter()
        .map(|t| t.map(|i| index[i as usize]))
        .collect();
    (out, near.len() as u32)
}

/// What a skeleton is drawn from: the link's place among the others.
struct Skeleton<'a> {
    names: &'a [String],
    /// Whether the link is a coordinate frame (not drawn).
    frames_only: &'a [bool],
    /// The robot's mass (balls are sized by each link's share of it).
    total_mass: f64,
    /// The robot's extent.
    size: f64,
}

/// The parts of one link: its visual shapes, else its collision shapes, else a skeleton:
/// a capsule to each child joint and collision point, one stretching along each prismatic
/// joint to the child's origin, and, where no capsule leaves the link, a ball whose volume
/// follows its share of the robot's mass. Meshes that failed go to `failures`.
fn link_parts(
    link: usize,
    geometry: &LinkGeometry,
    skeleton: &Skeleton,
    files: &mut MeshFiles,
    failures: &mut Vec<String>,
) -> Vec<Part> {
    if skeleton.frames_only[link] {
        return Vec::new();
    }
    let mut draw = |shapes: &[Shape], failures: &mut Vec<String>| -> Vec<Part> {
        let mut parts = Vec::new();
        for shape in shapes.iter().filter(|s| has_volume(s)) {
            match shape_mesh(shape, files) {
                Ok(mesh) => parts.push(Part {
                    link,
                    color: shape
                        .rgba
                        .map_or(LINK_COLOR, |c| [c[0] as f32, c[1] as f32, c[2] as f32]),
                    vertices: mesh.vertices,
                    triangles: mesh.triangles,
                    slide: None,
                }),
                Err(why) => {
                    if let ShapeKind::Mesh { filename, .. } = &shape.kind {
                        failures.push(format!("{filename}: {why}"));
                    }
                }
            }
        }
        parts
    };
    let visual = draw(&geometry.visual, failures);
    if !visual.is_empty() {
        return visual;
    }
    let collision = draw(&geometry.collision, &mut Vec::new());
    if !collision.is_empty() {
        return collision;
    }
    let size = skeleton.size;
    let targets = geometry.children.iter().map(|c| c.xyz).chain(
        geometry
            .collision
            .iter()
            .filter(|s| matches!(s.kind, ShapeKind::Sphere { .. }))
            .map(|s| s.xyz),
    );
    fn add(mesh: &mut Mesh, part: Mesh) {
        let offset = mesh.vertices.len() as u32;
        mesh.vertices.extend(part.vertices);
        mesh.triangles
            .extend(part.triangles.iter().map(|t| t.map(|i| i + offset)));
    }
    let mut mesh = Mesh::default();
    for target in targets {
        let length = target.iter().map(|v| v * v).sum::<f64>().sqrt();
        if length > 1e-3 * size {
            let radius = (0.1 * length).clamp(0.008 * size, 0.025 * size);
            add(&mut mesh, capsule_between([0.0; 3], target, radius));
        }
    }
    let mut parts = Vec::new();
    for child in &geometry.children {
        let (Some(axis), Some(c)) = (
            child.slide,
            skeleton.names.iter().position(|n| *n == child.link),
        ) else {
            continue;
        };
        let rotation = rpy_matrix(&child.rpy);
        let a = [0, 1, 2].map(|i| (0..3).map(|j| rotation[i][j] * axis[j]).sum::<f64>());
        let norm = a.iter().map(|v| v * v).sum::<f64>().sqrt();
        if norm.partial_cmp(&0.0) != Some(std::cmp::Ordering::Greater) || skeleton.frames_only[c] {
            continue;
        }
        let (slide, first) =
            sliding_capsule(child.xyz, a.map(|v| v / norm), &rotation, 0.025 * size);
        parts.push(Part {
            link,
            color: SKELETON_COLOR,
            vertices: slide.vertices,
            triangles: slide.triangles,
            slide: Some((c, first)),
        });
    }
    if mesh.vertices.is_empty() {
        let share = if skeleton.total_mass > 0.0 {
            geometry.mass / skeleton.total_mass
        } else {
            0.0
        };
        let radius = (0.08 * share.cbrt() * size).clamp(0.02 * size, 0.08 * size);
        add(&mut mesh, capsule(radius, 0.0));
    }
    parts.insert(
        0,
        Part {
            link,
            color: SKELETON_COLOR,
            vertices: mesh.vertices,
            triangles: mesh.triangles,
            slide: None,
        },
    );
    parts
}

/// The robot of `model` as drawn; `urdf` locates mesh files, `size` (the robot's extent)
/// sizes the skeleton capsules.
pub fn body(model: &Model, urdf: &Path, size: f64) -> Body {
    let mut files = MeshFiles {
        urdf_dir: urdf
            .canonicalize()
            .ok()
            .and_then(|p| p.parent().map(Path::to_owned))
            .unwrap_or_else(|| urdf.parent().unwrap_or(Path::new(".")).to_owned()),
        root: package_root(urdf),
        loaded: Vec::new(),
    };
    let mut body = Body::default();
    let mut failures = Vec::new();
    let frames_only = frames_only(model);
    let skeleton = Skeleton {
        names: model.link_names(),
        frames_only: &frames_only,
        total_mass: model.total_mass(),
        size,
    };
    for (link, geometry) in model.link_geometry().iter().enumerate() {
        body.parts.extend(link_parts(
            link,
            geometry,
            &skeleton,
            &mut files,
            &mut failures,
        ));
    }
    failures.sort();
    failures.dedup();
    if !failures.is_empty() {
        let shown: Vec<&str> = failures.iter().take(3).map(String::as_str).collect();
        body.warnings.push(format!(
            "{} mesh file(s) of {} not drawn ({}{}); those links are drawn from their collision \
             shapes or as capsules between their joints",
            failures.len(),
            urdf.display(),
            shown.join("; "),
            if failures.len() > 3 { "; …" } else { "" }
        ));
    }
    body
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::model::BaseType;

    fn urdf_with_mesh(filename: &str) -> String {
        format!(
            r#"<robot name="r">
  <link name="a"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial>
    <visual><geometry><mesh filename="{filename}"/></geometry></visual></link>
  <link name="b"><inertial><mass value="1"/><inertia ixx="1" iyy="1" izz="1" ixy="0" ixz="0" iyz="0"/></inertial></link>
  <joint name="j" type="revolute"><parent link="a"/><child link="b"/><origin xyz="0 0 -0.5"/><axis xyz="0 1 0"/></joint>
</robot>"#
        )
    }

    /// Writes `robot/r.urdf` (mesh `filename`) and a 1-triangle STL `robot/m.stl`.
    fn setup(filename: &str) -> (tempfile::TempDir, PathBuf) {
        let dir = tempfile::tempdir().unwrap();
        let robot = dir.path().join("robot");
        std::fs::create_dir(&robot).unwrap();
        let tri = [[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]];
        std::fs::write(robot.join("m.stl"), stl::tests::binary_stl(&[tri])).unwrap();
        std::fs::write(
            dir.path().join("secret.stl"),
            stl::tests::binary_stl(&[tri]),
        )
        .unwrap();
        let urdf = robot.join("r.urdf");
        std::fs::write(&urdf, urdf_with_mesh(filename)).unwrap();
        (dir, urdf)
    }

    fn drawn(urdf: &Path) -> Body {
        let model = Model::from_urdf_file(urdf, BaseType::Fixed).unwrap();
        body(&model, urdf, 1.0)
    }

    #[test]
    fn a_mesh_inside_the_package_is_drawn() {
        let (_dir, urdf) = setup("m.stl");
        let body = drawn(&urdf);
        assert!(body.warnings.is_empty(), "{:?}", body.warnings);
        assert_eq!(body.parts[0].triangles.len(), 1);
        assert_eq!(body.parts[0].vertices[1], [1.0, 0.0, 0.0]);
    }

    #[test]
    fn meshes_outside_the_package_are_not_read_and_fall_back_with_one_warning() {
        for filename in [
            "../secret.stl",
            "../../../../../../etc/passwd",
            "/etc/passwd",
            "file:///etc/passwd",
            "http://example.com/m.stl",
            "missing.stl",
        ] {
            let (dir, urdf) = setup(filename);
            // The absolute path of the secret file inside the temporary directory is refused too.
            let body = drawn(&urdf);
            assert_eq!(body.warnings.len(), 1, "{filename}: {:?}", body.warnings);
            assert!(body.warnings[0].contains(filename), "{}", body.warnings[0]);
            // Link a falls back to a capsule to its child joint: nothing of the mesh.
            let a: Vec<&Part> = body.parts.iter().filter(|p| p.link == 0).collect();
            assert_eq!(a.len(), 1);
            assert_eq!(a[0].color, SKELETON_COLOR);
            let lowest = a[0].vertices.iter().map(|v| v[2]).fold(0.0, f64::min);
            assert!(
                lowest < -0.5,
                "{filename}: the capsule reaches the joint at z = -0.5"
            );
            drop(dir);
        }
        let (dir, _) = setup("m.stl");
        let secret = dir.path().join("secret.stl");
        let root = dir.path().join("robot");
        let err = resolve_mesh(secret.to_str().unwrap(), &root, &root).unwrap_err();
        assert!(err.contains("absolute"), "{err}");
    }

    #[test]
    fn every_shape_kind_is_closed_around_its_origin() {
        for mesh in [
            cuboid([1.0, 2.0, 3.0]),
            cylinder(0.5, 2.0),
            capsule(0.5, 1.0),
        ] {
            assert!(!mesh.triangles.is_empty());
            assert!(
                mesh.triangles
                    .iter()
                    .flatten()
                    .all(|&i| (i as usize) < mesh.vertices.len())
            );
            let top = mesh.vertices.iter().map(|v| v[2]).fold(f64::MIN, f64::max);
            let bottom = mesh.vertices.iter().map(|v| v[2]).fold(f64::MAX, f64::min);
            assert!((top + bottom).abs() < 1e-12);
        }
        assert_eq!(
            capsule(0.5, 1.0)
                .vertices
                .iter()
                .map(|v| v[2])
                .fold(0.0, f64::max),
            1.0
        );
    }
}

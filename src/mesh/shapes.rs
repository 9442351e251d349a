//! Procedural shapes: the fixtures of the tests and benchmarks, and the editor's starter meshes.
//!
//! Each returns a [`PolygonSoup`] with outward, counter-clockwise faces, so it goes through the
//! same builder as a file. Their Euler characteristics are known exactly:
//!
//! | shape | V | E | F | χ | genus | boundary loops |
//! |---|---|---|---|---|---|---|
//! | [`tetrahedron`] | 4 | 6 | 4 | 2 | 0 | 0 |
//! | [`cube`] (quads) | 8 | 12 | 6 | 2 | 0 | 0 |
//! | [`icosphere`]`(n)` | 10·4ⁿ+2 | 30·4ⁿ | 20·4ⁿ | 2 | 0 | 0 |
//! | [`torus`]`(r, s)` (quads) | r·s | 2·r·s | r·s | 0 | 1 | 0 |
//! | [`grid`]`(nx, ny)` (triangles) | (nx+1)(ny+1) | | 2·nx·ny | 1 | 0 | 1 |
//! | [`slab_with_holes`]`(k)` | | | | 2−2k | k | 0 |

use bevy::math::Vec3;
use bevy::platform::collections::HashMap;

use super::soup::PolygonSoup;

/// A regular tetrahedron inscribed in the unit sphere.
pub fn tetrahedron() -> PolygonSoup {
    let s = 1.0 / 3f32.sqrt();
    PolygonSoup::from_faces(
        vec![
            Vec3::new(s, s, s),
            Vec3::new(s, -s, -s),
            Vec3::new(-s, s, -s),
            Vec3::new(-s, -s, s),
        ],
        &[[0, 1, 2], [0, 3, 1], [0, 2, 3], [1, 3, 2]],
    )
}

/// The cube `[-1, 1]³` as six quads.
pub fn cube() -> PolygonSoup {
    let p = |x: f32, y: f32, z: f32| Vec3::new(x, y, z);
    PolygonSoup::from_faces(
        vec![
            p(-1.0, -1.0, -1.0),
            p(1.0, -1.0, -1.0),
            p(1.0, 1.0, -1.0),
            p(-1.0, 1.0, -1.0),
            p(-1.0, -1.0, 1.0),
            p(1.0, -1.0, 1.0),
            p(1.0, 1.0, 1.0),
            p(-1.0, 1.0, 1.0),
        ],
        &[
            [0, 3, 2, 1], // -z
            [4, 5, 6, 7], // +z
            [0, 1, 5, 4], // -y
            [2, 3, 7, 6], // +y
            [0, 4, 7, 3], // -x
            [1, 2, 6, 5], // +x
        ],
    )
}

/// The regular icosahedron inscribed in the unit sphere.
pub fn icosahedron() -> PolygonSoup {
    let t = (1.0 + 5f32.sqrt()) / 2.0;
    let positions = [
        [-1.0, t, 0.0],
        [1.0, t, 0.0],
        [-1.0, -t, 0.0],
        [1.0, -t, 0.0],
        [0.0, -1.0, t],
        [0.0, 1.0, t],
        [0.0, -1.0, -t],
        [0.0, 1.0, -t],
        [t, 0.0, -1.0],
        [t, 0.0, 1.0],
        [-t, 0.0, -1.0],
        [-t, 0.0, 1.0],
    ]
    .map(|p| Vec3::from_array(p).normalize())
    .to_vec();
    PolygonSoup::from_faces(
        positions,
        &[
            [0, 11, 5],
            [0, 5, 1],
            [0, 1, 7],
            [0, 7, 10],
            [0, 10, 11],
            [1, 5, 9],
            [5, 11, 4],
            [11, 10, 2],
            [10, 7, 6],
            [7, 1, 8],
            [3, 9, 4],
            [3, 4, 2],
            [3, 2, 6],
            [3, 6, 8],
            [3, 8, 9],
            [4, 9, 5],
            [2, 4, 11],
            [6, 2, 10],
            [8, 6, 7],
            [9, 8, 1],
        ],
    )
}

/// An icosahedron whose triangles are split `levels` times into four, projected onto the unit
/// sphere: `20·4ⁿ` triangles.
pub fn icosphere(levels: u32) -> PolygonSoup {
    let mut soup = icosahedron();
    for _ in 0..levels {
        let mut midpoints: HashMap<(u32, u32), u32> = HashMap::default();
        let mut positions = soup.positions.clone();
        let mut faces = Vec::with_capacity(soup.face_count() * 4);
        let mut midpoint = |a: u32, b: u32, positions: &mut Vec<Vec3>| {
            *midpoints.entry((a.min(b), a.max(b))).or_insert_with(|| {
                let p = (positions[a as usize] + positions[b as usize]).normalize();
                positions.push(p);
                (positions.len() - 1) as u32
            })
        };
        for f in soup.faces() {
            let [a, b, c] = [f[0], f[1], f[2]];
            let ab = midpoint(a, b, &mut positions);
            let bc = midpoint(b, c, &mut positions);
            let ca = midpoint(c, a, &mut positions);
            faces.extend([[a, ab, ca], [b, bc, ab], [c, ca, bc], [ab, bc, ca]]);
        }
        soup = PolygonSoup::from_faces(positions, &faces);
    }
    soup
}

/// A torus around the z axis (major radius 1, minor radius 0.35) as `rings × sides` quads.
/// Needs `rings, sides >= 3`.
pub fn torus(rings: u32, sides: u32) -> PolygonSoup {
    let (rings, sides) = (rings.max(3), sides.max(3));
    let mut positions = Vec::with_capacity((rings * sides) as usize);
    for i in 0..rings {
        let u = i as f32 / rings as f32 * std::f32::consts::TAU;
        for j in 0..sides {
            let v = j as f32 / sides as f32 * std::f32::consts::TAU;
            let r = 1.0 + 0.35 * v.cos();
            positions.push(Vec3::new(r * u.cos(), r * u.sin(), 0.35 * v.sin()));
        }
    }
    let at = |i: u32, j: u32| (i % rings) * sides + (j % sides);
    let mut faces = Vec::with_capacity((rings * sides) as usize);
    for i in 0..rings {
        for j in 0..sides {
            faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    PolygonSoup::from_faces(positions, &faces)
}

/// An open `nx × ny` grid on the unit square in the z = 0 plane, each cell split into two
/// triangles along its rising diagonal: one boundary loop, χ = 1.
pub fn grid(nx: u32, ny: u32) -> PolygonSoup {
    let quads = quad_grid(nx, ny);
    triangulate_fans(&quads)
}

/// An open `nx × ny` grid of quads on the unit square in the z = 0 plane.
pub fn quad_grid(nx: u32, ny: u32) -> PolygonSoup {
    let (nx, ny) = (nx.max(1), ny.max(1));
    let mut positions = Vec::with_capacity(((nx + 1) * (ny + 1)) as usize);
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(Vec3::new(i as f32 / nx as f32, j as f32 / ny as f32, 0.0));
        }
    }
    let at = |i: u32, j: u32| j * (nx + 1) + i;
    let mut faces = Vec::with_capacity((nx * ny) as usize);
    for j in 0..ny {
        for i in 0..nx {
            faces.push([at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
        }
    }
    PolygonSoup::from_faces(positions, &faces)
}

/// A `(2k + 1) × 3` quad grid with `k` single-cell holes in its middle row (at odd columns):
/// an open surface with `k + 1` boundary loops, χ = 1 − k.
pub fn grid_with_holes(holes: u32) -> PolygonSoup {
    let (nx, ny) = (2 * holes + 1, 3);
    let mut soup = PolygonSoup::with_capacity(0, 0, 0);
    let mut positions = Vec::new();
    for j in 0..=ny {
        for i in 0..=nx {
            positions.push(Vec3::new(i as f32, j as f32, 0.0));
        }
    }
    soup.positions = positions;
    for (i, j) in slab_cells(holes) {
        let at = |i: u32, j: u32| j * (nx + 1) + i;
        soup.push_face(&[at(i, j), at(i + 1, j), at(i + 1, j + 1), at(i, j + 1)]);
    }
    soup
}

fn slab_cells(holes: u32) -> impl Iterator<Item = (u32, u32)> {
    let nx = 2 * holes + 1;
    (0..3u32)
        .flat_map(move |j| (0..nx).map(move |i| (i, j)))
        .filter(|&(i, j)| !(j == 1 && i % 2 == 1))
}

/// The closed surface of a slab (a thickened [`grid_with_holes`]) with `k` holes through it:
/// a closed surface of genus `k` made of quads (k = 2 is a double torus).
pub fn slab_with_holes(holes: u32) -> PolygonSoup {
    let (nx, ny) = (2 * holes + 1, 3u32);
    let layer = (nx + 1) * (ny + 1);
    let mut positions = Vec::with_capacity(2 * layer as usize);
    for z in [0.0, 1.0] {
        for j in 0..=ny {
            for i in 0..=nx {
                positions.push(Vec3::new(i as f32, j as f32, z));
            }
        }
    }
    let bottom = |i: u32, j: u32| j * (nx + 1) + i;
    let top = |i: u32, j: u32| layer + j * (nx + 1) + i;
    let present = |i: i64, j: i64| {
        (0..nx as i64).contains(&i) && (0..ny as i64).contains(&j) && !(j == 1 && i % 2 == 1)
    };
    let mut faces: Vec<[u32; 4]> = Vec::new();
    for (i, j) in slab_cells(holes) {
        faces.push([top(i, j), top(i + 1, j), top(i + 1, j + 1), top(i, j + 1)]);
        faces.push([
            bottom(i, j),
            bottom(i, j + 1),
            bottom(i + 1, j + 1),
            bottom(i + 1, j),
        ]);
        // Walls where the neighbour across a side is missing. Each side a→b runs the way the
        // top face runs it; the wall runs b→a on top.
        let (ii, jj) = (i64::from(i), i64::from(j));
        let sides = [
            ((i, j), (i + 1, j), present(ii, jj - 1)),
            ((i + 1, j), (i + 1, j + 1), present(ii + 1, jj)),
            ((i + 1, j + 1), (i, j + 1), present(ii, jj + 1)),
            ((i, j + 1), (i, j), present(ii - 1, jj)),
        ];
        for (a, b, neighbour) in sides {
            if !neighbour {
                faces.push([
                    top(b.0, b.1),
                    top(a.0, a.1),
                    bottom(a.0, a.1),
                    bottom(b.0, b.1),
                ]);
            }
        }
    }
    PolygonSoup::from_faces(positions, &faces)
}

/// Two triangles sharing one edge (the "diamond" of local-operation tests).
pub fn diamond() -> PolygonSoup {
    PolygonSoup::from_faces(
        vec![
            Vec3::new(0.0, -1.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(0.0, 1.0, 0.0),
            Vec3::new(-1.0, 0.0, 0.0),
        ],
        &[[0, 1, 2], [0, 2, 3]],
    )
}

/// `n` triangles around a centre vertex (index 0), closing into a disc when `closed`.
pub fn triangle_fan(n: u32, closed: bool) -> PolygonSoup {
    let n = n.max(3);
    let mut positions = vec![Vec3::ZERO];
    let rim = if closed { n } else { n + 1 };
    for i in 0..rim {
        let a = i as f32 / n as f32 * std::f32::consts::TAU * if closed { 1.0 } else { 0.75 };
        positions.push(Vec3::new(a.cos(), a.sin(), 0.0));
    }
    let faces: Vec<[u32; 3]> = (0..n).map(|i| [0, 1 + i, 1 + (i + 1) % rim]).collect();
    PolygonSoup::from_faces(positions, &faces)
}

/// Splits every polygon of `soup` into a fan of triangles from its first corner.
pub fn triangulate_fans(soup: &PolygonSoup) -> PolygonSoup {
    let mut out = PolygonSoup::with_capacity(soup.positions.len(), soup.face_count() * 2, 0);
    out.positions = soup.positions.clone();
    for f in soup.faces() {
        for i in 1..f.len().saturating_sub(1) {
            out.push_face(&[f[0], f[i], f[i + 1]]);
        }
    }
    out
}

/// Why a `shape:` name gives no shape.
#[derive(Debug, Clone, PartialEq, thiserror::Error)]
pub enum ShapeError {
    /// The name (or its sizes' syntax) is not one [`by_name`] knows.
    #[error("unknown shape `{0}`; known: {known}", known = SHAPE_NAMES.join(", "))]
    Unknown(String),
    /// The sizes ask for more than a mesh may have, or than the memory budget allows.
    #[error("shape `{name}`: {why}")]
    TooLarge {
        /// The name as given.
        name: String,
        /// The counts, and the limit they pass.
        why: String,
    },
}

/// The sizes of the mesh a shape name makes, counted in 64 bits before anything is made.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
struct ShapeSize {
    vertices: u64,
    faces: u64,
    /// Face corners (halfedges).
    corners: u64,
}

/// The most face corners a mesh may have (the builder's limit).
const MAX_CORNERS: u64 = 1 << 31;

/// A shape by name, for the command line and the editor's menu: `tetrahedron`, `cube`,
/// `icosahedron`, `icosphere`, `torus`, `grid`, `quad-grid`, `grid-with-holes`, `double-torus`.
/// Sizes can follow after colons: `icosphere:6` (levels), `torus:64:32` (rings, sides),
/// `grid:100` or `grid:100:50`, `quad-grid:…`, `grid-with-holes:3`, `slab:3` (genus 3).
///
/// # Errors
/// [`ShapeError::Unknown`] for a name or size syntax it does not know;
/// [`ShapeError::TooLarge`] when the sizes, multiplied out in 64 bits, pass 2³¹ face corners
/// or the memory budget ([`crate::memory_budget`]). Both are found before anything is made.
pub fn by_name(name: &str) -> Result<PolygonSoup, ShapeError> {
    let (shape, args) = parse_name(name)?;
    let arg = |i: usize, default: u32| args.get(i).copied().unwrap_or(default);
    Ok(match shape {
        "tetrahedron" => tetrahedron(),
        "cube" => cube(),
        "icosahedron" => icosahedron(),
        "icosphere" => icosphere(arg(0, 3)),
        "torus" => torus(arg(0, 24), arg(1, 12)),
        "grid" => grid(arg(0, 10), arg(1, arg(0, 10))),
        "quad-grid" => quad_grid(arg(0, 10), arg(1, arg(0, 10))),
        "grid-with-holes" => grid_with_holes(arg(0, 2)),
        "double-torus" => slab_with_holes(2),
        "slab" => slab_with_holes(arg(0, 2)),
        _ => return Err(ShapeError::Unknown(name.to_string())),
    })
}

/// Checks a shape name as [`by_name`] does, without making the mesh: for the command line's
/// argument checks.
///
/// # Errors
/// As [`by_name`].
pub fn check_name(name: &str) -> Result<(), ShapeError> {
    parse_name(name).map(|_| ())
}

/// The shape and its sizes, once they pass the size checks.
fn parse_name(name: &str) -> Result<(&str, Vec<u32>), ShapeError> {
    let unknown = || ShapeError::Unknown(name.to_string());
    let mut parts = name.split(':');
    let shape = parts.next().ok_or_else(unknown)?;
    let args: Vec<u32> = parts
        .map(|p| p.parse().ok())
        .collect::<Option<_>>()
        .ok_or_else(unknown)?;
    let size = shape_size(shape, &args).ok_or_else(unknown)?;
    let too_large = |why: String| ShapeError::TooLarge {
        name: name.to_string(),
        why,
    };
    if size.corners >= MAX_CORNERS || size.vertices >= MAX_CORNERS {
        return Err(too_large(format!(
            "{} faces with {} corners, more than a mesh may have (2^31 corners)",
            size.faces, size.corners
        )));
    }
    let estimate = crate::memory_budget::Estimate {
        what: "it".into(),
        faces: size.faces,
        rows: size.vertices + size.corners + size.corners.div_ceil(2) + size.faces,
        instead: "use smaller sizes",
    };
    crate::memory_budget::check(&estimate).map_err(|refusal| too_large(refusal.to_string()))?;
    Ok((shape, args))
}

/// The sizes `shape` with `args` makes, in 64 bits (saturating), or `None` for a shape name
/// that is not known.
fn shape_size(shape: &str, args: &[u32]) -> Option<ShapeSize> {
    let arg = |i: usize, default: u32| u64::from(args.get(i).copied().unwrap_or(default));
    let quads = |vertices: u64, faces: u64| ShapeSize {
        vertices,
        faces,
        corners: faces.saturating_mul(4),
    };
    let grid_size = |nx: u64, ny: u64| (nx.max(1), ny.max(1));
    Some(match shape {
        "tetrahedron" | "cube" | "icosahedron" => quads(12, 20),
        "icosphere" => {
            let split = 4u64.saturating_pow(arg(0, 3).min(64) as u32);
            ShapeSize {
                vertices: split.saturating_mul(10).saturating_add(2),
                faces: split.saturating_mul(20),
                corners: split.saturating_mul(60),
            }
        }
        "torus" => {
            let cells = arg(0, 24).max(3).saturating_mul(arg(1, 12).max(3));
            quads(cells, cells)
        }
        "grid" | "quad-grid" => {
            let nx = arg(0, 10);
            let (nx, ny) = grid_size(nx, args.get(1).map_or(nx, |&n| u64::from(n)));
            let vertices = (nx + 1).saturating_mul(ny + 1);
            let cells = nx.saturating_mul(ny);
            if shape == "grid" {
                ShapeSize {
                    vertices,
                    faces: cells.saturating_mul(2),
                    corners: cells.saturating_mul(6),
                }
            } else {
                quads(vertices, cells)
            }
        }
        "grid-with-holes" | "slab" => {
            let k = arg(0, 2);
            let cells = k.saturating_mul(2).saturating_add(1).saturating_mul(6);
            quads(cells.saturating_mul(2), cells.saturating_mul(2))
        }
        "double-torus" => quads(64, 64),
        _ => return None,
    })
}

/// The names [`by_name`] knows.
pub const SHAPE_NAMES: [&str; 9] = [
    "tetrahedron",
    "cube",
    "icosahedron",
    "icosphere",
    "torus",
    "grid",
    "quad-grid",
    "grid-with-holes",
    "double-torus",
];

#[cfg(test)]
mod tests {
    use super::*;

    /// The sizes checked before a shape is made are the sizes of the shape made (the
    /// placeholders for the fixed shapes only bound them).
    #[test]
    fn sizes_are_counted_before_the_shape_is_made() {
        for name in [
            "icosphere:2",
            "torus:7:5",
            "grid:4:3",
            "quad-grid:6",
            "grid:0",
            "torus:1:1",
        ] {
            let (shape, args) = parse_name(name).unwrap();
            let size = shape_size(shape, &args).unwrap();
            let soup = by_name(name).unwrap();
            assert_eq!(
                (size.vertices, size.faces, size.corners),
                (
                    soup.positions.len() as u64,
                    soup.face_count() as u64,
                    soup.indices.len() as u64
                ),
                "{name}"
            );
        }
        for name in ["grid-with-holes:3", "slab:3", "double-torus", "cube"] {
            let (shape, args) = parse_name(name).unwrap();
            let size = shape_size(shape, &args).unwrap();
            let soup = by_name(name).unwrap();
            assert!(size.faces >= soup.face_count() as u64, "{name}");
            assert!(size.corners >= soup.indices.len() as u64, "{name}");
        }
    }

    /// Sizes that would wrap 32 bits, or pass the memory, are refused before anything is
    /// made; a bad size is an unknown name.
    #[test]
    fn huge_sizes_are_refused_up_front() {
        for name in [
            "grid:100000",
            "torus:100000:100000",
            "quad-grid:4294967295",
            "icosphere:40",
        ] {
            let err = check_name(name).unwrap_err();
            assert!(matches!(err, ShapeError::TooLarge { .. }), "{name}: {err}");
            assert!(err.to_string().starts_with(&format!("shape `{name}`: ")));
        }
        assert_eq!(
            check_name("grid:100000").unwrap_err().to_string(),
            "shape `grid:100000`: 20000000000 faces with 60000000000 corners, more than a mesh \
             may have (2^31 corners)"
        );
        // Within 2^31 corners, beyond this machine's memory: the budget's reason.
        let err = check_name("grid:10000").unwrap_err().to_string();
        assert!(
            err.starts_with(
                "shape `grid:10000`: it would make 200 M faces, about 137 GB; the budget is "
            ),
            "{err}"
        );
        for name in ["sphere", "grid:-1", "grid:x", "torus:99999999999"] {
            assert!(
                matches!(check_name(name), Err(ShapeError::Unknown(_))),
                "{name}"
            );
        }
    }
}

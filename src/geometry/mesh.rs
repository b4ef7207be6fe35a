//! Triangle meshes as files hold them: STL (binary and ASCII), COLLADA and Wavefront OBJ, parsed
//! by the `mesh-loader` crate → exact f32 vertices, welded, with three indices per triangle.
//! [`read_mesh`] is the one place a mesh file is read.

use std::borrow::Cow;
use std::collections::HashMap;
use std::path::Path;

use super::claims::{self, Format};
use crate::error::{Error, Result, one_line};
use crate::input::{MAX_MESH_BYTES, MAX_SIDE_FILE_BYTES, read_file_capped};

/// An indexed triangle mesh: the file's exact f32 vertices (metres, in the mesh's own frame),
/// identical positions welded into one vertex, and three vertex indices per triangle.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct Mesh {
    /// Distinct vertex positions (m).
    pub vertices: Vec<[f32; 3]>,
    /// Three indices into `vertices` per triangle; no triangle repeats an index.
    pub triangles: Vec<[u32; 3]>,
}

impl Mesh {
    /// Indexes a triangle soup (three corners per triangle): bit-identical positions become one
    /// vertex (`-0.0` and `0.0` are the same point), and triangles whose corners weld together
    /// (zero area by repetition) are dropped. Coordinates are kept exactly.
    pub fn from_soup(corners: &[[f32; 3]]) -> Mesh {
        let key = |p: &[f32; 3]| [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits(), (p[2] + 0.0).to_bits()];
        let mut welded: HashMap<[u32; 3], u32> = HashMap::with_capacity(corners.len() / 3);
        let mut mesh = Mesh {
            vertices: Vec::with_capacity(corners.len() / 3),
            triangles: Vec::with_capacity(corners.len() / 3),
        };
        for c in corners.chunks_exact(3) {
            let t = [0, 1, 2].map(|k| {
                *welded.entry(key(&c[k])).or_insert_with(|| {
                    mesh.vertices.push(c[k]);
                    (mesh.vertices.len() - 1) as u32
                })
            });
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                mesh.triangles.push(t);
            }
        }
        mesh
    }

    /// The built-in Faze4 mesh `name` as the collision loader reads it ([`Mesh::from_indexed`]):
    /// its points (m) and triangles, as `build.rs` makes its hierarchy and hulls of them.
    #[cfg(test)]
    pub(super) fn built_in(name: &str) -> (Vec<parry3d_f64::math::Vector>, Vec<[u32; 3]>) {
        let m = crate::faze4::meshes::mesh(name).expect("built in");
        let mesh = Mesh::from_indexed(&m.positions, &m.indices);
        let points = (mesh.vertices.iter())
            .map(|v| parry3d_f64::math::Vector::from_array(v.map(f64::from)))
            .collect();
        (points, mesh.triangles)
    }

    /// [`Mesh::from_soup`] of the triangles of an indexed mesh (`indices`: three per triangle
    /// into `positions`) without writing the soup out: the same vertices in the same order and
    /// the same triangles, with one weld lookup per position instead of one per corner.
    pub fn from_indexed(positions: &[[f32; 3]], indices: &[u32]) -> Mesh {
        let key = |p: &[f32; 3]| [(p[0] + 0.0).to_bits(), (p[1] + 0.0).to_bits(), (p[2] + 0.0).to_bits()];
        let mut welded: HashMap<[u32; 3], u32> = HashMap::with_capacity(positions.len());
        // each position's vertex, once first used
        let mut vertex_of = vec![u32::MAX; positions.len()];
        let mut mesh = Mesh {
            vertices: Vec::with_capacity(positions.len()),
            triangles: Vec::with_capacity(indices.len() / 3),
        };
        for t in indices.chunks_exact(3) {
            let t = [0, 1, 2].map(|k| {
                let i = t[k] as usize;
                if vertex_of[i] == u32::MAX {
                    vertex_of[i] = *welded.entry(key(&positions[i])).or_insert_with(|| {
                        mesh.vertices.push(positions[i]);
                        (mesh.vertices.len() - 1) as u32
                    });
                }
                vertex_of[i]
            });
            if t[0] != t[1] && t[1] != t[2] && t[0] != t[2] {
                mesh.triangles.push(t);
            }
        }
        mesh
    }

    /// The triangle corners again, three per triangle (the soup this mesh indexes).
    pub fn soup(&self) -> Vec<[f32; 3]> {
        (self.triangles.iter())
            .flat_map(|t| t.map(|i| self.vertices[i as usize]))
            .collect()
    }
}

/// A colour: red, green, blue, alpha in [0, 1].
pub type Rgba = [f32; 4];

/// A mesh file as read: its triangles as a welded [`Mesh`], and the colour its first material
/// gives (diffuse RGBA, COLLADA `<effect>` or OBJ `.mtl` `Kd`/`d`), if any.
#[derive(Clone, Debug, Default, PartialEq)]
pub struct MeshFile {
    /// The triangles (metres, in the mesh's own frame: COLLADA's `<unit meter>` applied).
    pub mesh: Mesh,
    /// Diffuse colour of the file's first material that has one.
    pub color: Option<Rgba>,
}

/// The formats [`read_mesh`] reads, named as in its errors.
pub const FORMATS: &str = "STL (binary or ASCII), COLLADA (.dae) or Wavefront OBJ (.obj)";

/// Reads the mesh file at `path` (STL binary or ASCII, COLLADA `.dae`, Wavefront `.obj`) into a
/// welded indexed [`Mesh`]. Every mesh faze4 uses, for drawing or for distances, is read here.
/// It reads no other file (an OBJ's `mtllib` is left out: [`read_mesh_file`] reads it).
///
/// The files are parsed by the `mesh-loader` crate; the format follows the extension (any
/// case), else the contents. A file of several meshes (COLLADA geometries, OBJ groups) is their
/// union. COLLADA's `<unit meter>` scales the vertices and its node transforms place them, and
/// its `<up_axis>` is ignored, as rviz and MoveIt do (see docs/model.md, "Meshes"). The file
/// must be a regular file of at most [`MAX_MESH_BYTES`], and what it claims is checked against
/// what it holds before mesh-loader reads it (`geometry/claims.rs`).
///
/// Errors: [`Error::Io`] if the file cannot be read, [`Error::InvalidData`] if it is none of
/// those formats, too large, a directory or a stream, [`Error::MeshNotFinite`] for a NaN or
/// infinite coordinate, [`Error::MeshEmpty`] if no triangle of non-zero extent remains.
pub fn read_mesh(path: &Path) -> Result<Mesh> {
    let bytes = read_file_capped(path, MAX_MESH_BYTES, "a mesh file")?;
    parse_mesh(&bytes, path)
}

/// [`read_mesh`], with the file's material colour. An OBJ's `mtllib` is read from beside it
/// only if, links resolved, it lies in the OBJ's folder (or below) and is a regular file of at
/// most [`MAX_SIDE_FILE_BYTES`]; else (or missing) the colour is left out.
pub fn read_mesh_file(path: &Path) -> Result<MeshFile> {
    let bytes = read_file_capped(path, MAX_MESH_BYTES, "a mesh file")?;
    parse_mesh_file(&bytes, path, |side: &Path| side_file(path, side))
}

/// The file `side` that the mesh file `mesh` refers to (an OBJ's `.mtl`), if it lies in the
/// mesh's folder once links are resolved and is a regular file of at most
/// [`MAX_SIDE_FILE_BYTES`].
fn side_file(mesh: &Path, side: &Path) -> std::io::Result<Vec<u8>> {
    let folder = match mesh.parent() {
        Some(d) if !d.as_os_str().is_empty() => d,
        _ => Path::new("."),
    };
    let (folder, side) = (std::fs::canonicalize(folder)?, std::fs::canonicalize(side)?);
    if !side.starts_with(&folder) {
        return Err(std::io::Error::new(
            std::io::ErrorKind::PermissionDenied,
            "outside the mesh's folder",
        ));
    }
    read_file_capped(&side, MAX_SIDE_FILE_BYTES, "a material file").map_err(|e| std::io::Error::other(e.to_string()))
}

/// The mesh a URDF mesh reference stands for, with its colour, for drawing: the file it
/// resolved to (`path`), read by [`read_mesh_file`], else the copy built into the binary when
/// `uri` names one of the official Faze4 meshes ([`crate::faze4::meshes::for_uri`]) and
/// `built_in` (the geometry's [`super::GeometryModel::built_in_meshes`]); `None` when there is
/// neither. Every visual mesh is loaded here.
pub fn load(uri: &str, path: Option<&Path>, built_in: bool) -> Option<Result<MeshFile>> {
    match origin(uri, path, built_in) {
        Origin::File(path) => Some(read_mesh_file(path)),
        Origin::BuiltIn => built_in_copy(uri).map(|mesh| Ok(MeshFile { mesh, color: None })),
        Origin::NotFound => None,
    }
}

/// [`load`] for collision: the triangles only, so no side file is read ([`read_mesh`]), with
/// what identifies them for a cache of what is made of them ([`Contents`]). Every collision
/// mesh is loaded here.
pub fn load_shape(uri: &str, path: Option<&Path>, built_in: bool) -> Option<Result<(Mesh, Contents)>> {
    match origin(uri, path, built_in) {
        Origin::File(path) => Some((|| {
            let bytes = read_file_capped(path, MAX_MESH_BYTES, "a mesh file")?;
            let mesh = parse_mesh(&bytes, path)?;
            Ok((mesh, Contents::File(contents_hash(&bytes))))
        })()),
        Origin::BuiltIn => Some(Ok((
            built_in_copy(uri)?,
            Contents::BuiltIn(crate::faze4::meshes::name_of(uri)?),
        ))),
        Origin::NotFound => None,
    }
}

/// What a collision mesh's triangles were read from, as a cache of what is made of them
/// (`mesh_cache.rs`) tells meshes apart.
#[derive(Clone, Copy, Debug, PartialEq, Eq, Hash)]
pub enum Contents {
    /// A file, by a 128-bit hash of its bytes (two SipHash-1-3 of them, std's
    /// `DefaultHasher`, under two prefixes) and its length.
    File([u64; 3]),
    /// The built-in Faze4 mesh of this link.
    BuiltIn(&'static str),
}

/// The hash of a mesh file's bytes that [`Contents::File`] holds.
pub fn contents_hash(bytes: &[u8]) -> [u64; 3] {
    use std::hash::{Hash, Hasher};
    let hash = |prefix: &str| {
        let mut h = std::collections::hash_map::DefaultHasher::new();
        prefix.hash(&mut h);
        bytes.hash(&mut h);
        h.finish()
    };
    [hash("faze4 mesh a"), hash("faze4 mesh b"), bytes.len() as u64]
}

/// The built-in copy of the official Faze4 mesh `uri` names, if any.
fn built_in_copy(uri: &str) -> Option<Mesh> {
    crate::faze4::meshes::for_uri(uri).map(|mesh| Mesh::from_indexed(&mesh.positions, &mesh.indices))
}

/// Where [`load`] takes a mesh reference's triangles from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Origin<'a> {
    /// The file the reference resolved to.
    File(&'a Path),
    /// The copy of an official Faze4 mesh built into the binary (no file found).
    BuiltIn,
    /// Nowhere: the mesh is left out (its link's clearance is not checked, its view not drawn).
    NotFound,
}

/// Where the mesh reference `uri`, resolved to `path` (if a file was found), is loaded from,
/// without reading it: the file, else the built-in Faze4 copy when `built_in` (a bundled
/// description's geometry), else nowhere.
pub fn origin<'a>(uri: &str, path: Option<&'a Path>, built_in: bool) -> Origin<'a> {
    match path {
        Some(path) => Origin::File(path),
        None if built_in && crate::faze4::meshes::is_built_in(uri) => Origin::BuiltIn,
        None => Origin::NotFound,
    }
}

/// [`read_mesh`] on a file's contents already in memory; `path` names it in errors and gives
/// its format by extension. Reads no other file (an OBJ's `mtllib` is left out).
pub fn parse_mesh(bytes: &[u8], path: &Path) -> Result<Mesh> {
    Ok(parse_mesh_file(bytes, path, no_side_files)?.mesh)
}

/// The side-file reader that reads none.
fn no_side_files(p: &Path) -> std::io::Result<Vec<u8>> {
    Err(std::io::Error::new(
        std::io::ErrorKind::NotFound,
        p.display().to_string(),
    ))
}

/// [`read_mesh_file`] on contents in memory; `side_file` reads the files it refers to (an OBJ's
/// `.mtl`).
fn parse_mesh_file(
    bytes: &[u8],
    path: &Path,
    side_file: impl FnMut(&Path) -> std::io::Result<Vec<u8>>,
) -> Result<MeshFile> {
    let (soup, color) = triangle_corners(bytes, path, side_file).map_err(|message| Error::InvalidData {
        path: path.to_path_buf(),
        message,
    })?;
    if let Some(i) = soup.iter().position(|p| p.iter().any(|c| !c.is_finite())) {
        return Err(Error::MeshNotFinite {
            path: path.to_path_buf(),
            triangle: i / 3,
        });
    }
    let mesh = Mesh::from_soup(&soup);
    if mesh.triangles.is_empty() {
        return Err(Error::MeshEmpty {
            path: path.to_path_buf(),
        });
    }
    Ok(MeshFile { mesh, color })
}

/// The triangle corners of a mesh file's contents (three per triangle, every mesh of the file
/// in its order, each triangle as stored, degenerate ones included; non-finite coordinates are
/// passed through, see [`parse_mesh`]), and the diffuse colour of its first material that has
/// one. What the file claims is checked first (`geometry/claims.rs`). The error is one line.
pub fn triangle_corners(
    bytes: &[u8],
    path: &Path,
    side_file: impl FnMut(&Path) -> std::io::Result<Vec<u8>>,
) -> std::result::Result<(Vec<[f32; 3]>, Option<Rgba>), String> {
    let loader = mesh_loader::Loader::default();
    let named = Format::of_extension(path.extension().and_then(|e| e.to_str()));
    let format = named.or_else(|| Format::of_contents(bytes)).ok_or_else(|| {
        format!("not a mesh faze4 reads ({FORMATS}): its name does not end in .stl, .dae or .obj, and its contents are neither STL nor COLLADA")
    })?;
    let unnamed = |message: String| match named {
        Some(_) => message,
        None => format!("not a mesh faze4 reads ({FORMATS}): {message}"),
    };
    // COLLADA and OBJ as mesh-loader decodes them, so that what is checked is what it reads
    let bytes = match format {
        Format::Stl => Cow::Borrowed(bytes),
        Format::Collada | Format::Obj => claims::decode_text(bytes).map_err(unnamed)?,
    };
    claims::check(format, &bytes).map_err(unnamed)?;
    // mesh-loader panics on some malformed COLLADA files (fuzz/artifacts of mesh_file): a panic
    // is caught, unprinted, and reported as the file's one-line error
    let scene = crate::model::urdf::quietly(std::panic::AssertUnwindSafe(|| match format {
        Format::Stl => loader.load_stl_from_slice(&bytes, path),
        Format::Collada => loader.load_collada_from_slice(&bytes, path),
        Format::Obj => loader.load_obj_from_slice_with_reader(&bytes, path, side_file),
    }))
    .map_err(|panic| format!("the mesh reader (mesh-loader) failed on this file: {panic}"))?
    .map_err(|e| unnamed(one_line(&e.to_string())))?;
    let mut soup = Vec::new();
    for mesh in &scene.meshes {
        for face in &mesh.faces {
            for &i in face {
                let corner = mesh.vertices.get(i as usize).ok_or_else(|| {
                    format!(
                        "mesh '{}': a face refers to vertex {i} of {}",
                        mesh.name,
                        mesh.vertices.len()
                    )
                })?;
                soup.push(*corner);
            }
        }
    }
    let color = scene.materials.iter().find_map(|m| m.color.diffuse);
    Ok((soup, color))
}

#[cfg(test)]
pub(crate) mod tests {
    use super::*;

    /// A unit cube centred on the origin as 12 triangles (36 corners), outward winding.
    pub(crate) fn cube_soup() -> Vec<[f32; 3]> {
        let mut soup = Vec::new();
        for (axis, sign) in [(0, 1.0f32), (0, -1.0), (1, 1.0), (1, -1.0), (2, 1.0), (2, -1.0)] {
            let (u, w) = ((axis + 1) % 3, (axis + 2) % 3);
            let corner = |a: f32, b: f32| {
                let mut p = [0.0; 3];
                p[axis] = sign * 0.5;
                p[u] = a * 0.5 * sign;
                p[w] = b * 0.5;
                p
            };
            let q = [
                corner(-1.0, -1.0),
                corner(1.0, -1.0),
                corner(1.0, 1.0),
                corner(-1.0, 1.0),
            ];
            soup.extend([q[0], q[1], q[2], q[0], q[2], q[3]]);
        }
        soup
    }

    pub(crate) fn binary_stl(soup: &[[f32; 3]], header: &[u8]) -> Vec<u8> {
        let mut b = vec![0u8; 80];
        b[..header.len()].copy_from_slice(header);
        b.extend((soup.len() as u32 / 3).to_le_bytes());
        for t in soup.chunks(3) {
            b.extend([0u8; 12]); // facet normal, ignored
            for p in t {
                for c in p {
                    b.extend(c.to_le_bytes());
                }
            }
            b.extend([0u8; 2]);
        }
        b
    }

    fn ascii_stl(soup: &[[f32; 3]]) -> String {
        let mut s = String::from("solid cube\n");
        for t in soup.chunks(3) {
            s += "  facet normal 0 0 0\n    outer loop\n";
            for p in t {
                s += &format!("      vertex {:e} {} {}\n", p[0], p[1], p[2]);
            }
            s += "    endloop\n  endfacet\n";
        }
        s + "endsolid cube\n"
    }

    #[test]
    fn binary_and_ascii_stl_give_the_same_welded_cube() {
        let soup = cube_soup();
        let here = Path::new("cube.stl");
        // a binary file whose header starts with "solid", as SolidWorks writes them
        let bin = parse_mesh(&binary_stl(&soup, b"solid SolidWorks export"), here).unwrap();
        let txt = parse_mesh(ascii_stl(&soup).as_bytes(), here).unwrap();
        assert_eq!(bin, txt);
        assert_eq!(bin.vertices.len(), 8, "each corner welded once");
        assert_eq!(bin.triangles.len(), 12);
        assert_eq!(bin.soup(), soup, "exact coordinates, same order");
    }

    #[test]
    fn welding_drops_collapsed_triangles_and_merges_signed_zeros() {
        let soup = [
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [-0.0, 0.0, 0.0],
            [0.0, 0.0, 0.0],
            [1.0, 0.0, 0.0],
            [0.0, 1.0, 0.0],
        ];
        let mesh = Mesh::from_soup(&soup);
        assert_eq!(mesh.vertices.len(), 3);
        assert_eq!(mesh.triangles, vec![[0, 1, 2]]);
    }

    #[test]
    fn malformed_stl_is_refused_with_a_reason() {
        let here = Path::new("bad.stl");
        let e = parse_mesh(b"hello", here).unwrap_err().to_string();
        assert!(e.starts_with("bad.stl: "), "{e}");
        let text = b"solid x\n facet normal 0 0 1\n outer loop\n vertex 0 0 0\n vertex 1 0 zero\n";
        let e = parse_mesh(text, here).unwrap_err().to_string();
        assert!(e.starts_with("bad.stl: ") && !e.contains('\n'), "{e}");
        let e = parse_mesh(b"hello", Path::new("bad.xyz")).unwrap_err().to_string();
        assert!(e.contains("not a mesh faze4 reads (STL"), "{e}");
        let mut bin = binary_stl(&cube_soup(), b"");
        bin[84 + 50 + 12..84 + 50 + 16].copy_from_slice(&f32::NAN.to_le_bytes());
        assert!(matches!(
            parse_mesh(&bin, here),
            Err(Error::MeshNotFinite { triangle: 1, .. })
        ));
        assert!(matches!(
            parse_mesh(b"solid empty\nendsolid empty\n", here),
            Err(Error::MeshEmpty { .. })
        ));
        let collapsed = binary_stl(&[[1.0, 2.0, 3.0]; 3], b"");
        assert!(matches!(parse_mesh(&collapsed, here), Err(Error::MeshEmpty { .. })));
    }

    /// The cube of [`cube_soup`] as COLLADA text: one `<geometry>` of 8 positions and 12
    /// triangles, placed by a node `<matrix>`, with a material of diffuse colour (0.1, 0.2,
    /// 0.3, 1) and the given `<unit meter>` and `<up_axis>`.
    pub(crate) fn collada_cube(unit: &str, up_axis: &str, matrix: &str) -> String {
        let mesh = Mesh::from_soup(&cube_soup());
        let positions: Vec<String> = mesh.vertices.iter().flatten().map(|c| c.to_string()).collect();
        let indices: Vec<String> = mesh.triangles.iter().flatten().map(|i| i.to_string()).collect();
        format!(
            r##"<?xml version="1.0" encoding="utf-8"?>
<COLLADA xmlns="http://www.collada.org/2005/11/COLLADASchema" version="1.4.1">
  <asset><unit name="u" meter="{unit}"/><up_axis>{up_axis}</up_axis></asset>
  <library_effects><effect id="paint"><profile_COMMON><technique sid="common"><phong>
    <diffuse><color>0.1 0.2 0.3 1</color></diffuse>
  </phong></technique></profile_COMMON></effect></library_effects>
  <library_materials><material id="paint-material" name="paint"><instance_effect url="#paint"/></material></library_materials>
  <library_geometries><geometry id="cube" name="cube"><mesh>
    <source id="cube-positions"><float_array id="cube-positions-array" count="{np}">{positions}</float_array>
      <technique_common><accessor source="#cube-positions-array" count="{nv}" stride="3">
        <param name="X" type="float"/><param name="Y" type="float"/><param name="Z" type="float"/>
      </accessor></technique_common></source>
    <vertices id="cube-vertices"><input semantic="POSITION" source="#cube-positions"/></vertices>
    <triangles material="paint" count="{nt}"><input semantic="VERTEX" source="#cube-vertices" offset="0"/><p>{indices}</p></triangles>
  </mesh></geometry></library_geometries>
  <library_visual_scenes><visual_scene id="scene" name="scene">
    <node id="part" name="part"><matrix sid="transform">{matrix}</matrix>
      <instance_geometry url="#cube"><bind_material><technique_common>
        <instance_material symbol="paint" target="#paint-material"/>
      </technique_common></bind_material></instance_geometry>
    </node>
  </visual_scene></library_visual_scenes>
  <scene><instance_visual_scene url="#scene"/></scene>
</COLLADA>
"##,
            np = positions.len(),
            positions = positions.join(" "),
            nv = mesh.vertices.len(),
            nt = mesh.triangles.len(),
            indices = indices.join(" "),
        )
    }

    const IDENTITY: &str = "1 0 0 0 0 1 0 0 0 0 1 0 0 0 0 1";

    #[test]
    fn collada_gives_the_stl_cube_with_its_unit_and_colour() {
        let here = Path::new("cube.DAE");
        let stl = parse_mesh(&binary_stl(&cube_soup(), b""), Path::new("cube.stl")).unwrap();
        let dae = collada_cube("1", "Z_UP", IDENTITY);
        let (soup, color) = triangle_corners(dae.as_bytes(), here, |p: &Path| std::fs::read(p)).unwrap();
        assert_eq!(Mesh::from_soup(&soup), stl, "same vertices, same triangles");
        assert_eq!(color, Some([0.1, 0.2, 0.3, 1.0]));
        // millimetres: every coordinate × 0.001 (as rviz does with <unit meter>)
        let mm = parse_mesh(collada_cube("0.001", "Z_UP", IDENTITY).as_bytes(), here).unwrap();
        for (a, b) in mm.vertices.iter().zip(&stl.vertices) {
            for k in 0..3 {
                assert!((a[k] - b[k] * 0.001).abs() <= 1e-9, "{a:?} vs {b:?}");
            }
        }
        // <up_axis> Y_UP is ignored, as rviz and MoveIt ignore it: no rotation
        let y_up = parse_mesh(collada_cube("1", "Y_UP", IDENTITY).as_bytes(), here).unwrap();
        assert_eq!(y_up, stl);
        // a node's matrix places the geometry (row-major, translation in the last column)
        let moved = parse_mesh(
            collada_cube("1", "Z_UP", "1 0 0 2 0 1 0 0 0 0 1 0 0 0 0 1").as_bytes(),
            here,
        )
        .unwrap();
        assert!(
            moved.vertices.iter().all(|p| p[0] == 1.5 || p[0] == 2.5),
            "{:?}",
            moved.vertices
        );
        let e = parse_mesh(b"<COLLADA><broken", here).unwrap_err().to_string();
        assert!(e.starts_with("cube.DAE: ") && !e.contains('\n'), "{e}");
    }

    /// An OBJ's `mtllib` gives the colour only from the OBJ's folder (links resolved), never
    /// from outside it, and is not read for the triangles alone.
    #[test]
    fn an_objs_material_file_is_read_from_its_folder_only() {
        let dir = std::env::temp_dir().join(format!("faze4-mtl-{}", std::process::id()));
        std::fs::create_dir_all(dir.join("in")).unwrap();
        let mtl = "newmtl paint\nKd 0.1 0.2 0.3\n";
        std::fs::write(dir.join("in/ok.mtl"), mtl).unwrap();
        std::fs::write(dir.join("out.mtl"), mtl).unwrap();
        std::os::unix::fs::symlink(dir.join("out.mtl"), dir.join("in/link.mtl")).unwrap();
        let obj = |lib: &str| format!("mtllib {lib}\nv 0 0 0\nv 1 0 0\nv 0 1 0\nusemtl paint\nf 1 2 3\n");
        for (lib, colour) in [
            ("ok.mtl", Some([0.1, 0.2, 0.3, 1.0])),
            ("../out.mtl", None),
            (dir.join("out.mtl").to_str().unwrap(), None),
            ("link.mtl", None),
        ] {
            let path = dir.join("in/m.obj");
            std::fs::write(&path, obj(lib)).unwrap();
            assert_eq!(read_mesh_file(&path).unwrap().color, colour, "mtllib {lib}");
            assert_eq!(read_mesh(&path).unwrap().triangles.len(), 1);
        }
        std::fs::remove_dir_all(&dir).unwrap();
    }

    #[test]
    fn obj_groups_make_one_mesh_with_the_stl_vertices() {
        let stl = parse_mesh(&binary_stl(&cube_soup(), b""), Path::new("cube.stl")).unwrap();
        // the cube in two groups (faces 1-based, two per quad), as OBJ exporters write it
        let mut obj = String::from("# cube\n");
        for v in &stl.vertices {
            obj += &format!("v {} {} {}\n", v[0], v[1], v[2]);
        }
        for (k, t) in stl.triangles.iter().enumerate() {
            if k % 6 == 0 {
                obj += &format!("g part{}\n", k / 6);
            }
            obj += &format!("f {} {} {}\n", t[0] + 1, t[1] + 1, t[2] + 1);
        }
        let mesh = parse_mesh(obj.as_bytes(), Path::new("cube.obj")).unwrap();
        assert_eq!(mesh.triangles.len(), 12);
        assert_eq!(mesh.soup(), stl.soup(), "same triangles in the same order");
    }
}

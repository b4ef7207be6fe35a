//! Each collision mesh's bounding-volume hierarchy, made once: the Faze4's built-in meshes carry
//! theirs in the binary (made by `build.rs`), and any other mesh's is kept in the user's cache
//! folder, `$XDG_CACHE_HOME/faze4/bvh/` (else `~/.cache/faze4/bvh/`), one file per mesh file
//! contents and scale.
//!
//! A cache file is named by a hash of the mesh file's bytes, its `<mesh scale>` and
//! [`FORMAT`], so an edited mesh file, another scale or another faze4 format of the file is a
//! different entry: nothing is ever invalidated in place, and old entries can be deleted at
//! any time (`rm -r ~/.cache/faze4`). Whatever a file holds, it is used only when it is a sound
//! hierarchy of exactly the mesh's triangles ([`Bvh::from_bytes`] checks every box against its
//! children and triangles), so a stale, truncated or foreign file costs a rebuild, never a wrong
//! distance. A cache that cannot be read or written (no home folder, a read-only disk) is not
//! an error: the hierarchy is built for the run, as it would be the first time.
//!
//! The built-in meshes also carry their upper nodes' convex hulls (`node_hulls.rs`), made by
//! `build.rs` of the very triangles the binary carries with the same code, so read with their
//! indices checked only; other meshes' are made at their first use, not cached.

use std::hash::{Hash, Hasher};
use std::path::PathBuf;

use parry3d_f64::math::Vector as PVector;

use super::bvh::Bvh;
use super::mesh::Contents;
use super::node_hulls::NodeHulls;
use super::triangles::arrays;

/// The version of the cache's file format (and of the hierarchy's layout): part of every
/// entry's name.
pub const FORMAT: u32 = 1;

/// Where a mesh's hierarchy came from.
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Made {
    /// Carried in the binary (a built-in Faze4 mesh).
    BuiltIn,
    /// Read from the user's cache.
    Cached,
    /// Built now (and stored in the cache when it could be).
    Built,
}

/// The hierarchy of the triangles `triangles` (indices into `points`, m, scaled) of the mesh
/// read from `contents` at `scale` (its bits), as made before when it was, else built now and
/// stored in the cache (see the module documentation), and its nodes' hulls: a built-in
/// mesh's as `build.rs` made them, any other's to be made at their first use.
pub(super) fn hierarchy(
    contents: Contents,
    scale: [u64; 3],
    points: &[PVector],
    triangles: &[[u32; 3]],
) -> (Bvh, NodeHulls, Made) {
    hierarchy_in(folder(), contents, scale, points, triangles)
}

/// [`hierarchy`] with the cache in `folder` (`None`: no cache).
fn hierarchy_in(
    folder: Option<PathBuf>,
    contents: Contents,
    scale: [u64; 3],
    points: &[PVector],
    triangles: &[[u32; 3]],
) -> (Bvh, NodeHulls, Made) {
    // the points as the hierarchy takes them (f64 arrays), made once for whichever path below
    let point_arrays = arrays(points);
    if let Contents::BuiltIn(name) = contents
        && scale == [1.0f64.to_bits(); 3]
        && let Some(bytes) = crate::faze4::meshes::hierarchy(name)
        && let Some((bvh, rest)) = Bvh::from_bytes(bytes, &point_arrays, triangles)
        && let Some(hulls) = NodeHulls::from_bytes(rest, &bvh, points)
    {
        return (bvh, hulls, Made::BuiltIn);
    }
    let file = folder.map(|dir| dir.join(entry(contents, scale)));
    if let Some(file) = &file
        && let Ok(bytes) = std::fs::read(file)
        && let Some((bvh, [])) = Bvh::from_bytes(&bytes, &point_arrays, triangles)
    {
        let hulls = NodeHulls::new(&bvh);
        return (bvh, hulls, Made::Cached);
    }
    let bvh = Bvh::build(&point_arrays, triangles);
    if let Some(file) = file {
        store(&file, &bvh.to_bytes());
    }
    let hulls = NodeHulls::new(&bvh);
    (bvh, hulls, Made::Built)
}

/// The cache's folder: `$XDG_CACHE_HOME/faze4/bvh`, else `$HOME/.cache/faze4/bvh` (an empty or
/// relative `XDG_CACHE_HOME` is ignored, as the XDG specification asks); `None` without either.
pub fn folder() -> Option<PathBuf> {
    let xdg = std::env::var_os("XDG_CACHE_HOME").map(PathBuf::from);
    let base = match xdg.filter(|p| p.is_absolute()) {
        Some(dir) => dir,
        None => PathBuf::from(std::env::var_os("HOME").filter(|h| !h.is_empty())?).join(".cache"),
    };
    Some(base.join("faze4").join("bvh"))
}

/// The file name of the entry of a mesh read from `contents` at `scale`.
fn entry(contents: Contents, scale: [u64; 3]) -> String {
    let mut h = std::collections::hash_map::DefaultHasher::new();
    (FORMAT, contents, scale).hash(&mut h);
    let key = h.finish();
    match contents {
        Contents::File([a, b, len]) => format!("{a:016x}{b:016x}-{len}-{key:016x}.bvh"),
        Contents::BuiltIn(name) => format!("{name}-{key:016x}.bvh"),
    }
}

/// Writes `bytes` to `file` whole or not at all (a temporary file renamed into place), its
/// folder made first; any failure leaves the cache as it was.
fn store(file: &std::path::Path, bytes: &[u8]) {
    let Some(dir) = file.parent() else {
        return;
    };
    let temporary = dir.join(format!(
        ".{}.{}",
        std::process::id(),
        file.file_name().map_or("", |n| n.to_str().unwrap_or(""))
    ));
    let written = std::fs::create_dir_all(dir)
        .and_then(|_| std::fs::write(&temporary, bytes))
        .and_then(|_| std::fs::rename(&temporary, file));
    if written.is_err() {
        let _ = std::fs::remove_file(&temporary);
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::geometry::mesh::{Mesh, contents_hash};

    #[test]
    fn the_built_in_meshes_carry_the_hierarchy_built_of_their_triangles() {
        for name in crate::faze4::meshes::names() {
            let (points, triangles) = Mesh::built_in(name);
            let (bvh, _, made) = hierarchy_in(
                None,
                Contents::BuiltIn(name),
                [1.0f64.to_bits(); 3],
                &points,
                &triangles,
            );
            assert_eq!(made, Made::BuiltIn, "{name}: build.rs's triangles are the loader's");
            // the same tree as built here, its inner boxes rounded outwards to f32
            let (again, _) = Bvh::from_bytes(
                &Bvh::build(&arrays(&points), &triangles).to_bytes(),
                &arrays(&points),
                &triangles,
            )
            .unwrap();
            assert_eq!(bvh, again, "{name}");
            // at another scale it is built, not taken
            let (_, _, made) = hierarchy_in(
                None,
                Contents::BuiltIn(name),
                [2.0f64.to_bits(); 3],
                &points,
                &triangles,
            );
            assert_eq!(made, Made::Built);
        }
    }

    #[test]
    fn another_meshs_hierarchy_is_cached_by_contents_and_a_bad_entry_is_rebuilt() {
        let dir = std::env::temp_dir().join(format!("faze4-bvh-cache-{}", std::process::id()));
        let _ = std::fs::remove_dir_all(&dir);
        let (points, triangles) = Mesh::built_in("hvataljka");
        let contents = Contents::File(contents_hash(b"a mesh file"));
        let one = [1.0f64.to_bits(); 3];
        let get = |contents, points: &[PVector]| {
            let (bvh, _, made) = hierarchy_in(Some(dir.clone()), contents, one, points, &triangles);
            (bvh, made)
        };
        let (first, made) = get(contents, &points);
        assert_eq!(made, Made::Built);
        let (second, made) = get(contents, &points);
        assert_eq!((made, &second), (Made::Cached, &first));
        // another file's contents are another entry
        assert_eq!(get(Contents::File(contents_hash(b"another")), &points).1, Made::Built);
        // an entry that is not this mesh's hierarchy (the same contents hash, moved points: its
        // boxes no longer hold the triangles) is rebuilt, not used
        let moved: Vec<PVector> = points.iter().map(|p| *p + PVector::X * 0.01).collect();
        assert_eq!(get(contents, &moved).1, Made::Built);
        // a truncated entry
        let entry = dir.join(entry(contents, one));
        let bytes = std::fs::read(&entry).unwrap();
        std::fs::write(&entry, &bytes[..bytes.len() / 2]).unwrap();
        assert_eq!(get(contents, &points).1, Made::Built);
        assert_eq!(get(contents, &points).1, Made::Cached, "written again whole");
        // a cache that cannot be written: built, no error
        let file = dir.join("not a folder");
        std::fs::write(&file, b"").unwrap();
        let (bvh, _, made) = hierarchy_in(Some(file.join("bvh")), contents, one, &points, &triangles);
        assert_eq!((made, bvh), (Made::Built, first));
        std::fs::remove_dir_all(&dir).unwrap();
    }
}

//! The Faze4's collision meshes (or the binary STL files named) simplified at several bounds,
//! each with its one-sided distances to the original certified (`simplify.rs`): the tables of
//! docs/clearance.md, "Simplified meshes". From the repository root:
//!
//!     cargo run --release --manifest-path tools/simplify/Cargo.toml [-- [checked] ERROR… [FILE.stl…] [--out=DIR]]
//!
//! (errors in metres; `checked` uses our simplifier whose every collapse is checked against the
//! bound, `checked.rs`, else meshoptimizer's; `--out=DIR` writes each simplified mesh as
//! `DIR/<error in µm>um/<its file name>`, a binary STL). `cargo test --manifest-path
//! tools/simplify/Cargo.toml` checks the certified bounds against exact distances at many points.

#[allow(dead_code)]
#[path = "../../../src/geometry/bvh.rs"]
mod bvh;
mod checked;
mod simplify;

use bvh::Point;
use std::collections::HashMap;

const MESHES: &str = concat!(env!("CARGO_MANIFEST_DIR"), "/../../assets/faze4_description/meshes");

/// The binary STL at `path` as welded points (m) and triangles, degenerate ones dropped.
fn read_stl(path: &std::path::Path) -> (Vec<Point>, Vec<[u32; 3]>) {
    let bytes = std::fs::read(path).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
    let f32_at = |o: usize| f32::from_le_bytes(bytes[o..o + 4].try_into().unwrap());
    let count = u32::from_le_bytes(bytes[80..84].try_into().unwrap()) as usize;
    let mut index: HashMap<[u32; 3], u32> = HashMap::new();
    let (mut points, mut triangles) = (Vec::new(), Vec::new());
    for t in 0..count {
        let corner = |k: usize| {
            let o = 84 + 50 * t + 12 + 12 * k;
            [f32_at(o), f32_at(o + 4), f32_at(o + 8)]
        };
        let ids = [0, 1, 2].map(|k| {
            let p = corner(k);
            *index.entry(p.map(|c| (c + 0.0).to_bits())).or_insert_with(|| {
                points.push(p.map(f64::from));
                (points.len() - 1) as u32
            })
        });
        if ids[0] != ids[1] && ids[1] != ids[2] && ids[0] != ids[2] {
            triangles.push(ids);
        }
    }
    (points, triangles)
}

/// Writes the mesh as a binary STL at `path` (f32 coordinates: the read ones, unchanged).
fn write_stl(path: &std::path::Path, points: &[Point], triangles: &[[u32; 3]]) {
    let mut bytes = vec![0u8; 80];
    bytes.extend((triangles.len() as u32).to_le_bytes());
    for t in triangles {
        bytes.extend([0u8; 12]);
        for v in t {
            bytes.extend(points[*v as usize].iter().flat_map(|&c| (c as f32).to_le_bytes()));
        }
        bytes.extend([0u8; 2]);
    }
    std::fs::write(path, bytes).unwrap_or_else(|e| panic!("{}: {e}", path.display()));
}

fn main() {
    let args: Vec<String> = std::env::args().skip(1).collect();
    let checked = args.first().is_some_and(|a| a == "checked");
    let (mut errors, mut files, mut out) = (Vec::new(), Vec::new(), None);
    for a in &args[checked as usize..] {
        if let Some(dir) = a.strip_prefix("--out=") {
            out = Some(std::path::PathBuf::from(dir));
            continue;
        }
        match a.parse::<f64>() {
            Ok(e) => errors.push(e),
            Err(_) => files.push(std::path::PathBuf::from(a)),
        }
    }
    if errors.is_empty() {
        errors = vec![1e-4, 5e-5, 2e-5];
    }
    if files.is_empty() {
        files = std::fs::read_dir(MESHES).unwrap().map(|e| e.unwrap().path()).collect();
        files.sort();
    }
    let name = if checked {
        "bound ε (checked)"
    } else {
        "meshoptimizer's error"
    };
    println!("| {name} | mesh | triangles | kept | simplified → original | original → simplified | time |");
    println!("|---|---|---|---|---|---|---|");
    for error in errors {
        for file in &files {
            let (points, triangles) = read_stl(file);
            let name = file.file_stem().unwrap().to_string_lossy();
            let start = std::time::Instant::now();
            let s = if checked {
                Some(checked::certified(&points, &triangles, error))
            } else {
                simplify::simplify(&points, &triangles, error)
            };
            let time = start.elapsed().as_secs_f64();
            if let (Some(dir), Some(s)) = (&out, &s) {
                let dir = dir.join(format!("{:.0}um", error * 1e6));
                std::fs::create_dir_all(&dir).unwrap();
                write_stl(&dir.join(file.file_name().unwrap()), &s.points, &s.triangles);
            }
            match s {
                Some(s) => println!(
                    "| {:.0} µm | {name} | {} | {} ({:.0} %) | {:.4} mm | {:.4} mm | {time:.2} s |",
                    error * 1e6,
                    triangles.len(),
                    s.triangles.len(),
                    100.0 * s.triangles.len() as f64 / triangles.len() as f64,
                    s.to_original * 1e3,
                    s.from_original * 1e3
                ),
                None => println!(
                    "| {:.0} µm | {name} | {} | (more than {:.0} %) | | | |",
                    error * 1e6,
                    triangles.len(),
                    simplify::MOST_KEPT * 100.0
                ),
            }
        }
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use bvh::point_triangle_squared;

    /// A seeded pseudo-random number in [0, 1).
    fn rng(state: &mut u64) -> f64 {
        *state = state
            .wrapping_mul(6364136223846793005)
            .wrapping_add(1442695040888963407);
        (*state >> 11) as f64 / (1u64 << 53) as f64
    }

    /// The exact distance from `p` to the mesh, over every triangle.
    fn exact(p: Point, points: &[Point], triangles: &[[u32; 3]]) -> f64 {
        (triangles.iter())
            .map(|t| point_triangle_squared(p, t.map(|v| points[v as usize])))
            .fold(f64::INFINITY, f64::min)
            .sqrt()
    }

    /// `n` random points on the surface (uniform in each triangle picked at random), and every
    /// triangle's centroid and edge midpoints.
    fn points_on(points: &[Point], triangles: &[[u32; 3]], n: usize, state: &mut u64) -> Vec<Point> {
        let at = |t: [u32; 3], u: f64, v: f64| {
            let c = t.map(|i| points[i as usize]);
            [0, 1, 2].map(|k| c[0][k] + u * (c[1][k] - c[0][k]) + v * (c[2][k] - c[0][k]))
        };
        let mut out: Vec<Point> = (0..n)
            .map(|_| {
                let t = triangles[(rng(state) * triangles.len() as f64) as usize];
                let (mut u, mut v) = (rng(state), rng(state));
                if u + v > 1.0 {
                    (u, v) = (1.0 - u, 1.0 - v);
                }
                at(t, u, v)
            })
            .collect();
        for &t in triangles {
            out.extend([
                at(t, 1.0 / 3.0, 1.0 / 3.0),
                at(t, 0.5, 0.0),
                at(t, 0.0, 0.5),
                at(t, 0.5, 0.5),
            ]);
        }
        out
    }

    /// Checks that `s`'s certified bounds hold at `n` random points and every centroid and edge
    /// midpoint of each surface (exact distances, every triangle of the other mesh), and come
    /// within 15 % of the farthest of them when they are above 1 µm (the bound is the largest
    /// distance its own search found, within its slack).
    fn assert_bounds_hold(points: &[Point], triangles: &[[u32; 3]], s: &simplify::Simplified, n: usize) {
        let mut state = 3;
        for (from, to, bound, name) in [
            (
                (&s.points[..], &s.triangles[..]),
                (points, triangles),
                s.to_original,
                "simplified → original",
            ),
            (
                (points, triangles),
                (&s.points[..], &s.triangles[..]),
                s.from_original,
                "original → simplified",
            ),
        ] {
            let farthest = (points_on(from.0, from.1, n, &mut state).into_iter())
                .map(|p| exact(p, to.0, to.1))
                .fold(0.0f64, f64::max);
            // (1 pm: the round-off of a point's distance to a triangle)
            assert!(
                farthest <= bound + 1e-12,
                "{name}: a point {farthest} m away, above the bound {bound} m"
            );
            assert!(
                bound < 1e-6 || bound - farthest < 0.15 * bound,
                "{name}: bound {bound} m, exact points reach {farthest} m"
            );
        }
    }

    #[test]
    fn a_simplified_meshs_stated_bounds_hold_at_many_points_and_are_tight() {
        let (points, triangles) = read_stl(&std::path::Path::new(MESHES).join("hvataljka.STL"));
        let s = simplify::simplify(&points, &triangles, 1e-4).expect("it simplifies");
        assert!(s.triangles.len() < triangles.len());
        assert_bounds_hold(&points, &triangles, &s, 20_000);
    }

    #[test]
    fn the_checked_simplifier_keeps_both_distances_within_its_bound() {
        let (points, triangles) = read_stl(&std::path::Path::new(MESHES).join("hvataljka.STL"));
        for bound in [1e-4, 3e-4] {
            let s = checked::certified(&points, &triangles, bound);
            assert!(
                s.to_original <= bound && s.from_original <= bound,
                "{bound} m: certified {} and {} m",
                s.to_original,
                s.from_original
            );
            // it cuts (meshoptimizer at a 100 µm target kept 73 % for 0.38 mm)
            assert!(
                s.triangles.len() < triangles.len() * 4 / 5,
                "{bound} m: kept {}",
                s.triangles.len()
            );
            assert_bounds_hold(&points, &triangles, &s, 20_000);
        }
    }

    /// A grid of `n` × `n` squares (two triangles each) of side 1 m, lifted by `height(x, y)`.
    fn grid(n: u32, height: impl Fn(f64, f64) -> f64) -> (Vec<Point>, Vec<[u32; 3]>) {
        let at = |i: u32, j: u32| i * (n + 1) + j;
        let points = (0..=n)
            .flat_map(|i| (0..=n).map(move |j| (i as f64 / n as f64, j as f64 / n as f64)))
            .map(|(x, y)| [x, y, height(x, y)])
            .collect();
        let triangles = (0..n)
            .flat_map(|i| {
                (0..n).flat_map(move |j| {
                    [
                        [at(i, j), at(i + 1, j), at(i + 1, j + 1)],
                        [at(i, j), at(i + 1, j + 1), at(i, j + 1)],
                    ]
                })
            })
            .collect();
        (points, triangles)
    }

    #[test]
    fn a_flat_plate_collapses_to_a_few_triangles_and_a_curved_one_within_its_bound() {
        // flat: every collapse inside the plane and along its straight borders is exact, but a
        // cell of a new triangle is proven by one original triangle, so one that straddles an
        // original edge must shrink to the bound's width (here 1 % of the plate) to be proven
        let (points, triangles) = grid(16, |_, _| 0.0);
        let s = checked::certified(&points, &triangles, 1e-2);
        assert!(s.triangles.len() <= 16, "kept {} of 512", s.triangles.len());
        assert!(s.to_original <= 1e-2 && s.from_original <= 1e-2);
        assert_bounds_hold(&points, &triangles, &s, 2_000);
        // a dome 0.1 m high: it keeps more at a tighter bound, and each within it
        let dome = |x: f64, y: f64| 0.1 * (1.0 - (2.0 * x - 1.0).powi(2)) * (1.0 - (2.0 * y - 1.0).powi(2));
        let (points, triangles) = grid(24, dome);
        let mut kept = Vec::new();
        for bound in [5e-3, 2e-2] {
            let s = checked::certified(&points, &triangles, bound);
            assert!(s.to_original <= bound && s.from_original <= bound);
            assert_bounds_hold(&points, &triangles, &s, 5_000);
            kept.push(s.triangles.len());
        }
        assert!(
            kept[1] < kept[0] && kept[0] < triangles.len(),
            "{kept:?} of {}",
            triangles.len()
        );
    }

    #[test]
    fn odd_meshes_are_kept_or_cut_within_the_bound() {
        // a lone triangle has nothing to give: every collapse would uncover it
        let lone = ([[0.0, 0.0, 0.0], [1.0, 0.0, 0.0], [0.0, 1.0, 0.0]], [[0u32, 1, 2]]);
        assert_eq!(checked::simplify(&lone.0, &lone.1, 0.1), vec![[0, 1, 2]]);
        // at a bound of 0 a bent strip stays exact; a triangle with no area and a vertex of none
        // do not upset it
        let (mut points, mut triangles) = grid(4, |x, _| (x - 0.5).abs());
        triangles.push([0, 1, 2]);
        points.push([5.0, 5.0, 5.0]);
        let kept = checked::simplify(&points, &triangles, 0.0);
        let s = simplify::certify(&points, &triangles, &kept);
        assert!(
            s.to_original <= simplify::SLACK && s.from_original <= simplify::SLACK,
            "{} {}",
            s.to_original,
            s.from_original
        );
        assert_bounds_hold(&points, &triangles, &s, 1_000);
        // an open half cylinder (a border) at a bound above its facets' sagitta: a large cut
        let (points, triangles) = half_cylinder(64);
        let s = checked::certified(&points, &triangles, 0.01);
        assert!(s.to_original <= 0.01 && s.from_original <= 0.01);
        assert!(s.triangles.len() < triangles.len() / 2, "kept {}", s.triangles.len());
        assert_bounds_hold(&points, &triangles, &s, 5_000);
    }

    /// A half cylinder of radius 1 and height 1 in `facets` facets (two triangles each), open.
    fn half_cylinder(facets: usize) -> (Vec<Point>, Vec<[u32; 3]>) {
        let mut points = Vec::new();
        for i in 0..=facets {
            let a = std::f64::consts::PI * i as f64 / facets as f64;
            points.extend([[a.cos(), a.sin(), 0.0], [a.cos(), a.sin(), 1.0]]);
        }
        let triangles: Vec<[u32; 3]> = (0..facets as u32)
            .flat_map(|i| [[2 * i, 2 * i + 2, 2 * i + 1], [2 * i + 1, 2 * i + 2, 2 * i + 3]])
            .collect();
        (points, triangles)
    }

    #[test]
    fn the_one_sided_distance_of_a_chord_is_its_sagitta() {
        // a half cylinder of radius 1 in 64 facets against the same in 8
        let (fine, coarse) = (half_cylinder(64), half_cylinder(8));
        let bvh = |(p, t): &(Vec<Point>, Vec<[u32; 3]>)| bvh::Bvh::build(p, t);
        let sagitta = |facets: f64| 1.0 - (std::f64::consts::PI / (2.0 * facets)).cos();
        let coarse_to_fine = simplify::one_sided((&coarse.0, &coarse.1), (&fine.0, &fine.1, &bvh(&fine)));
        // a coarse chord's middle lies sagitta(8) inside the circle, in the direction of a fine
        // vertex: its distance to the two fine facets there is cos(π/64)·sagitta(8)
        let exact = (std::f64::consts::PI / 64.0).cos() * sagitta(8.0);
        assert!(
            coarse_to_fine >= exact - 1e-12 && coarse_to_fine <= exact + 5e-5,
            "{coarse_to_fine} against {exact}"
        );
        // that fine vertex is sagitta(8) from the coarse chord
        let fine_to_coarse = simplify::one_sided((&fine.0, &fine.1), (&coarse.0, &coarse.1, &bvh(&coarse)));
        let exact = sagitta(8.0);
        assert!(
            fine_to_coarse >= exact - 1e-12 && fine_to_coarse <= exact + 5e-5,
            "{fine_to_coarse} against {exact}"
        );
    }
}

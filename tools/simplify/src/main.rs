//! meshoptimizer's simplification of the Faze4's collision meshes at several error targets,
//! each with its one-sided distances to the original certified (`simplify.rs`): the table of
//! docs/clearance.md, "Simplified meshes". From the repository root:
//!
//!     cargo run --release --manifest-path tools/simplify/Cargo.toml [-- 1e-4 5e-5 2e-5]
//!
//! (errors in metres). `cargo test --manifest-path tools/simplify/Cargo.toml` checks the
//! certified bounds against exact distances at many points.

#[allow(dead_code)]
#[path = "../../../src/geometry/bvh.rs"]
mod bvh;
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

fn main() {
    let errors: Vec<f64> = std::env::args()
        .skip(1)
        .map(|a| a.parse().expect("an error in m"))
        .collect();
    let errors = if errors.is_empty() {
        vec![1e-4, 5e-5, 2e-5]
    } else {
        errors
    };
    let mut files: Vec<_> = std::fs::read_dir(MESHES).unwrap().map(|e| e.unwrap().path()).collect();
    files.sort();
    println!("| meshoptimizer's error | mesh | triangles | kept | simplified → original | original → simplified |");
    println!("|---|---|---|---|---|---|");
    for error in errors {
        for file in &files {
            let (points, triangles) = read_stl(file);
            let name = file.file_stem().unwrap().to_string_lossy();
            match simplify::simplify(&points, &triangles, error) {
                Some(s) => println!(
                    "| {:.0} µm | {name} | {} | {} ({:.0} %) | {:.3} mm | {:.3} mm |",
                    error * 1e6,
                    triangles.len(),
                    s.triangles.len(),
                    100.0 * s.triangles.len() as f64 / triangles.len() as f64,
                    s.to_original * 1e3,
                    s.from_original * 1e3
                ),
                None => println!(
                    "| {:.0} µm | {name} | {} | (more than {:.0} %) | | |",
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

    #[test]
    fn a_simplified_meshs_stated_bounds_hold_at_many_points_and_are_tight() {
        let (points, triangles) = read_stl(&std::path::Path::new(MESHES).join("hvataljka.STL"));
        let s = simplify::simplify(&points, &triangles, 1e-4).expect("it simplifies");
        assert!(s.triangles.len() < triangles.len());
        let mut state = 3;
        for (from, to, bound, name) in [
            (
                (&s.points, &s.triangles),
                (&points, &triangles),
                s.to_original,
                "simplified → original",
            ),
            (
                (&points, &triangles),
                (&s.points, &s.triangles),
                s.from_original,
                "original → simplified",
            ),
        ] {
            let farthest = (points_on(from.0, from.1, 20_000, &mut state).into_iter())
                .map(|p| exact(p, to.0, to.1))
                .fold(0.0f64, f64::max);
            assert!(
                farthest <= bound,
                "{name}: a point {farthest} m away, above the bound {bound} m"
            );
            // the bound is the largest distance found by its own search, within its slack: the
            // exact distances at these points come close to it
            assert!(
                bound - farthest < 0.1 * bound,
                "{name}: bound {bound} m, exact points reach {farthest} m"
            );
        }
    }

    #[test]
    fn the_one_sided_distance_of_a_chord_is_its_sagitta() {
        // a half cylinder of radius 1 in 64 facets against the same in 8
        let half = |facets: usize| {
            let mut points = Vec::new();
            for i in 0..=facets {
                let a = std::f64::consts::PI * i as f64 / facets as f64;
                points.extend([[a.cos(), a.sin(), 0.0], [a.cos(), a.sin(), 1.0]]);
            }
            let triangles: Vec<[u32; 3]> = (0..facets as u32)
                .flat_map(|i| [[2 * i, 2 * i + 2, 2 * i + 1], [2 * i + 1, 2 * i + 2, 2 * i + 3]])
                .collect();
            (points, triangles)
        };
        let (fine, coarse) = (half(64), half(8));
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

//! A drawing board, the three shapes the tool draws on it, and an arm's board: its maker's, else
//! one from its reach.

use std::f64::consts::{FRAC_PI_2, PI, TAU};

use crate::choice::Choice;
use crate::id::FrameId;
pub use crate::model::Board;
use crate::model::Model;
use crate::spatial::Vec3;

/// Radius of the circle, and of the circle the triangle is inscribed in (m), on a board
/// [`SHAPES_WIDTH`] wide; on another board the shapes scale with its width.
pub const CIRCLE_RADIUS: f64 = 0.16;
/// Half-length L of the sine's sweep (m), on a board [`SHAPES_WIDTH`] wide.
pub const SINE_HALF_LENGTH: f64 = 0.19;
/// Amplitude A of the sine (m), on a board [`SHAPES_WIDTH`] wide.
pub const SINE_AMPLITUDE: f64 = 0.12;
/// The board width the shapes' sizes are given for (m): the original's board
/// (`crate::faze4::BOARD`), on which they are drawn at exactly those sizes.
pub const SHAPES_WIDTH: f64 = 0.50;
/// Time for one loop of a shape (s), on every arm.
pub const PERIOD: f64 = 5.0;

/// How far in front of an arm's base (along −y, where the original's board stands) a board
/// from its reach R ([`board`]) stands, in R.
pub const REACH_DEPTH: f64 = 0.5;
/// How high above the arm's base that board's centre is, in R.
pub const REACH_HEIGHT: f64 = 0.45;
/// That board's width, in R (the shapes scaled with it).
pub const REACH_WIDTH: f64 = 0.35;
/// That board's height for its width: the original's (0.44 m for 0.50 m).
pub const REACH_ASPECT: f64 = 0.88;

/// The board `model` draws its shapes on with `tool` as the pen: its maker's
/// ([`crate::model::ArmDefaults::board`]), else one from its reach R ([`reach`]): the vertical
/// plane [`REACH_DEPTH`]·R in front of its base (along −y), centred [`REACH_HEIGHT`]·R above
/// it, [`REACH_WIDTH`]·R wide and [`REACH_ASPECT`] times as tall (docs/model.md, 4.3: the ratios with which the shapes' IK reaches on six public arms).
pub fn board(model: &Model, tool: FrameId) -> Board {
    if let Some(board) = model.defaults.board {
        return board;
    }
    let (base, r) = reach(model, tool);
    let width = REACH_WIDTH * r;
    Board {
        center: base + Vec3::new(0.0, -REACH_DEPTH * r, REACH_HEIGHT * r),
        width,
        height: REACH_ASPECT * width,
    }
}

/// The reach of the chain that carries `tool`: its base, the world position of the chain's first
/// moving joint (at the zero pose), and its length from there, the sum of the offsets between
/// its joints and of the tool's in its body (m). No point the tool reaches is farther than that
/// from the base. A tool on no moving body has length 0 at its own position.
pub fn reach(model: &Model, tool: FrameId) -> (Vec3, f64) {
    let frame = model.frame(tool);
    let Some(mut body) = frame.body.map(|b| b.0) else {
        return (frame.placement.pos, 0.0);
    };
    let mut length = frame.placement.pos.norm();
    while let Some(parent) = model.parent[body] {
        length += model.tree_pose[body].pos.norm();
        body = parent;
    }
    (model.tree_pose[body].pos, length)
}

/// The three closed paths of the original experiment (docs/model.md).
#[derive(Clone, Copy, Debug, PartialEq, Eq)]
pub enum Shape {
    /// One sine period across the board and back.
    Sine,
    /// A circle, counter-clockwise from the right.
    Circle,
    /// The inscribed triangle, counter-clockwise from the top vertex.
    Tri,
}

impl Choice for Shape {
    const VALUES: &'static [Self] = &Shape::ALL;
    const WORDS: &'static [&'static str] = &["sine", "circle", "tri"];
}

impl Shape {
    /// All shapes, in the order the command line lists them.
    pub const ALL: [Shape; 3] = [Shape::Sine, Shape::Circle, Shape::Tri];

    /// Its word (`sine`, `circle`, `tri`: the `shape` option's).
    pub fn name(self) -> &'static str {
        self.word()
    }

    /// The point at path parameter `s` ∈ [0, 1) on `board` (world, m), the shape's sizes
    /// scaled by the board's width over [`SHAPES_WIDTH`].
    pub fn point(self, s: f64, board: &Board) -> Vec3 {
        let scale = board.width / SHAPES_WIDTH;
        let radius = CIRCLE_RADIUS * scale;
        let (u, w) = match self {
            Shape::Circle => (radius * (TAU * s).cos(), radius * (TAU * s).sin()),
            Shape::Tri => {
                // vertices at 90°, 210°, 330°; each edge takes a third of the loop
                let vertex = |k: usize| {
                    let a = FRAC_PI_2 + k as f64 * TAU / 3.0;
                    (radius * a.cos(), radius * a.sin())
                };
                let edge = ((3.0 * s).floor() as usize).min(2);
                let f = 3.0 * s - edge as f64;
                let (a, b) = (vertex(edge), vertex((edge + 1) % 3));
                (a.0 + f * (b.0 - a.0), a.1 + f * (b.1 - a.1))
            }
            Shape::Sine => {
                let l = SINE_HALF_LENGTH * scale;
                let u = if s < 0.5 {
                    -l + 4.0 * l * s
                } else {
                    l - 4.0 * l * (s - 0.5)
                };
                (u, SINE_AMPLITUDE * scale * (PI / l * u).sin())
            }
        };
        Vec3::new(board.center.x + u, board.center.y, board.center.z + w)
    }

    /// The `n` targets `point(k/n)`, k = 0..n−1 (the loop closes back to the first).
    pub fn targets(self, n: usize, board: &Board) -> Vec<Vec3> {
        (0..n).map(|k| self.point(k as f64 / n as f64, board)).collect()
    }
}

/// Distance from `p` to the closed polyline through `path` (the last point joins the first).
pub fn distance_to_closed_path(p: &Vec3, path: &[Vec3]) -> f64 {
    let n = path.len();
    (0..n)
        .map(|k| distance_to_segment(p, &path[k], &path[(k + 1) % n]))
        .fold(f64::INFINITY, f64::min)
}

fn distance_to_segment(p: &Vec3, a: &Vec3, b: &Vec3) -> f64 {
    let ab = b - a;
    let len2 = ab.norm_squared();
    let t = if len2 > 0.0 {
        ((p - a).dot(&ab) / len2).clamp(0.0, 1.0)
    } else {
        0.0
    };
    (a + ab * t - p).norm()
}

#[cfg(test)]
mod tests {
    use super::*;
    use crate::faze4::BOARD;

    fn range(points: &[Vec3], axis: usize) -> (f64, f64) {
        points.iter().fold((f64::INFINITY, f64::NEG_INFINITY), |(lo, hi), p| {
            (lo.min(p[axis]), hi.max(p[axis]))
        })
    }

    #[test]
    fn triangle_spans_the_spec_ranges() {
        let t = Shape::Tri.targets(240, &BOARD);
        let (x, z) = (range(&t, 0), range(&t, 2));
        assert!((x.0 + 0.0586).abs() < 1e-4 && (x.1 - 0.2186).abs() < 1e-4, "{x:?}");
        assert!((z.0 - 0.47).abs() < 1e-12 && (z.1 - 0.71).abs() < 1e-12, "{z:?}");
        assert!(
            (t[0] - Vec3::new(0.08, -0.48, 0.71)).norm() < 1e-15,
            "starts at the top vertex"
        );
    }

    #[test]
    fn shapes_lie_on_the_board_and_close() {
        for shape in Shape::ALL {
            let t = shape.targets(240, &BOARD);
            assert!(t.iter().all(|p| p.y == -0.48));
            // consecutive targets, including last → first, are close (a closed loop)
            let gap = (0..t.len())
                .map(|k| (t[(k + 1) % t.len()] - t[k]).norm())
                .fold(0.0, f64::max);
            assert!(gap < 0.01, "{shape:?}: gap {gap}");
        }
        let c = Shape::Circle.targets(4, &BOARD);
        assert!(
            (c[1] - Vec3::new(0.08, -0.48, 0.71)).norm() < 1e-15,
            "counter-clockwise"
        );
        let s = Shape::Sine.targets(4, &BOARD);
        assert!((s[0].x - (0.08 - 0.19)).abs() < 1e-15 && (s[2].x - (0.08 + 0.19)).abs() < 1e-15);
    }

    #[test]
    fn distance_to_a_closed_square() {
        let sq = [
            Vec3::new(0.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 0.0),
            Vec3::new(1.0, 0.0, 1.0),
            Vec3::new(0.0, 0.0, 1.0),
        ];
        assert_eq!(distance_to_closed_path(&Vec3::new(0.5, 0.0, 0.5), &sq), 0.5);
        assert_eq!(
            distance_to_closed_path(&Vec3::new(-0.5, 0.0, 0.5), &sq),
            0.5,
            "the closing edge counts"
        );
        assert_eq!(distance_to_closed_path(&Vec3::new(0.5, 0.3, 0.0), &sq), 0.3);
    }
}

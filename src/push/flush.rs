//! Flush pushes: the fingers meet one face of the object flat, the jaw line along that face, and push
//! within a cone about the face's inward normal, so that the object slides without turning
//! (`formulations/pushing.md`, "Flush pushes").
//!
//! Quasi-statically, an object sliding on the table without turning feels the table's friction as
//! one force `μ_t·m·g` against its motion, through its centroid; the pusher must supply that force. A
//! face flat against both fingers (or against the closed block) can, when the line of the motion
//! through the centroid crosses the face between the contacts and the motion lies inside the
//! contacts' friction cone about the face's normal, `atan μ_f` (21.8° for the pads' 0.4). A push
//! that first meets the object with one finger or a corner turns it until a face lies flat against
//! the fingers. In the simulator (push-mog-opt, training scenes 5001–5100, 490 pushed pairs), pushes
//! within 5° of a face normal with the jaw line across the push turned their object a median 3.8°
//! and the pair was carried together 91 % of the time; pushes 10–30° off turned it 12–15° and 73–76 %
//! were. Flush pushes (scenes 5001–5040) turned it a median 1.5° (p90 3.6°) along the normal, 1.4–2.0°
//! (p90 3.7–4.4°) at 10° off it with the jaw line along the face, and 1.7–2.2° but p90 16° at 20°
//! off: the planner keeps within `cone` (default half the friction cone).
//!
//! Flush pushes are made with the jaws closed to one block (plate centres `w + 1 mm` apart, `w` the
//! plate thickness: a front `2w + 1 mm` wide, continuous but for the 1 mm between the plates).
//! Every face the open fork can meet flat the block meets too (the fork's fingers sit 7.75 mm
//! either side of the push line); the block needs less room behind the object; and every push of
//! a trip then finds the jaws where the last one left them, so a trip's later pushes send no jaw
//! command. In the simulator the block's flush pushes of pairs pushed ahead were carried together
//! as often as the fork's (0.86 of 845 against 0.84 of 415).
//!
//! A face of an outline (counter-clockwise), from `a` to `b`, with unit direction `j` and inward
//! normal `n`, lies at distance `h` from the centroid. Pushed along `d` (`n·d ≥ cos cone`), the line
//! of the motion through the centroid crosses the face at `o = −h·(d·j)/(d·n)` along `j`, and the
//! block is centred there. The push is flush when the face reaches `error + margin` past the
//! crossing on both sides, `error` being how far the block may land beside its place across the
//! push: the contact then straddles the line of the force by `margin` at least,
//!
//! ```text
//! a·j ≤ o − error − margin    and    b·j ≥ o + error + margin.
//! ```
//!
//! For a pair, where one member is pushed along `d` and the other stays, the row's closing axis is
//! the line through both centroids once the pushed one stops ([`pair_axis`]): both centroids then lie
//! on the plates' centre line.

use nalgebra::{Point2, Vector2};

use crate::geometry::{ConvexPolygon, cast_distance};
use crate::scene::{Gripper, Scene};

/// Gap between the plates when pushing with the gripper closed, metres.
pub(super) const CLOSED_GAP: f64 = 0.001;

/// How far the fingers may land beside their planned place across the push, metres: the
/// simulator's perception (2 mm) and actuation (1 mm) noise together, rounded.
const PLACEMENT_ERROR: f64 = 0.002;

/// Slack on the cone when a planned push is checked, radians (0.01°): the solver returns directions
/// on the cone's edge to within far less.
const CONE_SLACK: f64 = 1.7e-4;

/// The distance between plate centres of a flush push: the jaws closed to one block.
pub fn block_opening(gripper: &Gripper) -> f64 {
    gripper.plate_thickness + CLOSED_GAP
}

/// A face of an object that a push meets flat.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct Face {
    /// The face's unit inward normal: the way the block faces.
    pub normal: Vector2<f64>,
}

/// The face of `outline` that a push along the unit vector `direction` meets flat, within `cone`
/// of its normal: the face reaches `margin` past the crossing on both sides after
/// 2 mm of placement error. `None` when no face does.
pub fn flush_face(
    outline: &ConvexPolygon,
    margin: f64,
    direction: &Vector2<f64>,
    cone: f64,
) -> Option<Face> {
    let centroid = outline.centroid();
    let reach = PLACEMENT_ERROR + margin;
    outline.edges().find_map(|(a, b)| {
        let edge = b - a;
        let length = edge.norm();
        if length <= 0.0 {
            return None;
        }
        let along = edge / length;
        let normal = Vector2::new(-along.y, along.x);
        let facing = normal.dot(direction);
        if facing < (cone + CONE_SLACK).cos() {
            return None;
        }
        let depth = -(a - centroid).dot(&normal);
        let crossing = -depth * direction.dot(&along) / facing;
        let (low, high) = ((a - centroid).dot(&along), (b - centroid).dot(&along));
        (low <= crossing - reach && high >= crossing + reach).then_some(Face { normal })
    })
}

/// The faces of `outline` that a push along their own normal meets flat ([`flush_face`]).
pub fn flush_faces(outline: &ConvexPolygon, margin: f64) -> Vec<Face> {
    outline
        .edges()
        .filter_map(|(a, b)| {
            let edge = b - a;
            let length = edge.norm();
            (length > 0.0).then(|| Vector2::new(-edge.y, edge.x) / length)
        })
        .filter_map(|normal| flush_face(outline, margin, &normal, 0.0))
        .collect()
}

/// `direction` turned by `angle` radians (counter-clockwise).
pub fn turned(direction: &Vector2<f64>, angle: f64) -> Vector2<f64> {
    let (sin, cos) = angle.sin_cos();
    Vector2::new(
        direction.x * cos - direction.y * sin,
        direction.x * sin + direction.y * cos,
    )
}

/// Directions tried within a face's cone: its normal, the cone's edges and halfway between.
pub fn cone_directions(normal: &Vector2<f64>, cone: f64) -> Vec<Vector2<f64>> {
    if cone <= 0.0 {
        return vec![*normal];
    }
    [0.0, -0.5, 0.5, -1.0, 1.0]
        .iter()
        .map(|&k| turned(normal, k * cone))
        .collect()
}

/// What a pair's row needs of its closing axis.
#[derive(Clone, Copy, Debug, PartialEq)]
pub struct PairRow {
    /// Longest extent of the row along the axis, metres (the usable gap less the margin).
    pub row_limit: f64,
    /// Least gap between the two along the axis, metres.
    pub gap: f64,
    /// How far each must reach past the plates' centre line on both sides, metres.
    pub straddle: f64,
    /// When set, the pushed one goes on until it is at most this far from the other along the
    /// axis (a tight row), metres.
    pub tight: Option<f64>,
}

/// Step of the search along the push, metres.
const SEARCH_STEP: f64 = 0.0005;

/// The closing axis of the shortest row of a pair when the member at `pushed` (outline `moving`
/// about its centroid) is pushed along `direction` and the member at `fixed` (outline `staying`)
/// stays: the direction from `fixed` to where the pushed centroid stops, for the shortest push (of
/// at most `longest`, searched in 0.5 mm steps) after which the two, centroids on that line, make a
/// row that fits (a tight one, with `row.tight`), and that push's length. `None` when no push along
/// `direction` does.
///
/// The search ends where the pushed one would first touch the other: a row beyond that point (the
/// pushed one on the far side of the other) could only be reached by pushing it through the other.
pub fn pair_axis(
    (pushed, moving): (Point2<f64>, &ConvexPolygon),
    (fixed, staying): (Point2<f64>, &ConvexPolygon),
    direction: &Vector2<f64>,
    row: PairRow,
    longest: f64,
) -> Option<(Vector2<f64>, f64)> {
    let moving_centre = moving.centroid().coords;
    let staying_centre = staying.centroid().coords;
    let support = |outline: &ConvexPolygon, centre: &Vector2<f64>, d: &Vector2<f64>| {
        outline.support(d) - centre.dot(d)
    };
    let placed =
        |outline: &ConvexPolygon, at: Point2<f64>| outline.translated(&(at - outline.centroid()));
    let contact = cast_distance(
        &placed(moving, pushed),
        direction,
        longest,
        &placed(staying, fixed),
    );
    let steps = match contact {
        Some(contact) if contact < longest => (contact / SEARCH_STEP).floor() as usize,
        _ => (longest / SEARCH_STEP).ceil() as usize,
    };
    (0..=steps).find_map(|k| {
        let length = k as f64 * SEARCH_STEP;
        let at = pushed + direction * length;
        let joining = at - fixed;
        let between = joining.norm();
        if between <= 0.0 {
            return None;
        }
        let axis = joining / between;
        let across = Vector2::new(-axis.y, axis.x);
        let apart = between
            - support(staying, &staying_centre, &axis)
            - support(moving, &moving_centre, &-axis);
        let span = between
            + support(moving, &moving_centre, &axis)
            + support(staying, &staying_centre, &-axis);
        let straddles = [(moving, &moving_centre), (staying, &staying_centre)]
            .iter()
            .all(|(outline, centre)| {
                support(outline, centre, &across) >= row.straddle
                    && support(outline, centre, &-across) >= row.straddle
            });
        let limit = row.tight.map_or(row.row_limit, |tight| {
            row.row_limit.min(span - apart + tight)
        });
        (apart >= row.gap && span <= limit && straddles).then_some((axis, length))
    })
}

/// Whether the objects at scene indices `a` and `b` can be lined up for one grasp by a flush push
/// of either one toward the other, in some direction of [`cone_directions`] of one of its faces
/// ([`pair_axis`]): the pair test of the clustering when pushes are flush. Paths and fingers are
/// not checked here.
pub fn admits_flush_pair(
    scene: &Scene,
    (a, b): (usize, usize),
    row: PairRow,
    (margin, cone): (f64, f64),
) -> bool {
    let (pa, pb) = (scene.centroid(a), scene.centroid(b));
    let (oa, ob) = (scene.world_polygon(a), scene.world_polygon(b));
    [((pa, oa), (pb, ob)), ((pb, ob), (pa, oa))]
        .into_iter()
        .any(|((p, moving), (q, staying))| {
            let towards = q - p;
            let longest = towards.norm() + row.row_limit;
            flush_faces(moving, margin).iter().any(|face| {
                cone_directions(&face.normal, cone)
                    .iter()
                    .filter(|d| d.dot(&towards) > 0.0)
                    .filter(|d| flush_face(moving, margin, d, cone).is_some())
                    .any(|d| pair_axis((p, moving), (q, staying), d, row, longest).is_some())
            })
        })
}

#[cfg(test)]
mod tests {
    use super::*;

    fn square(half: f64) -> ConvexPolygon {
        ConvexPolygon::rectangle(&Point2::origin(), &Vector2::x(), half, half)
    }

    #[test]
    fn a_square_is_pushed_flush_on_each_face() {
        let faces = flush_faces(&square(0.015), 0.002);
        assert_eq!(faces.len(), 4);
        for face in &faces {
            // Axis-aligned inward normals.
            assert!((face.normal.x.abs() - 1.0).abs() < 1e-12 || face.normal.x.abs() < 1e-12);
        }
        // The pushes go inward: the face at +x is pushed toward −x.
        let east = flush_face(&square(0.015), 0.002, &-Vector2::x(), 0.0);
        assert_eq!(east.map(|f| f.normal), Some(-Vector2::x()));
        // 10° off the normal: only within a cone that wide.
        let oblique = turned(&-Vector2::x(), 10f64.to_radians());
        assert!(flush_face(&square(0.015), 0.002, &oblique, 0.0).is_none());
        let within = flush_face(&square(0.015), 0.002, &oblique, 0.19);
        assert_eq!(within.map(|f| f.normal), Some(-Vector2::x()));
        // The block is centred where the line through the centroid crosses the face, h·tan θ off
        // its middle: 30° off, 5.2 mm on a face 9 mm from the centroid, whose far end is then only
        // 3.8 mm away, less than the 4 mm needed; on a face 15 mm away, 8.7 mm of 15.
        let steep = turned(&-Vector2::x(), 30f64.to_radians());
        assert!(flush_face(&square(0.015), 0.002, &steep, 0.6).is_some());
        assert!(flush_face(&square(0.009), 0.002, &steep, 0.6).is_none());
    }

    #[test]
    fn very_narrow_faces_are_never_flush() {
        // Faces 8 mm long reach 4 mm each side: just enough; 6 mm long, not.
        assert_eq!(flush_faces(&square(0.004), 0.002).len(), 4);
        assert!(flush_faces(&square(0.003), 0.002).is_empty());
    }

    #[test]
    fn a_pair_lines_up_along_the_line_through_both_centroids() {
        let row = PairRow {
            row_limit: 0.065,
            gap: 0.001,
            straddle: 0.003,
            tight: None,
        };
        let (a, b) = (square(0.015), square(0.015));
        // Pushed straight at the other: the axis is the push line, the row 65 mm long.
        let axis = pair_axis(
            (Point2::new(0.1, 0.0), &a),
            (Point2::origin(), &b),
            &-Vector2::x(),
            row,
            0.2,
        );
        let (axis, length) = axis.unwrap_or_default();
        assert!((axis - Vector2::x()).norm() < 1e-9);
        // Centroids 35 mm apart: a push of 65 mm, to the 0.5 mm step.
        assert!((length - 0.065).abs() < SEARCH_STEP);
        // Pushed past it 10 mm to one side: the axis leans toward the side. A leaning axis
        // meets the squares' corners, so the row needs more room than 65 mm: about 44 mm between
        // centroids plus 30·(cos + sin) of the lean, 80 mm in all.
        let roomy = PairRow {
            row_limit: 0.08,
            ..row
        };
        let axis = pair_axis(
            (Point2::new(0.1, 0.01), &a),
            (Point2::origin(), &b),
            &-Vector2::x(),
            roomy,
            0.2,
        )
        .map_or_else(Vector2::zeros, |(axis, _)| axis);
        assert!(axis.y > 0.0 && axis.x > 0.9);
        // Tight: on until the two are 3 mm apart, so the row is 63 mm long and the axis the same.
        let tight = PairRow {
            tight: Some(0.003),
            ..row
        };
        let straight = pair_axis(
            (Point2::new(0.1, 0.0), &a),
            (Point2::origin(), &b),
            &-Vector2::x(),
            tight,
            0.2,
        );
        assert!(straight.is_some_and(|(axis, _)| (axis - Vector2::x()).norm() < 1e-9));
        // Pushed away: never a row.
        assert!(
            pair_axis(
                (Point2::new(0.1, 0.0), &a),
                (Point2::origin(), &b),
                &Vector2::x(),
                row,
                0.2
            )
            .is_none()
        );
    }

    #[test]
    fn a_pair_is_never_lined_up_beyond_the_other() {
        // Two built-in outlines at random poses, each pushed along its faces' inward normals
        // toward the other: wherever a row is found, the push that makes it is clear of the
        // other all the way (a row past the other could only be reached through it).
        let outlines: Vec<ConvexPolygon> = crate::scene::builtin_object_set()
            .objects
            .iter()
            .filter_map(|o| o.polygon().ok())
            .collect();
        let row = PairRow {
            row_limit: 0.065,
            gap: 0.001,
            straddle: 0.003,
            tight: Some(0.003),
        };
        let mut rng = crate::random::SeededRng::new(11);
        let mut rows = 0;
        for _ in 0..3000 {
            let place = |rng: &mut crate::random::SeededRng, at: Vector2<f64>| {
                let outline = &outlines[rng.index(outlines.len())];
                let yaw = rng.uniform(-std::f64::consts::PI, std::f64::consts::PI);
                outline
                    .transformed(&nalgebra::Isometry2::new(Vector2::zeros(), yaw))
                    .translated(&at)
            };
            let staying = place(&mut rng, Vector2::zeros());
            let angle = rng.uniform(-std::f64::consts::PI, std::f64::consts::PI);
            let start = Vector2::new(angle.cos(), angle.sin()) * rng.uniform(0.03, 0.12);
            let moving = place(&mut rng, start);
            let (pushed, fixed) = (moving.centroid(), staying.centroid());
            for face in flush_faces(&moving, 0.002) {
                let direction = face.normal;
                if direction.dot(&(fixed - pushed)) <= 0.0 {
                    continue;
                }
                let longest = (fixed - pushed).norm() + row.row_limit;
                let found = pair_axis(
                    (pushed, &moving),
                    (fixed, &staying),
                    &direction,
                    row,
                    longest,
                );
                if let Some((_, length)) = found {
                    rows += 1;
                    let hit = cast_distance(&moving, &direction, length, &staying);
                    assert!(
                        hit.is_none_or(|hit| hit >= length - 1e-9),
                        "a row {length} m along the push, the other met at {hit:?} m"
                    );
                }
            }
        }
        assert!(rows > 300, "only {rows} rows found");
    }
}

//! Object sets: the built-in library of 34 extruded convex polygons, and sets loaded from JSON.
//!
//! The built-in set stands in for the Push-MOG paper's 34 physical objects (3- to 8-sided, sizes a
//! Robotiq 2F-85 can hold two or three of at once). Outlines are centred on their area centroid; every
//! object is 30 mm high, the extrusion of the multi-object-grasping papers' polygon sets. Minimum grasp
//! diameters `d*` run from 22 to 37 mm, so any two fit the 75 mm usable gap and many triples do. The
//! table below is checked against the code by a test (`pushmog library` prints it).
//!
//! <!-- library-table:start -->
//! | # | name | sides | d* (mm) | radius (mm) | area (mm²) |
//! |---:|---|---:|---:|---:|---:|
//! | 0 | triangle-equilateral-30 | 3 | 26.0 | 17.3 | 389.7 |
//! | 1 | triangle-equilateral-38 | 3 | 32.9 | 21.9 | 625.3 |
//! | 2 | triangle-right-30x40 | 3 | 24.0 | 28.5 | 600.0 |
//! | 3 | triangle-right-isosceles-36 | 3 | 25.5 | 26.8 | 648.0 |
//! | 4 | triangle-isosceles-32x30 | 3 | 28.2 | 20.0 | 480.0 |
//! | 5 | triangle-scalene | 3 | 28.0 | 25.8 | 588.0 |
//! | 6 | triangle-obtuse | 3 | 22.0 | 26.4 | 506.0 |
//! | 7 | square-24 | 4 | 24.0 | 17.0 | 576.0 |
//! | 8 | square-30 | 4 | 30.0 | 21.2 | 900.0 |
//! | 9 | square-35 | 4 | 35.0 | 24.7 | 1225.0 |
//! | 10 | rectangle-22x40 | 4 | 22.0 | 22.8 | 880.0 |
//! | 11 | rectangle-26x44 | 4 | 26.0 | 25.6 | 1144.0 |
//! | 12 | rectangle-32x42 | 4 | 32.0 | 26.4 | 1344.0 |
//! | 13 | rhombus | 4 | 26.0 | 26.0 | 780.0 |
//! | 14 | parallelogram | 4 | 24.0 | 25.9 | 864.0 |
//! | 15 | trapezoid-isosceles | 4 | 26.0 | 24.8 | 832.0 |
//! | 16 | trapezoid-right | 4 | 30.0 | 26.8 | 1020.0 |
//! | 17 | kite | 4 | 28.8 | 20.7 | 684.0 |
//! | 18 | quad-irregular | 4 | 30.5 | 23.3 | 1010.0 |
//! | 19 | pentagon-regular-16 | 5 | 28.9 | 16.0 | 608.7 |
//! | 20 | pentagon-regular-19 | 5 | 34.4 | 19.0 | 858.3 |
//! | 21 | pentagon-house | 5 | 28.0 | 20.8 | 840.0 |
//! | 22 | pentagon-irregular | 5 | 34.0 | 22.4 | 1032.0 |
//! | 23 | hexagon-regular-15 | 6 | 26.0 | 15.0 | 584.6 |
//! | 24 | hexagon-regular-19 | 6 | 32.9 | 19.0 | 937.9 |
//! | 25 | hexagon-elongated | 6 | 24.0 | 24.0 | 912.0 |
//! | 26 | hexagon-irregular | 6 | 32.2 | 21.3 | 1078.0 |
//! | 27 | heptagon-regular-15 | 7 | 28.5 | 15.0 | 615.7 |
//! | 28 | heptagon-regular-18 | 7 | 34.2 | 18.0 | 886.6 |
//! | 29 | heptagon-irregular | 7 | 37.2 | 22.0 | 1204.0 |
//! | 30 | octagon-regular-14 | 8 | 25.9 | 14.0 | 554.4 |
//! | 31 | octagon-regular-18 | 8 | 33.3 | 18.0 | 916.4 |
//! | 32 | octagon-truncated-rectangle | 8 | 26.0 | 21.2 | 968.0 |
//! | 33 | octagon-irregular | 8 | 36.6 | 21.9 | 1200.6 |
//! <!-- library-table:end -->
//!
//! "radius" is the distance from the centroid to the furthest vertex; the scene generator keeps circles
//! of the set's largest radius apart.
//!
//! A set loaded from JSON has the form `{ "name": "…", "objects": [{ "name", "vertices", "height" }] }`
//! (`pushmog schema object-set` prints its schema, `pushmog library --json` writes the built-in set).

use std::fmt::Write as _;

use nalgebra::Point2;
use schemars::JsonSchema;
use serde::{Deserialize, Serialize};

use crate::error::{Error, Result};
use crate::geometry::{ConvexPolygon, min_grasp_diameter};

/// One shape of an object set.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct LibraryObject {
    /// A name for the shape, copied into each object made from it.
    pub name: String,
    /// Outline in metres in the shape's own frame, `[x, y]` pairs, either orientation.
    pub vertices: Vec<[f64; 2]>,
    /// Extrusion height in metres.
    pub height: f64,
    /// Mass in kilograms, when known.
    #[serde(default, skip_serializing_if = "Option::is_none")]
    pub mass: Option<f64>,
}

/// A named set of shapes to draw scenes from.
#[derive(Clone, Debug, PartialEq, Serialize, Deserialize, JsonSchema)]
#[serde(deny_unknown_fields)]
pub struct ObjectSet {
    /// The set's name.
    pub name: String,
    /// Its shapes; a scene drawn from the set uses each shape once before repeating any.
    pub objects: Vec<LibraryObject>,
}

impl LibraryObject {
    /// The validated outline.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the shape and `vertices` when the outline is not convex.
    pub fn polygon(&self) -> Result<ConvexPolygon> {
        let points = self
            .vertices
            .iter()
            .map(|&[x, y]| Point2::new(x, y))
            .collect();
        ConvexPolygon::new(points).map_err(|e| {
            Error::field(
                format!("object set shape `{}`", self.name),
                "vertices",
                e.to_string(),
            )
        })
    }
}

impl ObjectSet {
    /// Checks every shape: a convex outline, a positive finite height and mass, at least one shape.
    ///
    /// # Errors
    /// [`Error::InvalidField`] naming the shape and the field.
    pub fn validate(&self) -> Result<()> {
        if self.objects.is_empty() {
            return Err(Error::field(
                format!("object set `{}`", self.name),
                "objects",
                "holds no shapes",
            ));
        }
        for shape in &self.objects {
            shape.polygon()?;
            let component = format!("object set shape `{}`", shape.name);
            if !(shape.height.is_finite() && shape.height > 0.0) {
                return Err(Error::field(
                    component,
                    "height",
                    format!(
                        "must be a positive finite number of metres, got {}",
                        shape.height
                    ),
                ));
            }
            if let Some(mass) = shape.mass
                && !(mass.is_finite() && mass > 0.0)
            {
                return Err(Error::field(
                    component,
                    "mass",
                    format!("must be a positive finite number of kilograms, got {mass}"),
                ));
            }
        }
        Ok(())
    }

    /// The largest distance from a shape's area centroid to its furthest vertex, metres.
    ///
    /// # Errors
    /// As [`ObjectSet::validate`].
    pub fn max_radius(&self) -> Result<f64> {
        let mut radius: f64 = 0.0;
        for shape in &self.objects {
            let polygon = shape.polygon()?;
            radius = radius.max(polygon.radius_about(&polygon.centroid()));
        }
        Ok(radius)
    }

    /// A Markdown table of the shapes: sides, minimum grasp diameter, radius and area in millimetres.
    ///
    /// # Errors
    /// As [`ObjectSet::validate`].
    pub fn markdown_table(&self) -> Result<String> {
        let mut out = String::from(
            "| # | name | sides | d* (mm) | radius (mm) | area (mm²) |\n|---:|---|---:|---:|---:|---:|\n",
        );
        for (k, shape) in self.objects.iter().enumerate() {
            let polygon = shape.polygon()?;
            let _ = writeln!(
                out,
                "| {k} | {} | {} | {:.1} | {:.1} | {:.1} |",
                shape.name,
                polygon.len(),
                min_grasp_diameter(&polygon).diameter * 1e3,
                polygon.radius_about(&polygon.centroid()) * 1e3,
                polygon.area() * 1e6
            );
        }
        Ok(out)
    }
}

/// Height of every built-in object, metres.
const BUILTIN_HEIGHT: f64 = 0.030;

/// The built-in set of 34 objects (see the module docs for the table).
pub fn builtin_object_set() -> ObjectSet {
    let objects = builtin_outlines_mm()
        .into_iter()
        .map(|(name, outline)| LibraryObject {
            name: name.to_string(),
            vertices: centred_metres(&outline),
            height: BUILTIN_HEIGHT,
            mass: None,
        })
        .collect();
    ObjectSet {
        name: "pushmog-34".to_string(),
        objects,
    }
}

/// Converts an outline in millimetres to metres, moved so its area centroid is the origin.
fn centred_metres(outline_mm: &[(f64, f64)]) -> Vec<[f64; 2]> {
    let n = outline_mm.len();
    let (mut twice_area, mut cx, mut cy) = (0.0, 0.0, 0.0);
    for i in 0..n {
        let (x0, y0) = outline_mm[i];
        let (x1, y1) = outline_mm[(i + 1) % n];
        let c = x0 * y1 - x1 * y0;
        twice_area += c;
        cx += (x0 + x1) * c;
        cy += (y0 + y1) * c;
    }
    let (cx, cy) = (cx / (3.0 * twice_area), cy / (3.0 * twice_area));
    outline_mm
        .iter()
        .map(|&(x, y)| [to_nanometre((x - cx) * 1e-3), to_nanometre((y - cy) * 1e-3)])
        .collect()
}

/// Rounds a length in metres to whole nanometres, so files show `0.015`, not `0.015000000000000003`.
fn to_nanometre(metres: f64) -> f64 {
    (metres * 1e9).round() / 1e9 + 0.0
}

/// A regular polygon of `sides` vertices on a circle of `radius` mm, first vertex at angle `phase`.
fn regular(sides: usize, radius: f64, phase: f64) -> Vec<(f64, f64)> {
    (0..sides)
        .map(|k| {
            let angle = phase + std::f64::consts::TAU * k as f64 / sides as f64;
            (radius * angle.cos(), radius * angle.sin())
        })
        .collect()
}

fn rectangle(width: f64, depth: f64) -> Vec<(f64, f64)> {
    vec![(0.0, 0.0), (width, 0.0), (width, depth), (0.0, depth)]
}

fn scaled(outline: &[(f64, f64)], factor: f64) -> Vec<(f64, f64)> {
    outline
        .iter()
        .map(|&(x, y)| (x * factor, y * factor))
        .collect()
}

/// The built-in outlines in millimetres, counter-clockwise.
fn builtin_outlines_mm() -> Vec<(&'static str, Vec<(f64, f64)>)> {
    use std::f64::consts::{FRAC_PI_2, FRAC_PI_8};
    let h30 = 30.0 * 3f64.sqrt() / 2.0;
    let h38 = 38.0 * 3f64.sqrt() / 2.0;
    vec![
        (
            "triangle-equilateral-30",
            vec![(0.0, 0.0), (30.0, 0.0), (15.0, h30)],
        ),
        (
            "triangle-equilateral-38",
            vec![(0.0, 0.0), (38.0, 0.0), (19.0, h38)],
        ),
        (
            "triangle-right-30x40",
            vec![(0.0, 0.0), (40.0, 0.0), (0.0, 30.0)],
        ),
        (
            "triangle-right-isosceles-36",
            vec![(0.0, 0.0), (36.0, 0.0), (0.0, 36.0)],
        ),
        (
            "triangle-isosceles-32x30",
            vec![(0.0, 0.0), (32.0, 0.0), (16.0, 30.0)],
        ),
        (
            "triangle-scalene",
            vec![(0.0, 0.0), (42.0, 0.0), (12.0, 28.0)],
        ),
        (
            "triangle-obtuse",
            vec![(0.0, 0.0), (46.0, 0.0), (30.0, 22.0)],
        ),
        ("square-24", rectangle(24.0, 24.0)),
        ("square-30", rectangle(30.0, 30.0)),
        ("square-35", rectangle(35.0, 35.0)),
        ("rectangle-22x40", rectangle(40.0, 22.0)),
        ("rectangle-26x44", rectangle(44.0, 26.0)),
        ("rectangle-32x42", rectangle(42.0, 32.0)),
        (
            "rhombus",
            vec![(0.0, 0.0), (30.0, 0.0), (45.0, 26.0), (15.0, 26.0)],
        ),
        (
            "parallelogram",
            vec![(0.0, 0.0), (36.0, 0.0), (46.0, 24.0), (10.0, 24.0)],
        ),
        (
            "trapezoid-isosceles",
            vec![(0.0, 0.0), (44.0, 0.0), (32.0, 26.0), (12.0, 26.0)],
        ),
        (
            "trapezoid-right",
            vec![(0.0, 0.0), (40.0, 0.0), (28.0, 30.0), (0.0, 30.0)],
        ),
        (
            "kite",
            vec![(0.0, 0.0), (18.0, -14.0), (36.0, 0.0), (18.0, 24.0)],
        ),
        (
            "quad-irregular",
            vec![(0.0, 0.0), (34.0, -4.0), (38.0, 26.0), (6.0, 30.0)],
        ),
        ("pentagon-regular-16", regular(5, 16.0, FRAC_PI_2)),
        ("pentagon-regular-19", regular(5, 19.0, FRAC_PI_2)),
        (
            "pentagon-house",
            vec![
                (0.0, 0.0),
                (28.0, 0.0),
                (28.0, 24.0),
                (14.0, 36.0),
                (0.0, 24.0),
            ],
        ),
        (
            "pentagon-irregular",
            vec![
                (0.0, 0.0),
                (30.0, 0.0),
                (38.0, 20.0),
                (18.0, 34.0),
                (-4.0, 22.0),
            ],
        ),
        ("hexagon-regular-15", regular(6, 15.0, FRAC_PI_2)),
        ("hexagon-regular-19", regular(6, 19.0, FRAC_PI_2)),
        (
            "hexagon-elongated",
            vec![
                (0.0, 0.0),
                (28.0, 0.0),
                (38.0, 12.0),
                (28.0, 24.0),
                (0.0, 24.0),
                (-10.0, 12.0),
            ],
        ),
        (
            "hexagon-irregular",
            vec![
                (0.0, 0.0),
                (26.0, -2.0),
                (36.0, 14.0),
                (28.0, 30.0),
                (4.0, 32.0),
                (-6.0, 16.0),
            ],
        ),
        ("heptagon-regular-15", regular(7, 15.0, FRAC_PI_2)),
        ("heptagon-regular-18", regular(7, 18.0, FRAC_PI_2)),
        (
            "heptagon-irregular",
            vec![
                (0.0, 0.0),
                (24.0, -4.0),
                (36.0, 8.0),
                (36.0, 24.0),
                (22.0, 34.0),
                (2.0, 30.0),
                (-6.0, 14.0),
            ],
        ),
        ("octagon-regular-14", regular(8, 14.0, FRAC_PI_8)),
        ("octagon-regular-18", regular(8, 18.0, FRAC_PI_8)),
        (
            "octagon-truncated-rectangle",
            vec![
                (6.0, 0.0),
                (34.0, 0.0),
                (40.0, 6.0),
                (40.0, 20.0),
                (34.0, 26.0),
                (6.0, 26.0),
                (0.0, 20.0),
                (0.0, 6.0),
            ],
        ),
        (
            "octagon-irregular",
            scaled(
                &[
                    (0.0, 0.0),
                    (20.0, -6.0),
                    (34.0, 0.0),
                    (40.0, 14.0),
                    (34.0, 28.0),
                    (18.0, 34.0),
                    (2.0, 28.0),
                    (-4.0, 14.0),
                ],
                0.97,
            ),
        ),
    ]
}

#[cfg(test)]
mod tests {
    use super::*;

    #[test]
    fn builtin_set_is_valid_and_sized_for_the_2f85() {
        let set = builtin_object_set();
        set.validate().unwrap();
        assert_eq!(set.objects.len(), 34);
        for shape in &set.objects {
            let polygon = shape.polygon().unwrap();
            assert!((3..=8).contains(&polygon.len()), "{}", shape.name);
            let d = min_grasp_diameter(&polygon).diameter;
            // Any two fit the 75 mm usable gap of a 2F-85.
            assert!((0.020..=0.0375).contains(&d), "{}: {d}", shape.name);
            assert!(polygon.centroid().coords.norm() < 1e-9, "{}", shape.name);
        }
    }

    #[test]
    fn documented_table_matches_the_code() {
        let source = include_str!("library.rs");
        let start = source.find("<!-- library-table:start -->").unwrap();
        let end = source.find("<!-- library-table:end -->").unwrap();
        let documented: String = source[start..end]
            .lines()
            .skip(1)
            .map(|line| line.trim_start_matches("//!").trim())
            .filter(|line| !line.is_empty())
            .map(|line| format!("{line}\n"))
            .collect();
        let generated = builtin_object_set().markdown_table().unwrap();
        assert_eq!(documented, generated, "regenerate with `pushmog library`");
    }
}

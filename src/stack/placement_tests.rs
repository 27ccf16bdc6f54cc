//! Tests of the rider placement search and its checks (`placement.rs`).

use super::*;

fn square(x: f64, y: f64, half: f64) -> ConvexPolygon {
    ConvexPolygon::rectangle(&Point2::new(x, y), &Vector2::x(), half, half)
}

/// Two 40 mm cubes side by side along x, the jaws closing along x.
fn pair(heights: [f64; 2]) -> Row {
    Row {
        outlines: vec![square(0.0, 0.0, 0.02), square(0.04, 0.0, 0.02)],
        heights: heights.to_vec(),
        axis: Vector2::x(),
        closing: None,
    }
}

#[test]
fn a_small_rider_stands_in_the_middle_of_a_pair_clear_of_the_pads() {
    let rider = square(0.3, 0.1, 0.01);
    let settings = StackSettings::default();
    let placed = place_rider(&pair([0.03, 0.03]), &rider, 0.02, 0.4, &settings).unwrap();
    assert_eq!(placed.base, 0.03);
    assert_eq!(placed.resting_on, vec![0, 1]);
    let footprint = rider.transformed(&placed.pose.isometry());
    let (front, back) = footprint.projection(&Vector2::x());
    assert!(front >= -0.02 + settings.pad_margin - 1e-9, "{front}");
    assert!(back <= 0.06 - settings.pad_margin + 1e-9, "{back}");
    // The most room on a 80 × 40 mm top for a 20 mm square: its centroid in the middle, 20 mm
    // from the long edges.
    let centroid = footprint.centroid();
    assert!(
        (centroid.x - 0.02).abs() < 1e-6 && centroid.y.abs() < 1e-6,
        "{centroid} {placed:?}"
    );
    assert!((placed.margin - 0.01).abs() < 1e-6, "{}", placed.margin);
}

#[test]
fn the_rider_rests_on_the_taller_member_only() {
    let rider = square(0.0, 0.0, 0.01);
    let placed = place_rider(
        &pair([0.03, 0.05]),
        &rider,
        0.02,
        0.4,
        &StackSettings::default(),
    )
    .unwrap();
    assert_eq!(placed.base, 0.05);
    assert_eq!(placed.resting_on, vec![1]);
}

#[test]
fn refusals_say_why() {
    let settings = StackSettings::default();
    let wide = square(0.0, 0.0, 0.04);
    assert_eq!(
        place_rider(&pair([0.03, 0.03]), &wide, 0.02, 0.4, &settings),
        Err(NoPlacement::TooWide)
    );
    let small = square(0.0, 0.0, 0.01);
    let slides = place_rider(&pair([0.03, 0.03]), &small, 0.02, 0.1, &settings);
    assert!(
        matches!(slides, Err(NoPlacement::Slides { .. })),
        "{slides:?}"
    );
    // A demanding margin no 40 mm-deep top gives.
    let strict = StackSettings {
        support_margin: 0.025,
        ..settings
    };
    let no_room = place_rider(&pair([0.03, 0.03]), &small, 0.02, 0.4, &strict);
    assert!(
        matches!(no_room, Err(NoPlacement::NoRoom { .. })),
        "{no_room:?}"
    );
}

#[test]
fn the_tipping_bound_takes_over_for_tall_riders() {
    // A 0.5 m tall rider at 1.2 m/s² needs (1.2/9.81)·0.25 = 30.6 mm: more than the 20 mm a
    // 40 mm-deep top offers.
    let rider = square(0.0, 0.0, 0.01);
    let refused = place_rider(
        &pair([0.03, 0.03]),
        &rider,
        0.5,
        0.4,
        &StackSettings::default(),
    );
    let Err(NoPlacement::NoRoom { needed, .. }) = refused else {
        panic!("{refused:?}");
    };
    assert!((needed - tipping_bound(0.5, 1.2)).abs() < 1e-12);
}

/// A tall 40 mm cube and, 10 mm beyond it along the closing axis, a low 10 mm-thick slab; the
/// jaws close the gap, each member moving 5 mm toward the other.
fn cube_and_slab(closing: bool) -> Row {
    Row {
        outlines: vec![
            square(0.0, 0.0, 0.02),
            ConvexPolygon::rectangle(&Point2::new(0.035, 0.0), &Vector2::x(), 0.005, 0.02),
        ],
        heights: vec![0.05, 0.03],
        axis: Vector2::x(),
        closing: closing.then(|| {
            vec![
                Isometry2::translation(0.005, 0.0),
                Isometry2::translation(-0.005, 0.0),
            ]
        }),
    }
}

fn bar(length: f64) -> ConvexPolygon {
    ConvexPolygon::rectangle(&Point2::origin(), &Vector2::x(), length / 2.0, 0.01)
}

#[test]
fn the_pads_are_judged_where_the_closing_leaves_the_row() {
    // The bars lie along the closing axis only (turned across it they would fit anywhere).
    let settings = StackSettings {
        yaws: 2,
        ..StackSettings::default()
    };
    // A 48 mm bar on the cube reaches over the slab: as the row stands it fits between the
    // pads with 6 mm either side, but the cube carries it 5 mm toward the slab's pad, which
    // closes 5 mm toward it.
    let long = bar(0.048);
    assert!(place_rider(&cube_and_slab(false), &long, 0.02, 0.4, &settings).is_ok());
    assert_eq!(
        place_rider(&cube_and_slab(true), &long, 0.02, 0.4, &settings),
        Err(NoPlacement::PadsClose)
    );
    // A 30 mm bar is placed where, carried by the cube, it stays 5 mm inside the closed pads.
    let row = cube_and_slab(true);
    let placed = place_rider(&row, &bar(0.03), 0.02, 0.4, &settings).unwrap();
    assert_eq!(placed.resting_on, vec![0]);
    let carried = bar(0.03)
        .transformed(&placed.pose.isometry())
        .transformed(&row.closing.as_ref().unwrap()[0]);
    let (front, back) = carried.projection(&Vector2::x());
    let (lo, hi) = row.closed_extent();
    assert!(
        (lo - -0.015).abs() < 1e-12 && (hi - 0.035).abs() < 1e-12,
        "{lo} {hi}"
    );
    assert!(front >= lo + settings.pad_margin - 1e-9, "{front}");
    assert!(back <= hi - settings.pad_margin + 1e-9, "{back}");
}

#[test]
fn the_plates_carry_the_riders_weight_too() {
    // 0.4 × 20 N carries 16 N: 1.5 kg (14.7 N) but not 1.7 kg.
    assert!(plates_carry(0.4, 20.0, &[0.5, 0.5], &[0.5]));
    assert!(!plates_carry(0.4, 20.0, &[0.5, 0.5], &[0.7]));
}

/// A triangle resting across two faces, whose clipped contact has a corner in line with the
/// footprint's edge to within rounding (seed 2 of the rider pricing test): the margin is that
/// of the contact's hull, not "no support" (a hull refused as having collinear corners).
#[test]
fn a_contact_with_corners_nearly_in_line_still_has_its_margin() {
    let p = |v: &[[f64; 2]]| {
        ConvexPolygon::new(v.iter().map(|a| Point2::new(a[0], a[1])).collect()).unwrap()
    };
    let tops = vec![
        p(&[
            [0.5420246501163011, 0.10768583498525439],
            [0.547084645236654, 0.09569308578829387],
            [0.5596158095698713, 0.09217179172451079],
            [0.5701819209148725, 0.09977356037263253],
            [0.5708264818327576, 0.1127741036639446],
            [0.5610641248564424, 0.12138374836053449],
            [0.5482461038696261, 0.11911925516971496],
        ]),
        p(&[
            [0.5575325820576622, 0.14776036244871374],
            [0.576980642244009, 0.10829172990351106],
            [0.5949989996062615, 0.13054793798049855],
            [0.5861589722488311, 0.1484882255010452],
        ]),
    ];
    let footprint = p(&[
        [0.5959695953260712, 0.1232220601510629],
        [0.556132426751987, 0.1462220601510629],
        [0.558988833212538, 0.11916950126780526],
    ]);
    let margin = standing_margin(&tops, &footprint);
    // The centroid lies inside the contact's hull: a finite, positive margin.
    assert!(margin.is_finite() && margin > 0.0, "{margin}");
}

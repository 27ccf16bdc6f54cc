//! The time model's charges checked command by command.

use super::*;

#[test]
fn moves_follow_a_trapezoid() {
    let model = TimeModel::default();
    // Long move: cruise plus one ramp time.
    assert!((model.move_seconds(0.3) - (0.3 / 0.25 + 0.25 / 1.2)).abs() < 1e-12);
    // Short move: a triangle.
    assert!((model.move_seconds(0.01) - 2.0 * (0.01f64 / 1.2).sqrt()).abs() < 1e-12);
    // The two meet at d = v²/a.
    let knee = 0.25 * 0.25 / 1.2;
    assert!((model.move_seconds(knee) - 2.0 * (knee / 1.2).sqrt()).abs() < 1e-12);
}

#[test]
fn a_push_is_cheaper_than_a_trip_by_default() {
    let (model, gripper) = (TimeModel::default(), Gripper::default());
    assert!(model.nominal_push_seconds(&gripper, 0.05) < model.nominal_trip_seconds(&gripper));
}

#[test]
fn the_nominal_trip_has_seven_commands_and_six_stops() {
    let gripper = Gripper::default();
    let settle_free = |model: &TimeModel| TimeModel {
        arm_settle: 0.0,
        gripper_settle: 0.0,
        ..model.clone()
    };
    // As the real cell moved: every command stops.
    let stopping = TimeModel {
        blend_free_moves: false,
        ..TimeModel::default()
    };
    let with = stopping.nominal_trip_seconds(&gripper);
    let without = settle_free(&stopping).nominal_trip_seconds(&gripper);
    assert!((with - without - 7.0 * FITTED_SETTLE).abs() < 1e-12);
    let fitted = TimeModel::default().fit_settle(with).unwrap_or(f64::NAN);
    assert!((fitted - FITTED_SETTLE).abs() < 1e-12);
    // Blending, the lift flows into the run to the bin: the same motion, one settle fewer.
    let blending = TimeModel::default();
    let with = blending.nominal_trip_seconds(&gripper);
    let without = settle_free(&blending).nominal_trip_seconds(&gripper);
    assert!((with - without - 6.0 * FITTED_SETTLE).abs() < 1e-12);
    assert_eq!(
        without,
        settle_free(&stopping).nominal_trip_seconds(&gripper)
    );
}

#[test]
fn a_blended_push_saves_two_stops_unless_a_look_follows_it() {
    let (blending, gripper) = (TimeModel::default(), Gripper::default());
    let stopping = TimeModel {
        blend_free_moves: false,
        ..blending.clone()
    };
    let grasp = TimeModel::nominal_grasp(&gripper);
    let push = |y: f64, look_after: bool| PushPath {
        approach: Point2::new(0.0, y + 0.02),
        end: Point2::new(0.0, y),
        opening: gripper.fork_push_opening(),
        look_after,
    };
    let added = |model: &TimeModel, pushes: &[PushPath]| {
        model.trip_seconds(&gripper, pushes, &grasp) - model.trip_seconds(&gripper, &[], &grasp)
    };
    let pushes = [push(0.0, false), push(0.1, false)];
    let saved = added(&stopping, &pushes) - added(&blending, &pushes);
    // Travel and rise of each push flow on: two settles a push.
    assert!((saved - 4.0 * FITTED_SETTLE).abs() < 1e-9, "{saved}");
    // A look after the second push: its rise stops.
    let looked = [push(0.0, false), push(0.1, true)];
    let saved = added(&stopping, &looked) - added(&blending, &looked);
    assert!((saved - 3.0 * FITTED_SETTLE).abs() < 1e-9, "{saved}");
    // So does a rise followed by a jaw command (a push at another opening).
    let narrow = PushPath {
        opening: gripper.plate_thickness + 0.002,
        ..push(0.1, false)
    };
    let reopened = [push(0.0, false), narrow];
    let saved = added(&stopping, &reopened) - added(&blending, &reopened);
    assert!((saved - 3.0 * FITTED_SETTLE).abs() < 1e-9, "{saved}");
    // The planning estimate of a later push is the trip's commands but for where it travels:
    // here 0.12 m to its approach (the estimate: its length, 0.02 m), and the grasp 0.1 m away.
    let later = blending.nominal_later_push_seconds(0.02);
    let one = added(&blending, &pushes[..1]);
    let two = added(&blending, &pushes);
    let travel =
        blending.move_seconds(0.12) - blending.move_seconds(0.02) + blending.move_seconds(0.1);
    assert!(
        (two - one - later - travel).abs() < 1e-9,
        "{}",
        two - one - later
    );
}

#[test]
fn travel_inside_the_workspace_counts_between_actions() {
    let (model, gripper) = (TimeModel::default(), Gripper::default());
    let grasp = TimeModel::nominal_grasp(&gripper);
    let near = PushPath {
        approach: Point2::new(0.0, 0.02),
        end: Point2::new(0.0, 0.01),
        opening: gripper.fork_push_opening(),
        look_after: false,
    };
    let far = PushPath {
        approach: Point2::new(0.0, 0.30),
        end: Point2::new(0.0, 0.29),
        opening: gripper.fork_push_opening(),
        look_after: false,
    };
    assert!(
        model.trip_seconds(&gripper, &[far], &grasp)
            > model.trip_seconds(&gripper, &[near], &grasp)
    );
}

#[test]
fn only_the_first_of_several_fork_pushes_moves_the_jaws() {
    let (model, gripper) = (TimeModel::default(), Gripper::default());
    let grasp = TimeModel::nominal_grasp(&gripper);
    let push = |y: f64| PushPath {
        approach: Point2::new(0.0, y + 0.01),
        end: Point2::new(0.0, y),
        opening: gripper.fork_push_opening(),
        look_after: false,
    };
    let jaw_commands = |pushes: &[PushPath]| {
        model
            .trip_commands(&gripper, pushes, &grasp)
            .iter()
            .filter(|c| matches!(c, Command::Jaws(_)))
            .count()
    };
    // The grasp's three jaw commands, plus one for the first push only.
    assert_eq!(jaw_commands(&[]), 3);
    assert_eq!(jaw_commands(&[push(0.0)]), 4);
    assert_eq!(jaw_commands(&[push(0.0), push(0.05), push(0.1)]), 4);
    // A push at another opening (a separating push, jaws nearly closed) moves them again.
    let narrow = PushPath {
        opening: gripper.plate_thickness + 0.002,
        ..push(0.2)
    };
    assert_eq!(jaw_commands(&[push(0.0), narrow]), 5);
    // The estimate of a later push is the first push's without its jaw command.
    let jaw =
        (gripper.stroke - gripper.fork_push_opening()) / model.jaw_speed + model.gripper_settle;
    let (first, later) = (
        model.nominal_push_seconds(&gripper, 0.04),
        model.nominal_later_push_seconds(0.04),
    );
    assert!((first - later - jaw).abs() < 1e-12);
}

#[test]
fn a_rider_costs_its_pick_and_its_release_before_the_grasp() {
    let (model, gripper) = (TimeModel::default(), Gripper::default());
    let grasp = GraspPath {
        center: Point2::new(0.0, 0.0),
        ..TimeModel::nominal_grasp(&gripper)
    };
    let rider = RiderPath {
        pick: GraspPath {
            center: Point2::new(0.1, 0.0),
            ..TimeModel::nominal_grasp(&gripper)
        },
        release: Point2::new(0.0, 0.02),
    };
    let without = model.trip_commands_with_riders(&gripper, &[], &[], &grasp);
    let with = model.trip_commands_with_riders(&gripper, &[], &[rider], &grasp);
    // Nine commands: travel, jaws, descend, close, lift (blended), travel over the row, descend,
    // open, rise (blended); seven of them stop.
    assert_eq!(with.len(), without.len() + 9);
    let stops = |commands: &[Command]| {
        commands
            .iter()
            .filter(|c| !matches!(c, Command::Through(_)))
            .count()
    };
    assert_eq!(stops(&with), stops(&without) + 7);
    assert!(
        model.seconds(&with) - model.seconds(&without) > 6.0 * model.arm_settle,
        "{}",
        model.seconds(&with) - model.seconds(&without)
    );
}

#[test]
fn a_look_during_a_trip_moves_the_arm_out_of_view_and_back_when_asked() {
    let gripper = Gripper::default();
    let grasp = GraspPath {
        center: Point2::new(0.2, 0.0),
        ..TimeModel::nominal_grasp(&gripper)
    };
    let push = |look_after: bool| PushPath {
        approach: Point2::new(0.0, 0.05),
        end: Point2::new(0.0, 0.0),
        opening: gripper.fork_push_opening(),
        look_after,
    };
    let staying = TimeModel::default();
    let leaving = TimeModel {
        look_away: 0.3,
        ..TimeModel::default()
    };
    // Without a look the setting changes nothing.
    assert_eq!(
        leaving.trip_commands(&gripper, &[push(false)], &grasp),
        staying.trip_commands(&gripper, &[push(false)], &grasp)
    );
    // With one: a stopping move of 0.3 m after the rise, and the travel to the grasp is 0.3 m
    // instead of the 0.2 m from the push's end.
    let stay = staying.trip_commands(&gripper, &[push(true)], &grasp);
    let leave = leaving.trip_commands(&gripper, &[push(true)], &grasp);
    assert_eq!(leave.len(), stay.len() + 1);
    let rise = stay
        .iter()
        .position(|c| matches!(c, Command::Push(_)))
        .map_or(0, |k| k + 1);
    assert_eq!(leave[..=rise], stay[..=rise]);
    assert_eq!(leave[rise + 1], Command::Arm(0.3));
    assert_eq!(stay[rise + 1], Command::Arm(0.2));
    assert_eq!(leave[rise + 2], Command::Arm(0.3));
    assert_eq!(leave[rise + 3..], stay[rise + 2..]);
    // The planning estimate of the extra: the move there with its settle, and the way back.
    let extra = leaving.seconds(&leave) - leaving.seconds(&stay);
    let expected = leaving.move_seconds(0.3) + leaving.arm_settle + leaving.move_seconds(0.3)
        - leaving.move_seconds(0.2);
    assert!((extra - expected).abs() < 1e-12, "{extra}");
    assert!(leaving.look_away_seconds() > extra);
    assert_eq!(staying.look_away_seconds(), 0.0);
}

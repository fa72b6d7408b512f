//! The obstacle-type grid's rules, one at a time, on a 10 × 10 grid of 0.1 m cells.
//!
//! The sensor sits at (0.05, 0.55), in cell (0, 5), and looks along +x down row 5 unless a test says
//! otherwise; a hit at x = k + 0.05 (tenths) lands in cell (k, 5).

use nalgebra::Point2;
use nudge_perception::ObjectId;
use nudge_perception::grid::{
    CellClass, CellIndex, Evidence, Footprint, GridConfig, GridError, GridGeometry, ObstacleGrid,
    RangeFrame, Rule, Verdict,
};

const ROW: f64 = 0.55;

fn grid() -> ObstacleGrid {
    let geom =
        GridGeometry::with_cells(Point2::new(0.0, 0.0), 10, 10, 0.1).expect("valid geometry");
    // Small cells: motion steps and radii in this grid's scale.
    let cfg = GridConfig {
        moving_step: 0.1,
        rest_radius: 0.3,
        clear_margin: 0.3,
        clear_tail: 0.0,
        free_gap: 0.0,
        appear_gap: 0.06,
    };
    ObstacleGrid::new(geom, cfg)
}

fn sensor() -> Point2<f64> {
    Point2::new(0.05, ROW)
}

/// A frame with one beam down row 5 ending in a hit at cell column `k`.
fn hit_at(k: u32) -> RangeFrame {
    let mut f = RangeFrame::new(sensor()).expect("finite sensor");
    f.push_hit(Point2::new(k as f64 / 10.0 + 0.05, ROW));
    f
}

/// A frame with one clear beam down row 5 to the far edge.
fn clear_row() -> RangeFrame {
    let mut f = RangeFrame::new(sensor()).expect("finite sensor");
    f.push_clear(Point2::new(0.99, ROW));
    f
}

/// A frame that sees nothing in row 5 (one clear beam along column 0 only).
fn look_away() -> RangeFrame {
    let mut f = RangeFrame::new(sensor()).expect("finite sensor");
    f.push_clear(Point2::new(0.05, 0.01));
    f
}

fn c(x: u32) -> CellIndex {
    CellIndex::new(x, 5)
}

fn run(g: &mut ObstacleGrid, frames: &[RangeFrame]) {
    let t0 = g.frames() as f64;
    for (k, f) in frames.iter().enumerate() {
        g.update(f, t0 + k as f64).expect("in-order finite stamps");
    }
}

fn evidence(g: &ObstacleGrid, cell: CellIndex) -> Evidence {
    g.cell(cell).expect("in grid").evidence
}

#[test]
fn visible_area_is_free_and_the_return_cell_is_not() {
    // Invariant (Tamura 3.1): cells crossed by a ray are free; the return's cell is not.
    let mut g = grid();
    run(&mut g, &[hit_at(6)]);
    for x in 0..6 {
        assert_eq!(g.class(c(x)), Some(CellClass::Free), "cell {x}");
        assert_eq!(evidence(&g, c(x)), Evidence::Passive(Rule::SeenFree));
    }
    assert_eq!(g.class(c(6)), Some(CellClass::Unknown));
    assert_eq!(evidence(&g, c(6)), Evidence::Passive(Rule::Tentative));
    assert_eq!(g.class(c(7)), Some(CellClass::Unknown));
    assert_eq!(g.class(CellIndex::new(3, 4)), Some(CellClass::Unknown));
}

#[test]
fn a_return_where_last_frame_saw_free_space_is_moving() {
    // Invariant (Tamura 3.1): seen free (well before the ray's return) in V_{t−1} + return at t ⇒ Moving.
    let mut g = grid();
    run(&mut g, &[clear_row(), hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Moving));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::Moving));
}

#[test]
fn a_return_in_free_space_seen_only_earlier_is_not_moving() {
    // Invariant: the visible areas of the last three frames count (the cell unseen in between), not
    // older ones: three frames without a look at the cell make the return tentative.
    let mut g = grid();
    run(&mut g, &[clear_row(), look_away(), look_away(), hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Moving));
    let mut g = grid();
    let away = look_away();
    run(
        &mut g,
        &[clear_row(), away.clone(), away.clone(), away, hit_at(5)],
    );
    assert_eq!(g.class(c(5)), Some(CellClass::Unknown));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::Tentative));
}

#[test]
fn a_return_next_to_last_frames_return_is_not_moving() {
    // Invariant (8-neighbour guard): a return beside last frame's return (a grazed wall) is not moving.
    let mut g = grid();
    // Frame 1: the beam ends in (6,5) and crosses (5,5). Frame 2: the return is in (5,5).
    run(&mut g, &[hit_at(6), hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Unknown));
}

#[test]
fn three_frames_of_the_same_return_make_it_stationary() {
    // Invariant (Tamura 3.3, Chen 2.3): temporarily stationary at t−2, t−1 and t ⇒ Stationary, not before.
    let mut g = grid();
    run(&mut g, &[hit_at(8), hit_at(8)]);
    assert_eq!(g.class(c(8)), Some(CellClass::Unknown));
    run(&mut g, &[hit_at(8)]);
    assert_eq!(g.class(c(8)), Some(CellClass::Stationary));
    assert_eq!(evidence(&g, c(8)), Evidence::Passive(Rule::Stationary));
}

#[test]
fn one_cell_of_jitter_still_makes_stationary() {
    // Invariant (Chen 2.4): returns moving within the 8-neighbourhood between frames still count.
    let mut g = grid();
    run(&mut g, &[hit_at(8), hit_at(9), hit_at(8)]);
    assert_eq!(g.class(c(8)), Some(CellClass::Stationary));
}

#[test]
fn something_that_moved_and_then_rests_becomes_movable() {
    // Invariant (Tamura 3.2.1): moving at t−1, in place since → Movable by addition, never Stationary.
    let mut g = grid();
    run(&mut g, &[clear_row(), clear_row(), hit_at(6)]);
    assert_eq!(g.class(c(6)), Some(CellClass::Moving));
    // It comes one cell closer: the moving obstacle went on (continued, not a new fresh return).
    run(&mut g, &[hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Moving));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::MovingContinued));
    // Now it stays: returned around it at t−1 and t−2, no other motion ⇒ movable.
    run(&mut g, &[hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::MovableAddition));
    // Retention (3.2.2): it stays movable however long it rests.
    run(&mut g, &[hit_at(5), hit_at(5), hit_at(5), hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
    assert_eq!(
        evidence(&g, c(5)),
        Evidence::Passive(Rule::MovableRetention)
    );
}

#[test]
fn a_resting_thing_next_to_ongoing_motion_stays_moving() {
    // Invariant: the rest test fails while other motion lies within rest_radius in the same frame.
    let mut g = grid();
    let two = |a: u32, b: f64| {
        let mut f = hit_at(a);
        f.push_hit(Point2::new(b, 0.75));
        f
    };
    let mut f1 = clear_row();
    f1.push_clear(Point2::new(0.99, 0.75));
    // The row-5 thing arrives at 7, goes on to 6 and rests; a thing two rows up keeps moving towards
    // the sensor.
    run(
        &mut g,
        &[
            f1.clone(),
            f1.clone(),
            two(7, 0.95),
            two(6, 0.85),
            two(6, 0.75),
        ],
    );
    assert_eq!(g.class(CellIndex::new(7, 7)), Some(CellClass::Moving));
    assert_eq!(g.class(c(6)), Some(CellClass::Moving), "motion 0.22 m away");
    // Without the other motion the same history rests: movable.
    let mut g = grid();
    run(
        &mut g,
        &[f1.clone(), f1.clone(), hit_at(7), hit_at(6), hit_at(6)],
    );
    assert_eq!(g.class(c(6)), Some(CellClass::Movable));
    // A return that appears in free space and stays in its cell, never going on, is a blip (a grazed
    // wall's return looks just so): not movable, it goes to the stationary test.
    let mut g = grid();
    run(&mut g, &[f1.clone(), f1, hit_at(6), hit_at(6), hit_at(6)]);
    assert_eq!(g.class(c(6)), Some(CellClass::Unknown));
}

#[test]
fn a_movable_seen_free_is_deleted() {
    // Invariant (Tamura 3.2.3): a movable cell crossed well before the return is Free again.
    let mut g = grid();
    run(
        &mut g,
        &[clear_row(), clear_row(), hit_at(6), hit_at(5), hit_at(5)],
    );
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
    run(&mut g, &[clear_row()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Free));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::MovableDeletion));
}

#[test]
fn a_movable_out_of_view_is_kept() {
    // Invariant (Tamura 3.2.3): movable cells outside the visible area stay movable.
    let mut g = grid();
    run(
        &mut g,
        &[clear_row(), clear_row(), hit_at(6), hit_at(5), hit_at(5)],
    );
    run(&mut g, &[look_away(), look_away(), look_away()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
}

#[test]
fn a_movable_crossed_just_before_a_return_is_kept() {
    // Invariant: a crossing within clear_margin of the return (a grazing ray) does not delete.
    let mut g = grid();
    run(
        &mut g,
        &[clear_row(), clear_row(), hit_at(6), hit_at(5), hit_at(5)],
    );
    // A ray ending 0.2 m past cell 5 (return in cell 7) crosses it inside the 0.3 m margin.
    run(&mut g, &[hit_at(7)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
}

#[test]
fn moving_cells_no_longer_returned_and_unseen_expire_to_unknown() {
    // Invariant: moving is not remembered out of view: Unknown (MovingExpired), or Free if seen free.
    let mut g = grid();
    run(&mut g, &[clear_row(), clear_row(), hit_at(5), look_away()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Unknown));
    assert_eq!(evidence(&g, c(5)), Evidence::Passive(Rule::MovingExpired));
    let mut g = grid();
    run(&mut g, &[clear_row(), clear_row(), hit_at(5), clear_row()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Free));
}

#[test]
fn stationary_cells_clear_only_when_seen_through_twice() {
    // Invariant: a wall cell crossed near a return keeps its class; two far crossings clear it.
    let mut g = grid();
    run(&mut g, &[hit_at(5), hit_at(5), hit_at(5)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Stationary));
    run(&mut g, &[hit_at(7), hit_at(7)]);
    assert_eq!(g.class(c(5)), Some(CellClass::Stationary), "near crossings");
    run(&mut g, &[clear_row()]);
    assert_eq!(
        g.class(c(5)),
        Some(CellClass::Stationary),
        "one far crossing"
    );
    run(&mut g, &[clear_row()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Free));
    assert_eq!(
        evidence(&g, c(5)),
        Evidence::Passive(Rule::StationaryCleared)
    );
}

#[test]
fn cells_out_of_view_keep_their_class_and_age() {
    // Invariant (Tamura 3.2.3 memory): unobserved cells keep class; age = now − last observation.
    let mut g = grid();
    run(&mut g, &[hit_at(5), hit_at(5), hit_at(5)]);
    let seen_at = 2.0;
    assert_eq!(g.age(c(5), seen_at), Some(0.0));
    run(&mut g, &[look_away(), look_away()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Stationary));
    assert_eq!(g.age(c(5), 10.0), Some(10.0 - seen_at));
    assert_eq!(g.age(CellIndex::new(9, 9), 10.0), None, "never seen");
    assert_eq!(g.age(CellIndex::new(10, 0), 10.0), None, "outside");
}

#[test]
fn active_verdicts_outrank_passive_rules() {
    // Invariant: a marked cell keeps class and evidence under returns and near crossings.
    let mut g = grid();
    let id = ObjectId(3);
    run(&mut g, &[clear_row()]);
    let n = g
        .mark_object(id, Footprint::Cells(&[c(5)]), Verdict::Static, 17, 1.5)
        .expect("valid mark");
    assert_eq!(n, 1);
    // Returns on it: the moving rule would fire on a passive free cell; here nothing changes.
    run(&mut g, &[hit_at(5), hit_at(5), hit_at(7)]);
    let info = g.cell(c(5)).expect("in grid");
    assert_eq!(info.class, CellClass::Stationary);
    assert_eq!(info.object, Some(id));
    assert_eq!(
        info.evidence,
        Evidence::Active {
            object: id,
            push_test: 17
        }
    );
    assert_eq!(g.object_cells(id), vec![c(5)]);
    assert_eq!(g.verdict(id), Some((Verdict::Static, 17)));
}

#[test]
fn active_cells_seen_through_twice_go_back_to_passive() {
    // Invariant: the object provably gone (two far crossings, nothing around) frees an active cell.
    let mut g = grid();
    let id = ObjectId(4);
    g.mark_object(id, Footprint::Cells(&[c(5)]), Verdict::Movable, 2, 0.0)
        .expect("valid mark");
    run(&mut g, &[clear_row()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Movable));
    run(&mut g, &[clear_row()]);
    assert_eq!(g.class(c(5)), Some(CellClass::Free));
    assert!(g.object_cells(id).is_empty());
}

#[test]
fn a_confirmed_push_clears_the_old_footprint_and_writes_the_new() {
    // Invariant: object_moved frees the old cells (even unseen ones) and marks the new ones Movable.
    let mut g = grid();
    let id = ObjectId(9);
    let square = |x0: f64, y0: f64| {
        [
            Point2::new(x0, y0),
            Point2::new(x0 + 0.2, y0),
            Point2::new(x0 + 0.2, y0 + 0.2),
            Point2::new(x0, y0 + 0.2),
        ]
    };
    let (old, new) = (square(0.21, 0.21), square(0.61, 0.21));
    let n = g
        .mark_object(id, Footprint::Polygon(&old), Verdict::Movable, 5, 1.0)
        .expect("valid mark");
    assert_eq!(n, 9, "a 0.2 m square from 0.21 spans cells 2..4");
    g.object_moved(id, Footprint::Polygon(&old), Footprint::Polygon(&new), 2.0)
        .expect("known object");
    let cells = g.object_cells(id);
    assert_eq!(cells.len(), 9);
    assert!(
        cells
            .iter()
            .all(|c| (6..=8).contains(&c.x) && (2..=4).contains(&c.y))
    );
    let freed = g.cell(CellIndex::new(2, 2)).expect("in grid");
    assert_eq!(freed.class, CellClass::Free);
    assert_eq!(
        freed.evidence,
        Evidence::Active {
            object: id,
            push_test: 5
        }
    );
    assert_eq!(freed.object, None, "a free cell belongs to no object");
    assert_eq!(g.class(CellIndex::new(7, 3)), Some(CellClass::Movable));
    assert_eq!(g.age(CellIndex::new(7, 3), 2.5), Some(0.5));
    // Cells moved over are overlap-safe: (4,y) was old and is not new, so it is free.
    assert_eq!(g.class(CellIndex::new(4, 3)), Some(CellClass::Free));
}

#[test]
fn bad_active_inputs_are_errors() {
    // Invariant: unknown objects, the reserved id, oversized push tests and NaN times are refused.
    let mut g = grid();
    let fp = Footprint::Cells(&[]);
    assert_eq!(
        g.object_moved(ObjectId(1), fp, fp, 0.0),
        Err(GridError::UnknownObject(ObjectId(1)))
    );
    assert!(
        g.mark_object(ObjectId(u32::MAX), fp, Verdict::Static, 0, 0.0)
            .is_err()
    );
    assert!(
        g.mark_object(ObjectId(1), fp, Verdict::Static, u32::MAX, 0.0)
            .is_err()
    );
    assert!(
        g.mark_object(ObjectId(1), fp, Verdict::Static, 0, f64::NAN)
            .is_err()
    );
}

#[test]
fn watched_cells_turning_into_obstacles_raise_the_replan_flag_once() {
    // Invariant (Lopez-Perez 2.2): a watched cell turning Moving raises the flag; take clears it.
    let mut g = grid();
    g.set_watched_path(&[c(4), c(5)]);
    run(&mut g, &[clear_row(), clear_row()]);
    assert_eq!(g.take_replan_flag(), None, "free cells do not raise it");
    run(&mut g, &[hit_at(5)]);
    let r = g.take_replan_flag().expect("flag raised");
    assert_eq!(
        (r.cell, r.was, r.became, r.cells),
        (c(5), CellClass::Free, CellClass::Moving, 1)
    );
    assert_eq!(g.take_replan_flag(), None);
    // Unwatched cells do not raise it.
    g.set_watched_path(&[]);
    run(&mut g, &[clear_row(), clear_row(), hit_at(3)]);
    assert_eq!(g.class(c(3)), Some(CellClass::Moving));
    assert_eq!(g.take_replan_flag(), None);
}

#[test]
fn frames_out_of_clock_order_or_with_bad_stamps_are_refused() {
    // Invariant: stamps must be finite and non-decreasing; a refused frame changes nothing.
    let mut g = grid();
    g.update(&hit_at(5), 2.0).expect("first frame");
    let before = g.class_codes().to_vec();
    assert!(matches!(
        g.update(&clear_row(), 1.0),
        Err(GridError::TimeWentBack { .. })
    ));
    assert_eq!(g.update(&clear_row(), f64::NAN), Err(GridError::NonFinite));
    assert_eq!(g.class_codes(), &before[..]);
    assert_eq!(g.frames(), 1);
}

#[test]
fn queries_answer_by_point_path_and_raw_codes() {
    // Invariant: class_at, cells along a path with a radius, and the raw codes agree with the cells.
    let mut g = grid();
    run(&mut g, &[hit_at(6)]);
    assert_eq!(g.class_at(Point2::new(0.33, ROW)), Some(CellClass::Free));
    assert_eq!(g.class_at(Point2::new(5.0, ROW)), None);
    let codes = g.class_codes();
    assert_eq!(codes.len(), 100);
    assert_eq!(codes[5 * 10 + 3], CellClass::Free.code());
    let path = [Point2::new(0.05, 0.55), Point2::new(0.95, 0.55)];
    let thin = g.cells_along_path(&path, 0.0);
    assert_eq!(thin, (0..10).map(c).collect::<Vec<_>>());
    let wide = g.cells_along_path(&path, 0.1);
    assert_eq!(
        wide.len(),
        30,
        "rows 4–6: their squares are within 0.1 m of the path"
    );
    let classes = g.classes_along_path(&path, 0.0);
    assert_eq!(classes[2], (c(2), CellClass::Free));
    assert_eq!(classes[6], (c(6), CellClass::Unknown));
    assert_eq!(g.class_counts()[CellClass::Free.code() as usize], 6);
}

#[test]
fn the_snapshot_has_one_pixel_per_cell_north_up() {
    // Invariant: pixel (x, h−1−y) has the colour of cell (x, y); the palette is per class.
    let mut g = grid();
    run(&mut g, &[clear_row(), clear_row(), hit_at(5)]);
    let img = g.to_rgba_image();
    assert_eq!(img.dimensions(), (10, 10));
    assert_eq!(img.get_pixel(5, 4).0, CellClass::Moving.colour());
    assert_eq!(img.get_pixel(2, 4).0, CellClass::Free.colour());
    assert_eq!(img.get_pixel(2, 5).0, CellClass::Unknown.colour());
    let path = std::env::temp_dir().join(format!("nudge-grid-{}.png", std::process::id()));
    g.write_png(&path).expect("temp dir is writable");
    let back = image::open(&path).expect("a PNG was written").to_rgba8();
    assert_eq!(back, img);
    let _ = std::fs::remove_file(&path);
}

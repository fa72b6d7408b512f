//! Colour ICP accuracy on synthetic pushes of a textured chair and a flat panel.

mod common;

use common::{chair, look_at, object_points, object_points_occluded, panel, planar};
use nalgebra::{Isometry3, Point3, Translation3, UnitQuaternion};
use nudge_perception::icp::initial_from_centroids;
use nudge_perception::{ColourCloud, IcpConfig, IcpResult, colour_icp};

const CHAIR_X: f64 = 3.8;
const CHAIR_Y: f64 = 0.85;

fn eye() -> Isometry3<f64> {
    // The robot's head, behind and to the side of the chair: only the near faces are visible.
    look_at(Point3::new(2.9, 0.3, 1.45), Point3::new(3.9, 0.85, 0.45))
}

/// Position and angle error of `result` against the true motion, at the before-cloud's centroid.
fn errors(result: &IcpResult, truth: &Isometry3<f64>, before: &ColourCloud) -> (f64, f64) {
    let c = before.centroid().expect("points");
    let pos_mm = ((result.transform * c) - (truth * c)).norm() * 1000.0;
    let ang_deg = (result.transform.rotation * truth.rotation.inverse())
        .angle()
        .to_degrees();
    (pos_mm, ang_deg)
}

fn push_case(push_m: f64, yaw_deg: f64, guess_error: f64, seed: u64) -> (f64, f64, IcpResult) {
    let start = planar(CHAIR_X, CHAIR_Y, 0.0);
    let end = planar(
        CHAIR_X + push_m,
        CHAIR_Y + 0.1 * push_m * 0.1,
        yaw_deg.to_radians(),
    );
    let truth = end * start.inverse();
    let before = object_points(&chair("chair", start, [40, 90, 160]), &eye(), seed);
    let after = object_points(&chair("chair", end, [40, 90, 160]), &eye(), seed + 1000);
    // The executive's guess: the hand's travel along x, off by `guess_error` of the push.
    let guess = Isometry3::translation(push_m * (1.0 + guess_error), 0.0, 0.0);
    let result = colour_icp(&before, &after, &guess, &IcpConfig::default()).expect("enough points");
    let (pos, ang) = errors(&result, &truth, &before);
    (pos, ang, result)
}

#[test]
fn chair_pushes_from_20_to_800_mm_are_recovered_within_2_mm_and_0_2_degrees() {
    // Invariant: with a guess off by 15 % of the push, the chair's displacement is found within 2 mm
    // and 0.2° for pushes of 20–800 mm with up to 5° of yaw.
    for (k, (push, yaw)) in [
        (0.02, 0.0),
        (0.05, 1.0),
        (0.1, 2.0),
        (0.2, -2.5),
        (0.4, 3.0),
        (0.6, -4.0),
        (0.8, 5.0),
    ]
    .into_iter()
    .enumerate()
    {
        let (pos, ang, r) = push_case(push, yaw, -0.15, 10 + k as u64);
        eprintln!(
            "push {:>4.0} mm yaw {yaw:>4.1}°: error {pos:.2} mm {ang:.3}°, fitness {:.2}, rmse {:.1} mm, {} it",
            push * 1000.0,
            r.fitness,
            r.rmse * 1000.0,
            r.iterations
        );
        assert!(pos < 2.0, "push {push}: {pos} mm");
        assert!(ang < 0.2, "push {push}: {ang}°");
    }
}

#[test]
fn a_long_push_converges_from_guesses_off_by_10_and_20_percent_either_way() {
    // Invariant: the 800 mm push is recovered within 2 mm / 0.2° from guesses 10–20 % off.
    for (k, off) in [-0.2, -0.1, 0.1, 0.2].into_iter().enumerate() {
        let (pos, ang, _) = push_case(0.8, 3.0, off, 40 + k as u64);
        eprintln!(
            "800 mm, guess off {:+.0} %: {pos:.2} mm {ang:.3}°",
            off * 100.0
        );
        assert!(pos < 2.0 && ang < 0.2, "guess off {off}: {pos} mm {ang}°");
    }
}

#[test]
fn without_a_guess_centroid_alignment_recovers_moderate_pushes() {
    // Invariant: with no guess (centroid alignment) a 200 mm push is still recovered within 2 mm.
    let start = planar(CHAIR_X, CHAIR_Y, 0.0);
    let end = planar(CHAIR_X + 0.2, CHAIR_Y, 2f64.to_radians());
    let truth = end * start.inverse();
    let before = object_points(&chair("chair", start, [40, 90, 160]), &eye(), 60);
    let after = object_points(&chair("chair", end, [40, 90, 160]), &eye(), 61);
    let guess = initial_from_centroids(&before, &after).expect("points");
    let r = colour_icp(&before, &after, &guess, &IcpConfig::default()).expect("enough points");
    let (pos, ang) = errors(&r, &truth, &before);
    eprintln!("200 mm without guess: {pos:.2} mm {ang:.3}°");
    assert!(pos < 2.0 && ang < 0.2, "{pos} mm {ang}°");
}

#[test]
fn a_static_object_reads_under_3_mm() {
    // Invariant: pushing a static object (same pose, fresh noise) reads a displacement under 3 mm.
    let pose = planar(CHAIR_X, CHAIR_Y, 0.0);
    let before = object_points(&chair("chair", pose, [40, 90, 160]), &eye(), 70);
    let after = object_points(&chair("chair", pose, [40, 90, 160]), &eye(), 71);
    let r = colour_icp(
        &before,
        &after,
        &Isometry3::identity(),
        &IcpConfig::default(),
    )
    .expect("enough points");
    eprintln!("static: {:.2} mm, {:.3}° yaw", r.distance_mm(), r.yaw_deg);
    assert!(r.distance_mm() < 3.0, "{} mm", r.distance_mm());
}

#[test]
fn partial_overlap_from_an_arm_in_front_still_gives_the_push() {
    // Invariant: when the arm hides a block of the after-view, the push is still recovered within 2 mm.
    let start = planar(CHAIR_X, CHAIR_Y, 0.0);
    let end = planar(CHAIR_X + 0.2, CHAIR_Y, 1f64.to_radians());
    let truth = end * start.inverse();
    let before = object_points(&chair("chair", start, [40, 90, 160]), &eye(), 80);
    let after = object_points_occluded(
        &chair("chair", end, [40, 90, 160]),
        &eye(),
        81,
        60..110,
        40..144,
    );
    assert!(after.len() < before.len());
    let guess = Isometry3::translation(0.17, 0.0, 0.0);
    let r = colour_icp(&before, &after, &guess, &IcpConfig::default()).expect("enough points");
    let (pos, ang) = errors(&r, &truth, &before);
    eprintln!(
        "occluded: {pos:.2} mm {ang:.3}° ({} of {} points left), fitness {:.2}",
        after.len(),
        before.len(),
        r.fitness
    );
    assert!(pos < 2.0 && ang < 0.2, "{pos} mm {ang}°");
}

fn panel_case(config: &IcpConfig, guess_mm: f64) -> (f64, IcpResult) {
    panel_case_of_width(config, guess_mm, 3.0)
}

fn panel_case_of_width(config: &IcpConfig, guess_mm: f64, width: f64) -> (f64, IcpResult) {
    // The panel stands facing the sensor 1.2 m away; it slides 100 mm along its own plane (map y).
    // 3 m wide, its edges are out of view: nothing but texture shows the slide.
    let start = planar(2.0, 0.0, 0.0);
    let end = Isometry3::from_parts(Translation3::new(2.0, 0.1, 0.0), UnitQuaternion::identity());
    let view = look_at(Point3::new(0.8, 0.05, 0.5), Point3::new(2.0, 0.05, 0.5));
    let before = object_points(&panel("panel", start, width), &view, 90);
    let after = object_points(&panel("panel", end, width), &view, 91);
    let guess = Isometry3::translation(0.0, guess_mm / 1000.0, 0.0);
    let r = colour_icp(&before, &after, &guess, config).expect("enough points");
    (r.translation_mm.y, r)
}

#[test]
fn geometry_alone_cannot_see_a_slide_along_a_flat_panel() {
    // Invariant: point-to-plane ICP without colour does not move along the panel: from no guess it
    // reads about 0, from a guess 15 mm short it stays about there (it cannot correct it).
    let (slide, r) = panel_case(&IcpConfig::geometric_only(), 0.0);
    eprintln!(
        "geometric-only slide from 0: {slide:.1} mm ({:?})",
        r.translation_mm
    );
    assert!(slide.abs() < 15.0, "geometric ICP read {slide} mm");
    let (slide, _) = panel_case(&IcpConfig::geometric_only(), 85.0);
    eprintln!("geometric-only slide from 85 mm: {slide:.1} mm");
    assert!(
        (slide - 100.0).abs() > 10.0,
        "geometric ICP read {slide} mm"
    );
}

#[test]
fn colour_icp_reads_a_100_mm_slide_along_a_flat_panel_within_5_mm() {
    // Invariant: from the hand's guess (15 % short) the photometric term recovers the in-plane slide the
    // geometry cannot see, within 5 mm.
    let (slide, r) = panel_case(&IcpConfig::default(), 85.0);
    eprintln!(
        "colour slide: {slide:.1} mm ({:?}), {} it",
        r.translation_mm, r.iterations
    );
    assert!((slide - 100.0).abs() < 5.0, "colour ICP read {slide} mm");
    // Without a guess the slide (100 mm) is beyond the photometric basin (about a texture period):
    // reported, not required; the executive passes the hand's travel.
    let (slide0, _) = panel_case(&IcpConfig::default(), 0.0);
    eprintln!("colour slide without a guess: {slide0:.1} mm");
}

#[test]
fn a_panel_with_its_edges_in_view_is_found_by_colour_and_partly_by_geometry() {
    // Invariant: with the edges of a 0.8 m panel in view, colour ICP from the hand's guess reads the
    // 100 mm slide within 5 mm; geometry alone gets only part of it (through the edges).
    let (colour, _) = panel_case_of_width(&IcpConfig::default(), 85.0, 0.8);
    let (geometric, _) = panel_case_of_width(&IcpConfig::geometric_only(), 0.0, 0.8);
    eprintln!("0.8 m panel: colour {colour:.1} mm, geometric-only {geometric:.1} mm");
    assert!((colour - 100.0).abs() < 5.0, "colour ICP read {colour} mm");
}

#[test]
fn icp_is_deterministic_whatever_the_thread_count() {
    // Invariant: the same clouds and guess give the same result bit for bit on 1 thread and on many.
    let start = planar(CHAIR_X, CHAIR_Y, 0.0);
    let end = planar(CHAIR_X + 0.3, CHAIR_Y, 2f64.to_radians());
    let before = object_points(&chair("chair", start, [40, 90, 160]), &eye(), 100);
    let after = object_points(&chair("chair", end, [40, 90, 160]), &eye(), 101);
    let guess = Isometry3::translation(0.25, 0.0, 0.0);
    let run = || colour_icp(&before, &after, &guess, &IcpConfig::default()).expect("enough points");
    let one = rayon::ThreadPoolBuilder::new()
        .num_threads(1)
        .build()
        .expect("a one-thread pool")
        .install(run);
    let many = rayon::ThreadPoolBuilder::new()
        .num_threads(4)
        .build()
        .expect("a four-thread pool")
        .install(run);
    assert_eq!(one, many);
}

//! Bad input gives an error or an empty result, never a panic.

use nalgebra::{Isometry2, Isometry3, Point3, Vector2};
use nudge_perception::{
    CloudFrame, ColourCloud, IcpConfig, PerceptionConfig, PerceptionError, colour_icp,
    detect_objects, fuse,
};
use proptest::prelude::*;

fn cloud(points: &[[f32; 3]], colour: [u8; 3]) -> ColourCloud {
    let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
    for p in points {
        c.push(Point3::new(p[0], p[1], p[2]), colour);
    }
    c
}

fn origin() -> Isometry2<f64> {
    Isometry2::identity()
}

#[test]
fn empty_and_all_nan_clouds_are_empty_cloud_errors() {
    // Invariant: a cloud with no valid point is EmptyCloud, whether it has no slots or only NaNs.
    let cfg = PerceptionConfig::default();
    assert_eq!(
        detect_objects(&cloud(&[], [0; 3]), &origin(), &cfg, &[]),
        Err(PerceptionError::EmptyCloud)
    );
    let nans = cloud(&[[f32::NAN, 0.0, 0.0], [0.0, f32::INFINITY, 0.0]], [0; 3]);
    assert_eq!(
        detect_objects(&nans, &origin(), &cfg, &[]),
        Err(PerceptionError::EmptyCloud)
    );
}

#[test]
fn no_floor_in_front_and_one_point_are_floor_errors() {
    // Invariant: no point in the known-floor square, or too few, is an error naming the cause.
    let cfg = PerceptionConfig::default();
    let behind = cloud(&[[-1.0, 0.0, 0.0], [-1.2, 0.1, 0.0]], [150, 150, 140]);
    assert!(matches!(
        detect_objects(&behind, &origin(), &cfg, &[]),
        Err(PerceptionError::NoFloorPoints { .. })
    ));
    let one = cloud(&[[1.0, 0.0, 0.0]], [150, 150, 140]);
    assert!(matches!(
        detect_objects(&one, &origin(), &cfg, &[]),
        Err(PerceptionError::TooFewFloorPoints { found: 1, .. })
    ));
}

#[test]
fn all_points_at_one_spot_give_no_obstacle() {
    // Invariant: a thousand copies of one floor point learn a (regularised) floor and find nothing.
    let same = cloud(&[[1.0, 0.0, 0.0]; 1000], [150, 150, 140]);
    let prisms = detect_objects(&same, &origin(), &PerceptionConfig::default(), &[])
        .expect("the spot is in the floor square");
    assert!(prisms.is_empty());
}

#[test]
fn a_non_finite_base_pose_is_an_error() {
    // Invariant: a NaN pose is rejected, not propagated into the map.
    let floor = cloud(&[[1.0, 0.0, 0.0]; 100], [150, 150, 140]);
    let bad = Isometry2::new(Vector2::new(f64::NAN, 0.0), 0.0);
    assert!(matches!(
        detect_objects(&floor, &bad, &PerceptionConfig::default(), &[]),
        Err(PerceptionError::InvalidInput(_))
    ));
}

#[test]
fn icp_on_too_few_points_or_a_nan_guess_is_an_error() {
    // Invariant: ICP refuses clouds below its minimum and non-finite guesses.
    let few = cloud(&[[0.0, 0.0, 0.0]; 5], [1, 2, 3]);
    let cfg = IcpConfig::default();
    assert!(matches!(
        colour_icp(&few, &few, &Isometry3::identity(), &cfg),
        Err(PerceptionError::TooFewIcpPoints { .. })
    ));
    let many: Vec<[f32; 3]> = (0..100).map(|i| [i as f32 * 0.01, 0.0, 0.0]).collect();
    let line = cloud(&many, [1, 2, 3]);
    let nan_guess = Isometry3::translation(f64::NAN, 0.0, 0.0);
    assert!(matches!(
        colour_icp(&line, &line, &nan_guess, &cfg),
        Err(PerceptionError::InvalidInput(_))
    ));
}

#[test]
fn icp_on_one_spot_or_far_apart_clouds_does_not_panic() {
    // Invariant: degenerate geometry gives a result or an error, and clouds too far apart for the
    // first stage give TooFewCorrespondences.
    let spot = cloud(&[[1.0, 1.0, 1.0]; 100], [9, 9, 9]);
    let cfg = IcpConfig::default();
    let _ = colour_icp(&spot, &spot, &Isometry3::identity(), &cfg);
    let grid: Vec<[f32; 3]> = (0..400)
        .map(|i| [(i % 20) as f32 * 0.01, (i / 20) as f32 * 0.01, 0.0])
        .collect();
    let a = cloud(&grid, [100, 100, 100]);
    let far = Isometry3::translation(10.0, 0.0, 0.0);
    assert!(matches!(
        colour_icp(&a, &a, &far, &cfg),
        Err(PerceptionError::TooFewCorrespondences { .. })
    ));
}

fn coord() -> impl Strategy<Value = f32> {
    prop_oneof![
        20 => -3.0f32..3.0,
        1 => Just(f32::NAN),
        1 => Just(f32::INFINITY),
        1 => Just(1e30f32),
    ]
}

fn small_cloud() -> impl Strategy<Value = ColourCloud> {
    prop::collection::vec(((coord(), coord(), -0.5f32..2.0), any::<[u8; 3]>()), 0..300).prop_map(
        |pts| {
            let mut c = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
            for ((x, y, z), rgb) in pts {
                c.push(Point3::new(x, y, z), rgb);
            }
            c
        },
    )
}

/// The seed of the fixed cases.
const SEED: u64 = 1;

/// The proptest configuration: 64 cases from a fixed seed, so every run (CI's included) tries the same
/// cases and a failure reproduces; `PROPTEST_RNG_SEED=<n>` explores others.
fn config() -> ProptestConfig {
    let mut config = ProptestConfig::with_cases(64);
    if std::env::var_os("PROPTEST_RNG_SEED").is_none() {
        config.rng_seed = proptest::test_runner::RngSeed::Fixed(SEED);
    }
    config
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_small_clouds_never_panic(
        c in small_cloud(),
        x in -3.0f64..3.0,
        y in -3.0f64..3.0,
        yaw in -3.2f64..3.2,
    ) {
        // Invariant: any small cloud through the whole pipeline, fusion and ICP returns, never panics,
        // and every prism it returns is a finite CCW polygon with z_min ≤ z_max.
        let pose = Isometry2::new(Vector2::new(x, y), yaw);
        let cfg = PerceptionConfig { floor: nudge_perception::FloorConfig { min_patch_points: 3, ..Default::default() }, ..Default::default() };
        if let Ok(prisms) = detect_objects(&c, &pose, &cfg, &[]) {
            for p in &prisms {
                prop_assert!(p.footprint.iter().all(|v| v.x.is_finite() && v.y.is_finite()));
                prop_assert!(nudge_perception::prism::polygon_area(&p.footprint) > 0.0);
                prop_assert!(p.z_min <= p.z_max);
            }
        }
        let fused = fuse(&[c.clone(), c.clone()]);
        prop_assert_eq!(fused.len(), 2 * c.valid_count());
        let _ = colour_icp(&c, &fused, &Isometry3::identity(), &IcpConfig { min_points: 3, neighbours: 3, ..Default::default() });
    }
}

proptest! {
    #![proptest_config(config())]

    #[test]
    fn random_clutter_on_a_known_floor_never_panics(
        c in small_cloud(),
        x in -3.0f64..3.0,
        y in -3.0f64..3.0,
        yaw in -3.2f64..3.2,
    ) {
        // Invariant: with a valid floor patch in front, random clutter goes through every stage to
        // well-formed prisms (finite CCW footprints, 0 ≤ z_min ≤ z_max), deterministically.
        let pose = Isometry2::new(Vector2::new(x, y), yaw);
        let mut cloud = c.clone();
        for i in 0..60 {
            let b = nalgebra::Point2::new(0.85 + 0.3 * f64::from(i % 6) / 6.0, -0.15 + 0.3 * f64::from(i / 6) / 10.0);
            let m = pose * b;
            cloud.push(Point3::new(m.x as f32, m.y as f32, 0.0), [150, 150, 140]);
        }
        let cfg = PerceptionConfig::default();
        let prisms = detect_objects(&cloud, &pose, &cfg, &[]);
        prop_assert!(prisms.is_ok(), "{:?}", prisms);
        let prisms = prisms.unwrap_or_default();
        for p in &prisms {
            prop_assert!(p.footprint.iter().all(|v| v.x.is_finite() && v.y.is_finite()));
            prop_assert!(nudge_perception::prism::polygon_area(&p.footprint) > 0.0);
            prop_assert!(0.0 <= p.z_min && p.z_min <= p.z_max);
        }
        prop_assert_eq!(detect_objects(&cloud, &pose, &cfg, &prisms).map(|v| v.len()), Ok(prisms.len()));
    }
}

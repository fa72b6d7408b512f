//! The colour range sensor against exact geometry: ranges, colours, layout, limits, exclusion, pose.

mod range_scene;

use nalgebra::{Point3, Vector3};
use nudge_perception::CloudFrame;
use nudge_sim::sensors::colour_range::{ColourRangeConfig, ColourRangeSensor, RayCaster};
use nudge_sim::surface::Owner;
use range_scene::{TestScene, pose, range_of};
use rapier3d::prelude::RigidBodyType;

const BOX_COLOUR: [u8; 3] = [200, 60, 40];

/// Floor plus a box whose front face is the plane x = 2 m, y ∈ [-0.5, 0.5], z ∈ [0.5, 1.5].
fn box_ahead_scene() -> TestScene {
    let mut scene = TestScene::with_floor();
    scene.add_box(
        RigidBodyType::Fixed,
        [2.25, 0.0, 1.0],
        [0.25, 0.5, 0.5],
        BOX_COLOUR,
        Owner::Object(0),
    );
    scene.refresh();
    scene
}

/// Pixels whose ray from (0, 0, 1) looking along +x meets the box face at least `margin` inside its
/// edges, with the exact range.
fn face_pixels(sensor: &ColourRangeSensor, margin: f64) -> Vec<(usize, f64)> {
    let c = sensor.config();
    let mut out = Vec::new();
    for row in 0..c.camera.height {
        for col in 0..c.camera.width {
            let d = sensor.ray_direction(row, col).expect("inside the image");
            let t = 2.0 / d.x;
            if (t * d.y).abs() < 0.5 - margin && (t * d.z).abs() < 0.5 - margin {
                out.push((row * c.camera.width + col, t));
            }
        }
    }
    out
}

fn noise_free() -> ColourRangeConfig {
    ColourRangeConfig {
        range_sigma_ref: 0.0,
        colour_noise_sigma: 0.0,
        ..ColourRangeConfig::default()
    }
}

#[test]
fn noise_free_ranges_are_the_exact_geometry() {
    // Without noise every ray that meets the box face returns the analytic range, to within half the camera's range step (it reports 14-bit counts over 5 m, 0.31 mm), and the box colour.
    let scene = box_ahead_scene();
    let sensor = ColourRangeSensor::new(noise_free());
    let half_step = sensor.config().camera.range_step() / 2.0;
    let cloud = scene.capture(&sensor, &pose([0.0, 0.0, 1.0], 0.0, 0.0), 1, None);
    let face = face_pixels(&sensor, 0.01);
    assert!(face.len() > 5000, "only {} face pixels", face.len());
    for &(i, truth) in &face {
        let r = range_of(&cloud, i).expect("a face pixel has a return");
        assert!(
            (r - truth).abs() < half_step + 1e-5,
            "slot {i}: {r} vs {truth}"
        );
        assert_eq!(cloud.colours()[i], BOX_COLOUR);
    }
}

#[test]
fn box_two_metres_ahead_has_small_mean_range_error_and_its_colour() {
    // With the default noise the mean range error over the face is under 5 mm, the spread matches the
    // noise model, and the mean colour is the box colour within a unit.
    let scene = box_ahead_scene();
    let sensor = ColourRangeSensor::new(ColourRangeConfig::default());
    let cloud = scene.capture(&sensor, &pose([0.0, 0.0, 1.0], 0.0, 0.0), 42, None);
    let face = face_pixels(&sensor, 0.01);

    let mut err_sum = 0.0;
    let mut normalised_sq = 0.0;
    let mut colour_sum = [0.0f64; 3];
    for &(i, truth) in &face {
        let r = range_of(&cloud, i).expect("a face pixel has a return");
        let d = sensor
            .ray_direction(
                i / sensor.config().camera.width,
                i % sensor.config().camera.width,
            )
            .expect("inside the image");
        let sigma = sensor.config().range_sigma(truth, d.x);
        err_sum += r - truth;
        normalised_sq += ((r - truth) / sigma).powi(2);
        for (sum, c) in colour_sum.iter_mut().zip(cloud.colours()[i]) {
            *sum += f64::from(c);
        }
    }
    let n = face.len() as f64;
    let mean_err = err_sum / n;
    let normalised_sd = (normalised_sq / n).sqrt();
    assert!(mean_err.abs() < 0.005, "mean range error {mean_err} m");
    assert!(
        (normalised_sd - 1.0).abs() < 0.05,
        "error / σ has sd {normalised_sd}"
    );
    for (sum, want) in colour_sum.iter().zip(BOX_COLOUR) {
        let mean = sum / n;
        assert!(
            (mean - f64::from(want)).abs() < 1.0,
            "mean channel {mean} vs {want}"
        );
    }
}

#[test]
fn returns_past_max_range_and_inside_min_range_are_nan() {
    // A wall 4.5 m ahead returns where the slant range is under 5 m and NaN (colour black) where it is
    // over; a wall 0.095 m ahead is NaN where nearer than 0.1 m; nothing at all gives all NaN.
    let sensor = ColourRangeSensor::new(noise_free());
    let c = sensor.config().clone();
    let slant = |i: usize, x: f64| {
        let d = sensor
            .ray_direction(i / c.camera.width, i % c.camera.width)
            .expect("inside the image");
        x / d.x
    };
    for wall_x in [4.5, 0.095] {
        let mut scene = TestScene::empty();
        scene.add_box(
            RigidBodyType::Fixed,
            [wall_x as f32 + 0.05, 0.0, 0.0],
            [0.05, 10.0, 10.0],
            [225, 222, 210],
            Owner::Wall,
        );
        scene.refresh();
        let cloud = scene.capture(&sensor, &pose([0.0, 0.0, 0.0], 0.0, 0.0), 3, None);
        let (mut kept, mut lost) = (0, 0);
        for i in 0..cloud.len() {
            let r = slant(i, wall_x);
            let in_limits = r > c.camera.min_range + 1e-4 && r < c.camera.max_range - 1e-4;
            let out_of_limits = r < c.camera.min_range - 1e-4 || r > c.camera.max_range + 1e-4;
            if in_limits {
                assert!(cloud.point(i).is_some(), "slot {i} at {r} m lost");
                kept += 1;
            } else if out_of_limits {
                assert!(cloud.point(i).is_none(), "slot {i} at {r} m kept");
                assert!(cloud.xs()[i].is_nan());
                assert_eq!(cloud.colours()[i], [0, 0, 0]);
                lost += 1;
            }
        }
        assert!(
            kept > 1000 && lost > 100,
            "wall {wall_x}: {kept} kept, {lost} lost"
        );
    }

    let nothing = TestScene::empty();
    let cloud = nothing.capture(&sensor, &pose([0.0, 0.0, 0.0], 0.0, 0.0), 3, None);
    assert_eq!(
        (cloud.width(), cloud.height()),
        (c.camera.width, c.camera.height)
    );
    assert_eq!(cloud.valid_count(), 0);
}

#[test]
fn the_robots_own_body_is_seen_through_and_its_parts_are_filtered() {
    // A robot part in front of the sensor: excluded, the box behind it is seen; not excluded, its
    // pixels are lost under the self filter and show the part without it.
    let mut scene = box_ahead_scene();
    let (robot, _) = scene.add_box(
        RigidBodyType::KinematicPositionBased,
        [0.5, 0.0, 1.0],
        [0.05, 0.3, 0.3],
        [40, 40, 40],
        Owner::Robot,
    );
    scene.refresh();
    let filtered = ColourRangeSensor::new(noise_free());
    let unfiltered = ColourRangeSensor::new(ColourRangeConfig {
        self_filter: false,
        ..noise_free()
    });
    let c = filtered.config();
    let centre = (c.camera.height / 2) * c.camera.width + c.camera.width / 2;
    let at = pose([0.0, 0.0, 1.0], 0.0, 0.0);

    let excluded = scene.capture(&filtered, &at, 5, Some(robot));
    let r = range_of(&excluded, centre).expect("the box returns");
    assert!((r - 2.0).abs() < 0.01, "range {r}");
    assert_eq!(excluded.colours()[centre], BOX_COLOUR);

    let lost = scene.capture(&filtered, &at, 5, None);
    assert!(lost.point(centre).is_none());

    let seen = scene.capture(&unfiltered, &at, 5, None);
    let r = range_of(&seen, centre).expect("the robot part returns");
    assert!((r - 0.45).abs() < 0.01, "range {r}");
    assert_eq!(seen.colours()[centre], [40, 40, 40]);
}

#[test]
fn row_culled_and_query_pipeline_casters_agree() {
    // Both ray casters return the same pixels with the same ranges and colours (up to float rounding
    // at silhouettes), on a scene with a compound, a rotated box and objects beside and behind, seen
    // from level, tilted, steep and rolled poses.
    let mut scene = TestScene::with_floor();
    scene.add_box(
        RigidBodyType::Fixed,
        [2.5, 0.4, 0.5],
        [0.3, 0.2, 0.5],
        BOX_COLOUR,
        Owner::Object(0),
    );
    scene.add_rotated_box([1.8, -0.6, 0.3], [0.2, 0.4, 0.3], 0.7, [20, 160, 60]);
    scene.add_table([3.0, -0.2], [0.4, 0.6], 0.72, [140, 90, 50]);
    scene.add_box(
        RigidBodyType::Fixed,
        [-1.0, 0.0, 0.5],
        [0.3, 0.3, 0.5],
        [90, 90, 200],
        Owner::Object(3),
    );
    scene.add_box(
        RigidBodyType::Fixed,
        [0.3, 1.2, 1.0],
        [0.2, 0.2, 1.0],
        [200, 200, 90],
        Owner::Object(4),
    );
    scene.refresh();
    let culled = ColourRangeSensor::new(ColourRangeConfig {
        caster: RayCaster::RowCulled,
        ..ColourRangeConfig::default()
    });
    let reference = ColourRangeSensor::new(ColourRangeConfig {
        caster: RayCaster::QueryPipeline,
        ..ColourRangeConfig::default()
    });
    for at in [
        pose([0.0, 0.0, 1.4], 0.0, 0.35),
        pose([0.0, 0.0, 1.4], 0.6, 0.2),
        pose([0.5, 0.2, 1.2], 2.0, 0.5),
        pose([1.0, -0.5, 0.6], -0.4, -0.1),
        pose([0.5, 0.0, 1.5], 0.2, 1.4),
        nalgebra::Isometry3::from_parts(
            nalgebra::Translation3::new(0.2, 0.1, 1.3),
            nalgebra::UnitQuaternion::from_euler_angles(0.4, 0.3, -0.2),
        ),
    ] {
        let a = scene.capture(&culled, &at, 21, None);
        let b = scene.capture(&reference, &at, 21, None);
        let mut mismatched = 0;
        for i in 0..a.len() {
            match (range_of(&a, i), range_of(&b, i)) {
                (Some(ra), Some(rb)) => {
                    if (ra - rb).abs() > 1e-4 || a.colours()[i] != b.colours()[i] {
                        mismatched += 1;
                    }
                }
                (None, None) => {}
                _ => mismatched += 1,
            }
        }
        assert!(
            a.valid_count() > 3000,
            "{} returns at {at}",
            a.valid_count()
        );
        assert!(
            mismatched * 1000 < a.len(),
            "{mismatched} pixels differ at {at}"
        );
    }
}

#[test]
fn layout_is_row_major_from_the_top_left() {
    // A box left of the optical axis appears only in the left half of the columns, a box above it
    // only in the top half of the rows; the cloud is organised, in the sensor frame, with the pose and
    // stamp given.
    let sensor = ColourRangeSensor::new(noise_free());
    let c = sensor.config().clone();
    let at = pose([0.0, 0.0, 1.0], 0.0, 0.0);
    // (box centre, true when the box is left of the axis rather than above it)
    for (centre, left) in [([2.0, 0.5, 1.0], true), ([2.0, 0.0, 1.4], false)] {
        let inside = |row: usize, col: usize| {
            if left {
                col < c.camera.width / 2
            } else {
                row < c.camera.height / 2
            }
        };
        let mut scene = TestScene::empty();
        scene.add_box(
            RigidBodyType::Fixed,
            centre,
            [0.1, 0.2, 0.2],
            BOX_COLOUR,
            Owner::Object(0),
        );
        scene.refresh();
        let cloud = scene.capture(&sensor, &at, 9, None);
        assert!(cloud.is_organised());
        assert_eq!(cloud.frame(), CloudFrame::Sensor);
        assert_eq!(cloud.sensor_pose(), &at);
        assert_eq!(cloud.stamp(), 0.5);
        let hits: Vec<usize> = cloud.iter_valid().map(|(i, _, _)| i).collect();
        assert!(hits.len() > 200, "{} returns", hits.len());
        for i in hits {
            assert!(
                inside(i / c.camera.width, i % c.camera.width),
                "slot {i} outside the expected half"
            );
        }
    }
}

#[test]
fn map_frame_points_land_on_the_surface_for_a_turned_and_tilted_sensor() {
    // With the sensor turned 90° left and tilted down, the points mapped through the recorded sensor
    // pose lie on the box face (y = 2, its top is above the sensor) and the floor (z = 0), nowhere else.
    let mut scene = TestScene::with_floor();
    scene.add_box(
        RigidBodyType::Fixed,
        [0.0, 2.25, 0.75],
        [2.0, 0.25, 0.75],
        BOX_COLOUR,
        Owner::Object(0),
    );
    scene.refresh();
    let sensor = ColourRangeSensor::new(noise_free());
    let at = pose([0.0, 0.0, 1.4], std::f64::consts::FRAC_PI_2, 0.4);
    let cloud = scene.capture(&sensor, &at, 1, None).to_map();
    let (mut on_face, mut on_floor) = (0, 0);
    for (_, p, colour) in cloud.iter_valid() {
        let p = Point3::new(f64::from(p.x), f64::from(p.y), f64::from(p.z));
        if colour == BOX_COLOUR {
            assert!((p.y - 2.0).abs() < 1e-3 && p.z <= 1.5 + 1e-3, "{p}");
            on_face += 1;
        } else {
            assert!(p.z.abs() < 1e-3, "{p}");
            on_floor += 1;
        }
        // Every return is in front of the sensor, i.e. towards +y.
        assert!((p.coords - at.translation.vector).dot(&Vector3::y()) > 0.0);
    }
    assert!(
        on_face > 1000 && on_floor > 1000,
        "{on_face} face, {on_floor} floor"
    );
}

#[test]
fn grazing_returns_are_lost() {
    // Looking level from 0.3 m, floor pixels seen at more than the maximum incidence (80°, i.e. rays
    // less than 10° below the horizon) are lost even within range; steeper ones return.
    let scene = {
        let mut s = TestScene::with_floor();
        s.refresh();
        s
    };
    let sensor = ColourRangeSensor::new(noise_free());
    let c = sensor.config().clone();
    let cloud = scene.capture(&sensor, &pose([0.0, 0.0, 0.3], 0.0, 0.0), 2, None);
    let col = c.camera.width / 2;
    let (mut lost, mut kept) = (0, 0);
    for row in c.camera.height / 2..c.camera.height {
        let d = sensor.ray_direction(row, col).expect("inside the image");
        let depression = (-d.z).asin().to_degrees();
        let range = 0.3 / -d.z;
        let i = row * c.camera.width + col;
        if depression < 90.0 - c.max_incidence_deg - 0.2 && range < c.camera.max_range {
            assert!(cloud.point(i).is_none(), "row {row} at {depression}° kept");
            lost += 1;
        } else if depression > 90.0 - c.max_incidence_deg + 0.2 {
            assert!(cloud.point(i).is_some(), "row {row} at {depression}° lost");
            kept += 1;
        }
    }
    assert!(lost > 10 && kept > 10, "{lost} lost, {kept} kept");
}

#[test]
fn colliders_without_a_surface_get_the_unknown_colour() {
    // A collider the surface lookup does not know still returns, in the configured unknown colour.
    let mut scene = TestScene::empty();
    scene.world.insert(
        rapier3d::prelude::RigidBodyBuilder::fixed()
            .translation(rapier3d::prelude::Vector::new(2.0, 0.0, 0.0))
            .build(),
        rapier3d::prelude::ColliderBuilder::cuboid(0.1, 1.0, 1.0),
    );
    scene.refresh();
    let sensor = ColourRangeSensor::new(noise_free());
    let cloud = scene.capture(&sensor, &pose([0.0, 0.0, 0.0], 0.0, 0.0), 2, None);
    assert!(cloud.valid_count() > 1000);
    for (_, _, colour) in cloud.iter_valid() {
        assert_eq!(colour, sensor.config().unknown_colour);
    }
}

#[test]
fn an_invalid_config_or_pose_captures_nothing_without_panicking() {
    // A sensor built from a bad configuration returns an empty cloud; a NaN pose returns no points.
    let scene = box_ahead_scene();
    for bad in [
        ColourRangeConfig {
            camera: nudge_robot_model::CameraModel {
                h_fov_deg: -3.0,
                ..Default::default()
            },
            ..ColourRangeConfig::default()
        },
        ColourRangeConfig {
            camera: nudge_robot_model::CameraModel {
                width: usize::MAX,
                height: 3,
                ..Default::default()
            },
            ..ColourRangeConfig::default()
        },
    ] {
        let bad = ColourRangeSensor::new(bad);
        let cloud = scene.capture(&bad, &pose([0.0, 0.0, 1.0], 0.0, 0.0), 1, None);
        assert!(cloud.is_empty());
    }

    let good = ColourRangeSensor::new(ColourRangeConfig::default());
    let cloud = scene.capture(&good, &pose([f64::NAN, 0.0, 1.0], 0.0, 0.0), 1, None);
    assert_eq!(cloud.len(), 176 * 144);
    assert_eq!(cloud.valid_count(), 0);
}

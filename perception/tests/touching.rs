//! Things that touch: a box flush against a wall, two boxes abreast, told apart by their colours.

use nalgebra::{Isometry2, Isometry3, Point3};
use nudge_perception::{CloudFrame, ColourCloud, PerceptionConfig, Prism, detect_objects};

/// Floor in front of a robot at the origin facing +x (x 0.5–3.5, y −1.5–1.5), grey.
fn floor(cloud: &mut ColourCloud) {
    for i in 0..60 {
        for j in 0..60 {
            let (x, y) = (0.5 + 0.05 * i as f32, -1.5 + 0.05 * j as f32);
            cloud.push(Point3::new(x, y, 0.0), [150, 150, 140]);
        }
    }
}

/// A vertical face at `x` from `y0` to `y1`, heights `z0` to `z1`, sampled every 1 cm, with a
/// shade that alternates every 5 cm (a texture: same hue, 60 % brightness).
fn face(cloud: &mut ColourCloud, x: f32, (y0, y1): (f32, f32), (z0, z1): (f32, f32), rgb: [u8; 3]) {
    let (ny, nz) = (((y1 - y0) / 0.01) as i32, ((z1 - z0) / 0.01) as i32);
    for j in 0..=ny {
        for k in 0..=nz {
            let (y, z) = (y0 + 0.01 * j as f32, z0 + 0.01 * k as f32);
            cloud.push(Point3::new(x, y, z), shade(rgb, j / 5 + k / 5));
        }
    }
}

/// A horizontal top at height `z` over `x0..x1` × `y0..y1`, sampled every 1 cm.
fn top(cloud: &mut ColourCloud, (x0, x1): (f32, f32), (y0, y1): (f32, f32), z: f32, rgb: [u8; 3]) {
    let (nx, ny) = (((x1 - x0) / 0.01) as i32, ((y1 - y0) / 0.01) as i32);
    for i in 0..=nx {
        for j in 0..=ny {
            let p = Point3::new(x0 + 0.01 * i as f32, y0 + 0.01 * j as f32, z);
            cloud.push(p, shade(rgb, i / 5 + j / 5));
        }
    }
}

fn shade(rgb: [u8; 3], parity: i32) -> [u8; 3] {
    if parity % 2 == 0 {
        rgb
    } else {
        rgb.map(|c| (f32::from(c) * 0.6).round() as u8)
    }
}

/// A red box 0.5 m deep and 0.7 m tall flush against a grey wall at x = 3, as the robot sees it:
/// the box's front face and top, the wall's face above the box and beside it.
fn box_flush_against_wall() -> ColourCloud {
    let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
    floor(&mut cloud);
    let (red, grey) = ([200, 60, 40], [225, 222, 210]);
    face(&mut cloud, 2.5, (-0.3, 0.3), (0.0, 0.7), red);
    top(&mut cloud, (2.5, 3.0), (-0.3, 0.3), 0.7, red);
    face(&mut cloud, 3.0, (-1.5, 1.5), (0.7, 2.0), grey);
    face(&mut cloud, 3.0, (-1.5, -0.31), (0.0, 0.7), grey);
    face(&mut cloud, 3.0, (0.31, 1.5), (0.0, 0.7), grey);
    cloud
}

/// The prisms holding any point of the box: within its footprint (x 2.5–3.0, y −0.3–0.3, short
/// of the wall's face) up to its top.
fn over_the_box(prisms: &[Prism]) -> Vec<&Prism> {
    prisms
        .iter()
        .filter(|p| {
            p.points.iter_valid().any(|(_, q, _)| {
                q.x > 2.49 && q.x < 2.99 && q.y.abs() < 0.29 && q.z > 0.05 && q.z < 0.71
            })
        })
        .collect()
}

#[test]
fn a_box_flush_against_a_wall_of_another_colour_is_an_obstacle_of_its_own() {
    // Invariant: a red box against a grey wall becomes a prism of its own, its footprint the box's (within a cell) and its top the box's; without the colour split it is one obstacle with the wall.
    let cloud = box_flush_against_wall();
    let config = PerceptionConfig::default();
    let prisms = detect_objects(&cloud, &Isometry2::identity(), &config, &[]).expect("detects");
    let boxes = over_the_box(&prisms);
    assert_eq!(boxes.len(), 1, "{} prisms hold the box", boxes.len());
    let b = boxes[0];
    let (xs, ys): (Vec<f64>, Vec<f64>) = b.footprint.iter().map(|p| (p.x, p.y)).unzip();
    let span = |v: &[f64]| {
        (
            v.iter().copied().fold(f64::MAX, f64::min),
            v.iter().copied().fold(f64::MIN, f64::max),
        )
    };
    let ((x0, x1), (y0, y1)) = (span(&xs), span(&ys));
    assert!(x0 > 2.45 && x1 < 3.05, "x {x0:.3}..{x1:.3}");
    assert!(y0 > -0.35 && y1 < 0.35, "y {y0:.3}..{y1:.3}");
    assert!((b.z_max - 0.7).abs() < 0.03, "top {:.3}", b.z_max);
    // No grey in the box's obstacle.
    let grey = b
        .points
        .iter_valid()
        .filter(|(_, _, c)| c[0] > 130 && c[1] > 130)
        .count();
    assert_eq!(grey, 0, "{grey} of the wall's points in the box's obstacle");

    let mut colourless = config.clone();
    colourless.elevation.hue = None;
    let merged = detect_objects(&cloud, &Isometry2::identity(), &colourless, &[]).expect("detects");
    let boxes = over_the_box(&merged);
    assert!(
        boxes.iter().any(|p| p.z_max > 1.5),
        "without colour the box is one obstacle with the wall"
    );
}

#[test]
fn two_boxes_abreast_of_different_colours_are_two_obstacles() {
    // Invariant: a blue and a green box standing side by side with no gap are two prisms, each with only its own points.
    let mut cloud = ColourCloud::empty(CloudFrame::Map, Isometry3::identity(), 0.0);
    floor(&mut cloud);
    let (blue, green) = ([40, 70, 170], [40, 150, 70]);
    for (rgb, (y0, y1)) in [(blue, (-0.5, 0.0)), (green, (0.0, 0.5))] {
        face(&mut cloud, 2.0, (y0, y1), (0.0, 0.6), rgb);
        top(&mut cloud, (2.0, 2.5), (y0, y1), 0.6, rgb);
    }
    let prisms = detect_objects(
        &cloud,
        &Isometry2::identity(),
        &PerceptionConfig::default(),
        &[],
    )
    .expect("detects");
    let holding = |rgb: [u8; 3]| {
        prisms
            .iter()
            .filter(|p| {
                p.points
                    .iter_valid()
                    .any(|(_, _, c)| c == rgb || c == shade(rgb, 1))
            })
            .count()
    };
    assert_eq!(holding(blue), 1);
    assert_eq!(holding(green), 1);
    let tall: Vec<&Prism> = prisms.iter().filter(|p| p.z_max > 0.3).collect();
    assert_eq!(tall.len(), 2, "{} obstacles", tall.len());
}

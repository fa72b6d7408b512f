//! Builders of Foxglove messages from nudge's types. Pure functions: no I/O.

use foxglove::bytes::Bytes;
use foxglove::messages::{
    ArrowPrimitive, Color, FrameTransform, Grid, LinePrimitive, PackedElementField,
    Point3 as FxPoint3, PointCloud, Pose, Quaternion, SceneEntity, SceneUpdate, Timestamp,
    TriangleListPrimitive, Vector2 as FxVector2, Vector3 as FxVector3, line_primitive,
    packed_element_field::NumericType,
};
use nalgebra::{Isometry3, Point2, UnitQuaternion, Vector3};
use nudge_perception::{ColourCloud, Prism};

use super::observer::GridView;
use crate::push_test::PushIntent;

/// Robot-clock seconds as a Foxglove timestamp (the run starts at 0 s).
pub fn timestamp(stamp: f64) -> Timestamp {
    let ns = nanos(stamp);
    Timestamp::new((ns / 1_000_000_000) as u32, (ns % 1_000_000_000) as u32)
}

/// Robot-clock seconds as MCAP nanoseconds; negative and non-finite stamps clamp to 0.
pub fn nanos(stamp: f64) -> u64 {
    if stamp.is_finite() && stamp > 0.0 {
        (stamp * 1e9).round() as u64
    } else {
        0
    }
}

fn pose(iso: &Isometry3<f64>) -> Pose {
    let t = iso.translation.vector;
    let q = iso.rotation;
    Pose {
        position: Some(FxVector3 {
            x: t.x,
            y: t.y,
            z: t.z,
        }),
        orientation: Some(quaternion(&q)),
    }
}

fn quaternion(q: &UnitQuaternion<f64>) -> Quaternion {
    Quaternion {
        x: q.i,
        y: q.j,
        z: q.k,
        w: q.w,
    }
}

fn point(x: f64, y: f64, z: f64) -> FxPoint3 {
    FxPoint3 { x, y, z }
}

fn colour(r: f64, g: f64, b: f64, a: f64) -> Color {
    Color { r, g, b, a }
}

fn field(name: &str, offset: u32, kind: NumericType) -> PackedElementField {
    PackedElementField {
        name: name.to_string(),
        offset,
        r#type: kind as i32,
    }
}

/// Points per metre of the recorded clouds' coordinate grid (1/1024 m, about 1 mm).
const QUANTUM_INV: f32 = 1024.0;

/// A colour cloud as a `foxglove.PointCloud`: x, y, z as float32 and red, green, blue as uint8,
/// expressed in the sensor frame and placed in `map` by the sensor pose (valid points only). Of an
/// organised cloud it keeps the pixels of every `stride`-th row and column (of an unorganised one,
/// every `stride`-th point); a stride of 1 keeps them all.
pub fn point_cloud(cloud: &ColourCloud, stride: usize) -> PointCloud {
    const STRIDE: usize = 16;
    let stride = stride.max(1);
    let width = cloud.width().max(1);
    let mut data = Vec::with_capacity(cloud.len() / (stride * stride) * STRIDE);
    // Coordinates are rounded to 1/1024 m: far below the sensor's noise and invisible in a viewer,
    // and a float with few mantissa bits compresses several times better than sensor noise does.
    let quantised = |v: f32| ((v * QUANTUM_INV).round() / QUANTUM_INV).to_le_bytes();
    // Only the shown slots are visited: at the default stride a twenty-fifth of them, in the run's
    // own thread.
    let rows = cloud.len() / width;
    let shown = (0..rows)
        .step_by(stride)
        .flat_map(|row| (0..width).step_by(stride).map(move |col| row * width + col));
    for i in shown {
        let Some(p) = cloud.point(i) else {
            continue;
        };
        let c = cloud.colours()[i];
        data.extend_from_slice(&quantised(p.x));
        data.extend_from_slice(&quantised(p.y));
        data.extend_from_slice(&quantised(p.z));
        data.extend_from_slice(&[c[0], c[1], c[2], 255]);
    }
    let origin = match cloud.frame() {
        nudge_perception::CloudFrame::Sensor => *cloud.sensor_pose(),
        nudge_perception::CloudFrame::Map => Isometry3::identity(),
    };
    PointCloud {
        timestamp: Some(timestamp(cloud.stamp())),
        frame_id: "map".into(),
        pose: Some(pose(&origin)),
        point_stride: STRIDE as u32,
        fields: vec![
            field("x", 0, NumericType::Float32),
            field("y", 4, NumericType::Float32),
            field("z", 8, NumericType::Float32),
            field("red", 12, NumericType::Uint8),
            field("green", 13, NumericType::Uint8),
            field("blue", 14, NumericType::Uint8),
            field("alpha", 15, NumericType::Uint8),
        ],
        data: Bytes::from(data),
    }
}

/// The obstacle-type grid as a `foxglove.Grid` with one uint8 field, `class`.
pub fn grid(stamp: f64, view: &GridView<'_>) -> Grid {
    let origin = Isometry3::translation(view.origin.x, view.origin.y, 0.0);
    Grid {
        timestamp: Some(timestamp(stamp)),
        frame_id: "map".into(),
        pose: Some(pose(&origin)),
        column_count: view.width as u32,
        cell_size: Some(FxVector2 {
            x: view.resolution,
            y: view.resolution,
        }),
        row_stride: view.width as u32,
        cell_stride: 1,
        fields: vec![field("class", 0, NumericType::Uint8)],
        data: Bytes::copy_from_slice(view.classes),
    }
}

/// One entity holding every prism: side walls and top as triangles, outlines as lines.
pub fn prisms(stamp: f64, prisms: &[Prism]) -> SceneUpdate {
    let mut entities = Vec::with_capacity(prisms.len());
    for prism in prisms {
        let n = prism.footprint.len();
        if n < 3 {
            continue;
        }
        let (lo, hi) = (prism.z_min, prism.z_max);
        let mut points = Vec::new();
        for i in 0..n {
            let (a, b) = (prism.footprint[i], prism.footprint[(i + 1) % n]);
            points.extend([
                point(a.x, a.y, lo),
                point(b.x, b.y, lo),
                point(b.x, b.y, hi),
                point(a.x, a.y, lo),
                point(b.x, b.y, hi),
                point(a.x, a.y, hi),
            ]);
        }
        for i in 1..n - 1 {
            let (a, b, c) = (
                prism.footprint[0],
                prism.footprint[i],
                prism.footprint[i + 1],
            );
            points.extend([
                point(a.x, a.y, hi),
                point(b.x, b.y, hi),
                point(c.x, c.y, hi),
            ]);
        }
        let outline: Vec<FxPoint3> = prism
            .footprint
            .iter()
            .map(|p| point(p.x, p.y, hi))
            .collect();
        entities.push(SceneEntity {
            timestamp: Some(timestamp(stamp)),
            frame_id: "map".into(),
            id: format!("prism/{}", prism.id.0),
            triangles: vec![TriangleListPrimitive {
                pose: Some(pose(&Isometry3::identity())),
                points,
                color: Some(colour(0.9, 0.6, 0.1, 0.5)),
                ..Default::default()
            }],
            lines: vec![LinePrimitive {
                r#type: line_primitive::Type::LineLoop as i32,
                pose: Some(pose(&Isometry3::identity())),
                thickness: 0.01,
                points: outline,
                color: Some(colour(0.2, 0.1, 0.0, 1.0)),
                ..Default::default()
            }],
            ..Default::default()
        });
    }
    SceneUpdate {
        deletions: vec![],
        entities,
    }
}

/// A polyline on the floor as a scene entity (the path, or the planner's tree as a line list).
pub fn lines(
    stamp: f64,
    id: &str,
    points: &[Point2<f64>],
    list: bool,
    rgba: [f64; 4],
) -> SceneUpdate {
    let kind = if list {
        line_primitive::Type::LineList
    } else {
        line_primitive::Type::LineStrip
    };
    SceneUpdate {
        deletions: vec![],
        entities: vec![SceneEntity {
            timestamp: Some(timestamp(stamp)),
            frame_id: "map".into(),
            id: id.to_string(),
            lines: vec![LinePrimitive {
                r#type: kind as i32,
                pose: Some(pose(&Isometry3::identity())),
                thickness: if list { 0.005 } else { 0.03 },
                points: points.iter().map(|p| point(p.x, p.y, 0.02)).collect(),
                color: Some(colour(rgba[0], rgba[1], rgba[2], rgba[3])),
                ..Default::default()
            }],
            ..Default::default()
        }],
    }
}

/// The push direction at the hand height, and the measured force arrow when there is one.
pub fn push(stamp: f64, intent: &PushIntent, force: Option<nalgebra::Vector2<f64>>) -> SceneUpdate {
    let start = intent.stand.translation.vector;
    let arrow = |dir: Vector3<f64>, length: f64, rgba: Color| {
        let rot = UnitQuaternion::rotation_between(&Vector3::x(), &dir)
            .unwrap_or_else(UnitQuaternion::identity);
        ArrowPrimitive {
            pose: Some(pose(&Isometry3::from_parts(
                nalgebra::Translation3::new(start.x, start.y, intent.hand_height),
                rot,
            ))),
            shaft_length: length,
            shaft_diameter: 0.02,
            head_length: 0.08,
            head_diameter: 0.06,
            color: Some(rgba),
        }
    };
    let d = intent.direction.into_inner();
    let mut arrows = vec![arrow(
        Vector3::new(d.x, d.y, 0.0),
        intent.distance,
        colour(0.1, 0.4, 1.0, 1.0),
    )];
    if let Some(f) = force.filter(|f| f.norm() > 1e-6) {
        // 1 N draws as 2 cm.
        arrows.push(arrow(
            Vector3::new(f.x, f.y, 0.0),
            0.02 * f.norm(),
            colour(1.0, 0.1, 0.1, 1.0),
        ));
    }
    SceneUpdate {
        deletions: vec![],
        entities: vec![SceneEntity {
            timestamp: Some(timestamp(stamp)),
            frame_id: "map".into(),
            id: format!("push/{}", intent.target.0),
            arrows,
            ..Default::default()
        }],
    }
}

/// A parent → child transform.
pub fn frame(stamp: f64, parent: &str, child: &str, iso: &Isometry3<f64>) -> FrameTransform {
    let t = iso.translation.vector;
    FrameTransform {
        timestamp: Some(timestamp(stamp)),
        parent_frame_id: parent.into(),
        child_frame_id: child.into(),
        translation: Some(FxVector3 {
            x: t.x,
            y: t.y,
            z: t.z,
        }),
        rotation: Some(quaternion(&iso.rotation)),
    }
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Point3;
    use nudge_perception::CloudFrame;

    #[test]
    fn recorded_cloud_points_lie_on_the_millimetre_grid_within_half_a_step_of_the_cloud() {
        // Invariant: each recorded coordinate is the cloud's rounded to 1/1024 m (off by at most half a step, a multiple of the step), with its colour, in the cloud's order.
        let mut cloud = ColourCloud::empty(CloudFrame::Sensor, Isometry3::identity(), 1.5);
        let points = [(1.234_567, -0.000_49, 4.999_9), (-2.5, 0.333_33, 0.0)];
        for (k, &(x, y, z)) in points.iter().enumerate() {
            cloud.push(Point3::new(x, y, z), [10 * k as u8, 20, 30]);
        }
        let message = point_cloud(&cloud, 1);
        let data = message.data.as_ref();
        assert_eq!(data.len(), points.len() * 16);
        for (k, &(x, y, z)) in points.iter().enumerate() {
            let record = &data[k * 16..(k + 1) * 16];
            for (axis, truth) in [x, y, z].into_iter().enumerate() {
                let bytes: [u8; 4] = record[axis * 4..axis * 4 + 4].try_into().expect("4 bytes");
                let v = f32::from_le_bytes(bytes);
                assert!(
                    (v - truth).abs() <= 0.5 / QUANTUM_INV + 1e-7,
                    "{v} vs {truth}"
                );
                assert_eq!((v * QUANTUM_INV).fract(), 0.0, "{v} is on the grid");
            }
            assert_eq!(&record[12..16], &[10 * k as u8, 20, 30, 255]);
        }
    }

    #[test]
    fn a_strided_view_keeps_every_strided_row_and_column_of_an_organised_cloud() {
        // Invariant: with stride 2, a 4 × 3 cloud shows the pixels of rows 0 and 2 and columns 0 and 2 that returned, in image order, and nothing else.
        let n = 12;
        let x: Vec<f32> = (0..n).map(|i| i as f32).collect();
        let mut y = vec![0.0f32; n];
        y[8] = f32::NAN; // row 2, column 0: no return
        let cloud = ColourCloud::organised(
            4,
            3,
            x,
            y,
            vec![1.0; n],
            vec![[1, 2, 3]; n],
            CloudFrame::Sensor,
            Isometry3::identity(),
            0.0,
        )
        .expect("a 4 × 3 cloud");
        let message = point_cloud(&cloud, 2);
        let xs: Vec<f32> = message
            .data
            .chunks(16)
            .map(|r| f32::from_le_bytes(r[0..4].try_into().expect("4 bytes")))
            .collect();
        assert_eq!(xs, [0.0, 2.0, 10.0]);
    }
}

//! The wrist's wrench as a protobuf message, `nudge.WristWrench`, with its schema: a
//! `FileDescriptorSet` built here, so Foxglove decodes and plots it (`/wrist/wrench.force.x`, …)
//! with no `.proto` file to ship. A sample is at most 67 bytes (two nested vectors of three doubles
//! and the norm; proto3 leaves zeros out): the paper run's 99,300 samples made its recording 5.4 MB
//! smaller than the JSON they replace.

use prost::Message;
use prost_types::field_descriptor_proto::{Label, Type};
use prost_types::{DescriptorProto, FieldDescriptorProto, FileDescriptorProto, FileDescriptorSet};

use crate::robot::Wrench;

/// The schema's name, as Foxglove shows it.
pub const WRIST_WRENCH_SCHEMA: &str = "nudge.WristWrench";

/// A vector of three doubles (`nudge.Vector3`).
#[derive(Clone, PartialEq, Message)]
pub struct Vector3 {
    /// x.
    #[prost(double, tag = "1")]
    pub x: f64,
    /// y.
    #[prost(double, tag = "2")]
    pub y: f64,
    /// z.
    #[prost(double, tag = "3")]
    pub z: f64,
}

/// One wrist sample (`nudge.WristWrench`): force (N) and torque (N·m) in the wrist frame, and the
/// force's norm, the quantity the push test thresholds.
#[derive(Clone, PartialEq, Message)]
pub struct WristWrench {
    /// Force (N).
    #[prost(message, optional, tag = "1")]
    pub force: Option<Vector3>,
    /// Torque (N·m).
    #[prost(message, optional, tag = "2")]
    pub torque: Option<Vector3>,
    /// The force's norm (N).
    #[prost(double, tag = "3")]
    pub force_norm: f64,
    /// The largest force norm of the samples a viewing window averages (N); 0 for one sample.
    #[prost(double, tag = "4")]
    pub peak_force_norm: f64,
}

impl From<&Wrench> for WristWrench {
    fn from(w: &Wrench) -> Self {
        let v = |v: &nalgebra::Vector3<f64>| Vector3 {
            x: v.x,
            y: v.y,
            z: v.z,
        };
        Self {
            force: Some(v(&w.force)),
            torque: Some(v(&w.torque)),
            force_norm: w.force_norm(),
            peak_force_norm: 0.0,
        }
    }
}

/// The window the recording's `/wrist/wrench` averages the sensor's samples over (s): 100 Hz,
/// finer than any force a plot of a push test shows (a 2 cm/s stroke's rise at contact takes
/// tens of milliseconds on the 20 kN/m wrist), and a tenth of the 1 kHz messages, whose record,
/// index entry and noise made most of a recording. Every sample stays on the replay tape.
pub const VIEW_WINDOW: f64 = 0.01;

/// Sums of the samples in one viewing window.
#[derive(Debug)]
struct Window {
    index: i64,
    force: nalgebra::Vector3<f64>,
    torque: nalgebra::Vector3<f64>,
    peak: f64,
    samples: u32,
    last_stamp: f64,
}

/// Turns the wrist's samples into one [`WristWrench`] per [`VIEW_WINDOW`]: the mean force and
/// torque, the mean force's norm, and the largest norm of a single sample, so that a spike the
/// guard saw still shows.
#[derive(Debug, Default)]
pub struct WrenchWindows {
    open: Option<Window>,
}

impl WrenchWindows {
    /// Adds a sample taken at `stamp` (s); returns the window it closed, stamped with that window's
    /// last sample, when it is the first of a new one.
    pub fn push(&mut self, stamp: f64, w: &Wrench) -> Option<(f64, WristWrench)> {
        let index = (stamp / VIEW_WINDOW).floor() as i64;
        let closed = match &self.open {
            Some(open) if open.index != index => self.close(),
            _ => None,
        };
        let open = self.open.get_or_insert(Window {
            index,
            force: nalgebra::Vector3::zeros(),
            torque: nalgebra::Vector3::zeros(),
            peak: 0.0,
            samples: 0,
            last_stamp: stamp,
        });
        open.force += w.force;
        open.torque += w.torque;
        open.peak = open.peak.max(w.force_norm());
        open.samples += 1;
        open.last_stamp = stamp;
        closed
    }

    /// Closes the open window, if any.
    pub fn close(&mut self) -> Option<(f64, WristWrench)> {
        let open = self.open.take()?;
        let n = f64::from(open.samples);
        // Shown to 1/1024 N and N·m, far finer than a plot draws: a float with few mantissa bits
        // compresses where a mean's full bits do not.
        let shown = |v: f64| (v * 1024.0).round() / 1024.0;
        let mean = Wrench {
            force: (open.force / n).map(shown),
            torque: (open.torque / n).map(shown),
        };
        let mut message = WristWrench::from(&mean);
        message.force_norm = shown(message.force_norm);
        message.peak_force_norm = shown(open.peak);
        Some((open.last_stamp, message))
    }
}

/// The schema of [`WristWrench`]: a `FileDescriptorSet` of one proto3 file, encoded.
pub fn wrist_wrench_schema() -> Vec<u8> {
    let field =
        |name: &str, number: i32, kind: Type, type_name: Option<&str>| FieldDescriptorProto {
            name: Some(name.into()),
            number: Some(number),
            label: Some(Label::Optional as i32),
            r#type: Some(kind as i32),
            type_name: type_name.map(Into::into),
            json_name: Some(name.into()),
            ..FieldDescriptorProto::default()
        };
    let vector = DescriptorProto {
        name: Some("Vector3".into()),
        field: vec![
            field("x", 1, Type::Double, None),
            field("y", 2, Type::Double, None),
            field("z", 3, Type::Double, None),
        ],
        ..DescriptorProto::default()
    };
    let wrench = DescriptorProto {
        name: Some("WristWrench".into()),
        field: vec![
            field("force", 1, Type::Message, Some(".nudge.Vector3")),
            field("torque", 2, Type::Message, Some(".nudge.Vector3")),
            field("force_norm", 3, Type::Double, None),
            field("peak_force_norm", 4, Type::Double, None),
        ],
        ..DescriptorProto::default()
    };
    FileDescriptorSet {
        file: vec![FileDescriptorProto {
            name: Some("nudge/WristWrench.proto".into()),
            package: Some("nudge".into()),
            message_type: vec![vector, wrench],
            syntax: Some("proto3".into()),
            ..FileDescriptorProto::default()
        }],
    }
    .encode_to_vec()
}

#[cfg(test)]
mod tests {
    use super::*;
    use nalgebra::Vector3 as V;

    #[test]
    fn a_wrench_reads_back_from_its_bytes_and_the_schema_describes_them() {
        // Invariant: a sample encodes and decodes to the same force, torque and norm bit for bit; the schema is one proto3 file of package nudge whose WristWrench has the message's field numbers and types (force and torque of .nudge.Vector3, force_norm a double).
        let w = Wrench {
            force: V::new(-17.25, 0.5, 3.0e-7),
            torque: V::new(0.01, -0.2, f64::MIN_POSITIVE),
        };
        let bytes = WristWrench::from(&w).encode_to_vec();
        let back = WristWrench::decode(bytes.as_slice()).expect("decodes");
        let f = back.force.expect("force");
        let t = back.torque.expect("torque");
        assert_eq!([f.x, f.y, f.z], [w.force.x, w.force.y, w.force.z]);
        assert_eq!([t.x, t.y, t.z], [w.torque.x, w.torque.y, w.torque.z]);
        assert_eq!(back.force_norm.to_bits(), w.force_norm().to_bits());
        let set = FileDescriptorSet::decode(wrist_wrench_schema().as_slice()).expect("a set");
        let file = &set.file[0];
        assert_eq!(file.package(), "nudge");
        assert_eq!(file.syntax(), "proto3");
        let message = file
            .message_type
            .iter()
            .find(|m| m.name() == "WristWrench")
            .expect("WristWrench");
        let fields: Vec<(&str, i32, Type, &str)> = message
            .field
            .iter()
            .map(|f| (f.name(), f.number(), f.r#type(), f.type_name()))
            .collect();
        assert_eq!(
            fields,
            [
                ("force", 1, Type::Message, ".nudge.Vector3"),
                ("torque", 2, Type::Message, ".nudge.Vector3"),
                ("force_norm", 3, Type::Double, ""),
                ("peak_force_norm", 4, Type::Double, ""),
            ]
        );
        assert_eq!(format!("nudge.{}", message.name()), WRIST_WRENCH_SCHEMA);
    }

    #[test]
    fn a_window_holds_the_mean_of_its_samples_and_the_peak_of_any() {
        // Invariant: samples within one 10 ms window become one message, stamped with their last sample, whose force is their mean and whose peak is the largest single norm; the first sample of the next window closes it, and close() flushes the last.
        let mut windows = WrenchWindows::default();
        let sample = |fx: f64| Wrench {
            force: V::new(fx, 0.0, 0.0),
            torque: V::new(0.0, 0.0, 1.0),
        };
        let mut out = Vec::new();
        for (i, fx) in [1.0, 3.0, 20.0, 4.0, 2.0].into_iter().enumerate() {
            let stamp = 0.1 + 0.001 * i as f64 + 0.0005;
            out.extend(windows.push(stamp, &sample(fx)));
        }
        assert!(out.is_empty(), "one window so far");
        out.extend(windows.push(0.1105, &sample(8.0)));
        out.extend(windows.close());
        assert!(windows.close().is_none());
        assert_eq!(out.len(), 2);
        let (stamp, first) = &out[0];
        assert!((stamp - 0.1045).abs() < 1e-12, "{stamp}");
        assert!((first.force.as_ref().expect("force").x - 6.0).abs() < 1e-12);
        assert!((first.force_norm - 6.0).abs() < 1e-12);
        assert_eq!(first.peak_force_norm, 20.0);
        assert_eq!(first.torque.as_ref().expect("torque").z, 1.0);
        assert_eq!(out[1].1.peak_force_norm, 8.0);
    }
}

"""A ROS 2 robot's side of the wire, on Eclipse Cyclone DDS: the peer in nudge's interop test.

Usage: python3 cyclone_peer.py SECONDS

Joins DDS domain 0 and, on the ROS 2 topic names and types (rt/ prefix, pkg::msg::dds_::Name_
types), publishes what a robot publishes — a map → base_link transform on rt/tf, the head's joints
on rt/joint_states, and a known wrench on rt/wrist/wrench — every 10 ms, while it prints each
geometry_msgs/Twist it receives on rt/cmd_vel as one JSON line ({"linear": [...], "angular": [...]}).
Stops after SECONDS. Exit code 3 when cyclonedds is missing.
"""

import json
import sys
import time
from dataclasses import dataclass

try:
    from cyclonedds.domain import DomainParticipant
    from cyclonedds.idl import IdlStruct
    from cyclonedds.idl.types import float64, int32, sequence, uint32
    from cyclonedds.pub import DataWriter
    from cyclonedds.sub import DataReader
    from cyclonedds.topic import Topic
    from cyclonedds.core import Qos, Policy
    from cyclonedds.internal import InvalidSample
except ImportError:
    print("cyclonedds not installed", file=sys.stderr)
    sys.exit(3)


@dataclass
class Time(IdlStruct, typename="builtin_interfaces::msg::dds_::Time_"):
    sec: int32
    nanosec: uint32


@dataclass
class Header(IdlStruct, typename="std_msgs::msg::dds_::Header_"):
    stamp: Time
    frame_id: str


@dataclass
class Vector3(IdlStruct, typename="geometry_msgs::msg::dds_::Vector3_"):
    x: float64
    y: float64
    z: float64


@dataclass
class Quaternion(IdlStruct, typename="geometry_msgs::msg::dds_::Quaternion_"):
    x: float64
    y: float64
    z: float64
    w: float64


@dataclass
class Transform(IdlStruct, typename="geometry_msgs::msg::dds_::Transform_"):
    translation: Vector3
    rotation: Quaternion


@dataclass
class TransformStamped(IdlStruct, typename="geometry_msgs::msg::dds_::TransformStamped_"):
    header: Header
    child_frame_id: str
    transform: Transform


@dataclass
class TFMessage(IdlStruct, typename="tf2_msgs::msg::dds_::TFMessage_"):
    transforms: sequence[TransformStamped]


@dataclass
class JointState(IdlStruct, typename="sensor_msgs::msg::dds_::JointState_"):
    header: Header
    name: sequence[str]
    position: sequence[float64]
    velocity: sequence[float64]
    effort: sequence[float64]


@dataclass
class Wrench(IdlStruct, typename="geometry_msgs::msg::dds_::Wrench_"):
    force: Vector3
    torque: Vector3


@dataclass
class WrenchStamped(IdlStruct, typename="geometry_msgs::msg::dds_::WrenchStamped_"):
    header: Header
    wrench: Wrench


@dataclass
class Twist(IdlStruct, typename="geometry_msgs::msg::dds_::Twist_"):
    linear: Vector3
    angular: Vector3


def stamp():
    now = time.time()
    return Time(sec=int(now), nanosec=int((now % 1.0) * 1e9))


def main():
    seconds = float(sys.argv[1])
    dp = DomainParticipant(0)
    reliable = Qos(Policy.Reliability.Reliable(max_blocking_time=100_000_000), Policy.History.KeepLast(10))
    tf = DataWriter(dp, Topic(dp, "rt/tf", TFMessage), qos=reliable)
    joints = DataWriter(dp, Topic(dp, "rt/joint_states", JointState), qos=reliable)
    wrench = DataWriter(dp, Topic(dp, "rt/wrist/wrench", WrenchStamped), qos=reliable)
    cmd_vel = DataReader(dp, Topic(dp, "rt/cmd_vel", Twist), qos=reliable)
    end = time.time() + seconds
    while time.time() < end:
        tf.write(TFMessage(transforms=[TransformStamped(
            header=Header(stamp=stamp(), frame_id="map"),
            child_frame_id="base_link",
            transform=Transform(Vector3(1.5, -0.25, 0.0), Quaternion(0.0, 0.0, 0.0, 1.0)),
        )]))
        joints.write(JointState(
            header=Header(stamp=stamp(), frame_id=""),
            name=["head_pan", "head_tilt"], position=[0.25, 0.5], velocity=[0.0, 0.0], effort=[],
        ))
        wrench.write(WrenchStamped(
            header=Header(stamp=stamp(), frame_id="hand"),
            wrench=Wrench(Vector3(1.5, -2.25, 3.125), Vector3(0.5, 0.0, -0.75)),
        ))
        for twist in cmd_vel.take(N=100):
            # A writer that leaves (the adapter dropped) arrives as an InvalidSample: a change of
            # the instance's state (disposed, no writers), with no Twist in it.
            if isinstance(twist, InvalidSample):
                continue
            print(json.dumps({
                "linear": [twist.linear.x, twist.linear.y, twist.linear.z],
                "angular": [twist.angular.x, twist.angular.y, twist.angular.z],
            }), flush=True)
        time.sleep(0.01)


if __name__ == "__main__":
    main()

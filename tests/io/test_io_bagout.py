"""What ``ros2 bag play`` needs of a bag that ``write_bag`` writes.

ROS 2 itself is not installed here, so ``ros2 bag play`` was not run. These
tests check, with rosbags' own reader, what rosbag2 reads before it replays a
bag: ``metadata.yaml`` (rosbag2 format version 8) with every topic's type,
serialization format ``cdr``, message count and RIHS01 type hash; each
connection's full message definition; and that the messages deserialize with
a type store built from those definitions alone (the bag describes itself).
"""

import numpy as np
import pytest

pytest.importorskip("rosbags")

from rosbags.rosbag2 import Reader
from rosbags.typesys import Stores, get_types_from_msg, get_typestore

from bag_samples import generated
from ndlfd.io import write_bag

TYPES = {
    "/gen": "geometry_msgs/msg/PoseStamped",
    "/gen/joint_states": "sensor_msgs/msg/JointState",
    "/gen/gripper": "std_msgs/msg/Float64",
}


def _self_described_store(connections):
    """A type store that knows only the message definitions in the bag."""
    store = get_typestore(Stores.EMPTY)
    for c in connections:
        store.register(get_types_from_msg(c.msgdef.data, c.msgtype))
    return store


def test_a_bag_folder_has_the_metadata_ros2_bag_play_reads(tmp_path):
    yaml = pytest.importorskip("yaml")
    demo = generated()
    out = write_bag(demo, tmp_path / "bag", topic="/gen")
    assert sorted(p.name for p in out.iterdir()) == ["bag.mcap", "metadata.yaml"]
    info = yaml.safe_load((out / "metadata.yaml").read_text())
    info = info["rosbag2_bagfile_information"]
    assert info["version"] == 8 and info["storage_identifier"] == "mcap"
    assert info["relative_file_paths"] == ["bag.mcap"]
    assert info["message_count"] == 3 * demo.n_samples
    assert info["starting_time"]["nanoseconds_since_epoch"] == 0
    assert info["duration"]["nanoseconds"] == round(demo.t[-1] * 1e9)
    latest = get_typestore(Stores.LATEST)  # ROS 2's own definitions, by rosbags
    topics = {e["topic_metadata"]["name"]: e for e in info["topics_with_message_count"]}
    assert set(topics) == set(TYPES)
    for name, entry in topics.items():
        meta = entry["topic_metadata"]
        assert entry["message_count"] == demo.n_samples
        assert meta["type"] == TYPES[name]
        assert meta["serialization_format"] == "cdr"
        # the hash of the type's description, computed independently
        assert meta["type_description_hash"] == latest.hash_rihs01(TYPES[name])


@pytest.mark.parametrize("name", ["bag", "out.mcap", "out.db3"])
def test_every_written_bag_describes_its_messages(tmp_path, name):
    demo = generated()
    out = write_bag(demo, tmp_path / name, topic="/gen")
    latest = get_typestore(Stores.LATEST)
    with Reader(out) as reader:
        assert reader.message_count == 3 * demo.n_samples
        assert reader.start_time == 0
        conns = {c.topic: c for c in reader.connections}
        assert {t: c.msgtype for t, c in conns.items()} == TYPES
        for c in conns.values():
            assert c.ext.serialization_format == "cdr"
            assert c.msgcount == demo.n_samples
            # the full definition (with every nested type), as ROS 2 has it
            want = latest.generate_msgdef(c.msgtype, ros_version=2)[0]
            assert c.msgdef.data == want
            if name.endswith(".mcap"):
                assert c.digest == ""  # rosbags' MCAP writer stores no type hash
            else:
                assert c.digest == latest.hash_rihs01(c.msgtype)
        own = _self_described_store(conns.values())
        poses = [
            own.deserialize_cdr(raw, c.msgtype)
            for c, _, raw in reader.messages(connections=[conns["/gen"]])
        ]
        grip = [
            own.deserialize_cdr(raw, c.msgtype).data
            for c, _, raw in reader.messages(connections=[conns["/gen/gripper"]])
        ]
    P = np.array([[m.pose.position.x, m.pose.position.y, m.pose.position.z]
                  for m in poses])  # fmt: skip
    Q = np.array([[m.pose.orientation.w, m.pose.orientation.x, m.pose.orientation.y,
                   m.pose.orientation.z] for m in poses])  # fmt: skip
    assert np.array_equal(P, demo.get("position"))
    assert np.array_equal(Q, demo.get("orientation"))
    assert np.array_equal(grip, demo.get("gripper")[:, 0])
    stamps = [m.header.stamp.sec * 10**9 + m.header.stamp.nanosec for m in poses]
    assert stamps == [round(t * 1e9) for t in demo.t]
